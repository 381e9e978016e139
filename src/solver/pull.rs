//! The soft grab: a particle pulled towards a target point by a zero-length spring, so that a
//! hard pull stretches the body instead of moving the particle alone (docs/algorithm.md §1).

use std::ops::Range;

use crate::math::prelude::*;

/// Particle `particle` pulled towards `target` (m) by a spring of stiffness `stiffness` (N/m)
/// with the particle's critical damping `c = 2√(k m)`, integrated implicitly over each substep
/// of `h` seconds together with the constraints (docs/algorithm.md §1):
/// - the prediction: `m v' = m v + h (m g + k (t − x − h v') − c v')`, that is
///   `v' = (v + h g + h w k (t − x)) / r²` with `w = 1/m` and `r = 1 + h √(k w)`, `x' = x + h v'`;
/// - the constraint iterations: the spring eliminated into the particle, which answers a
///   constraint's correction as a particle of inverse mass `w̃ = w / r²` would (the linearised
///   implicit system's Schur complement); `k → ∞` pins it (`w̃ → 0`), `k → 0` frees it.
///
/// The solvers give the particle `w̃` for the frame's substeps ([`Pull::effective_inverse_mass`])
/// and make the prediction from it: with `a = h √(k w̃) = 1 − 1/r`, `v' = (1 − a)² (v + h g) +
/// h k w̃ (t − x)`. Stable at any stiffness; the particle trails a moving target by about the
/// force its body pulls back with divided by `k`. Pinned particles (`w = 0`) are not moved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pull {
    /// The particle.
    pub particle: u32,
    /// Where it is pulled (m).
    pub target: [f32; 3],
    /// Spring stiffness `k` (N/m).
    pub stiffness: f32,
}

impl Pull {
    /// The pull as seen from the particles `r`: its particle's index within them, where it is one
    /// of them.
    pub(crate) fn within(pull: Option<Pull>, r: Range<usize>) -> Option<(usize, Pull)> {
        pull.filter(|p| r.contains(&(p.particle as usize))).map(|p| (p.particle as usize - r.start, p))
    }

    /// The inverse mass `w̃ = w / (1 + h √(k w))²` (1/kg) the pulled particle of inverse mass `w`
    /// takes in the substeps of `h` seconds.
    pub fn effective_inverse_mass(&self, w: f32, h: f32) -> f32 {
        let k = self.stiffness.max(0.0);
        let root = 1.0 + h * (k * w.max(0.0)).sqrt();
        w / (root * root)
    }

    /// Redoes the prediction of the pulled particle, of inverse mass `w̃` (`w_eff`) for the
    /// substep, with the spring: from `x_prev` (the substep's start) and the predicted `v`
    /// (gravity included), `v ← (1 − a)² v + h k w̃ (t − x_prev)` with `a = h √(k w̃)`, and
    /// `x = x_prev + h v`.
    #[inline]
    pub(crate) fn apply<V: Vector>(&self, x: &mut V, x_prev: V, v: &mut V, w_eff: V::S, h: V::S) {
        let k = V::S::from_f64(self.stiffness as f64);
        if !(w_eff > V::S::zero() && k > V::S::zero()) {
            return;
        }
        let target = V::new(self.target[0].into(), self.target[1].into(), self.target[2].into());
        let keep = V::S::one() - h * (k * w_eff).sqrt();
        *v = *v * (keep * keep) + (target - x_prev) * (h * k * w_eff);
        *x = x_prev + *v * h;
    }
}
