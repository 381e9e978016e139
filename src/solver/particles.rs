//! Particle state as a struct of arrays, and the per-particle passes of a substep over a range of
//! particles (the whole state, or one thread's share).

use crate::math::prelude::*;
use crate::scene::Scene;

use super::contacts::Colliders;
use super::pull::Pull;

/// Particle state: positions, positions at the start of the substep, velocities, inverse
/// masses. Pinned particles have inverse mass 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Particles<V: Vector> {
    /// Positions `x` (m).
    pub x: Vec<V>,
    /// Positions at the start of the current substep (m).
    pub x_prev: Vec<V>,
    /// Velocities `v` (m/s).
    pub v: Vec<V>,
    /// Inverse masses `w` (1/kg).
    pub w: Vec<V::S>,
}

impl<V: Vector> Particles<V> {
    /// The scene's initial state, at rest.
    pub fn from_scene(scene: &Scene) -> Self {
        let x: Vec<V> = scene.positions.iter().map(|&p| V::from_vec3(p)).collect();
        Particles {
            x_prev: x.clone(),
            v: vec![V::ZERO; x.len()],
            w: scene.inv_mass.iter().map(|&w| <V::S as From<f32>>::from(w)).collect(),
            x,
        }
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// `true` when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// The positions as `f32` 3-vectors (m).
    pub fn positions(&self) -> Vec<glam::Vec3> {
        self.x.iter().map(|p| p.to_vec3()).collect()
    }

    /// The velocities as `f32` 3-vectors (m/s).
    pub fn velocities(&self) -> Vec<glam::Vec3> {
        self.v.iter().map(|v| v.to_vec3()).collect()
    }

    /// Sets the velocities (m/s) from `f32` 3-vectors, one per particle.
    pub fn set_velocities(&mut self, v: &[glam::Vec3]) {
        assert_eq!(v.len(), self.v.len(), "one velocity per particle");
        for (d, s) in self.v.iter_mut().zip(v) {
            *d = V::from_vec3(*s);
        }
    }

    /// Mass of particle `i` (kg), 0 for a pinned particle (left out of mass-weighted sums).
    pub fn mass(&self, i: usize) -> V::S {
        if self.w[i] > V::S::zero() { V::S::one() / self.w[i] } else { V::S::zero() }
    }
}

/// Particles per block of the finish pass's work sum: the sum runs block by block and the block
/// sums are added in order, so it comes out the same however the blocks are split over threads.
pub(crate) const WORK_BLOCK: usize = 256;

/// The prediction of a substep of `h` seconds over a range of particles: `x_prev = x`, then free
/// particles take `v += g h`, `x += v h`; pinned ones keep `x` and get `v = 0`. The pulled
/// particle, given by its index in the range ([`Pull::within`]), then takes the pull's.
pub(crate) fn predict<V: Vector>(
    x: &mut [V],
    x_prev: &mut [V],
    v: &mut [V],
    w: &[V::S],
    g: V,
    h: V::S,
    pull: Option<(usize, Pull)>,
) {
    for (((x, x_prev), v), &w) in x.iter_mut().zip(&mut *x_prev).zip(&mut *v).zip(w) {
        predict_one(x, x_prev, v, w, g, h);
    }
    if let Some((i, p)) = pull.filter(|(i, _)| *i < x.len()) {
        p.apply(&mut x[i], x_prev[i], &mut v[i], w[i], h);
    }
}

/// [`predict`] of one particle.
#[inline(always)]
fn predict_one<V: Vector>(x: &mut V, x_prev: &mut V, v: &mut V, w: V::S, g: V, h: V::S) {
    *x_prev = *x;
    if w > V::S::zero() {
        *v += g * h;
        *x += *v * h;
    } else {
        *v = V::ZERO;
    }
}

/// What a finish pass ([`finish`]) does for a substep of `h` seconds (s).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FinishStep<V: Vector> {
    /// The substep `h` (s).
    pub h: V::S,
    /// The velocity damping `β_v` (1/s).
    pub damping: V::S,
    /// The next substep's gravity (m/s²), to make its [`predict`] in the same visit; `None` for
    /// the frame's last substep and the global balance.
    pub next: Option<V>,
    /// The last iteration's in-loop contact pass is made here, just before the final one: the
    /// sweeps before it are over, so each particle's projection is the same as in a pass of its
    /// own; its work is counted with the final pass's, particle by particle.
    pub in_loop_contacts: bool,
    /// The soft grab within the range, for the next substep's prediction ([`Pull::within`]).
    pub pull: Option<(usize, Pull)>,
}

/// The final contact pass and the velocity update over a range of particles that starts at a
/// block boundary: `v = (x − x_prev)/h · keep` with `keep = max(1 − β_v h, 0)`. Adds, per
/// [`WORK_BLOCK`] particles, the work of physical dissipation (J, ≤ 0 for losses): the contact
/// passes' ([`Colliders::work`]) and the damping's, the kinetic energy it takes from the
/// velocities `(x − x_prev)/h` after the final pass. With `next = Some(g)` each particle then takes the next substep's
/// [`predict`] under gravity `g` (m/s²) in the same visit, and with `in_loop_contacts` the last
/// iteration's contact pass comes first in that visit: the same bits as the passes one after the
/// other, with one sweep over the particles instead of three.
pub(crate) fn finish<V: Vector>(
    scene: &Scene,
    x: &mut [V],
    x_prev: &mut [V],
    v: &mut [V],
    w: &[V::S],
    step: FinishStep<V>,
    work: &mut [f64],
) {
    let FinishStep { h, damping, next, in_loop_contacts, pull } = step;
    let keep = (V::S::one() - damping * h).max(V::S::zero());
    let inv_h = V::S::one() / h;
    let (scale, damped) = (inv_h * keep, keep != V::S::one());
    let colliders = Colliders::new(scene);
    let settle = Settle { colliders, in_loop_contacts, damped, keep: keep.to_f64(), inv_h: inv_h.to_f64() };
    for (b, sum) in work.iter_mut().enumerate() {
        let r = (b * WORK_BLOCK).min(x.len())..((b + 1) * WORK_BLOCK).min(x.len());
        let (x, x_prev, v, w) = (&mut x[r.clone()], &mut x_prev[r.clone()], &mut v[r.clone()], &w[r]);
        for (((x, x_prev_slot), v), &w) in x.iter_mut().zip(x_prev).zip(v).zip(w) {
            let x_prev = *x_prev_slot;
            if w > V::S::zero() {
                // Nothing to project and no damping: nothing to do but the velocity.
                if damped || !settle.colliders.clear(*x) {
                    settle.particle(x, x_prev, *v, w, sum);
                }
                *v = (*x - x_prev) * scale;
            } else {
                *v = V::ZERO;
            }
            if let Some(g) = next {
                predict_one(x, x_prev_slot, v, w, g, h);
            }
        }
    }
    if let Some((i, p)) = pull.filter(|(i, _)| next.is_some() && *i < x.len()) {
        p.apply(&mut x[i], x_prev[i], &mut v[i], w[i], h);
    }
}

/// The contact passes and the dissipation's work of [`finish`] for the particles that need them.
struct Settle<'a, V: Vector> {
    colliders: Colliders<'a, V>,
    in_loop_contacts: bool,
    /// `β_v > 0`: the damping does work on every free particle.
    damped: bool,
    /// `max(1 − β_v h, 0)` and `1/h` (1/s), in `f64`.
    keep: f64,
    inv_h: f64,
}

impl<V: Vector> Settle<'_, V> {
    /// Projects the free particle at `x` (mass `1/w`, start of substep `x_prev`, velocity from
    /// the prediction `v`): with
    /// `in_loop_contacts` the in-loop projection, then the final one of what it left (a particle
    /// the first left alone the second leaves too: the same function of the same positions).
    /// Adds to `sum` the work (J) of both passes ([`Colliders::work`]) and of the damping.
    #[inline(never)]
    fn particle(&self, x: &mut V, x_prev: V, v: V, w: V::S, sum: &mut f64) {
        let m = 1.0 / w.to_f64();
        let first = self.colliders.project(*x, x_prev);
        let (before, last) = match first {
            Some(p) if self.in_loop_contacts => {
                *sum += self.colliders.work(m, x_prev, v, *x, p, self.inv_h);
                (p, self.colliders.project(p, x_prev))
            }
            _ => (*x, first),
        };
        *x = last.unwrap_or(before);
        if last.is_some() {
            *sum += self.colliders.work(m, x_prev, v, before, *x, self.inv_h);
        }
        if self.damped {
            let va = (x.to_dvec3() - x_prev.to_dvec3()) * self.inv_h;
            *sum += 0.5 * m * va.length_squared() * (self.keep * self.keep - 1.0);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneOptions, build};
    use glam::Vec3A;

    /// The finish pass that makes the last iteration's contact pass and the next prediction gives
    /// the same bits as the three passes, for free and pinned particles, with particles inside
    /// the sphere and the ground and with damping, and the same work up to the order of its sum.
    #[test]
    fn finish_with_the_contacts_and_the_next_prediction_is_the_three_passes() {
        let scene = build("cloth-sphere", &SceneOptions { resolution: Some(12), ..SceneOptions::default() }).unwrap();
        let start = Particles::<Vec3A>::from_scene(&scene);
        let n = start.len();
        let (g, h, damping) = (Vec3A::new(0.0, -9.81, 0.0), 1.0 / 180.0, 0.3);
        let mut a = start.clone();
        a.w[0] = 0.0;
        // Positions spread towards a point under the ground, some inside the sphere, and
        // velocities, so that contacts and damping act.
        for (i, (x, v)) in a.x.iter_mut().zip(&mut a.v).enumerate() {
            *x = Vec3A::new(0.0, -0.02, 0.0).lerp(*x, (i % 7) as f32 / 6.0);
            *v = Vec3A::new(0.1, -((i % 5) as f32), 0.2);
        }
        a.x_prev = a.x.iter().map(|x| *x + Vec3A::new(0.01, 0.02, -0.01)).collect();
        let mut b = a.clone();
        let mut c = a.clone();
        let blocks = n.div_ceil(WORK_BLOCK);
        let (mut work_a, mut work_b) = (vec![0.0; blocks], vec![0.0; blocks]);
        crate::solver::contacts::project_range(&scene, &mut a.x, &a.x_prev, &a.v, &a.w, (1.0 / h) as f64, &mut work_a);
        // A soft grab on a free particle, made by the prediction either way.
        let pull = Pull::within(Some(Pull { particle: 40, target: [0.3, 1.0, 0.2], stiffness: 50.0 }), 0..n);
        let alone = FinishStep { h, damping, next: None, in_loop_contacts: false, pull: None };
        finish(&scene, &mut a.x, &mut a.x_prev, &mut a.v, &a.w, alone, &mut work_a);
        let unpulled = a.clone();
        predict(&mut a.x, &mut a.x_prev, &mut a.v, &a.w, g, h, pull);
        assert_ne!(a.x[40], unpulled.x[40] + unpulled.v[40] * h + g * h * h, "the pull moved its particle");
        let fused = FinishStep { h, damping, next: Some(g), in_loop_contacts: true, pull };
        finish(&scene, &mut b.x, &mut b.x_prev, &mut b.v, &b.w, fused, &mut work_b);
        let bits = |p: &Particles<Vec3A>| {
            let all = p.x.iter().chain(&p.x_prev).chain(&p.v);
            all.flat_map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>()
        };
        assert_eq!(bits(&a), bits(&b));
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (a.abs() + b.abs());
        // The fused pass adds the in-loop and the final work particle by particle.
        assert!(work_a.iter().zip(&work_b).all(|(a, b)| close(*a, *b)), "{work_a:?} against {work_b:?}");
        assert!(work_a.iter().any(|&w| w != 0.0), "the contacts and the damping did work: {work_a:?}");
        assert_ne!(bits(&a), bits(&start), "the passes changed the state");
        // Without the in-loop pass the final one meets the penetrations and counts nearly the
        // same work (a particle pushed out of the ground into the sphere and back differs).
        let mut work_c = vec![0.0; blocks];
        let no_loop = FinishStep { h, damping, next: Some(g), in_loop_contacts: false, pull };
        finish(&scene, &mut c.x, &mut c.x_prev, &mut c.v, &c.w, no_loop, &mut work_c);
        let (with, without) = (work_b.iter().sum::<f64>(), work_c.iter().sum::<f64>());
        assert!((without - with).abs() <= 1e-3 * with.abs(), "the final pass alone: {without} against {with}");
        assert!(with.abs() > 1e-3, "the contacts did work: {with}");
    }
}
