//! 3D elastic models: the signed SVD, zero energy and stress at rest, stress against central
//! finite differences of the energy (f64) over stretch, compression and inversion, rotation
//! invariance (and what the linear model satisfies instead), agreement at small strain, and
//! finite restoring stress for inverted and collapsed elements.

use eapbd::material::{Elastic, M3, Model, SIGMA_MIN, svd};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const E: f64 = 1.0e5;
const NU: f64 = 0.3;

fn models() -> Vec<Elastic> {
    Model::ALL.iter().map(|&m| Elastic::new(m, E, NU).unwrap()).collect()
}

fn random_matrix(rng: &mut SmallRng, spread: f64) -> M3<f64> {
    let mut m = M3::identity();
    for c in 0..3 {
        for r in 0..3 {
            m.0[c][r] += rng.random_range(-spread..spread);
        }
    }
    m
}

/// A rotation from a random axis and angle (Rodrigues).
fn rotation(rng: &mut SmallRng, angle: f64) -> M3<f64> {
    let mut a = [rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0f64..1.0)];
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    a = a.map(|x| x / n);
    let k = M3([[0.0, a[2], -a[1]], [-a[2], 0.0, a[0]], [a[1], -a[0], 0.0]]);
    M3::identity().add(&k.scale(angle.sin())).add(&k.mul(&k).scale(1.0 - angle.cos()))
}

fn max_abs(m: &M3<f64>) -> f64 {
    m.0.iter().flatten().fold(0.0, |a, b| a.max(b.abs()))
}

#[test]
fn signed_svd_reconstructs_and_flags_inversion() {
    let mut rng = SmallRng::seed_from_u64(1);
    for i in 0..2000 {
        let mut f = random_matrix(&mut rng, 1.0);
        if i % 3 == 0 {
            // A mirror: inverted element.
            for c in 0..3 {
                f.0[c][0] = -f.0[c][0];
            }
        }
        let d = svd(&f);
        let back = d.compose(d.sigma);
        let err = max_abs(&back.add(&f.scale(-1.0)));
        assert!(err < 1e-9 * (1.0 + max_abs(&f)), "reconstruction error {err:e}");
        for r in [d.u, d.v] {
            assert!(max_abs(&r.transpose().mul(&r).add(&M3::identity().scale(-1.0))) < 1e-9);
            assert!((r.det() - 1.0).abs() < 1e-9, "not a rotation: det {}", r.det());
        }
        let s = d.sigma;
        assert!(s[0] >= s[1] - 1e-12 && s[1] >= s[2].abs() - 1e-12, "order {s:?}");
        assert_eq!(s[2] < 0.0, f.det() < 0.0, "sign of σ₃ {s:?} vs det {}", f.det());
    }
    // Degenerate inputs stay finite.
    for f in [M3::<f64>::zero(), M3::diag([1.0, 0.0, 0.0]), M3::diag([2.0, 2.0, 0.0])] {
        let d = svd(&f);
        assert!(d.sigma.iter().all(|x: &f64| x.is_finite()) && max_abs(&d.compose(d.sigma).add(&f.scale(-1.0))) < 1e-9);
    }
}

#[test]
fn rest_shape_has_zero_energy_and_stress() {
    let id = M3::<f64>::identity();
    for m in models() {
        let psi = m.energy_density(&id);
        let p = m.stress(&id);
        assert!(psi.abs() < 1e-9 * E, "{:?}: Ψ(I) = {psi}", m.model);
        assert!(max_abs(&p) < 1e-9 * E, "{:?}: P(I) = {p:?}", m.model);
    }
}

/// Central differences of Ψ with respect to each entry of F.
fn fd_stress(m: &Elastic, f: &M3<f64>) -> M3<f64> {
    let h = 1e-6;
    let mut out = M3::zero();
    for c in 0..3 {
        for r in 0..3 {
            let (mut fp, mut fm) = (*f, *f);
            fp.0[c][r] += h;
            fm.0[c][r] -= h;
            out.0[c][r] = (m.energy_density(&fp) - m.energy_density(&fm)) / (2.0 * h);
        }
    }
    out
}

#[test]
fn stress_matches_finite_differences_of_the_energy() {
    let mut rng = SmallRng::seed_from_u64(2);
    // Small and large deformations, compression, stretch, and mirrored (inverted) ones.
    let cases: Vec<(f64, bool)> = vec![(0.05, false), (0.4, false), (0.8, false), (0.4, true), (0.8, true)];
    for m in models() {
        for &(spread, mirror) in &cases {
            for _ in 0..100 {
                let mut f = random_matrix(&mut rng, spread);
                if mirror {
                    for c in 0..3 {
                        f.0[c][2] = -f.0[c][2];
                    }
                }
                // Skip nearly repeated singular values, where the SVD's finite differences are
                // ill-conditioned (the stress formula holds there too).
                let s = svd(&f).sigma;
                if (s[0] - s[1]).abs() < 1e-3 || (s[1] - s[2].abs()).abs() < 1e-3 || s[2].abs() < 1e-3 {
                    continue;
                }
                let p = m.stress(&f);
                let fd = fd_stress(&m, &f);
                let err = max_abs(&p.add(&fd.scale(-1.0)));
                let scale = max_abs(&fd).max(1e-3 * E);
                assert!(
                    err < 2e-5 * scale,
                    "{:?} spread {spread} mirror {mirror}: |P − FD| = {err:e} of {scale:e}, σ = {s:?}",
                    m.model
                );
            }
        }
    }
}

#[test]
fn isotropic_models_are_rotation_invariant_and_the_linear_one_is_not() {
    let mut rng = SmallRng::seed_from_u64(3);
    for m in models() {
        for _ in 0..50 {
            let f = random_matrix(&mut rng, 0.4);
            let angle = rng.random_range(0.1..3.0);
            let r = rotation(&mut rng, angle);
            let (a, b) = (m.energy_density(&f), m.energy_density(&r.mul(&f)));
            if m.model == Model::Linear {
                continue;
            }
            assert!((a - b).abs() < 1e-7 * a.abs().max(E * 1e-6), "{:?}: Ψ(F) = {a}, Ψ(RF) = {b}", m.model);
        }
    }
    // The paper's linear model: a rotated rest shape has energy (not rotation invariant) ...
    let lin = Elastic::new(Model::Linear, E, NU).unwrap();
    let r = rotation(&mut rng, 0.5);
    assert!(lin.energy_density(&r) > 1e-3 * E, "linear Ψ(R) = {}", lin.energy_density(&r));
    // ... what it satisfies instead: invariance under translation (it sees only F) and under the
    // linearised rotations I + tW (W skew), whose symmetric part is the identity: ε = 0 exactly,
    // however large t, so it agrees with the rotation-invariant models only to first order.
    let w = M3([[0.0, 0.3, -0.2], [-0.3, 0.0, 0.1], [0.2, -0.1, 0.0]]);
    for t in [1e-3, 0.1, 1.0] {
        let psi: f64 = lin.energy_density(&M3::identity().add(&w.scale(t)));
        assert!(psi.abs() < 1e-12 * E, "Ψ(I + tW) = {psi} at t = {t}");
    }
}

#[test]
fn all_models_agree_at_small_strain() {
    let mut rng = SmallRng::seed_from_u64(4);
    let lin = Elastic::new(Model::Linear, E, NU).unwrap();
    for _ in 0..50 {
        // Symmetric small strain (no rotation), so the linear model is exact to second order.
        let d = random_matrix(&mut rng, 1e-4).add(&M3::identity().scale(-1.0));
        let f = M3::identity().add(&d.add(&d.transpose()).scale(0.5));
        let reference = lin.energy_density(&f);
        for m in models() {
            let psi = m.energy_density(&f);
            assert!((psi - reference).abs() < 2e-3 * reference, "{:?}: Ψ = {psi:e}, linear {reference:e}", m.model);
        }
    }
}

#[test]
fn inverted_and_collapsed_elements_have_finite_restoring_stress() {
    let mut rng = SmallRng::seed_from_u64(5);
    for m in models().into_iter().filter(|m| m.model != Model::Linear) {
        for i in 0..200 {
            // Large random deformations mirrored: finite energy and stress.
            let mut f = random_matrix(&mut rng, 0.6);
            for c in 0..3 {
                f.0[c][1] = -f.0[c][1];
            }
            let (psi, p) = (m.energy_density(&f), m.stress(&f));
            assert!(psi.is_finite() && p.0.iter().flatten().all(|x: &f64| x.is_finite()), "{:?}", m.model);
            // Near a mirrored rest shape (the mirrored cube), a small step down the energy
            // gradient raises the negative singular value towards positive. (The volume can
            // still shrink for StVK, whose λ term also expands the other directions.)
            let mut f = random_matrix(&mut rng, 0.1);
            for c in 0..3 {
                f.0[c][i % 3] = -f.0[c][i % 3];
            }
            assert!(f.det() < 0.0);
            let (psi, p) = (m.energy_density(&f), m.stress(&f));
            assert!(psi > 0.0, "{:?}: Ψ = {psi} for an inverted element", m.model);
            let step = f.add(&p.scale(-1e-3 / max_abs(&p)));
            let (before, after) = (svd(&f).sigma[2], svd(&step).sigma[2]);
            assert!(after > before, "{:?}: inverted singular value {before} → {after}", m.model);
        }
        for f in [M3::<f64>::zero(), M3::diag([1.0, 1.0, 0.0]), M3::diag([1.0, 0.0, 0.0]), M3::diag([1.0, 1.0, -1.0])] {
            let (psi, p) = (m.energy_density(&f), m.stress(&f));
            assert!(psi.is_finite() && p.0.iter().flatten().all(|x: &f64| x.is_finite()), "{:?} at {f:?}", m.model);
        }
    }
}

/// Below `σ_min` the energy keeps rising as an element inverts further (`F = diag(s, s, σ)`), its
/// slope at least
/// `κ_inv |σ − σ_min|`, also where the other two axes are stretched (where the model's own slope
/// at `σ_min` turns positive and a first-order continuation would reward inversion).
#[test]
fn the_inversion_continuation_rises_with_depth_even_when_stretched() {
    for m in models().into_iter().filter(|m| m.model != Model::Linear) {
        for stretch in [1.0, 2.0, 4.0] {
            let psi = |s: f64| m.energy_density(&M3::diag([stretch, stretch, s]));
            let mut last = psi(SIGMA_MIN);
            // Down to −0.9 × the stretch: beyond, the signed SVD moves the inversion to another
            // axis (|σ₃| is the smallest singular value).
            for s in (1..).map(|i| SIGMA_MIN - 0.05 * i as f64).take_while(|&s| s > -0.9 * stretch) {
                let h = 1e-6;
                let slope = (psi(s + h) - psi(s - h)) / (2.0 * h);
                let floor = m.inversion_stiffness * (SIGMA_MIN - s);
                assert!(
                    slope <= -floor * (1.0 - 1e-6),
                    "{:?}, stretch {stretch}: dΨ/dσ = {slope:e} at σ = {s}, want ≤ −{floor:e}",
                    m.model
                );
                let now = psi(s);
                assert!(now > last, "{:?}, stretch {stretch}: Ψ fell from {last:e} to {now:e} at σ = {s}", m.model);
                last = now;
            }
        }
    }
}

#[test]
fn absurd_material_parameters_are_refused() {
    for (e, nu) in [(-1.0, 0.3), (f64::NAN, 0.3), (1e5, 0.5), (1e5, -1.0), (0.0, 0.2)] {
        let err = Elastic::new(Model::NeoHookean, e, nu).unwrap_err().to_string();
        assert!(err.contains("--young") || err.contains("--poisson"), "{err}");
    }
}

/// The closed forms of `material::invariants` against the SVD reference (`Elastic::reference`):
/// the same `Ψ` and `P` within rounding wherever they apply (small and large strain, stretch,
/// compression, near the inversion threshold), in `f64` and in the solver's `f32`; never applied
/// to an inverted element or one with a singular value below `σ_min`, where `energy_stress` is
/// the reference itself.
#[test]
fn closed_forms_match_the_svd_reference() {
    use eapbd::material::SIGMA_MIN;
    use eapbd::material::invariants::closed_form;
    let mut rng = SmallRng::seed_from_u64(7);
    let to_f32 = |m: &M3<f64>| M3(m.0.map(|c| c.map(|x| x as f32)));
    for m in models() {
        let (mut fast, mut slow) = (0, 0);
        for i in 0..3000 {
            // Small and large strain, a uniform stretch or compression on top, some mirrored.
            let spread = [0.02, 0.3, 0.7, 1.2][i % 4];
            let mut f = random_matrix(&mut rng, spread).scale([1.0, 0.4, 2.5][i % 3]);
            if i % 7 == 0 {
                for c in 0..3 {
                    f.0[c][1] = -f.0[c][1];
                }
            }
            let (psi_ref, p_ref) = m.reference(&f);
            let scale = max_abs(&p_ref).max(1e-3 * E);
            let psi_scale = psi_ref.abs().max(1e-3 * E);
            let Some((psi, p)) = closed_form(&m, &f) else {
                slow += 1;
                assert_eq!(
                    m.energy_stress(&f),
                    (psi_ref, p_ref),
                    "{:?}: declined elements take the reference",
                    m.model
                );
                continue;
            };
            fast += 1;
            let sigma = svd(&f).sigma;
            if m.model != Model::Linear {
                assert!(sigma[2] >= SIGMA_MIN * (1.0 - 1e-9), "{:?}: closed form taken at σ = {sigma:?}", m.model);
            }
            let (ep, es) = ((psi - psi_ref).abs(), max_abs(&p.add(&p_ref.scale(-1.0))));
            assert!(
                ep < 1e-9 * psi_scale && es < 1e-9 * scale,
                "{:?} f64 at σ = {sigma:?}: |ΔΨ| {ep:e}, |ΔP| {es:e}",
                m.model
            );
            // In f32 the closed form is about as accurate as the reference path in f32 (both
            // against f64), up to 1e-4 of the stress (f32's 6e-8 amplified by the Mooney-Rivlin
            // terms' `J^{-7/3}` under strong compression) and a floor of the moduli times f32's
            // epsilon (the cancellation in `I₁ − 3` near rest).
            let err32 = |(psi, p): (f32, M3<f32>)| {
                let p = M3(p.0.map(|c| c.map(f64::from)));
                ((f64::from(psi) - psi_ref).abs(), max_abs(&p.add(&p_ref.scale(-1.0))))
            };
            let (ep, es) = err32(m.energy_stress(&to_f32(&f)));
            let (rp, rs) = err32(m.reference(&to_f32(&f)));
            let floor = 1e-6 * E * (1.0 + max_abs(&f).powi(4));
            assert!(
                ep < 4.0 * rp + 1e-4 * psi_scale + floor && es < 4.0 * rs + 1e-4 * scale + floor,
                "{:?} f32 at σ = {sigma:?}: |ΔΨ| {ep:e} (SVD path {rp:e}), |ΔP| {es:e} (SVD path {rs:e})",
                m.model
            );
        }
        // Both paths were exercised for the nonlinear models.
        assert!(fast > 1000 && (m.model == Model::Linear || slow > 300), "{:?}: {fast} closed, {slow} SVD", m.model);
    }
}

#[test]
fn only_neo_hookean_with_a_negative_lame_lambda_carries_a_caveat() {
    for model in [Model::Linear, Model::StVK, Model::NeoHookean, Model::MooneyRivlin, Model::ArrudaBoyce] {
        for nu in [-0.9, -0.2, 0.0, 0.3, 0.49] {
            let e = Elastic::new(model, 1e6, nu).unwrap();
            let expected = model == Model::NeoHookean && nu < 0.0;
            assert_eq!(e.caveat().is_some(), expected, "{model:?} at ν = {nu}");
            if let Some(c) = e.caveat() {
                assert!(c.contains(&format!("{nu:.3}")) && c.contains("no lower bound"), "{c}");
            }
        }
    }
}
