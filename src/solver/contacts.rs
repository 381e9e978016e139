//! Collision projection against the ground plane and analytic spheres, with position-based
//! Coulomb friction: a particle pushed out by depth `d` loses its tangential displacement since
//! the start of the substep, `t`, entirely when `|t| ≤ μ d` (static), else by `μ d` (kinetic).

use crate::math::prelude::*;
use crate::scene::Scene;

use super::Particles;

/// Projects every free particle out of the scene's colliders.
pub(crate) fn project_contacts<V: Vector>(scene: &Scene, p: &mut Particles<V>) {
    project_range(scene, &mut p.x, &p.x_prev, &p.w);
}

/// Projects the free particles of a range (positions `x`, substep starts `x_prev`, inverse masses
/// `w`, index for index) out of the scene's colliders.
pub(crate) fn project_range<V: Vector>(scene: &Scene, x: &mut [V], x_prev: &[V], w: &[V::S]) {
    for i in 0..x.len() {
        if w[i] > V::S::zero() {
            x[i] = project_particle(scene, x[i], x_prev[i]);
        }
    }
}

/// A free particle at `x` (start of substep `x_prev`) projected out of the ground, then out of
/// each sphere.
#[inline]
pub(crate) fn project_particle<V: Vector>(scene: &Scene, mut x: V, x_prev: V) -> V {
    let offset: V::S = scene.contact_offset.into();
    let zero = V::S::zero();
    if let Some(g) = scene.ground {
        let floor = <V::S as From<f32>>::from(g.height) + offset;
        let y = x.get(1);
        if y < floor {
            let n = V::new(zero, V::S::one(), zero);
            x += n * (floor - y);
            x = friction(x, x_prev, n, floor - y, g.friction.into());
        }
    }
    for s in &scene.spheres {
        let c = V::from_vec3(s.center);
        let r = <V::S as From<f32>>::from(s.radius) + offset;
        let d = x - c;
        let len = d.length();
        if len < r && len > V::S::epsilon() {
            let n = d * (V::S::one() / len);
            x += n * (r - len);
            x = friction(x, x_prev, n, r - len, s.friction.into());
        }
    }
    x
}

#[inline]
fn friction<V: Vector>(x: V, x_prev: V, n: V, depth: V::S, mu: V::S) -> V {
    let disp = x - x_prev;
    let t = disp - n * disp.dot(n);
    let tl = t.length();
    let limit = mu * depth;
    if tl <= limit { x - t } else { x - t * (limit / tl) }
}
