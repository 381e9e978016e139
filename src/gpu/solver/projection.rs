//! The energy-momentum projection on the GPU (`--energy-aware project`;
//! `shaders/solver/projection.wgsl`), the twin of [`crate::solver::projection`] and the CPU
//! solver's `project.rs`: after the frame's substeps, the energy reduction measures the honest
//! energy (kinetic, gravitational and the elastic energy the multipliers hold) and the
//! dissipated work, then five dispatches find the rigid motion, the kinetic energy to scale, the
//! budget and the scale, and set the velocities. Nothing is read back inside a frame.

use super::{FamilyKernels, GpuFamily, GpuProjection, GpuSolver, groups, read_buffer, reduce_groups};
use crate::error::Result;
use crate::gpu::kernels::dispatch;
use crate::solver::{EnergyAware, Settings};

/// What the projection does around one frame.
#[derive(Clone, Copy, Debug)]
pub(super) struct FramePlan {
    /// Start the budget before the frame (the projection was switched on after frames under the
    /// same settings, whose multipliers say what the forces hold).
    pub start_before: bool,
    /// Start the budget after the frame instead of projecting (first frame, or new settings).
    pub start_after: bool,
}

impl GpuSolver {
    /// Before recording a frame under `s`: `None` when the projection is off (its budget is
    /// dropped), otherwise where the budget starts. As on the CPU, a frame under other settings
    /// than the last projected one (the thread count aside) starts the budget again after it.
    pub(super) fn plan_projection(&mut self, s: &Settings) -> Option<FramePlan> {
        if s.energy_aware != EnergyAware::Project {
            self.projected_with = None;
            self.budget_set = false;
            return None;
        }
        let key = Settings { threads: 0, ..*s };
        if self.projected_with.is_some_and(|p| p != key) {
            self.budget_set = false;
        }
        // The held energy before the frame is measured with the current parameters, so the
        // budget starts before the frame only when the last frame ran under the same settings.
        let start_before = !self.budget_set && self.last.as_ref() == Some(s);
        let start_after = !self.budget_set && !start_before;
        self.projected_with = Some(key);
        self.budget_set = true;
        Some(FramePlan { start_before, start_after })
    }

    /// Records the projection: the energy reduction, then (with `start`) the budget's start
    /// from the current state, else the projection towards it.
    pub(super) fn encode_projection(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        families: &[(&GpuFamily, &FamilyKernels)],
        start: bool,
    ) {
        let Some(e) = &self.energy else { return };
        self.encode_energy(pass, families, 2);
        let k = self.kernels.energy();
        let mode = self.total_offsets[usize::from(!start)];
        pass.set_bind_group(3, &e.bind_group, &[]);
        dispatch(pass, &k.projection_moments, reduce_groups(self.n));
        pass.set_bind_group(2, &self.range_bind_group, &[mode]);
        dispatch(pass, &k.projection_rigid, 1);
        if !start {
            dispatch(pass, &k.projection_deform, reduce_groups(self.n));
        }
        pass.set_bind_group(2, &self.range_bind_group, &[mode]);
        dispatch(pass, &k.projection_scale, 1);
        if !start {
            dispatch(pass, &k.projection_apply, groups(self.n));
        }
    }

    /// The projection's state on the GPU (waits and reads it back), `None` before the
    /// projection first ran.
    pub fn projection_state(&self) -> Result<Option<GpuProjection>> {
        let Some(e) = self.energy.as_ref().filter(|_| self.budget_set) else { return Ok(None) };
        let state: Vec<GpuProjection> = read_buffer(&self.device, &self.queue, &e.projection)?;
        Ok(state.first().copied())
    }

    /// Starts the energy balances again from the state the next frame leaves (the global
    /// balance's carried energy, the projection's budget): for a hand that moved a particle,
    /// whose work no budget counts.
    pub fn restart_budgets(&mut self) {
        self.ledger_valid = false;
        self.budget_set = false;
    }
}
