//! Collision projection against the ground plane and analytic spheres, with position-based
//! Coulomb friction: a particle pushed out by depth `d` loses its tangential displacement since
//! the start of the substep, `t`, entirely when `|t| ≤ μ d` (static), else by `μ d` (kinetic).

use crate::math::prelude::*;
use crate::scene::{Scene, Sphere};

use super::Particles;

/// A scene's colliders in the solver's precision, taken once per pass.
pub(crate) struct Colliders<'a, V: Vector> {
    /// The ground's contact height `height + contact_offset` (m) and its friction coefficient.
    ground: Option<(V::S, V::S)>,
    spheres: &'a [Sphere],
    /// The scene's contact offset (m), added to every sphere's radius.
    offset: V::S,
    /// The ground's contact height (m), `−∞` without a ground.
    floor: V::S,
}

impl<'a, V: Vector> Colliders<'a, V> {
    pub fn new(scene: &'a Scene) -> Self {
        let offset: V::S = scene.contact_offset.into();
        let ground = scene.ground.map(|g| (<V::S as From<f32>>::from(g.height) + offset, g.friction.into()));
        let floor = ground.map_or(V::S::from_f64(f64::NEG_INFINITY), |(floor, _)| floor);
        Colliders { ground, spheres: &scene.spheres, offset, floor }
    }

    /// `true` when no collider can move a particle at `x`: no spheres, and `x` at or above the
    /// ground's contact height (or no ground). One comparison, so that the passes over every
    /// particle leave the projections to the few it fails for.
    #[inline(always)]
    pub fn clear(&self, x: V) -> bool {
        // Not below the floor: a NaN height passes here as it passes the ground's test.
        self.spheres.is_empty() && x.get(1).partial_cmp(&self.floor) != Some(std::cmp::Ordering::Less)
    }

    /// The distance from `x` to the nearest collider's contact surface (m; negative inside,
    /// `+∞` without a collider).
    pub fn distance(&self, x: V) -> f64 {
        let ground = self.ground.map_or(f64::INFINITY, |(floor, _)| (x.get(1) - floor).to_f64());
        self.spheres.iter().fold(ground, |d, s| {
            let r = <V::S as From<f32>>::from(s.radius) + self.offset;
            d.min((x - V::from_vec3(s.center)).length().to_f64() - r.to_f64())
        })
    }

    /// A free particle at `x` (start of substep `x_prev`) projected out of the ground, then out
    /// of each sphere; `None` when no collider moved it (always where [`Colliders::clear`]).
    pub fn project(&self, mut x: V, x_prev: V) -> Option<V> {
        let zero = V::S::zero();
        let mut moved = false;
        if let Some((floor, mu)) = self.ground {
            let y = x.get(1);
            if y < floor {
                let n = V::new(zero, V::S::one(), zero);
                x += n * (floor - y);
                x = friction(x, x_prev, n, floor - y, mu);
                moved = true;
            }
        }
        for s in self.spheres {
            let c = V::from_vec3(s.center);
            let r = <V::S as From<f32>>::from(s.radius) + self.offset;
            let d = x - c;
            let len = d.length();
            if len < r && len > V::S::epsilon() {
                let n = d * (V::S::one() / len);
                x += n * (r - len);
                x = friction(x, x_prev, n, r - len, s.friction.into());
                moved = true;
            }
        }
        moved.then_some(x)
    }
}

/// Projects every free particle out of the scene's colliders.
pub(crate) fn project_contacts<V: Vector>(scene: &Scene, p: &mut Particles<V>) {
    project_range(scene, &mut p.x, &p.x_prev, &p.w);
}

/// Projects the free particles of a range (positions `x`, substep starts `x_prev`, inverse masses
/// `w`, index for index) out of the scene's colliders.
pub(crate) fn project_range<V: Vector>(scene: &Scene, x: &mut [V], x_prev: &[V], w: &[V::S]) {
    let colliders = Colliders::new(scene);
    for ((x, &x_prev), &w) in x.iter_mut().zip(x_prev).zip(w) {
        if w > V::S::zero()
            && !colliders.clear(*x)
            && let Some(p) = colliders.project(*x, x_prev)
        {
            *x = p;
        }
    }
}

#[inline]
fn friction<V: Vector>(x: V, x_prev: V, n: V, depth: V::S, mu: V::S) -> V {
    let disp = x - x_prev;
    let t = disp - n * disp.dot(n);
    let tl = t.length();
    let limit = mu * depth;
    if tl <= limit { x - t } else { x - t * (limit / tl) }
}
