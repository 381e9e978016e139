//! The energy-momentum projection (`--energy-aware project`), after every frame, in the spirit
//! of FEPR (Dinev et al. 2018): the nearest velocities, in the mass-weighted norm, at which the
//! body's energy meets its budget while the step's linear and angular momentum stay as they are.
//!
//! - **Energy** is the honest one: `H = K + G + E_held`, kinetic, gravitational and the elastic
//!   energy the constraint forces hold ([`crate::metrics::ElasticAccount`]); the unresolved
//!   stretch of an under-converged iterate is not energy of the body, and correcting towards it
//!   is what freezes a cloth under the global balance.
//! - **Budget**: `H*` starts as the energy when the projection is switched on (after the first
//!   frame when it is on from the start: before a step there are no multipliers to say what the
//!   forces hold, and a body that starts deformed beyond what the solve can hold, like
//!   `cloth-free`, would otherwise be driven towards energy no step can carry) and is then
//!   carried from frame to frame, plus the work of physical dissipation of each frame `W`
//!   (velocity damping and every contact pass, in the loop and the final one, ≤ 0 for losses:
//!   `solver::contacts::Colliders::work`): `H*ₙ₊₁ = H*ₙ + Wₙ`, so an impact dissipates
//!   what its contact took and a body at rest on a collider keeps its budget. The work of gravity
//!   is part of `G`; pinned particles do none (they do not move).
//! - **Momenta**: with nothing pinned, the free particles' velocities split into the rigid motion
//!   with the same momenta, `v_rigid,i = V + ω × (xᵢ − c)` (`c` the centre of mass, `V = P / M`,
//!   `ω = I_c⁻¹ L_c`), and the deformation `v_def = v − v_rigid`, which carries neither linear nor
//!   angular momentum and is orthogonal to every rigid motion in the mass inner product. The
//!   minimiser of `Σ mᵢ |v'ᵢ − vᵢ|²` with the momenta `P*`, `L*` and the kinetic energy `K'`
//!   prescribed is `v' = v*_rigid + s v_def`, with `v*_rigid` the rigid motion of momenta `P*`,
//!   `L*` and `s² = (K' − K*_rigid) / K_def`. An isolated body (no pin, no gravity, no collider)
//!   keeps the momenta it had when the budget started (the position-based step keeps them only
//!   to first order in a spinning body); any other keeps the momenta its step produced. With a
//!   pinned particle the pins exert forces and no momentum is kept: the whole velocity is scaled,
//!   `v' = s v`, `s² = K' / K`.
//! - **Bounds**: `K' = K + (H* − H)`; `s` stays within `[1 − ε, 1 + ε]` per frame (`ε` =
//!   [`PROJECTION_EPSILON`]: at most twice the velocity) and the rest of the gap stays in the
//!   budget for later frames, so a turning point (little kinetic energy to scale) does not throw
//!   the body; `s = 1` where the gap or the scaled kinetic energy lies within the rounding band
//!   ([`PROJECTION_ROUNDING`]), so a body at rest does not jitter.
//! - **Settings**: a frame under other settings than the last (other than the thread count)
//!   measures the held energy with other multipliers and substeps, so the budget starts again
//!   after it.
//!
//! Positions are left alone: raising the energy through positions stretches the stiff springs
//! (with positions weighted `m / h²`, stretch is the cheapest energy to add), and lowering it
//! there works against the constraint solve. Measured alternatives (docs/energy-aware.md): a
//! smoothed velocity field scaled instead of the velocity (no gain in stretch), the gap scaled
//! by the trust `K / (K + U)` in the unresolved energy `U` (the cloth at one substep of 30
//! iterations then behaves like `off`, but 30 substeps of one iteration and the free cloth lose
//! energy again), and a bound `ε` of 0.1 or 0.3 (the same stretch; the free cloth's energy dips
//! to 32 % or 49 % in its first second).

use glam::{DMat3, DVec3};

use crate::math::prelude::*;

/// `ε`: the projection scales the deforming (or, with pins, the whole) velocity by a factor in
/// `[1 − ε, 1 + ε]` per frame, at most doubling it (the kinetic energy at most fourfold).
/// Measured against 0.1 and 0.3 (docs/energy-aware.md): the same stretch, and the free cloth's
/// energy level instead of dipping to 32 % and 49 % while the bound holds the give-back back.
pub const PROJECTION_EPSILON: f64 = 1.0;

/// Relative size of the rounding band within which the projection leaves velocities alone: the
/// energies of `f32` positions, summed in `f64`, wander by about 10⁻⁶ of the total at rest (the
/// hanging cloth's held energy by ±5 µJ of 5 J), and a kinetic energy within the band is no
/// motion to scale.
pub const PROJECTION_ROUNDING: f64 = 1e-5;

/// The rigid motion with the momenta of the free particles (inverse mass `w > 0`), and what
/// gives it: the centre of mass, the inertia tensor about it and the total mass.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RigidMotion {
    /// Centre of mass `c` (m).
    pub centre: DVec3,
    /// Velocity of the centre of mass `V = P / M` (m/s).
    pub velocity: DVec3,
    /// Angular velocity `ω = I_c⁻¹ L_c` (rad/s); zero where the inertia tensor is singular
    /// (fewer than three particles off one line).
    pub omega: DVec3,
    /// Total mass `M` (kg).
    pub mass: f64,
    /// Inertia tensor about the centre of mass `I_c = Σ mᵢ (|rᵢ|² 1 − rᵢ rᵢᵀ)` (kg·m²).
    pub inertia: DMat3,
}

impl RigidMotion {
    /// `V + ω × (x − c)` (m/s).
    #[inline]
    pub fn at(&self, x: DVec3) -> DVec3 {
        self.velocity + self.omega.cross(x - self.centre)
    }

    /// The rigid motion of the same body with linear momentum `p` (kg·m/s) and angular momentum
    /// about the origin `l` (kg·m²/s): `V = p / M`, `ω = I_c⁻¹ (l − c × p)`.
    pub fn with_momenta(&self, p: DVec3, l: DVec3) -> RigidMotion {
        let velocity = p / self.mass;
        RigidMotion { velocity, omega: solve_inertia(self.inertia, l - self.centre.cross(p)), ..*self }
    }
}

/// `I⁻¹ l`, or zero where `I` is singular against its scale (all particles on one line).
fn solve_inertia(inertia: DMat3, l: DVec3) -> DVec3 {
    let scale = inertia.x_axis.x + inertia.y_axis.y + inertia.z_axis.z;
    let det = inertia.determinant();
    if scale > 0.0 && det > 1e-12 * scale * scale * scale { inertia.inverse() * l } else { DVec3::ZERO }
}

/// Linear momentum `Σ mᵢ vᵢ` (kg·m/s) and angular momentum about the origin `Σ mᵢ xᵢ × vᵢ`
/// (kg·m²/s) of the free particles.
pub fn momenta<V: Vector>(x: &[V], v: &[V], w: &[V::S]) -> (DVec3, DVec3) {
    let (mut p, mut l) = (DVec3::ZERO, DVec3::ZERO);
    for ((x, v), w) in x.iter().zip(v).zip(w) {
        if *w > V::S::zero() {
            let m = 1.0 / w.to_f64();
            let (x, v) = (x.to_dvec3(), v.to_dvec3());
            p += m * v;
            l += m * x.cross(v);
        }
    }
    (p, l)
}

/// The scales `Σ mᵢ|vᵢ|` (kg·m/s) and `Σ mᵢ|xᵢ − c||vᵢ|` (kg·m²/s) of the free particles'
/// linear and angular momentum (`c` their centre of mass): what a drift of either is measured
/// against.
pub fn momentum_scales<V: Vector>(x: &[V], v: &[V], w: &[V::S]) -> (f64, f64) {
    let free = || x.iter().zip(v).zip(w).filter(|(_, w)| **w > V::S::zero());
    let (mut mass, mut centre) = (0.0, DVec3::ZERO);
    for ((x, _), w) in free() {
        mass += 1.0 / w.to_f64();
        centre += x.to_dvec3() / w.to_f64();
    }
    centre /= mass.max(1e-30);
    let (mut sp, mut sl) = (0.0, 0.0);
    for ((x, v), w) in free() {
        let (m, v) = (1.0 / w.to_f64(), v.to_dvec3().length());
        sp += m * v;
        sl += m * (x.to_dvec3() - centre).length() * v;
    }
    (sp, sl)
}

/// The [`RigidMotion`] of the free particles; `None` without a free particle.
pub fn rigid_motion<V: Vector>(x: &[V], v: &[V], w: &[V::S]) -> Option<RigidMotion> {
    let (mut mass, mut mx, mut mv) = (0.0, DVec3::ZERO, DVec3::ZERO);
    for ((x, v), w) in x.iter().zip(v).zip(w) {
        if *w > V::S::zero() {
            let m = 1.0 / w.to_f64();
            mass += m;
            mx += m * x.to_dvec3();
            mv += m * v.to_dvec3();
        }
    }
    if mass <= 0.0 {
        return None;
    }
    let (centre, velocity) = (mx / mass, mv / mass);
    let (mut l, mut inertia) = (DVec3::ZERO, DMat3::ZERO);
    for ((x, v), w) in x.iter().zip(v).zip(w) {
        if *w > V::S::zero() {
            let m = 1.0 / w.to_f64();
            let r = x.to_dvec3() - centre;
            l += m * r.cross(v.to_dvec3() - velocity);
            inertia += m * (DMat3::from_diagonal(DVec3::splat(r.length_squared())) - outer(r, r));
        }
    }
    Some(RigidMotion { centre, velocity, omega: solve_inertia(inertia, l), mass, inertia })
}

fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The rigid motions of a projection: the one the velocities have now, and the one they get.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid {
    /// The rigid motion with the velocities' momenta.
    pub now: RigidMotion,
    /// The rigid motion with the momenta to keep.
    pub target: RigidMotion,
}

/// The kinetic energies `(K, K_def, K*_rigid)` (J): the whole, the part the projection scales
/// (the deformation `v − rigid.now`, or all of it without rigid motions) and that of the target
/// rigid motion (0 without).
pub fn kinetic_parts<V: Vector>(x: &[V], v: &[V], w: &[V::S], rigid: Option<&Rigid>) -> (f64, f64, f64) {
    let (mut whole, mut scaled, mut target) = (0.0, 0.0, 0.0);
    for ((x, v), w) in x.iter().zip(v).zip(w) {
        if *w > V::S::zero() {
            let half_m = 0.5 / w.to_f64();
            let (xd, vd) = (x.to_dvec3(), v.to_dvec3());
            whole += half_m * vd.length_squared();
            match rigid {
                Some(r) => {
                    scaled += half_m * (vd - r.now.at(xd)).length_squared();
                    target += half_m * r.target.at(xd).length_squared();
                }
                None => scaled += half_m * vd.length_squared(),
            }
        }
    }
    (whole, scaled, target)
}

/// The projection's scale `s` for a gap `H* − H` (J) in the kinetic energy of the part it scales
/// (`k_scaled`, J: `K' − K*_rigid − K_def` with a rigid motion, `K' − K` without), with `k` the
/// whole kinetic energy and `budget` the scale of the energies for the rounding band (J).
pub fn projection_scale(gap: f64, k: f64, k_scaled: f64, budget: f64) -> f64 {
    let band = PROJECTION_ROUNDING * (budget.abs() + k.abs());
    if k_scaled <= band || gap.abs() <= band || !gap.is_finite() {
        return 1.0;
    }
    ((k_scaled + gap).max(0.0) / k_scaled).sqrt().clamp(1.0 - PROJECTION_EPSILON, 1.0 + PROJECTION_EPSILON)
}

/// The momenta an isolated body keeps: `Some((P, L))` of the free particles when nothing is
/// pinned, gravity is zero and the scene has no collider; `None` otherwise.
pub fn conserved_momenta<V: Vector>(
    scene: &crate::scene::Scene,
    x: &[V],
    v: &[V],
    w: &[V::S],
) -> Option<(DVec3, DVec3)> {
    let isolated =
        !any_pinned(w) && scene.gravity == glam::Vec3::ZERO && scene.ground.is_none() && scene.spheres.is_empty();
    isolated.then(|| momenta(x, v, w))
}

/// `v ← target + s (v − now)` on the free particles with rigid motions `now` and `target`
/// (`v ← s v` without).
pub fn apply_scale<V: Vector>(x: &[V], v: &mut [V], w: &[V::S], rigid: Option<&Rigid>, s: f64) {
    if s == 1.0 && rigid.is_none_or(|r| r.now == r.target) {
        return;
    }
    for ((x, v), w) in x.iter().zip(v.iter_mut()).zip(w) {
        if *w > V::S::zero() {
            let (xd, vd) = (x.to_dvec3(), v.to_dvec3());
            let out = match rigid {
                Some(r) => r.target.at(xd) + s * (vd - r.now.at(xd)),
                None => s * vd,
            };
            *v = V::new(V::S::from_f64(out.x), V::S::from_f64(out.y), V::S::from_f64(out.z));
        }
    }
}

/// `true` when some particle is pinned (inverse mass 0): the projection then keeps no momentum.
pub fn any_pinned<S: Real>(w: &[S]) -> bool {
    w.iter().any(|w| *w <= S::zero())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cloud() -> (Vec<DVec3>, Vec<DVec3>, Vec<f64>) {
        let x: Vec<DVec3> =
            (0..20).map(|i| DVec3::new((i as f64 * 0.37).sin(), (i as f64 * 0.71).cos(), i as f64 * 0.05)).collect();
        let v: Vec<DVec3> =
            (0..20).map(|i| DVec3::new((i as f64 * 1.3).cos(), 0.2 * i as f64 - 2.0, (i as f64).sin())).collect();
        let w = (0..20).map(|i| 1.0 / (0.5 + 0.1 * i as f64)).collect();
        (x, v, w)
    }

    #[test]
    fn scaling_the_deformation_keeps_both_momenta_and_meets_the_energy() {
        let (x, mut v, w) = cloud();
        let (p0, l0) = momenta(&x, &v, &w);
        let now = rigid_motion(&x, &v, &w).unwrap();
        let rigid = Rigid { now, target: now };
        let (k, k_def, k_rigid) = kinetic_parts(&x, &v, &w, Some(&rigid));
        assert!(k_def > 0.0 && k_def < k);
        assert!((k_rigid + k_def - k).abs() < 1e-12 * k, "the parts are orthogonal");
        let gap = 0.05 * k_def;
        let s = projection_scale(gap, k, k_def, k);
        assert!(s > 1.0 && s < 1.0 + PROJECTION_EPSILON);
        apply_scale(&x, &mut v, &w, Some(&rigid), s);
        let (p1, l1) = momenta(&x, &v, &w);
        let (k1, ..) = kinetic_parts(&x, &v, &w, None);
        assert!((p1 - p0).length() < 1e-12 * p0.length().max(1.0), "P {p0} -> {p1}");
        assert!((l1 - l0).length() < 1e-12 * l0.length().max(1.0), "L {l0} -> {l1}");
        assert!((k1 - (k + gap)).abs() < 1e-12 * k, "K {k1} against {}", k + gap);
    }

    #[test]
    fn the_target_rigid_motion_restores_the_momenta_to_keep() {
        let (x, mut v, w) = cloud();
        let (p0, l0) = momenta(&x, &v, &w);
        // A drift of both momenta, as a spinning position-based step leaves it.
        for (v, x) in v.iter_mut().zip(&x) {
            *v += DVec3::new(0.01, 0.0, -0.02) + DVec3::new(0.0, 0.03, 0.01).cross(*x);
        }
        let now = rigid_motion(&x, &v, &w).unwrap();
        let rigid = Rigid { now, target: now.with_momenta(p0, l0) };
        apply_scale(&x, &mut v, &w, Some(&rigid), 1.0);
        let (p1, l1) = momenta(&x, &v, &w);
        assert!((p1 - p0).length() < 1e-12 * p0.length().max(1.0), "P {p0} -> {p1}");
        assert!((l1 - l0).length() < 1e-12 * l0.length().max(1.0), "L {l0} -> {l1}");
    }

    #[test]
    fn a_rigid_motion_has_no_deformation_to_scale() {
        let (x, _, w) = cloud();
        let motion = RigidMotion {
            velocity: DVec3::new(0.3, -1.0, 2.0),
            omega: DVec3::new(1.0, 0.5, -2.0),
            ..RigidMotion::default()
        };
        let v: Vec<DVec3> = x.iter().map(|&x| motion.at(x)).collect();
        let now = rigid_motion(&x, &v, &w).unwrap();
        assert!((now.omega - motion.omega).length() < 1e-9, "{} against {}", now.omega, motion.omega);
        let (k, k_def, _) = kinetic_parts(&x, &v, &w, Some(&Rigid { now, target: now }));
        assert!(k_def < 1e-20 * k, "{k_def}");
        assert_eq!(projection_scale(0.1 * k, k, k_def, k), 1.0);
    }

    #[test]
    fn the_scale_is_bounded_and_leaves_rounding_alone() {
        assert_eq!(projection_scale(10.0, 1.0, 1.0, 5.0), 1.0 + PROJECTION_EPSILON);
        assert_eq!(projection_scale(-10.0, 1.0, 1.0, 5.0), 1.0 - PROJECTION_EPSILON);
        assert_eq!(projection_scale(1e-9, 1.0, 1.0, 5.0), 1.0);
        assert_eq!(projection_scale(1.0, 0.0, 0.0, 5.0), 1.0);
        assert_eq!(projection_scale(1.0, 1e-6, 1e-6, 5.0), 1.0, "a kinetic energy within rounding is no motion");
        assert_eq!(projection_scale(f64::NAN, 1.0, 1.0, 5.0), 1.0);
        let s = projection_scale(0.1, 1.0, 1.0, 5.0);
        assert!((s * s - 1.1).abs() < 1e-12);
    }

    #[test]
    fn pins_switch_the_momenta_off() {
        assert!(any_pinned(&[1.0f32, 0.0]));
        assert!(!any_pinned(&[1.0f32, 2.0]));
        assert!(rigid_motion::<DVec3>(&[DVec3::ZERO], &[DVec3::ONE], &[0.0]).is_none());
    }
}
