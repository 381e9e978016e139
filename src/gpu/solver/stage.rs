//! One stage of the stage list ([`crate::solver::stages`]) recorded on the GPU: the dispatches
//! of its kernels, the twins of the CPU solver's stages, and how many they are.

use glam::{Vec3, Vec4};

use super::{FamilyKernels, GpuFamily, GpuSolver, Run, groups, read_buffer, self_collision};
use crate::error::{Error, Result};
use crate::gpu::kernels::dispatch;
use crate::scene::FAMILY_COUNT;
use crate::solver::stages::Stage;
use crate::solver::{EnergyAware, Settings};

impl GpuSolver {
    /// Records one stage of a frame under `s` into `pass` ([`stages`]; the particles' bind group
    /// set; `families` from [`GpuSolver::with_kernels`]); `start_after`: [`Stage::Projection`]
    /// starts the budget instead of projecting; `fuse`: a run of one-element color groups is
    /// recorded whole by its first group's sweep and not by the others' (a whole frame), else
    /// each group's sweep by itself (stage by stage).
    pub(super) fn encode_stage(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        families: &[(&GpuFamily, &FamilyKernels)],
        stage: Stage,
        s: &Settings,
        (start_after, fuse): (bool, bool),
    ) {
        let k = &*self.kernels;
        let particle_groups = groups(self.n);
        let local = s.energy_aware == EnergyAware::Local;
        let local_groups = self.local.as_ref().filter(|_| local);
        match stage {
            Stage::ProjectionStart => self.encode_projection(pass, families, true),
            Stage::BalanceStart => self.encode_energy(pass, families, 0),
            Stage::Predict => {
                dispatch(pass, &k.predict, particle_groups);
            }
            Stage::Clear => {
                for (f, fk) in families {
                    self.dispatch_family(pass, &fk.clear, f, None, groups(f.len));
                }
            }
            Stage::LocalBegin => {
                let Some(lg) = local_groups else { return };
                pass.set_bind_group(3, lg, &[]);
                dispatch(pass, &k.local().begin, particle_groups);
                for (f, fk) in families {
                    if let Some(fl) = &f.local {
                        self.dispatch_family(pass, &fk.local_begin, f, Some(fl), groups(f.len));
                    }
                }
            }
            Stage::LocalSnapshot => {
                let Some(lg) = local_groups else { return };
                pass.set_bind_group(3, lg, &[]);
                dispatch(pass, &k.local().snapshot, particle_groups);
            }
            Stage::Sweep { family, color } => {
                let Some((f, fk)) = families.iter().find(|(f, _)| f.kind as usize == family) else { return };
                let local_family = f.local.as_ref().filter(|_| local);
                let d = f.sweeps[color];
                let (offset, workgroups, run) = match d.run {
                    Run::First(offset) if fuse => (offset, 1, true),
                    Run::Inside if fuse => return,
                    _ => (d.offset, groups(d.size), false),
                };
                pass.set_pipeline(match (local_family.is_some(), run) {
                    (false, false) => &fk.gauss_seidel,
                    (true, false) => &fk.gauss_seidel_local,
                    (false, true) => &fk.gauss_seidel_run,
                    (true, true) => &fk.gauss_seidel_local_run,
                });
                pass.set_bind_group(1, &f.bind_group, &[]);
                if let Some(fl) = local_family {
                    pass.set_bind_group(3, fl, &[]);
                }
                pass.set_bind_group(2, &self.range_bind_group, &[offset]);
                pass.dispatch_workgroups(workgroups, 1, 1);
            }
            Stage::Jacobi => {
                for (f, fk) in families {
                    if let Some((_, bg)) = &f.jacobi {
                        let local_family = f.local.as_ref().filter(|_| local);
                        pass.set_pipeline(if local_family.is_some() { &fk.jacobi_local } else { &fk.jacobi });
                        pass.set_bind_group(1, bg, &[]);
                        pass.set_bind_group(2, &self.range_bind_group, &[f.all_offset]);
                        if let Some(fl) = local_family {
                            pass.set_bind_group(3, fl, &[]);
                        }
                        pass.dispatch_workgroups(groups(f.len), 1, 1);
                    }
                }
                if let Some(j) = &self.jacobi {
                    pass.set_bind_group(1, &j.apply_bind_group, &[]);
                    dispatch(pass, k.jacobi_apply(), particle_groups);
                }
            }
            Stage::SelfPairs => self.encode_self_pairs(pass),
            Stage::SelfCollision => self.encode_self_collision(pass),
            Stage::Contacts => {
                dispatch(pass, &k.contacts, particle_groups);
            }
            Stage::Finish => {
                dispatch(pass, &k.finish, particle_groups);
            }
            Stage::Balance => {
                let Some(e) = &self.energy else { return };
                self.encode_energy(pass, families, 1);
                pass.set_bind_group(3, &e.bind_group, &[]);
                dispatch(pass, &k.energy().apply_scale, particle_groups);
            }
            Stage::Projection => self.encode_projection(pass, families, start_after),
        }
    }

    /// Dispatches [`GpuSolver::encode_stage`] records for `stage` under `s` in a whole frame.
    pub(super) fn stage_dispatches(&self, stage: Stage, s: &Settings) -> u64 {
        let present = self.families.len() as u64;
        // The energy reduction: the particles, each family, the total.
        let energy = present + 2;
        match stage {
            Stage::Sweep { family, color } => {
                let f = self.families.iter().find(|f| f.kind as usize == family);
                f.is_some_and(|f| f.sweeps[color].run != Run::Inside) as u64
            }
            Stage::Predict | Stage::LocalSnapshot | Stage::Contacts | Stage::Finish => 1,
            Stage::SelfPairs if self.self_collision.is_some() => self_collision::PAIRS_DISPATCHES as u64,
            Stage::SelfCollision if self.self_collision.is_some() => self_collision::PASS_DISPATCHES as u64,
            Stage::SelfPairs | Stage::SelfCollision => 0,
            Stage::Clear => present,
            Stage::LocalBegin => 1 + present,
            Stage::Jacobi => present + 1,
            Stage::BalanceStart => energy,
            Stage::Balance => energy + 1,
            // Mass moments, the rigid motion, the budget; projecting adds the kinetic energy to
            // scale and the velocities.
            Stage::ProjectionStart => energy + 2,
            Stage::Projection if s.energy_aware == EnergyAware::Project => energy + 5,
            Stage::Projection => 0,
        }
    }
}

impl GpuSolver {
    /// Records and submits `list`, a part of the stages [`crate::solver::stages::frame`] lists
    /// for `s` (one stage, say), after the same preparation as a frame: for stepping through a
    /// frame stage by stage, and for the per-stage parity tests (`tests/gpu_stages.rs`). The
    /// projection's budget is not planned here: a [`Stage::Projection`] projects towards the
    /// budget the GPU holds. Each color group's sweep is recorded by itself, also within a run of
    /// one-element groups that a whole frame records as one dispatch.
    pub fn step_stages(&mut self, list: &[Stage], s: &Settings) {
        self.prepare(s);
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("stages") });
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("stages"), timestamp_writes: None });
        pass.set_bind_group(0, &self.particles_bind_group, &[]);
        let families = self.with_kernels();
        for &stage in list {
            self.encode_stage(&mut pass, &families, stage, s, (false, false));
        }
        drop(pass);
        self.queue.submit([encoder.finish()]);
    }

    /// Overwrites the positions (m), one per particle, keeping everything else, the
    /// self-collision's references and candidates included: the next check renews the references
    /// of the particles that strayed, as after any motion.
    pub fn overwrite_positions(&mut self, x: &[Vec3]) -> Result<()> {
        let n = self.n as usize;
        if x.len() != n {
            return Err(Error::Gpu(format!("{} positions for {n} particles", x.len())));
        }
        let with_w: Vec<Vec4> = x.iter().zip(&self.scene.inv_mass).map(|(p, &w)| p.extend(w)).collect();
        self.queue.write_buffer(&self.x, 0, bytemuck::cast_slice(&with_w));
        Ok(())
    }

    /// Overwrites the positions, the substep's start positions, the velocities (each particle
    /// keeps its dissipated work) and the multipliers (per family in solve order, as
    /// [`crate::solver::CpuSolver::lambdas`] gives them): another solver's state, for the
    /// per-stage parity tests. Waits for the GPU (it reads the dissipated work back).
    pub fn set_state(
        &mut self,
        x: &[Vec3],
        x_prev: &[Vec3],
        v: &[Vec3],
        lambdas: [&[f32]; FAMILY_COUNT],
    ) -> Result<()> {
        let n = self.n as usize;
        if x.len() != n || x_prev.len() != n || v.len() != n {
            return Err(Error::Gpu(format!("state of {}, {}, {} particles for {n}", x.len(), x_prev.len(), v.len())));
        }
        let w = &self.scene.inv_mass;
        let work: Vec<Vec4> = read_buffer(&self.device, &self.queue, &self.v)?;
        let with_w = |p: &[Vec3]| -> Vec<Vec4> { p.iter().zip(w).map(|(p, &w)| p.extend(w)).collect() };
        self.queue.write_buffer(&self.x, 0, bytemuck::cast_slice(&with_w(x)));
        self.queue.write_buffer(&self.x_prev, 0, bytemuck::cast_slice(&with_w(x_prev)));
        let v4: Vec<Vec4> = v.iter().zip(&work).map(|(v, old)| v.extend(old.w)).collect();
        self.queue.write_buffer(&self.v, 0, bytemuck::cast_slice(&v4));
        self.invalidate_self_pairs();
        for f in &self.families {
            let l = lambdas[f.kind as usize];
            if l.len() != f.len as usize {
                return Err(Error::Gpu(format!("{} multipliers for {} {}", l.len(), f.len, f.kind.name())));
            }
            self.queue.write_buffer(&f.lambda, 0, bytemuck::cast_slice(l));
        }
        Ok(())
    }

    /// Reads the substep's start positions back (m; waits for the GPU).
    pub fn read_start_positions(&self) -> Result<Vec<Vec3>> {
        let x: Vec<Vec4> = read_buffer(&self.device, &self.queue, &self.x_prev)?;
        Ok(x.iter().map(|p| p.truncate()).collect())
    }
}
