//! The local energy-aware mode on the CPU (docs/algorithm.md §4): the snapshots of the
//! positions, each constraint's start energy and the adjusted constraint value `C̃`.

use crate::constraints::{Element, Form, gather};
use crate::math::prelude::*;
use crate::scene::Family;

use super::super::energy::local_constraint;
use super::super::xpbd::StepConstants;
use super::CpuSolver;

/// The local mode's snapshots of the positions at the start of the current and the previous
/// iteration (allocated only in that mode).
#[derive(Clone, Debug, Default)]
pub(super) struct LocalState<V> {
    pub(super) current: Vec<V>,
    pub(super) previous: Vec<V>,
}

/// Read-only context of the local mode for one family.
pub(super) struct LocalCtx<'a, V: Vector> {
    pub(super) current: &'a [V],
    pub(super) previous: &'a [V],
    pub(super) energy_start: &'a [V::S],
}

impl<V: Vector> CpuSolver<V> {
    /// Snapshots and start energies of the local mode.
    pub(super) fn begin_local(&mut self, k: &StepConstants<V::S>) {
        let Some(l) = &mut self.local else { return };
        l.previous.copy_from_slice(&self.particles.x_prev);
        l.current.copy_from_slice(&self.particles.x);
        let x_prev = &self.particles.x_prev;
        crate::for_each_family!(self.scene, |i, f| {
            let out = &mut self.fam[i].energy_start;
            out.resize(f.len(), V::S::zero());
            start_energies(f, x_prev, (k.form, k.energy_compliance), 0..f.len(), out)
        });
    }
}

pub(super) fn local_ctx<'a, V: Vector>(l: &'a LocalState<V>, energy_start: &'a [V::S]) -> LocalCtx<'a, V> {
    LocalCtx { current: &l.current, previous: &l.previous, energy_start }
}

/// Material energy of the elements of `f` in `out`'s range (`out[j]` for element `range.start +
/// j`) at `x` (the local mode's `E_j(x_start)`), computed the way the projection sees it: `C` in
/// the energy form, `C²/(2α)` in the compliant form.
pub(super) fn start_energies<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    x: &[V],
    (form, energy_compliance): (Form, V::S),
    range: std::ops::Range<usize>,
    out: &mut [V::S],
) {
    for (e, o) in f.elements[range].iter().zip(out) {
        let p = e.constraint(&f.params, &gather(x, e.particles()), form, energy_compliance);
        *o = projected_energy(p.c, p.alpha, form);
    }
}

/// The material energy of a constraint from its projection: `C` (energy form) or `C²/(2α)`.
#[inline(always)]
pub(super) fn projected_energy<S: Real>(c_val: S, alpha: S, form: Form) -> S {
    match form {
        Form::Energy => c_val,
        Form::Compliant => c_val * c_val / (alpha + alpha),
    }
}

/// The local mode's `C̃` for element `j` with particles `idx` at the live positions `xs`.
#[inline(always)]
pub(super) fn local_adjusted<V: Vector, const N: usize>(
    l: &LocalCtx<'_, V>,
    j: usize,
    idx: [u32; N],
    xs: &[V; N],
    ws: &[V::S; N],
    k: &StepConstants<V::S>,
    c_val: V::S,
    alpha: V::S,
) -> V::S {
    let mut kinetic = V::S::zero();
    for n in 0..N {
        if ws[n] > V::S::zero() {
            let i = idx[n] as usize;
            let now = (xs[n] - l.current[i]).length_squared();
            let before = (l.current[i] - l.previous[i]).length_squared();
            kinetic += (now - before) / ws[n];
        }
    }
    let r = c::<V::S>(0.5) * kinetic * k.inv_h2 + (projected_energy(c_val, alpha, k.form) - l.energy_start[j]);
    local_constraint(c_val, alpha, r, k.form)
}
