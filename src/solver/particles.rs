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
        *x_prev = *x;
        if w > V::S::zero() {
            *v += g * h;
            *x += *v * h;
        } else {
            *v = V::ZERO;
        }
    }
}

/// The final contact pass and the velocity update over a range of particles that starts at a
/// block boundary: `v = (x − x_prev)/h · keep` with `keep = max(1 − β_v h, 0)`. Writes, per
/// [`WORK_BLOCK`] particles, the work of physical dissipation (J, ≤ 0 for losses): the kinetic
/// energy the contact pass and the damping changed, with velocities `(x − x_prev)/h` before and
/// after the pass.
pub(crate) fn finish<V: Vector>(
    scene: &Scene,
    x: &mut [V],
    x_prev: &[V],
    v: &mut [V],
    w: &[V::S],
    (h, damping): (V::S, V::S),
    work: &mut [f64],
) {
    let keep = (V::S::one() - damping * h).max(V::S::zero());
    let inv_h = V::S::one() / h;
    let (scale, damped) = (inv_h * keep, keep != V::S::one());
    let (keep64, inv_h64) = (keep.to_f64(), inv_h.to_f64());
    let colliders = Colliders::new(scene);
    for (b, sum) in work.iter_mut().enumerate() {
        let r = (b * WORK_BLOCK).min(x.len())..((b + 1) * WORK_BLOCK).min(x.len());
        let (x, x_prev, v, w) = (&mut x[r.clone()], &x_prev[r.clone()], &mut v[r.clone()], &w[r]);
        *sum = 0.0;
        for (((x, &x_prev), v), &w) in x.iter_mut().zip(x_prev).zip(v).zip(w) {
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
        }
    }
}
