//! Solvers and their settings. The CPU reference solver ([`CpuSolver`]) runs the stage list that
//! every backend follows ([`stages`]), per substep of `h = dt / substeps` (docs/algorithm.md §1):
//!
//! 1. predict: `x_prev = x`, `v += h g`, `x += h v` (free particles only);
//! 2. `λ = 0`;
//! 3. `iterations` times: each family in order (springs, then bending), each color group in
//!    increasing color (Gauss-Seidel)
//!    or every constraint against the same iterate (Jacobi); then the contact projection;
//! 4. the final contact pass;
//! 5. `v = (x − x_prev) / h`, then `v ← v (1 − β_v h)`;
//! 6. with `--energy-aware global`, the energy balance of [`energy`] scales the velocities.
//!
//! With `--energy-aware project`, the energy-momentum projection of [`projection`] follows the
//! frame's last substep.
//!
//! Where the order allows it, passes over the particles share one visit of each particle, with
//! the same bits as the passes one after the other: the last iteration's contact projection, the
//! final contact pass and the velocity update, and (outside the global balance) the next
//! substep's prediction.

mod barrier;
mod contacts;
mod cpu;
pub mod energy;
pub mod jacobi;
mod particles;
pub mod precision;
pub mod projection;
mod pull;
pub mod self_collision;
mod shared;
pub mod stages;
mod xpbd;

pub use cpu::{CpuSolver, TeamTime};
pub use energy::EnergyAware;
pub use particles::Particles;
pub use pull::Pull;
pub use xpbd::{StepConstants, delta_lambda, residual};

use crate::constraints::Form;
use crate::error::{Error, Result};

/// How constraints are iterated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Method {
    /// Gauss-Seidel over color groups: each group sees the updates of the previous ones.
    #[default]
    GaussSeidel,
    /// Jacobi: every constraint reads the same iterate; constraint `j` scales its `Δλ` by
    /// `ω / max_{i∈j} nᵢ` (`nᵢ` = constraints touching particle `i`), and the scaled value is
    /// both applied and accumulated into `λ`.
    Jacobi,
}

crate::error::command_names!(Method, "solver", { GaussSeidel => "gauss-seidel", Jacobi => "jacobi" });

/// Solver settings; every field may change between frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Settings {
    /// Frame time step `dt` (s).
    pub dt: f32,
    /// Substeps per frame.
    pub substeps: u32,
    /// Constraint iterations per substep.
    pub iterations: u32,
    /// Projection form.
    pub form: Form,
    /// Iteration method.
    pub method: Method,
    /// Jacobi relaxation `ω` (0 < ω < 2).
    pub jacobi_omega: f32,
    /// Explicit velocity damping `β_v` (1/s): `v ← v (1 − β_v h)`.
    pub damping: f32,
    /// XPBD constraint damping `β` (s), eq. 26 of Macklin et al. 2016.
    pub constraint_damping: f32,
    /// Compliance `α` of the energy form (the paper's author used 1e-5).
    pub energy_compliance: f32,
    /// The energy-aware setting (docs/algorithm.md §4).
    pub energy_aware: EnergyAware,
    /// Successive over-relaxation `ω`: every `Δλ` is scaled by it (1 = plain).
    pub sor: f32,
    /// CPU threads: 1 runs single-threaded, 0 uses every core; at most one per core. On several threads the solver's
    /// pool runs each frame as a team that splits the per-particle passes and every color group
    /// of at least [`PARALLEL_MIN_GROUP`] elements (Gauss-Seidel and Jacobi, in either form and
    /// every energy-aware mode). The result is the
    /// same for any count: the elements of a group share no particle, and two elements that share
    /// one are visited in the order of their groups. A team over every core the process may use
    /// has its threads pinned one per core. The GPU backend ignores it.
    pub threads: u32,
    /// The soft grab, if a particle is pulled ([`Pull`]).
    pub pull: Option<Pull>,
}

/// Smallest color group (elements) that the CPU solver splits over threads; smaller groups run
/// whole on one thread of the team while the others wait at the group's barrier (about 0.2 µs on
/// two cores). Measured on two cores when it was chosen: 128 beats 400 on the 29×29 and 41×41
/// cloths (1.4× and 1.6× over one thread against 0.85× and 0.9×) and equals it on larger ones;
/// 32 is no faster than 128.
pub const PARALLEL_MIN_GROUP: usize = 128;

impl Default for Settings {
    fn default() -> Self {
        Settings {
            dt: 1.0 / 60.0,
            substeps: 1,
            iterations: 30,
            form: Form::Compliant,
            method: Method::GaussSeidel,
            jacobi_omega: 1.0,
            damping: 0.0,
            constraint_damping: 0.0,
            energy_compliance: 1.0e-5,
            energy_aware: EnergyAware::Off,
            sor: 1.0,
            threads: 0,
            pull: None,
        }
    }
}

impl Settings {
    /// Substep length `h = dt / substeps` (s).
    pub fn h(&self) -> f32 {
        self.dt / self.substeps as f32
    }

    /// `true` when iteration `iteration`'s contact pass runs as a pass of its own: every
    /// iteration's but the last, whose pass the finish pass makes first (same bits, one pass over
    /// the particles fewer a substep).
    pub(crate) fn contacts_in_loop(&self, iteration: u32) -> bool {
        iteration + 1 < self.iterations
    }

    /// `true` when the finish pass makes the last iteration's contact pass (there is an
    /// iteration).
    pub(crate) fn contacts_in_finish(&self) -> bool {
        self.iterations > 0
    }

    /// Rejects values that cannot give a meaningful simulation.
    pub fn validate(&self) -> Result<()> {
        let finite_pos = |v: f32| v.is_finite() && v > 0.0;
        if !(finite_pos(self.dt) && self.dt <= 1.0) {
            return Err(Error::param("--dt", self.dt, "must be in (0, 1] seconds"));
        }
        if !(1..=100_000).contains(&self.substeps) {
            return Err(Error::param("--substeps", self.substeps, "must be in 1..=100000"));
        }
        if self.iterations > 100_000 {
            return Err(Error::param("--iterations", self.iterations, "must be at most 100000"));
        }
        if !(finite_pos(self.jacobi_omega) && self.jacobi_omega < 2.0) {
            return Err(Error::param("--jacobi-omega", self.jacobi_omega, "must be in (0, 2)"));
        }
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return Err(Error::param("--damping", self.damping, "must be a finite rate ≥ 0 (1/s)"));
        }
        if !(self.constraint_damping.is_finite() && self.constraint_damping >= 0.0) {
            return Err(Error::param("--constraint-damping", self.constraint_damping, "must be finite and ≥ 0 (s)"));
        }
        if !(finite_pos(self.sor) && self.sor < 2.0) {
            return Err(Error::param("--sor", self.sor, "must be in (0, 2)"));
        }
        if !(finite_pos(self.energy_compliance)) {
            return Err(Error::param("--energy-compliance", self.energy_compliance, "must be positive and finite"));
        }
        if let Some(p) = self.pull {
            if !(p.stiffness.is_finite() && p.stiffness >= 0.0) {
                return Err(Error::param("grab stiffness", p.stiffness, "must be finite and ≥ 0 (N/m)"));
            }
            if !p.target.iter().all(|t| t.is_finite()) {
                return Err(Error::param("grab target", p.target[0], "must be a finite point (m)"));
            }
        }
        Ok(())
    }
}
