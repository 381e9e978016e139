//! Jacobi on the CPU (docs/algorithm.md §1): the per-constraint scales, one pass over a family
//! into per-particle corrections, and one element's scaled update (shared with the team).

use crate::constraints::{Element, gather};
use crate::math::prelude::*;
use crate::scene::Family;

use super::super::Particles;
use super::super::jacobi as scales;
use super::super::xpbd::{StepConstants, solve_element};
use super::CpuSolver;
use super::local::{LocalCtx, local_adjusted, local_ctx};

impl<V: Vector> CpuSolver<V> {
    pub(super) fn prepare_jacobi(&mut self, omega: f32) {
        if self.jacobi_omega == Some(omega) {
            return;
        }
        self.jacobi_omega = Some(omega);
        for (st, s) in self.fam.iter_mut().zip(scales::family_scales(&self.scene, omega.into())) {
            st.jacobi_scale = s;
        }
        self.dx = vec![V::ZERO; self.particles.len()];
    }

    pub(super) fn jacobi_iteration(&mut self, k: &StepConstants<V::S>, local: bool) {
        self.dx.fill(V::ZERO);
        let l = self.local.as_ref().filter(|_| local);
        crate::for_each_family!(self.scene, |i, f| {
            let st = &mut self.fam[i];
            let ctx = l.map(|l| local_ctx(l, &st.energy_start));
            jacobi(f, &mut st.lambda, &st.jacobi_scale, &self.particles, &mut self.dx, k, ctx)
        });
        for (x, d) in self.particles.x.iter_mut().zip(&self.dx) {
            *x += *d;
        }
    }
}

/// One Jacobi pass over a family: corrections accumulate into `dx`, scaled per constraint.
pub(super) fn jacobi<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    lambda: &mut [V::S],
    scale: &[V::S],
    p: &Particles<V>,
    dx: &mut [V],
    k: &StepConstants<V::S>,
    local: Option<LocalCtx<'_, V>>,
) {
    for (j, (e, l)) in f.elements.iter().zip(lambda.iter_mut()).enumerate() {
        let at = JacobiAt { x: &p.x, x_prev: &p.x_prev, w: &p.w, k };
        if let Some(corr) = jacobi_element(e, &f.params, j, l, scale[j], at, local.as_ref()) {
            for (i, c) in e.particles().into_iter().zip(corr) {
                dx[i as usize] += c;
            }
        }
    }
}

/// The state a Jacobi pass reads: positions `x`, substep starts, inverse masses, constants.
#[derive(Clone, Copy)]
pub(super) struct JacobiAt<'a, V: Vector> {
    pub(super) x: &'a [V],
    pub(super) x_prev: &'a [V],
    pub(super) w: &'a [V::S],
    pub(super) k: &'a StepConstants<V::S>,
}

/// Jacobi's update of element `j` (multiplier `lambda`, scale `s_j`): adds the scaled `Δλ` to
/// `lambda` and returns each particle's correction `w_i ∇C_i Δλ`, or `None` when the element is
/// skipped.
#[inline(always)]
pub(super) fn jacobi_element<E: Element<N>, V: Vector, const N: usize>(
    e: &E,
    params: &E::Params,
    j: usize,
    lambda: &mut V::S,
    scale: V::S,
    at: JacobiAt<'_, V>,
    local: Option<&LocalCtx<'_, V>>,
) -> Option<[V; N]> {
    let idx = e.particles();
    let xs = gather(at.x, idx);
    let ws = idx.map(|i| at.w[i as usize]);
    // Two instantiations, so the update without the local mode carries no trace of it.
    let (grad, d) = match local {
        Some(ctx) => {
            let adjust = |c_val, alpha| local_adjusted(ctx, j, idx, &xs, &ws, at.k, c_val, alpha);
            solve_element(e, params, &xs, &ws, at.x_prev, *lambda, at.k, adjust)?
        }
        None => solve_element(e, params, &xs, &ws, at.x_prev, *lambda, at.k, |c_val, _| c_val)?,
    };
    let d = d * scale;
    *lambda += d;
    Some(std::array::from_fn(|n| grad[n] * (ws[n] * d)))
}
