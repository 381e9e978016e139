//! The GPU solver's Jacobi buffers: each family's scales and corrections, and each particle's
//! correction slots in the CPU's summation order (docs/algorithm.md §1).

use super::{Element, Family, FamilyKind, GpuSolver, entry, jacobi, storage_buffer};

/// Jacobi's buffers, allocated on the first Jacobi frame.
#[derive(Debug)]
pub(super) struct JacobiBuffers {
    pub(super) apply_bind_group: wgpu::BindGroup,
    pub(super) omega: f32,
}

impl GpuSolver {
    /// Allocates Jacobi's scales, corrections and incidence (once per ω).
    pub(super) fn prepare_jacobi(&mut self, omega: f32) {
        if self.jacobi.as_ref().is_some_and(|j| j.omega == omega) {
            return;
        }
        let count = jacobi::constraint_counts(&self.scene);
        // For each particle, the correction slots touching it in the CPU's summation order
        // (families in solve order, elements in order); and each family's scales.
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); self.n as usize];
        let mut scales = Vec::with_capacity(self.families.len());
        for f in &self.families {
            let scene = &self.scene;
            scales.push(
                match f.kind {
                    FamilyKind::Springs => {
                        scene.springs.as_ref().map(|e| incidence(e, f.slot_base, &count, omega, &mut lists))
                    }
                    FamilyKind::Bending => {
                        scene.bends.as_ref().map(|e| incidence(e, f.slot_base, &count, omega, &mut lists))
                    }
                    FamilyKind::Tets => {
                        scene.tets.as_ref().map(|e| incidence(e, f.slot_base, &count, omega, &mut lists))
                    }
                    FamilyKind::Membranes => {
                        scene.membranes.as_ref().map(|e| incidence(e, f.slot_base, &count, omega, &mut lists))
                    }
                }
                .unwrap_or_default(),
            );
        }
        let total_slots: u32 = self.families.iter().map(|f| f.kind.arity() * f.len).sum();
        let corr = storage_buffer(
            &self.device,
            "jacobi corrections",
            &vec![0u8; total_slots as usize * 16],
            wgpu::BufferUsages::empty(),
        );
        let mut offsets = Vec::with_capacity(lists.len() + 1);
        let mut slots = Vec::new();
        offsets.push(0u32);
        for l in &lists {
            slots.extend_from_slice(l);
            offsets.push(slots.len() as u32);
        }
        let offsets = storage_buffer(
            &self.device,
            "incidence offsets",
            bytemuck::cast_slice(&offsets),
            wgpu::BufferUsages::empty(),
        );
        let slots =
            storage_buffer(&self.device, "incidence slots", bytemuck::cast_slice(&slots), wgpu::BufferUsages::empty());
        let apply_bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("jacobi apply"),
            layout: &self.kernels.apply_layout,
            entries: &[entry(0, &corr), entry(1, &offsets), entry(2, &slots)],
        });
        // The buffers of an earlier ω are dropped with their bind groups below.
        self.memory.jacobi = corr.size() + offsets.size() + slots.size();
        for (f, sc) in self.families.iter_mut().zip(scales) {
            {
                let scale = storage_buffer(
                    &self.device,
                    "jacobi scale",
                    bytemuck::cast_slice(&sc),
                    wgpu::BufferUsages::empty(),
                );
                self.memory.jacobi += scale.size();
                let bg = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("family jacobi"),
                    layout: &self.kernels.family_jacobi_layout,
                    entries: &[entry(0, &f.elements), entry(1, &f.lambda), entry(2, &scale), entry(3, &corr)],
                });
                f.jacobi = Some((scale, bg));
            }
        }
        self.jacobi = Some(JacobiBuffers { apply_bind_group, omega });
    }
}

/// Appends, for each particle, the correction slots of `f`'s elements that touch it, and returns
/// the elements' Jacobi scales.
fn incidence<E: Element<N>, const N: usize>(
    f: &Family<E, N>,
    slot_base: u32,
    count: &[u32],
    omega: f32,
    lists: &mut [Vec<u32>],
) -> Vec<f32> {
    for (j, e) in f.elements.iter().enumerate() {
        for (k, &p) in e.particles().iter().enumerate() {
            lists[p as usize].push(slot_base + (N * j + k) as u32);
        }
    }
    jacobi::scales(&f.elements, count, omega)
}
