//! The XPBD multiplier update (Macklin et al. 2016), shared by every family and method.

use crate::constraints::{Element, Form, Positions, gather};
use crate::math::prelude::*;

/// Constants of one substep.
#[derive(Clone, Copy, Debug)]
pub struct StepConstants<S: Real> {
    /// Substep `h` (s).
    pub h: S,
    /// `1 / h` (1/s).
    pub inv_h: S,
    /// `1 / h²` (1/s²), turning compliance `α` into `α̃ = α / h²`.
    pub inv_h2: S,
    /// Constraint damping `β` (s).
    pub beta: S,
    /// Projection form.
    pub form: Form,
    /// Compliance of the energy form.
    pub energy_compliance: S,
    /// Over-relaxation `ω` applied to every `Δλ`.
    pub sor: S,
}

impl<S: Real> StepConstants<S> {
    /// The constants of a substep under `s`.
    pub fn new(s: &super::Settings) -> Self {
        let h: S = s.h().into();
        StepConstants {
            h,
            inv_h: S::one() / h,
            inv_h2: S::one() / (h * h),
            beta: s.constraint_damping.into(),
            form: s.form,
            energy_compliance: s.energy_compliance.into(),
            sor: s.sor.into(),
        }
    }

    /// `true` where the lean kernels apply: the compliant form without constraint damping.
    pub fn plain(&self) -> bool {
        self.form == Form::Compliant && self.beta == S::zero()
    }
}

/// Denominators below this are treated as zero (a vanishing gradient with zero compliance).
const EPSILON: f64 = 1e-20;

/// `Δλ = (−C − α̃λ − γ Σ∇C·(x − x_prev)) / ((1 + γ) Σ w|∇C|² + α̃)` with `γ = α̃β̃/h`,
/// `β̃ = h²β` (XPBD eq. 26; `β = 0` gives the plain update). `None` when the denominator
/// vanishes or is not a number (the update is skipped).
#[inline(always)]
pub fn delta_lambda<S: Real>(
    c_val: S,
    sum_w_grad2: S,
    alpha_tilde: S,
    lambda: S,
    gamma: S,
    grad_dot_dx: S,
) -> Option<S> {
    let denom = (S::one() + gamma) * sum_w_grad2 + alpha_tilde;
    if denom.is_nan() || denom <= c(EPSILON) {
        return None;
    }
    Some((-c_val - alpha_tilde * lambda - gamma * grad_dot_dx) / denom)
}

/// One element's update, computed from gathered positions `xs` and inverse masses `ws`:
/// the gradient and `Δλ` (times the over-relaxation `ω`, before any Jacobi scale), or `None`
/// when it is skipped this iteration. `x_prev` holds the substep's start positions, read by
/// particle index for the constraint damping only. `adjust` may replace the constraint value (the local
/// energy-aware mode); it receives `C` and `α` and returns the value to use.
#[inline(always)]
pub(crate) fn solve_element<E: Element<N>, V: Vector, Q: Positions<V> + ?Sized, const N: usize>(
    e: &E,
    params: &E::Params,
    xs: &[V; N],
    ws: &[V::S; N],
    x_prev: &Q,
    lambda: V::S,
    k: &StepConstants<V::S>,
    adjust: impl FnOnce(V::S, V::S) -> V::S,
) -> Option<([V; N], V::S)> {
    let mut proj = e.constraint(params, xs, k.form, k.energy_compliance);
    proj.c = adjust(proj.c, proj.alpha);
    let alpha_tilde = proj.alpha * k.inv_h2;
    let mut sum = V::S::zero();
    for n in 0..N {
        sum += ws[n] * proj.grad[n].length_squared();
    }
    let (gamma, gdx) = if k.beta > V::S::zero() {
        let gamma = proj.alpha * k.beta * k.inv_h;
        let idx = e.particles();
        let mut gdx = V::S::zero();
        for n in 0..N {
            gdx += proj.grad[n].dot(xs[n] - x_prev.get(idx[n] as usize));
        }
        (gamma, gdx)
    } else {
        (V::S::zero(), V::S::zero())
    };
    delta_lambda(proj.c, sum, alpha_tilde, lambda, gamma, gdx).map(|d| (proj.grad, d * k.sor))
}

/// The XPBD residual `|C + α̃λ|` of element `e` at the positions in `p`.
#[inline]
pub fn residual<E: Element<N>, V: Vector, const N: usize>(
    e: &E,
    params: &E::Params,
    x: &[V],
    lambda: V::S,
    k: &StepConstants<V::S>,
) -> V::S {
    let proj = e.constraint(params, &gather(x, e.particles()), k.form, k.energy_compliance);
    (proj.c + proj.alpha * k.inv_h2 * lambda).abs()
}
