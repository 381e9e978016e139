//! Constraint families: zero energy and stress at rest, gradients against central finite
//! differences in f64, finite values on degenerate elements.

mod common;

use common::{check_gradients, rand_vec};
use eapbd::constraints::{Bend, BendParams, Element, Spring, SpringMaterial, SpringParams};
use glam::{DVec3, Vec3};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const MATERIALS: [SpringMaterial; 2] = [SpringMaterial::Hookean, SpringMaterial::StVK];

#[test]
fn springs_rest_state_has_zero_energy_and_stress() {
    let mut rng = SmallRng::seed_from_u64(1);
    for material in MATERIALS {
        for _ in 0..100 {
            let a = rand_vec(&mut rng, 1.0);
            let b = a + rand_vec(&mut rng, 1.0);
            let rest = a.distance(b) as f32;
            let s = Spring::new(0, 1, rest, rng.random_range(1.0..1e6), material);
            let p = SpringParams { material };
            // Rest length from f32 positions, so evaluate there.
            let x = [a.as_vec3(), a.as_vec3() + (b - a).as_vec3().normalize() * rest];
            let e = s.energy(&p, &x);
            let g = s.energy_gradient(&p, &x);
            assert!(e.abs() <= 1e-6 * s.k, "{material:?}: energy {e} at rest");
            assert!(g.iter().all(|g| g.length() <= 1e-3 * s.k.max(1.0)), "{material:?}: stress {g:?} at rest");
            let c = s.compliant(&p, &x).c;
            assert!(c.abs() <= 1e-5, "{material:?}: C = {c} at rest");
        }
    }
}

#[test]
fn spring_gradients_match_finite_differences() {
    let mut rng = SmallRng::seed_from_u64(2);
    for material in MATERIALS {
        for _ in 0..200 {
            let x = [rand_vec(&mut rng, 1.0), rand_vec(&mut rng, 1.0)];
            let s = Spring::new(0, 1, rng.random_range(0.1..2.0), rng.random_range(1.0..1e3), material);
            check_gradients(&format!("{material:?} spring"), &s, &SpringParams { material }, &x);
        }
    }
}

#[test]
fn stvk_spring_small_strain_stiffness_matches_hookean() {
    // With k = k_s/(4 l₀²), both springs have the same energy to second order in the strain.
    let (k_s, rest) = (500.0f32, 0.3f32);
    let h = Spring::new(0, 1, rest, k_s, SpringMaterial::Hookean);
    let s = Spring::new(0, 1, rest, k_s, SpringMaterial::StVK);
    let x = [DVec3::ZERO, DVec3::new(rest as f64 * 1.001, 0.0, 0.0)];
    let eh = h.energy(&SpringParams { material: SpringMaterial::Hookean }, &x);
    let es = s.energy(&SpringParams { material: SpringMaterial::StVK }, &x);
    assert!((eh - es).abs() / eh < 3e-3, "Hookean {eh} vs StVK {es} at 0.1% strain");
}

fn random_hinge(rng: &mut SmallRng) -> [DVec3; 4] {
    // Two triangles on the edge x₀ → x₁, wings on either side, folded by a random angle.
    let e = DVec3::new(rng.random_range(0.5..1.5), 0.0, 0.0);
    let w2 = DVec3::new(rng.random_range(-0.5..1.5), rng.random_range(0.3..1.0), rng.random_range(-0.8..0.8));
    let w3 = DVec3::new(rng.random_range(-0.5..1.5), -rng.random_range(0.3..1.0), rng.random_range(-0.8..0.8));
    let off = rand_vec(rng, 1.0);
    [off, off + e, off + w2, off + w3]
}

#[test]
fn bending_rest_state_has_zero_energy_and_stress() {
    let mut rng = SmallRng::seed_from_u64(3);
    for _ in 0..100 {
        let x = random_hinge(&mut rng).map(|v| v.as_vec3());
        let b = Bend::at_rest([0, 1, 2, 3], &x, rng.random_range(1e-3..10.0));
        let e = b.energy(&BendParams, &x);
        let g = b.energy_gradient(&BendParams, &x);
        assert!(e.abs() <= 1e-9, "energy {e} at rest");
        assert!(g.iter().all(|g| g.length() <= 1e-4 * b.k), "stress {g:?} at rest");
    }
}

#[test]
fn flat_hinge_has_zero_angle_and_a_defined_gradient() {
    let x = [Vec3::ZERO, Vec3::X, Vec3::new(0.5, 0.0, -1.0), Vec3::new(0.5, 0.0, 1.0)];
    let (theta, g) = eapbd::constraints::bending::dihedral(&x.map(|v| v.as_dvec3()));
    assert!(theta.abs() < 1e-12, "flat hinge angle {theta}");
    assert!(g.iter().all(|g| g.is_finite()) && g[2].length() > 0.5, "gradient at flat state {g:?}");
    let b = Bend::at_rest([0, 1, 2, 3], &x, 1.0);
    let xd = x.map(|v| v.as_dvec3());
    check_gradients("flat bend", &b, &BendParams, &xd);
}

#[test]
fn bending_gradients_match_finite_differences() {
    let mut rng = SmallRng::seed_from_u64(4);
    for _ in 0..200 {
        let rest = random_hinge(&mut rng).map(|v| v.as_vec3());
        let b = Bend::at_rest([0, 1, 2, 3], &rest, rng.random_range(0.01..10.0));
        let x = rest.map(|v| v.as_dvec3() + DVec3::new(0.0, 0.0, 0.0));
        let mut y = x;
        for v in &mut y {
            *v += rand_vec(&mut rng, 0.2);
        }
        check_gradients("bend", &b, &BendParams, &y);
    }
}

#[test]
fn degenerate_elements_stay_finite() {
    let p = DVec3::new(0.3, 0.2, 0.1);
    for material in MATERIALS {
        let s = Spring::new(0, 1, 0.5, 100.0, material);
        let sp = SpringParams { material };
        let x = [p, p];
        assert!(s.energy(&sp, &x).is_finite());
        assert!(s.energy_gradient(&sp, &x).iter().all(|g| g.is_finite()));
        let pr = s.compliant(&sp, &x);
        assert!(pr.c.is_finite() && pr.grad.iter().all(|g| g.is_finite()));
    }
    // Collinear wing (zero-area triangle), zero-length edge, all points equal.
    let cases =
        [[DVec3::ZERO, DVec3::X, DVec3::X * 2.0, DVec3::new(0.5, -1.0, 0.0)], [p, p, DVec3::Y, DVec3::Z], [p, p, p, p]];
    let b = Bend { p: [0, 1, 2, 3], rest_angle: 0.3, k: 1.0 };
    for x in cases {
        assert!(b.energy(&BendParams, &x).is_finite(), "{x:?}");
        assert!(b.energy_gradient(&BendParams, &x).iter().all(|g| g.is_finite()), "{x:?}");
        let pr = b.compliant(&BendParams, &x);
        assert!(pr.c.is_finite() && pr.grad.iter().all(|g| g.is_finite()), "{x:?}");
    }
}

fn random_tet(rng: &mut SmallRng) -> [Vec3; 4] {
    loop {
        let x = [0, 1, 2, 3].map(|_| rand_vec(rng, 0.5).as_vec3());
        let d = (x[1] - x[0]).cross(x[2] - x[0]).dot(x[3] - x[0]);
        if d.abs() > 0.05 {
            return x;
        }
    }
}

#[test]
fn tets_of_every_model_have_zero_energy_at_rest_and_exact_gradients() {
    use eapbd::constraints::{Tet, TetParams};
    use eapbd::material::{Elastic, Model};
    let mut rng = SmallRng::seed_from_u64(6);
    for model in Model::ALL {
        let p = TetParams { elastic: Elastic::new(model, 1e4, 0.3).unwrap(), scale: 1e4 };
        for _ in 0..50 {
            let rest = random_tet(&mut rng);
            let t = Tet::at_rest([0, 1, 2, 3], &rest).expect("non-degenerate");
            let xr = rest.map(|v| v.as_dvec3());
            let e0 = t.energy(&p, &xr);
            assert!(e0.abs() < 1e-6, "{model:?}: energy {e0} at rest");
            assert!(t.energy_gradient(&p, &xr).iter().all(|g| g.length() < 1e-3), "{model:?}: stress at rest");
            // Deformed, including inverted: move each vertex by up to 40% of the size.
            let mut y = xr;
            for v in &mut y {
                *v += rand_vec(&mut rng, 0.2);
            }
            check_gradients(&format!("{model:?} tet"), &t, &p, &y);
        }
    }
    // Degenerate rest shapes are refused; collapsed current shapes stay finite.
    assert!(Tet::at_rest([0, 1, 2, 3], &[Vec3::ZERO, Vec3::X, Vec3::X * 2.0, Vec3::Y]).is_none());
    let t = Tet::at_rest([0, 1, 2, 3], &[Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z]).unwrap();
    let p = TetParams { elastic: Elastic::new(Model::NeoHookean, 1e4, 0.3).unwrap(), scale: 1e4 };
    let flat = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(0.3, 0.3, 0.0)];
    assert!(t.energy(&p, &flat).is_finite() && t.energy_gradient(&p, &flat).iter().all(|g| g.is_finite()));
    let pr = t.compliant(&p, &flat);
    assert!(pr.c.is_finite() && pr.grad.iter().all(|g| g.is_finite()));
}
