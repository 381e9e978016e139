//! The isotropic models' energy density and stress in closed form, from the invariants of `F`
//! (docs/algorithm.md §3), for the regular case: `J = det F > 0` and every singular value at
//! least `σ_min`, where the inversion extension is inactive and `Ψ(F) = Ψ̂(σ)`. No SVD.
//!
//! With `C = FᵀF`, `I₁ = tr C = |F|²`, `J = det F`, `cof F = ∂J/∂F = J F⁻ᵀ` (columns
//! `f₁×f₂, f₂×f₀, f₀×f₁` for the columns `fᵢ` of `F`), `Ĵ = J^{−2/3}`:
//! - StVK: `E = ½(C − I)`, `Ψ = μ E:E + (λ/2) tr²E`, `P = F (2μE + λ tr E I)`;
//! - Neo-Hookean: `Ψ = (μ/2)(I₁ − 3) − μ log J + (λ/2) log² J`,
//!   `P = μF + (λ log J − μ) cof F / J`;
//! - Mooney-Rivlin: `a = I₁² − C:C`, `Ψ = (μ₀₁/2)(a Ĵ² − 6) + μ₁₀(I₁ Ĵ − 3) + ν₁(J − 1)²`,
//!   `P = (μ₀₁/2) Ĵ² (4(I₁F − FC) − (4/3) a cof F / J) + μ₁₀ Ĵ (2F − (2/3) I₁ cof F / J)
//!   + 2ν₁(J − 1) cof F`;
//! - Arruda-Boyce: `Ī₁ = Ĵ I₁`, `Ψ = Σᵢ αᵢ(Ī₁ⁱ − 3ⁱ) + (κ/2)(J − 1)²`,
//!   `P = (Σᵢ i αᵢ Ī₁ⁱ⁻¹)(2ĴF − (2/3) Ī₁ cof F / J) + κ(J − 1) cof F`.
//!
//! Which elements are regular, without the SVD: the eigenvalues `σ₁² ≥ σ₂² ≥ σ₃²` of `C` give
//! `I₂(C) = σ₁²σ₂² + σ₂²σ₃² + σ₃²σ₁² ≥ σ₁²σ₂²`, so `σ₃² = J²/(σ₁²σ₂²) ≥ J²/I₂(C)`. Where
//! `J > 0` and `J² ≥ σ_min² I₂(C)` the smallest singular value is at least `σ_min`. The test is
//! conservative (at rest `J²/I₂ = 1/3` against `σ₃² = 1`): an element it turns away takes the
//! SVD path, which gives the same values there.

use super::mat3::M3;
use super::models::{Elastic, Model, SIGMA_MIN};
use crate::math::prelude::*;

#[inline(always)]
fn cross<S: Real>(a: [S; 3], b: [S; 3]) -> [S; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

/// `cof F = ∂(det F)/∂F`, by columns.
#[inline(always)]
fn cofactor<S: Real>(f: &M3<S>) -> M3<S> {
    let [a, b, c] = f.0;
    M3([cross(b, c), cross(c, a), cross(a, b)])
}

/// The linear model: `ε = ½(F + Fᵀ) − I`, `Ψ = μ ε:ε + (λ/2) tr²ε`, `P = 2με + λ tr ε I`.
pub fn linear<S: Real>(e: &Elastic, f: &M3<S>) -> (S, M3<S>) {
    let eps = f.add(&f.transpose()).scale(c(0.5)).add(&M3::identity().scale(-S::one()));
    let tr = eps.trace();
    let psi = S::from_f64(e.mu) * eps.ddot(&eps) + S::from_f64(0.5 * e.lambda) * tr * tr;
    (psi, eps.scale(S::from_f64(2.0 * e.mu)).add(&M3::identity().scale(S::from_f64(e.lambda) * tr)))
}

/// `Ψ(F)` (J/m³) and `P(F)` (Pa) of the isotropic models in closed form, or `None` where `F` is
/// not regular (an element near or past inversion: the caller takes the SVD path). The linear
/// model is always regular.
#[inline(always)]
pub fn closed_form<S: Real>(e: &Elastic, f: &M3<S>) -> Option<(S, M3<S>)> {
    if e.model == Model::Linear {
        return Some(linear(e, f));
    }
    let k = |v: f64| S::from_f64(v);
    let one = S::one();
    let cof = cofactor(f);
    let j = f.0[0][0] * cof.0[0][0] + f.0[0][1] * cof.0[0][1] + f.0[0][2] * cof.0[0][2];
    let cm = f.transpose().mul(f);
    let i1 = cm.trace();
    let cc = cm.ddot(&cm);
    let i2 = (i1 * i1 - cc) * k(0.5);
    if !(j > S::zero() && j * j >= k(SIGMA_MIN * SIGMA_MIN) * i2) {
        return None;
    }
    Some(match e.model {
        Model::Linear => linear(e, f),
        Model::StVK => {
            let strain = cm.add(&M3::identity().scale(-one)).scale(k(0.5));
            let tr = (i1 - k(3.0)) * k(0.5);
            let psi = k(e.mu) * strain.ddot(&strain) + k(0.5 * e.lambda) * tr * tr;
            let s = strain.scale(k(2.0 * e.mu)).add(&M3::identity().scale(k(e.lambda) * tr));
            (psi, f.mul(&s))
        }
        Model::NeoHookean => {
            let l = j.ln();
            let psi = k(0.5 * e.mu) * (i1 - k(3.0)) - k(e.mu) * l + k(0.5 * e.lambda) * l * l;
            (psi, f.scale(k(e.mu)).add(&cof.scale((k(e.lambda) * l - k(e.mu)) / j)))
        }
        Model::MooneyRivlin => {
            let jh = one / (j.cbrt() * j.cbrt());
            let jh2 = jh * jh;
            let a = i1 * i1 - cc;
            let jm = j - one;
            let psi = k(0.5 * e.mu01) * (a * jh2 - k(6.0)) + k(e.mu10) * (i1 * jh - k(3.0)) + k(e.nu1) * jm * jm;
            let da = f.scale(i1).add(&f.mul(&cm).scale(-one)).scale(k(4.0));
            let p = da
                .add(&cof.scale(-k(4.0 / 3.0) * a / j))
                .scale(k(0.5 * e.mu01) * jh2)
                .add(&f.scale(k(2.0)).add(&cof.scale(-k(2.0 / 3.0) * i1 / j)).scale(k(e.mu10) * jh))
                .add(&cof.scale(k(2.0 * e.nu1) * jm));
            (psi, p)
        }
        Model::ArrudaBoyce => {
            let jh = one / (j.cbrt() * j.cbrt());
            let ib = jh * i1;
            let jm = j - one;
            let (mut psi, mut dpsi, mut pow) = (k(0.5 * e.kappa) * jm * jm, S::zero(), one);
            for (n, alpha) in e.arruda_boyce_alphas().into_iter().enumerate() {
                let i = (n + 1) as f64;
                dpsi += k(i * alpha) * pow;
                pow = pow * ib;
                psi += k(alpha) * (pow - k(3f64.powi(n as i32 + 1)));
            }
            let dib = f.scale(k(2.0) * jh).add(&cof.scale(-k(2.0 / 3.0) * ib / j));
            (psi, dib.scale(dpsi).add(&cof.scale(k(e.kappa) * jm)))
        }
    })
}
