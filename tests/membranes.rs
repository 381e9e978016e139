//! The anisotropic continuum cloth (orthotropic StVK triangle): rest state, gradients against
//! finite differences, rotation invariance, the moduli it reproduces, degenerate triangles,
//! parameter checks, and a hanging cloth that is visibly stiffer along its warp.

mod common;

use common::{check_gradients, rand_vec};
use eapbd::constraints::{Element, Membrane, MembraneParams, Orthotropic};
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, Settings};
use glam::{DMat3, DVec3, Vec2, Vec3A};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

fn params(warp: f64, weft: f64) -> MembraneParams {
    MembraneParams::new(Orthotropic::new(warp, weft, None, 0.3).unwrap())
}

/// A random non-degenerate triangle in material coordinates (m).
fn random_triangle(rng: &mut SmallRng) -> [Vec2; 3] {
    loop {
        let x = [0, 1, 2].map(|_| Vec2::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5)));
        if (x[1] - x[0]).perp_dot(x[2] - x[0]).abs() > 0.05 {
            return x;
        }
    }
}

/// The triangle placed in 3D by a random rotation (the rest state, in world space).
fn placed(uv: &[Vec2; 3], r: &DMat3) -> [DVec3; 3] {
    uv.map(|p| *r * DVec3::new(p.x as f64, 0.0, p.y as f64))
}

fn random_rotation(rng: &mut SmallRng) -> DMat3 {
    let axis = rand_vec(rng, 1.0).normalize_or(DVec3::Y);
    DMat3::from_axis_angle(axis, rng.random_range(-3.0..3.0))
}

#[test]
fn rest_state_has_zero_energy_and_stress_in_any_placement() {
    let mut rng = SmallRng::seed_from_u64(1);
    let p = params(1e4, 1e2);
    for _ in 0..50 {
        let uv = random_triangle(&mut rng);
        let m = Membrane::at_rest([0, 1, 2], &uv).unwrap();
        let x = placed(&uv, &random_rotation(&mut rng));
        // Zero up to the f32 rounding of the stored D_m⁻¹ (relative 1e-7 of the strain).
        assert!(m.energy(&p, &x).abs() < 1e-9, "energy at rest");
        assert!(m.energy_gradient(&p, &x).iter().all(|g| g.length() < 1e-6 * p.scale), "stress at rest");
        assert!(m.compliant(&p, &x).c < 1e-6, "the compliant constraint vanishes at rest");
    }
}

#[test]
fn gradients_match_finite_differences_in_stretch_and_compression() {
    let mut rng = SmallRng::seed_from_u64(2);
    for (warp, weft, shear, nu) in [(1e4, 1e2, None, 0.3), (50.0, 5e3, Some(7.0), 0.05), (1e3, 1e3, None, 0.4)] {
        let p = MembraneParams::new(Orthotropic::new(warp, weft, shear, nu).unwrap());
        for k in 0..60 {
            let uv = random_triangle(&mut rng);
            let m = Membrane::at_rest([0, 1, 2], &uv).unwrap();
            let r = random_rotation(&mut rng);
            // Up to 3× stretch, or compression to 20%, plus random displacement (may flip).
            let scale = [3.0, 0.2, 1.0][k % 3];
            let x = placed(&uv, &r).map(|v| v * scale + rand_vec(&mut rng, 0.2));
            check_gradients(&format!("membrane {warp}/{weft}"), &m, &p, &x);
        }
    }
}

#[test]
fn energy_is_invariant_under_rigid_motion() {
    let mut rng = SmallRng::seed_from_u64(3);
    let p = params(2e3, 3e2);
    for _ in 0..50 {
        let uv = random_triangle(&mut rng);
        let m = Membrane::at_rest([0, 1, 2], &uv).unwrap();
        let x = placed(&uv, &DMat3::IDENTITY).map(|v| v + rand_vec(&mut rng, 0.15));
        let (r, t) = (random_rotation(&mut rng), rand_vec(&mut rng, 2.0));
        let moved = x.map(|v| r * v + t);
        let (e0, e1) = (m.energy(&p, &x), m.energy(&p, &moved));
        assert!((e0 - e1).abs() <= 1e-9 * e0.max(1e-9), "rigid motion changed the energy: {e0} → {e1}");
    }
}

#[test]
fn uniaxial_stretch_sees_the_warp_and_weft_moduli() {
    // A unit right triangle stretched by a small strain e along the warp (x) or the weft (z)
    // with the other direction held: E = A₀ ½ c e², c = c_uu or c_vv.
    let p = params(1e4, 1e2);
    let uv = [Vec2::ZERO, Vec2::X, Vec2::Y];
    let m = Membrane::at_rest([0, 1, 2], &uv).unwrap();
    let e = 1e-4;
    let along_warp = [DVec3::ZERO, DVec3::new(1.0 + e, 0.0, 0.0), DVec3::Z];
    let along_weft = [DVec3::ZERO, DVec3::X, DVec3::new(0.0, 0.0, 1.0 + e)];
    let c_uu = 2.0 * m.energy(&p, &along_warp) / (0.5 * e * e);
    let c_vv = 2.0 * m.energy(&p, &along_weft) / (0.5 * e * e);
    assert!((c_uu / p.c[0] - 1.0).abs() < 1e-3, "warp stiffness {c_uu} vs c_uu {}", p.c[0]);
    assert!((c_vv / p.c[2] - 1.0).abs() < 1e-3, "weft stiffness {c_vv} vs c_vv {}", p.c[2]);
    assert!(c_uu > 90.0 * c_vv);
    // Shear γ: E = A₀ ½ G γ².
    let g = 1e-4;
    let sheared = [DVec3::ZERO, DVec3::X, DVec3::new(g, 0.0, 1.0)];
    let shear = 2.0 * m.energy(&p, &sheared) / (0.5 * g * g);
    assert!((shear / p.c[3] - 1.0).abs() < 1e-3, "shear stiffness {shear} vs G {}", p.c[3]);
}

#[test]
fn degenerate_triangles_are_refused_at_rest_and_finite_when_collapsed() {
    assert!(Membrane::at_rest([0, 1, 2], &[Vec2::ZERO, Vec2::X, Vec2::X * 2.0]).is_none());
    let m = Membrane::at_rest([0, 1, 2], &[Vec2::ZERO, Vec2::X, Vec2::Y]).unwrap();
    let p = params(1e3, 1e3);
    for x in [[DVec3::ZERO; 3], [DVec3::ZERO, DVec3::X, DVec3::X * 2.0], [DVec3::ZERO, DVec3::Z, DVec3::X]] {
        assert!(m.energy(&p, &x).is_finite());
        assert!(m.energy_gradient(&p, &x).iter().all(|g| g.is_finite()));
        let pr = m.compliant(&p, &x);
        assert!(pr.c.is_finite() && pr.grad.iter().all(|g| g.is_finite()));
    }
}

#[test]
fn absurd_moduli_are_refused() {
    for (warp, weft, shear, nu) in
        [(-1.0, 1.0, None, 0.3), (1.0, f64::NAN, None, 0.3), (1.0, 1.0, Some(0.0), 0.3), (1.0, 100.0, None, 0.2)]
    {
        let e = Orthotropic::new(warp, weft, shear, nu).unwrap_err().to_string();
        assert!(e.contains("--"), "{e}");
    }
    // ν_uv² E_v/E_u = 0.04 · 100 = 4 ≥ 1: C_orth would not be positive definite.
    let e = Orthotropic::new(1.0, 100.0, None, 0.2).unwrap_err().to_string();
    assert!(e.contains("--poisson"), "{e}");
}

/// Hangs the `cloth` scene (two corners of its first row, along x, pinned) and returns its
/// extent along z (m) after `frames` frames.
fn hanging_extent(warp: f64, weft: f64, frames: u32) -> f32 {
    let opts = SceneOptions {
        resolution: Some(21),
        membrane: Some(Orthotropic::new(warp, weft, None, 0.0).unwrap()),
        ..SceneOptions::default()
    };
    let sc = scene::build("cloth", &opts).unwrap();
    assert!(sc.springs.is_none() && sc.membranes.is_some(), "aniso-cloth replaces the springs");
    let mut sv = CpuSolver::<Vec3A>::new(sc);
    let s = Settings { substeps: 4, iterations: 10, damping: 1.0, ..Settings::default() };
    for _ in 0..frames {
        sv.step_frame(&s);
    }
    let x = &sv.particles.x;
    assert!(x.iter().all(|p| p.is_finite()));
    // The hanging direction: the largest distance from the pinned row, measured in the rest's z.
    let y_top = x[0].y;
    y_top - x.iter().map(|p| p.y).fold(f32::MAX, f32::min)
}

#[test]
fn a_cloth_soft_along_the_weft_hangs_longer_than_one_soft_along_the_warp() {
    // Pinned along its warp edge, the cloth hangs in its weft direction: a soft weft stretches.
    let soft_weft = hanging_extent(1e4, 20.0, 120);
    let soft_warp = hanging_extent(20.0, 1e4, 120);
    println!("drop: soft weft {soft_weft:.3} m, soft warp {soft_warp:.3} m");
    assert!(soft_weft > soft_warp + 0.1, "soft weft {soft_weft:.3} m vs soft warp {soft_warp:.3} m");
}
