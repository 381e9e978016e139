//! Collision projection against the ground plane and analytic spheres, with position-based
//! Coulomb friction: a particle pushed out by depth `d` loses its tangential displacement since
//! the start of the substep, `t`, entirely when `|t| ≤ μ d` (static), else by `μ d` (kinetic).
//!
//! Every pass, in the loop and the final one, counts its work ([`Colliders::work`]) per block
//! of [`WORK_BLOCK`] particles: the energy budget of `--energy-aware project` and `global`
//! takes it as physical dissipation.

use crate::math::prelude::*;
use crate::scene::{Scene, Sphere};

use super::particles::WORK_BLOCK;

/// A scene's colliders in the solver's precision, taken once per pass.
pub(crate) struct Colliders<'a, V: Vector> {
    /// The ground's contact height `height + contact_offset` (m) and its friction coefficient.
    ground: Option<(V::S, V::S)>,
    spheres: &'a [Sphere],
    /// The scene's contact offset (m), added to every sphere's radius.
    offset: V::S,
    /// The ground's contact height (m), `−∞` without a ground.
    floor: V::S,
    /// The scene's gravity (m/s²).
    gravity: glam::DVec3,
}

impl<'a, V: Vector> Colliders<'a, V> {
    pub fn new(scene: &'a Scene) -> Self {
        let offset: V::S = scene.contact_offset.into();
        let ground = scene.ground.map(|g| (<V::S as From<f32>>::from(g.height) + offset, g.friction.into()));
        let floor = ground.map_or(V::S::from_f64(f64::NEG_INFINITY), |(floor, _)| floor);
        Colliders { ground, spheres: &scene.spheres, offset, floor, gravity: scene.gravity.as_dvec3() }
    }

    /// The work (J) of a contact pass that moved a particle of mass `m` (kg) from `before` to
    /// `after` in a substep of `1/h = inv_h` (1/s) that started at `x_prev` with velocity
    /// `v − g h` (`v`, m/s: the particle's velocity after the prediction): the pass's impulse
    /// `J = m (after − before)/h` against the mean of the substep's start velocity and the
    /// velocity it leaves, `W = J·(v_start + v_a)/2`, `v_a = (after − x_prev)/h`. The work of an
    /// impulse that takes a particle from `v_start` to `v_a`; zero for a particle at rest on a
    /// collider (its prediction falls by `g h²` and the pass lifts it back) and for a particle in
    /// contact that the sweeps push into the collider again (the pushes are the iteration's, not
    /// motion), `−½ m u²` for a particle at speed `u` that the contact stops.
    pub fn work(&self, m: f64, x_prev: V, v: V, before: V, after: V, inv_h: f64) -> f64 {
        let (x_prev, before, after) = (x_prev.to_dvec3(), before.to_dvec3(), after.to_dvec3());
        let v_start = v.to_dvec3() - self.gravity / inv_h;
        let (dv, va) = ((after - before) * inv_h, (after - x_prev) * inv_h);
        0.5 * m * dv.dot(v_start + va)
    }

    /// `true` when no collider can move a particle at `x`: no spheres, and `x` at or above the
    /// ground's contact height (or no ground). One comparison, so that the passes over every
    /// particle leave the projections to the few it fails for.
    #[inline(always)]
    pub fn clear(&self, x: V) -> bool {
        // Not below the floor: a NaN height passes here as it passes the ground's test.
        self.spheres.is_empty() && x.get(1).partial_cmp(&self.floor) != Some(std::cmp::Ordering::Less)
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

/// Projects the free particles of a range that starts at a block boundary (positions `x`,
/// substep starts `x_prev`, velocities from the prediction `v`, inverse masses `w`, index for
/// index) out of the scene's colliders,
/// adding each pass's work (J, [`Colliders::work`], substep `1/h = inv_h`) to its block's sum in
/// `work` (one per [`WORK_BLOCK`] particles of the range, in particle order: the same sums on
/// any split of the particles into whole blocks).
pub(crate) fn project_range<V: Vector>(
    scene: &Scene,
    x: &mut [V],
    x_prev: &[V],
    v: &[V],
    w: &[V::S],
    inv_h: f64,
    work: &mut [f64],
) {
    let colliders = Colliders::new(scene);
    for (b, sum) in work.iter_mut().enumerate() {
        let r = (b * WORK_BLOCK).min(x.len())..((b + 1) * WORK_BLOCK).min(x.len());
        let (x, x_prev, v, w) = (&mut x[r.clone()], &x_prev[r.clone()], &v[r.clone()], &w[r]);
        for (((x, &x_prev), &v), &w) in x.iter_mut().zip(x_prev).zip(v).zip(w) {
            if w > V::S::zero()
                && !colliders.clear(*x)
                && let Some(p) = colliders.project(*x, x_prev)
            {
                *sum += colliders.work(1.0 / w.to_f64(), x_prev, v, *x, p, inv_h);
                *x = p;
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{Ground, SceneOptions, build};
    use glam::{Vec3A, vec3a};

    /// A scene with a frictionless ground at height 0 and no other collider.
    fn ground_scene() -> Scene {
        let mut scene = build("cloth", &SceneOptions { resolution: Some(4), ..SceneOptions::default() }).unwrap();
        scene.ground = Some(Ground { height: 0.0, friction: 0.0 });
        scene.contact_offset = 0.0;
        scene.spheres.clear();
        scene
    }

    /// The work of a pass over one particle of mass `m` at rest (`x_prev`, velocity `v_start`)
    /// after its prediction under gravity, and where the pass left it.
    fn one_pass(scene: &Scene, m: f32, x_prev: Vec3A, v_start: Vec3A, h: f32) -> (f64, Vec3A) {
        let v = v_start + Vec3A::from(scene.gravity) * h;
        let mut x = [x_prev + v * h];
        let mut work = [0.0];
        project_range(scene, &mut x, &[x_prev], &[v], &[1.0 / m], 1.0 / h as f64, &mut work);
        (work[0], x[0])
    }

    #[test]
    fn a_particle_at_rest_on_the_ground_costs_no_work() {
        let scene = ground_scene();
        let (work, x) = one_pass(&scene, 0.5, Vec3A::ZERO, Vec3A::ZERO, 1.0 / 600.0);
        assert_eq!(x.y, 0.0, "the pass lifted the particle back");
        assert!(work.abs() < 1e-9, "{work}");
    }

    #[test]
    fn a_particle_the_ground_stops_loses_its_kinetic_energy() {
        let scene = ground_scene();
        let (m, u, h) = (0.5f32, 2.0f32, 1.0 / 600.0);
        let (work, x) = one_pass(&scene, m, Vec3A::ZERO, vec3a(0.0, -u, 0.0), h);
        assert_eq!(x.y, 0.0);
        // J·(v_start + v_a)/2 with v_a = 0: ½ m u (u + g h).
        let expected = -0.5 * m as f64 * u as f64 * (u as f64 + 9.81 * h as f64);
        assert!((work - expected).abs() < 1e-5 * expected.abs(), "{work} against {expected}");
        // A particle sliding along the frictionless ground loses only its normal motion.
        let (sliding, _) = one_pass(&scene, m, Vec3A::ZERO, vec3a(3.0, -u, 0.0), h);
        assert!((sliding - expected).abs() < 1e-5 * expected.abs(), "{sliding} against {expected}");
    }
}
