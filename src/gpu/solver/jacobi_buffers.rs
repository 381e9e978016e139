//! The GPU solver's Jacobi buffers: each family's scales and corrections, and each particle's
//! correction slots in the CPU's summation order (docs/algorithm.md §1).

use super::{GpuSolver, entry, jacobi, storage_buffer};

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
        // Each particle's correction slots in the CPU's summation order (families in solve order,
        // elements in order: the team's `Slots`, whose family bases are the GPU's `slot_base`s),
        // and each family's scales.
        let incidence = jacobi::Slots::new(&self.scene);
        let mut scales = jacobi::family_scales::<f32>(&self.scene, omega);
        debug_assert!(self.families.iter().all(|f| incidence.base[f.kind as usize] == f.slot_base as usize));
        let corr = storage_buffer(
            &self.device,
            "jacobi corrections",
            &vec![0u8; incidence.total * 16],
            wgpu::BufferUsages::empty(),
        );
        let offsets = storage_buffer(
            &self.device,
            "incidence offsets",
            bytemuck::cast_slice(&incidence.offsets),
            wgpu::BufferUsages::empty(),
        );
        let slots = storage_buffer(
            &self.device,
            "incidence slots",
            bytemuck::cast_slice(&incidence.incident),
            wgpu::BufferUsages::empty(),
        );
        let apply_bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("jacobi apply"),
            layout: &self.kernels.apply_layout,
            entries: &[entry(0, &corr), entry(1, &offsets), entry(2, &slots)],
        });
        // The buffers of an earlier ω are dropped with their bind groups below.
        self.memory.jacobi = corr.size() + offsets.size() + slots.size();
        for f in &mut self.families {
            let sc = std::mem::take(&mut scales[f.kind as usize]);
            let scale =
                storage_buffer(&self.device, "jacobi scale", bytemuck::cast_slice(&sc), wgpu::BufferUsages::empty());
            self.memory.jacobi += scale.size();
            let bg = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("family jacobi"),
                layout: &self.kernels.family_jacobi_layout,
                entries: &[entry(0, &f.elements), entry(1, &f.lambda), entry(2, &scale), entry(3, &corr)],
            });
            f.jacobi = Some((scale, bg));
        }
        self.jacobi = Some(JacobiBuffers { apply_bind_group, omega });
    }
}
