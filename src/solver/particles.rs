//! Particle state as a struct of arrays, and the per-particle passes of a substep over a range of
//! particles (the whole state, or one thread's share).

use crate::math::prelude::*;
use crate::scene::Scene;

use super::contacts::Colliders;

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
/// particles take `v += g h`, `x += v h`; pinned ones keep `x` and get `v = 0`.
pub(crate) fn predict<V: Vector>(x: &mut [V], x_prev: &mut [V], v: &mut [V], w: &[V::S], g: V, h: V::S) {
    for (((x, x_prev), v), &w) in x.iter_mut().zip(x_prev).zip(v).zip(w) {
        predict_one(x, x_prev, v, w, g, h);
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

/// The final contact pass and the velocity update over a range of particles that starts at a
/// block boundary: `v = (x − x_prev)/h · keep` with `keep = max(1 − β_v h, 0)`. Writes, per
/// [`WORK_BLOCK`] particles, the work of physical dissipation (J, ≤ 0 for losses): the kinetic
/// energy the contact pass and the damping changed, with velocities `(x − x_prev)/h` before and
/// after the pass. With `next = Some(g)` each particle then takes the next substep's
/// [`predict`] under gravity `g` (m/s²) in the same visit: the same bits as the two passes one
/// after the other, with one sweep over the particles instead of two.
pub(crate) fn finish<V: Vector>(
    scene: &Scene,
    x: &mut [V],
    x_prev: &mut [V],
    v: &mut [V],
    w: &[V::S],
    (h, damping, next): (V::S, V::S, Option<V>),
    work: &mut [f64],
) {
    let keep = (V::S::one() - damping * h).max(V::S::zero());
    let inv_h = V::S::one() / h;
    let (scale, damped) = (inv_h * keep, keep != V::S::one());
    let (keep64, inv_h64) = (keep.to_f64(), inv_h.to_f64());
    let colliders = Colliders::new(scene);
    for (b, sum) in work.iter_mut().enumerate() {
        let r = (b * WORK_BLOCK).min(x.len())..((b + 1) * WORK_BLOCK).min(x.len());
        let (x, x_prev, v, w) = (&mut x[r.clone()], &mut x_prev[r.clone()], &mut v[r.clone()], &w[r]);
        *sum = 0.0;
        for (((x, x_prev_slot), v), &w) in x.iter_mut().zip(x_prev).zip(v).zip(w) {
            let x_prev = *x_prev_slot;
            if w > V::S::zero() {
                let before = *x;
                let moved = match colliders.project(before, x_prev) {
                    Some(p) => {
                        *x = p;
                        true
                    }
                    None => false,
                };
                // Both terms vanish (exactly) for a particle the pass left alone without damping.
                if moved || damped {
                    let m = 1.0 / w.to_f64();
                    let vb = (before.to_dvec3() - x_prev.to_dvec3()) * inv_h64;
                    let va = (x.to_dvec3() - x_prev.to_dvec3()) * inv_h64;
                    *sum += 0.5 * m * (va.length_squared() - vb.length_squared());
                    *sum += 0.5 * m * va.length_squared() * (keep64 * keep64 - 1.0);
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneOptions, build};
    use glam::Vec3A;

    /// The finish pass that makes the next prediction gives the same bits as the two passes,
    /// for free and pinned particles, with particles inside the sphere and with damping.
    #[test]
    fn finish_with_the_next_prediction_is_the_two_passes() {
        let scene = build("cloth-sphere", &SceneOptions { resolution: Some(12), ..SceneOptions::default() }).unwrap();
        let start = Particles::<Vec3A>::from_scene(&scene);
        let n = start.len();
        let (g, h, damping) = (Vec3A::new(0.0, -9.81, 0.0), 1.0 / 180.0, 0.3);
        let mut a = start.clone();
        a.w[0] = 0.0;
        // Positions spread towards the origin, some inside the sphere, and velocities, so that
        // contacts and damping act.
        for (i, (x, v)) in a.x.iter_mut().zip(&mut a.v).enumerate() {
            *x = Vec3A::new(0.0, 0.0, 0.0).lerp(*x, (i % 7) as f32 / 6.0);
            *v = Vec3A::new(0.1, -((i % 5) as f32), 0.2);
        }
        a.x_prev = a.x.iter().map(|x| *x + Vec3A::new(0.01, 0.02, -0.01)).collect();
        let mut b = a.clone();
        let blocks = n.div_ceil(WORK_BLOCK);
        let (mut work_a, mut work_b) = (vec![0.0; blocks], vec![0.0; blocks]);
        finish(&scene, &mut a.x, &mut a.x_prev, &mut a.v, &a.w, (h, damping, None), &mut work_a);
        predict(&mut a.x, &mut a.x_prev, &mut a.v, &a.w, g, h);
        finish(&scene, &mut b.x, &mut b.x_prev, &mut b.v, &b.w, (h, damping, Some(g)), &mut work_b);
        let bits = |p: &Particles<Vec3A>| {
            let all = p.x.iter().chain(&p.x_prev).chain(&p.v);
            all.flat_map(|v| v.to_array().map(f32::to_bits)).collect::<Vec<_>>()
        };
        assert_eq!(bits(&a), bits(&b));
        assert_eq!(
            work_a.iter().map(|w| w.to_bits()).collect::<Vec<_>>(),
            work_b.iter().map(|w| w.to_bits()).collect::<Vec<_>>()
        );
        assert!(work_a.iter().any(|&w| w != 0.0), "the contacts and the damping did work: {work_a:?}");
        assert_ne!(bits(&a), bits(&start), "the passes changed the state");
    }
}
