//! Energy-aware Gauss-Seidel (docs/algorithm.md §4): the setting and the two formulas every backend shares.
//! `on` names `project`, the energy-momentum projection ([`super::projection`]): of the four
//! settings the only one that keeps the honest energy and the motion of the hanging cloth at
//! 10 × 3 and 30 × 1 substeps × iterations (docs/energy-aware.md).
//!
//! **`local`** (the paper's reading): for constraint `j` in iteration `k` of a substep,
//! `r_j = ½ Σ_{i∈j, wᵢ>0} mᵢ (|Vᵢᵏ|² − |Vᵢᵏ⁻¹|²) + (E_j(xᵏ) − E_j(x_start))` with implicit
//! velocities `Vᵢᵏ = (xᵢ − xᵢ^{(k)}) / h` (live position against the snapshot at the start of
//! iteration k) and `Vᵢᵏ⁻¹ = (xᵢ^{(k)} − xᵢ^{(k−1)}) / h` (the snapshot at the start of iteration
//! k−1; before the first iteration that is the substep's start, so `V⁰⁻¹` is the predicted
//! velocity). The projection then uses `C̃` instead of `C`: energy form `C̃ = C + r` when
//! `|r| ≤ C`; compliant form `C̃ = sign(C) √(C² + 2αr)` when `|r| ≤ C²/(2α)`; otherwise `C`.
//!
//! **`global`**: after the substep, with `H₀` the kinetic + gravitational + elastic
//! energy at its start, `W` the work of physical dissipation in it (velocity damping and every
//! contact pass, `solver::contacts`), `K₁` and `P₁` the kinetic and potential energy after it:
//! `σ = clamp(√(max(H₀ + W − P₁, 0) / K₁), 1 − ε, 1 + ε)`, `ε = 0.1`, and `v ← σ v`. The next
//! substep starts from `H₀ = σ² K₁ + P₁`. `σ = 1` when `K₁ < 10⁻⁶ |H₀|` or when
//! `|H₀ + W − P₁ − K₁|` is within rounding of the sums, so a body at rest does not jitter.

use crate::constraints::Form;
use crate::math::prelude::*;

/// The energy-aware setting.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum EnergyAware {
    /// Plain XPBD.
    #[default]
    Off,
    /// The paper's per-constraint, per-iteration energy residual.
    Local,
    /// One energy balance per substep on the velocities.
    Global,
    /// The energy-momentum projection after every frame ([`super::projection`]): the honest
    /// energy (kinetic, gravitational, elastic energy the constraint forces hold) kept to its
    /// budget, linear and angular momentum kept where nothing is pinned.
    Project,
}

crate::error::command_names!(EnergyAware, "energy-aware setting", {
    Off => "off",
    Local => "local",
    Global => "global",
    Project => "project",
} also { "on" => Project });

/// `ε`: the global balance scales velocities by at most ±10% per substep.
pub const GLOBAL_EPSILON: f64 = 0.1;

/// Relative size of the rounding band within which the global balance leaves velocities alone.
pub const GLOBAL_ROUNDING: f64 = 1e-6;

/// The global balance's velocity scale `σ` (see the module documentation).
pub fn global_scale(h0: f64, work: f64, k1: f64, p1: f64) -> f64 {
    let target = h0 + work - p1;
    let band = GLOBAL_ROUNDING * (h0.abs() + work.abs() + k1.abs() + p1.abs());
    if k1 < 1e-6 * h0.abs() || k1 <= 0.0 || (target - k1).abs() <= band {
        return 1.0;
    }
    (target.max(0.0) / k1).sqrt().clamp(1.0 - GLOBAL_EPSILON, 1.0 + GLOBAL_EPSILON)
}

/// The local mode's constraint value `C̃` from `C`, the compliance `α` and the residual `r`.
#[inline(always)]
pub fn local_constraint<S: Real>(c_val: S, alpha: S, r: S, form: Form) -> S {
    match form {
        Form::Energy => {
            if r.abs() <= c_val.abs() {
                c_val + r
            } else {
                c_val
            }
        }
        Form::Compliant => {
            let two_alpha = alpha + alpha;
            let c2 = c_val * c_val;
            if two_alpha > S::zero() && r.abs() * two_alpha <= c2 {
                (c2 + two_alpha * r).max(S::zero()).sqrt().copysign(c_val)
            } else {
                c_val
            }
        }
    }
}
