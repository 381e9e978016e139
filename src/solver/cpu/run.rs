//! The stage list ([`crate::solver::stages`]) on one thread: each stage by the CPU twin of the
//! GPU's kernels for it.

use crate::math::prelude::*;

use super::super::contacts::project_range;
use super::super::energy::EnergyAware;
use super::super::particles::FinishStep;
use super::super::stages::{self, Stage};
use super::super::xpbd::StepConstants;
use super::super::{Pull, Settings};
use super::{CpuSolver, gauss_seidel, local_ctx};

impl<V: Vector> CpuSolver<V> {
    /// Runs `list` in order on this thread ([`stages`]; a finish pass followed by a prediction
    /// makes it in the same visit of each particle).
    pub(super) fn run_stages(&mut self, list: &[Stage], s: &Settings, k: &StepConstants<V::S>) {
        let local = s.energy_aware == EnergyAware::Local;
        // The finish pass made the prediction that follows it.
        let mut predicted = false;
        for (i, &stage) in list.iter().enumerate() {
            match stage {
                Stage::ProjectionStart => {
                    self.start_budget();
                    self.dissipated_before = Some(self.ledger.dissipated);
                }
                Stage::BalanceStart => self.ledger.carried = Some(self.total_energy()),
                Stage::Predict if predicted => predicted = false,
                Stage::Predict => self.predict(k.h, s.pull),
                Stage::Clear => {
                    self.work_blocks.fill(0.0);
                    for st in &mut self.fam {
                        st.lambda.fill(V::S::zero());
                    }
                }
                Stage::LocalBegin => self.begin_local(k),
                Stage::LocalSnapshot => {
                    if let Some(l) = &mut self.local {
                        std::mem::swap(&mut l.previous, &mut l.current);
                        l.current.copy_from_slice(&self.particles.x);
                    }
                }
                Stage::Sweep { family, color } => {
                    let l = self.local.as_ref().filter(|_| local);
                    crate::with_family!(self.scene, family, |f| {
                        let st = &mut self.fam[family];
                        let ctx = l.map(|l| local_ctx(l, &st.energy_start));
                        let group = f.colors[color].start as usize..f.colors[color].end as usize;
                        gauss_seidel(f, group, &mut st.lambda, (&st.lanes, st.bound), &mut self.particles, k, ctx)
                    });
                }
                Stage::Jacobi => self.jacobi_iteration(k, local),
                Stage::SelfPairs => {
                    if let Some(sc) = &self.scene.self_collision {
                        self.self_pairs.update(&self.particles.x, &self.particles.w, sc);
                    }
                }
                Stage::SelfCollision => {
                    if let Some(sc) = &self.scene.self_collision {
                        let p = &mut self.particles;
                        self.self_pairs.project(&mut p.x, &p.x_prev, &p.w, sc, &mut self.dx);
                    }
                }
                Stage::Contacts => {
                    let p = &mut self.particles;
                    let inv_h = (V::S::one() / k.h).to_f64();
                    project_range(&self.scene, &mut p.x, &p.x_prev, &p.v, &p.w, inv_h, &mut self.work_blocks);
                }
                Stage::Finish => {
                    predicted = stages::finish_predicts(list, i);
                    let next = predicted.then(|| V::from_vec3(self.scene.gravity));
                    let step = FinishStep {
                        h: k.h,
                        damping: s.damping.into(),
                        next,
                        in_loop_contacts: s.contacts_in_finish(),
                        pull: Pull::within(s.pull, 0..self.particles.len()),
                    };
                    self.substep_work = self.finish(step);
                    self.ledger.dissipated += self.substep_work;
                }
                Stage::Balance => {
                    if let Some(h0) = self.ledger.carried {
                        self.balance(h0, self.substep_work);
                    }
                }
                Stage::Projection => self.after_frame(),
            }
        }
    }
}
