//! The GPU solver's energy reduction: its buffers, its recording and the read-back of the
//! ledger (`shaders/solver/particles.wgsl`, the families' `energy` kernels; docs/algorithm.md §4).

use super::{
    FamilyKernels, GpuFamily, GpuLedger, GpuProjection, GpuSolver, PARTIAL_SLOTS, Result, entry, read_buffer,
    reduce_groups, storage_buffer,
};
use crate::gpu::kernels::dispatch;

/// Buffers of the energy reduction and the projection (allocated when first needed).
#[derive(Debug)]
pub(super) struct EnergyBuffers {
    pub(super) ledger: wgpu::Buffer,
    /// The projection's state ([`GpuProjection`]).
    pub(super) projection: wgpu::Buffer,
    pub(super) bind_group: wgpu::BindGroup,
}

/// Energies measured on the GPU by the reduction kernels (J).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuEnergies {
    /// Kinetic energy.
    pub kinetic: f64,
    /// Gravitational energy, heights from the ground as in [`crate::metrics::FrameStats`].
    pub gravitational: f64,
    /// The iterate's material energy, held and unresolved alike (the CPU's
    /// [`crate::metrics::FrameStats::material`]).
    pub elastic: f64,
    /// The part of it the multipliers hold (the CPU's [`crate::metrics::FrameStats::elastic`]).
    pub held: f64,
    /// Work of physical dissipation since the start.
    pub dissipated: f64,
    /// The last global velocity scale `σ`.
    pub last_scale: f64,
}

impl GpuSolver {
    /// Records the energy reduction; `mode` 0 sets the ledger's start energy, 1 runs the global
    /// balance, 2 only measures.
    pub(super) fn encode_energy(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        families: &[(&GpuFamily, &FamilyKernels)],
        mode: usize,
    ) {
        let Some(e) = &self.energy else { return };
        let k = self.kernels.energy();
        pass.set_bind_group(3, &e.bind_group, &[]);
        dispatch(pass, &k.particles, reduce_groups(self.n));
        for (f, fk) in families {
            self.dispatch_family(pass, &fk.energy, f, None, reduce_groups(f.len));
        }
        pass.set_bind_group(2, &self.range_bind_group, &[self.total_offsets[mode]]);
        dispatch(pass, &k.total, 1);
    }

    /// Allocates the reduction's buffers (once).
    pub(super) fn prepare_energy(&mut self) {
        if self.energy.is_some() {
            return;
        }
        let partials =
            storage_buffer(&self.device, "energy partials", &[0u8; PARTIAL_SLOTS * 16], wgpu::BufferUsages::empty());
        let ledger = storage_buffer(
            &self.device,
            "energy ledger",
            &[0u8; std::mem::size_of::<GpuLedger>()],
            wgpu::BufferUsages::empty(),
        );
        let projection = storage_buffer(
            &self.device,
            "projection",
            &[0u8; std::mem::size_of::<GpuProjection>()],
            wgpu::BufferUsages::empty(),
        );
        self.memory.energy = partials.size() + ledger.size() + projection.size();
        let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("energy"),
            layout: &self.kernels.energy_layout,
            entries: &[entry(2, &partials), entry(3, &ledger), entry(4, &projection)],
        });
        self.energy = Some(EnergyBuffers { ledger, projection, bind_group });
    }

    /// Energies by the GPU reduction (records one, waits and reads the ledger back).
    pub fn energies(&mut self) -> Result<GpuEnergies> {
        self.prepare_energy();
        let families = self.with_kernels();
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("energy") });
        {
            let mut pass = encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("energy"), timestamp_writes: None });
            pass.set_bind_group(0, &self.particles_bind_group, &[]);
            self.encode_energy(&mut pass, &families, 2);
        }
        self.queue.submit([encoder.finish()]);
        let Some(e) = &self.energy else { return Ok(GpuEnergies::default()) };
        let l: Vec<GpuLedger> = read_buffer(&self.device, &self.queue, &e.ledger)?;
        let l = l.first().copied().unwrap_or_default();
        Ok(GpuEnergies {
            kinetic: l.kinetic as f64,
            gravitational: l.gravitational as f64 + self.gravity_shift,
            elastic: l.elastic as f64,
            held: l.held as f64,
            dissipated: l.work as f64,
            last_scale: l.sigma as f64,
        })
    }
}
