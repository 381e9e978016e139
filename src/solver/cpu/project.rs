//! The solver's side of the energy-momentum projection ([`crate::solver::projection`]): the
//! budget before a frame, and the projection after it.

use crate::math::prelude::*;
use crate::solver::projection;
use crate::solver::{EnergyAware, Settings};

use super::CpuSolver;

/// What the projection needs from before a frame.
#[derive(Clone, Copy, Debug)]
pub(super) struct BeforeFrame {
    /// The budget starts before the frame ([`crate::solver::stages::Stage::ProjectionStart`]).
    pub start: bool,
    /// The work of physical dissipation until then (J).
    pub dissipated: f64,
}

impl<V: Vector> CpuSolver<V> {
    /// Before a frame under `s`: drops the budget when the projection is off or the settings
    /// changed, says whether it starts before the frame (the projection switched on after a step),
    /// and notes what [`CpuSolver::after_frame`] needs.
    pub(super) fn before_projection(&mut self, s: &Settings) -> Option<BeforeFrame> {
        if s.energy_aware != EnergyAware::Project {
            self.ledger.budget = None;
            self.ledger.projected_with = None;
            return None;
        }
        // Other settings measure the held energy with other multipliers: start again after the
        // frame (the thread count changes nothing).
        let settings = Settings { threads: 0, ..*s };
        let changed = self.ledger.projected_with.is_some_and(|p| p != settings);
        if changed {
            self.ledger.budget = None;
        }
        self.ledger.projected_with = Some(settings);
        let start = !changed && self.ledger.budget.is_none() && self.last.is_some();
        Some(BeforeFrame { start, dissipated: self.ledger.dissipated })
    }

    /// After a frame: the projection towards the budget plus the frame's dissipated work, or the
    /// budget's start after the first step.
    pub(super) fn after_frame(&mut self) {
        let before = self.dissipated_before.unwrap_or(self.ledger.dissipated);
        match self.ledger.budget {
            Some(budget) => self.project(budget + (self.ledger.dissipated - before)),
            None => self.start_budget(),
        }
    }

    /// The energy-momentum projection ([`super::projection`]) towards the budget `budget` (J).
    fn project(&mut self, budget: f64) {
        let held = self.held_energy();
        let p = &mut self.particles;
        let rigid = match projection::any_pinned(&p.w) {
            true => None,
            false => projection::rigid_motion(&p.x, &p.v, &p.w).map(|now| {
                let target = self.ledger.momenta.map_or(now, |(lp, ll)| now.with_momenta(lp, ll));
                projection::Rigid { now, target }
            }),
        };
        let (kinetic, scaled, rigid_target) = projection::kinetic_parts(&p.x, &p.v, &p.w, rigid.as_ref());
        // The gap in the scaled part: the energy's gap less what the new rigid motion changes.
        let rigid_now = kinetic - scaled;
        let gap = (budget - held) - (rigid_target - rigid_now);
        let s = projection::projection_scale(gap, kinetic, scaled, budget);
        projection::apply_scale(&p.x, &mut p.v, &p.w, rigid.as_ref(), s);
        self.ledger.budget = Some(budget);
        self.ledger.last_scale = s;
    }

    /// Starts the projection's budget from the current state: its energy and, for an isolated
    /// body, its momenta ([`projection::conserved_momenta`]).
    pub(super) fn start_budget(&mut self) {
        self.ledger.budget = Some(self.held_energy());
        let p = &self.particles;
        self.ledger.momenta = projection::conserved_momenta(&self.scene, &p.x, &p.v, &p.w);
    }
}
