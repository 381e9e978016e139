//! The five 3D elastic models of docs/algorithm.md §3, as energy densities `Ψ(F)` (J/m³) and first
//! Piola–Kirchhoff stresses `P = ∂Ψ/∂F` (Pa).
//!
//! Parameters come from Young's modulus `E` and Poisson's ratio `ν`: Lamé `μ = E/(2(1+ν))`,
//! `λ = Eν/((1+ν)(1−2ν))`, bulk `κ = λ + 2μ/3`.
//!
//! - Linear: `ε = ½(F + Fᵀ) − I`, `Ψ = μ ε:ε + (λ/2) tr²ε`, `P = 2μ ε + λ tr(ε) I`. Not invariant
//!   under rotation (a rotated rest shape has energy); only translation invariant and, to first
//!   order, insensitive to infinitesimal rotations.
//! - StVK: `Ψ = μ E:E + (λ/2) tr²E`, `E = ½(FᵀF − I)`.
//! - Neo-Hookean: `Ψ = (μ/2)(I₁ − log I₃ − 3) + (λ/8) log² I₃`.
//! - Mooney-Rivlin (Sin, Schroeder, Barbič 2013): `Ψ = (μ₀₁/2)((I₁² − I₂)/I₃^{2/3} − 6)
//!   + μ₁₀ (I₁/I₃^{1/3} − 3) + ν₁ (I₃^{1/2} − 1)²` with `μ₁₀ = μ₀₁ = μ/4` (small-strain shear
//!   modulus `2(μ₁₀ + μ₀₁) = μ`) and `ν₁ = κ/2`.
//! - Arruda-Boyce: `Ψ = Σᵢ αᵢ (Ī₁ⁱ − 3ⁱ) + (κ/2)(J − 1)²`, `Ī₁ = J^{−2/3} I₁`,
//!   `αᵢ = μ_AB Cᵢ / λ_m^{2i−2}`, `C = (1/2, 1/20, 11/1050, 19/7000, 519/673750)`, `λ_m = 2.8`,
//!   and `μ_AB = μ / (1 + 3/(5λ_m²) + 99/(175λ_m⁴) + 513/(875λ_m⁶) + 42039/(67375λ_m⁸))` so the
//!   initial shear modulus is `μ`.
//!
//! Inversion handling for all but the linear model: the energy is a symmetric function `Ψ̂(σ)`
//! of the signed singular values of `F` (negative smallest one when `det F < 0`, see
//! [`mod@super::svd`]); below `σ_min = 0.15` it is continued from the clamped values
//! `σ̂ = max(σ, σ_min)` (after Stomakhin et al. 2012) with `δ = σ − σ̂ ≤ 0`:
//! `Ψ(σ) = Ψ̂(σ̂) + Σ_k [min(ĝ_k, 0) δ_k + ½ κ_inv δ_k²]`, `ĝ = ∇Ψ̂(σ̂)`,
//! `κ_inv = 3 (λ + 2μ)` ([`INVERSION_STIFFNESS`] times the P-wave modulus, the curvature every
//! model has at rest along one axis). Energy and stress stay consistent (`P = U diag(∂Ψ/∂σ) Vᵀ`
//! is the exact derivative), the energy is bounded below, and an inverted element's restoring
//! force grows with the depth of the inversion. The quadratic term is what lets a tangled body
//! recover: with the first-order continuation alone `√Ψ` is concave there, so the compliant
//! form's Newton step overshoots twofold and Gauss-Seidel keeps a tangled body churning
//! (docs/stability/README.md). The `min(ĝ_k, 0)` keeps the continuation from rewarding inversion
//! where the other axes are stretched (`ĝ_k > 0` once `J = σ₁σ₂σ_min` exceeds about 1.9 for
//! Neo-Hookean at ν = 0.3), which otherwise lets an element run away inverted.

use super::hyperdual::Hd;
use super::invariants::{closed_form, linear};
use super::mat3::M3;
use super::svd::svd;
use crate::error::{Error, Result};
use crate::math::prelude::*;

/// A 3D elastic model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// Linear (small-strain) elasticity.
    Linear,
    /// St. Venant–Kirchhoff.
    StVK,
    /// Neo-Hookean.
    NeoHookean,
    /// Mooney-Rivlin.
    MooneyRivlin,
    /// Arruda-Boyce.
    ArrudaBoyce,
}

impl Model {
    /// All models, in documentation order.
    pub const ALL: [Model; 5] =
        [Model::Linear, Model::StVK, Model::NeoHookean, Model::MooneyRivlin, Model::ArrudaBoyce];
}

crate::error::command_names!(Model, "3D material", {
    Linear => "linear",
    StVK => "stvk",
    NeoHookean => "neo-hookean",
    MooneyRivlin => "mooney-rivlin",
    ArrudaBoyce => "arruda-boyce",
});

/// Singular values below this use the inversion extension.
pub const SIGMA_MIN: f64 = 0.15;
/// The inversion continuation's curvature `κ_inv` as a multiple of the P-wave modulus `λ + 2μ`
/// (dimensionless). Chosen with the stability study's Neo-Hookean bunny (docs/stability/README.md):
/// at 1 a body stays tangled after random 100 m/s velocities or a 1/5 s step; 2 and 3 recover
/// every case on both backends; from 4 up one backend or the other leaves a few tetrahedra
/// flattened on the ground or the mirrored cube still tangled at 3 s.
pub const INVERSION_STIFFNESS: f64 = 3.0;

/// Arruda-Boyce's locking stretch `λ_m` by default.
pub const ARRUDA_BOYCE_LOCKING: f64 = 2.8;

const AB_C: [f64; 5] = [0.5, 1.0 / 20.0, 11.0 / 1050.0, 19.0 / 7000.0, 519.0 / 673750.0];

/// A model with its constants (Pa).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Elastic {
    /// The model.
    pub model: Model,
    /// Lamé `μ` (Pa).
    pub mu: f64,
    /// Lamé `λ` (Pa).
    pub lambda: f64,
    /// Bulk modulus `κ = λ + 2μ/3` (Pa).
    pub kappa: f64,
    /// Mooney-Rivlin `μ₁₀` (Pa).
    pub mu10: f64,
    /// Mooney-Rivlin `μ₀₁` (Pa).
    pub mu01: f64,
    /// Mooney-Rivlin `ν₁` (Pa).
    pub nu1: f64,
    /// Arruda-Boyce `μ_AB` (Pa).
    pub mu_ab: f64,
    /// Arruda-Boyce `λ_m`.
    pub lambda_m: f64,
    /// Arruda-Boyce `αᵢ = μ_AB Cᵢ / λ_m^{2i−2}`, `i = 1..5` (Pa), computed once here rather than
    /// in every projection.
    alphas: [f64; 5],
    /// Curvature of the inversion continuation `κ_inv = INVERSION_STIFFNESS (λ + 2μ)` (Pa).
    pub inversion_stiffness: f64,
}

impl Elastic {
    /// `model` with Young's modulus `young` (Pa) and Poisson's ratio `poisson`.
    pub fn new(model: Model, young: f64, poisson: f64) -> Result<Self> {
        if !(young.is_finite() && young > 0.0) {
            return Err(Error::param("--young", young, "must be a positive finite modulus in Pa"));
        }
        if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
            return Err(Error::param("--poisson", poisson, "must be in (-1, 0.5)"));
        }
        let mu = young / (2.0 * (1.0 + poisson));
        let lambda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
        let kappa = lambda + 2.0 * mu / 3.0;
        let lm = ARRUDA_BOYCE_LOCKING;
        let l2 = lm * lm;
        let mu_ab = mu
            / (1.0
                + 3.0 / (5.0 * l2)
                + 99.0 / (175.0 * l2 * l2)
                + 513.0 / (875.0 * l2 * l2 * l2)
                + 42039.0 / (67375.0 * l2 * l2 * l2 * l2));
        let mut alphas = [0.0; 5];
        for (i, (o, c_i)) in alphas.iter_mut().zip(AB_C).enumerate() {
            *o = mu_ab * c_i / lm.powi(2 * i as i32);
        }
        let (mu10, mu01, nu1) = (mu / 4.0, mu / 4.0, kappa / 2.0);
        let inversion_stiffness = INVERSION_STIFFNESS * (lambda + 2.0 * mu);
        Ok(Elastic { model, mu, lambda, kappa, mu10, mu01, nu1, mu_ab, lambda_m: lm, alphas, inversion_stiffness })
    }

    /// What a user should know of this material before running it, if anything: Neo-Hookean with
    /// `ν < 0` has `λ < 0`, and its energy `μ/2 (I₁ − 3) − μ ln J + λ/2 (ln J)²` then has no lower
    /// bound as `J → 0` (the `(ln J)²` term outgrows `−μ ln J`), so a strongly compressed body
    /// can collapse into itself (the cube at `ν = −0.9` does, its total energy falling to
    /// −2·10⁵ J). The other models keep a lower bound at every `ν` in `(−1, 0.5)`: their
    /// volumetric parts rest on the bulk modulus `κ = λ + 2μ/3`, positive there.
    pub fn caveat(&self) -> Option<String> {
        (self.model == Model::NeoHookean && self.lambda < 0.0).then(|| {
            let nu = self.lambda / (2.0 * (self.lambda + self.mu));
            format!(
                "neo-hookean at --poisson {nu:.3} has a negative Lamé λ ({:.3e} Pa): its energy has no lower \
                 bound under strong compression, and a compressed body may collapse into itself; stvk, linear, \
                 mooney-rivlin and arruda-boyce hold at any Poisson's ratio",
                self.lambda
            )
        })
    }

    /// Arruda-Boyce's `αᵢ = μ_AB Cᵢ / λ_m^{2i−2}` for `i = 1..5` (Pa).
    pub fn arruda_boyce_alphas(&self) -> [f64; 5] {
        self.alphas
    }

    /// `Ψ̂(σ)` with derivatives, for the isotropic models (positive `σ`).
    fn psi_hat<S: Real>(&self, s: [Hd<S>; 3]) -> Hd<S> {
        let k = |v: f64| S::from_f64(v);
        let one = S::one();
        let sq = [s[0] * s[0], s[1] * s[1], s[2] * s[2]];
        let i1 = sq[0] + sq[1] + sq[2];
        match self.model {
            Model::Linear | Model::StVK => {
                let e = sq.map(|q| (q + (-one)) * k(0.5));
                let tr = e[0] + e[1] + e[2];
                (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) * k(self.mu) + tr * tr * k(0.5 * self.lambda)
            }
            Model::NeoHookean => {
                let l = s[0].ln() + s[1].ln() + s[2].ln();
                (i1 + k(-3.0)) * k(0.5 * self.mu) - l * k(self.mu) + l * l * k(0.5 * self.lambda)
            }
            Model::MooneyRivlin => {
                let j = s[0] * s[1] * s[2];
                let i2 = sq[0] * sq[0] + sq[1] * sq[1] + sq[2] * sq[2];
                let a = i1 * i1 - i2;
                let jm = j - Hd::constant(one);
                (a * j.powf(k(-4.0 / 3.0)) + k(-6.0)) * k(0.5 * self.mu01)
                    + (i1 * j.powf(k(-2.0 / 3.0)) + k(-3.0)) * k(self.mu10)
                    + jm * jm * k(self.nu1)
            }
            Model::ArrudaBoyce => {
                let j = s[0] * s[1] * s[2];
                let ib = i1 * j.powf(k(-2.0 / 3.0));
                let mut psi = Hd::constant(S::zero());
                for (n, alpha) in self.arruda_boyce_alphas().into_iter().enumerate() {
                    let i = n as u32 + 1;
                    psi = psi + (ib.powi(i) + k(-(3f64.powi(i as i32)))) * k(alpha);
                }
                let jm = j - Hd::constant(one);
                psi + jm * jm * k(0.5 * self.kappa)
            }
        }
    }

    /// `Ψ(σ)` and `∂Ψ/∂σ` with the inversion continuation below `σ_min` (module docs):
    /// `Ψ = Ψ̂(σ̂) + Σ_k [min(ĝ_k, 0) δ_k + ½ κ_inv δ_k²]`. Along a clamped axis the derivative is
    /// `min(ĝ_k, 0) + κ_inv δ_k`; along a free axis `ĝ_j + Σ_k ∂ĝ_k/∂σ_j δ_k` over the clamped
    /// `k` with `ĝ_k < 0`.
    fn extended<S: Real>(&self, sigma: [S; 3]) -> (S, [S; 3]) {
        let smin = S::from_f64(SIGMA_MIN);
        let kappa = S::from_f64(self.inversion_stiffness);
        let half = S::from_f64(0.5);
        let clamped = sigma.map(|x| x.max(smin));
        let h = self.psi_hat([0, 1, 2].map(|i| Hd::var(i, clamped[i])));
        let delta = [0, 1, 2].map(|i| sigma[i] - clamped[i]);
        // The clamped axes whose slope counts (ĝ_k < 0), and that slope (0 for the others).
        let pulls = [0, 1, 2].map(|k| delta[k] != S::zero() && h.g[k] < S::zero());
        let mut psi = h.v;
        let mut grad = h.g;
        for k in 0..3 {
            if delta[k] != S::zero() {
                let slope = if pulls[k] { h.g[k] } else { S::zero() };
                psi += (slope + half * kappa * delta[k]) * delta[k];
                grad[k] = slope + kappa * delta[k];
            } else {
                for i in (0..3).filter(|&i| pulls[i]) {
                    grad[k] += h.h[i][k] * delta[i];
                }
            }
        }
        (psi, grad)
    }

    /// Energy density `Ψ(F)` (J/m³).
    pub fn energy_density<S: Real>(&self, f: &M3<S>) -> S {
        self.energy_stress(f).0
    }

    /// First Piola–Kirchhoff stress `P(F) = ∂Ψ/∂F` (Pa).
    pub fn stress<S: Real>(&self, f: &M3<S>) -> M3<S> {
        self.energy_stress(f).1
    }

    /// `Ψ(F)` (J/m³) and `P(F)` (Pa) together: in closed form from the invariants of `F` where
    /// `det F > 0` and every singular value is at least `σ_min` ([`mod@super::invariants`]), else
    /// from the signed SVD ([`Elastic::reference`]).
    #[inline]
    pub fn energy_stress<S: Real>(&self, f: &M3<S>) -> (S, M3<S>) {
        closed_form(self, f).unwrap_or_else(|| self.reference(f))
    }

    /// `Ψ(F)` and `P(F)` by the generic path: the signed SVD of `F`, the energy `Ψ̂(σ)` with its
    /// derivatives by forward differentiation, the inversion extension below `σ_min` and
    /// `P = U diag(∂Ψ/∂σ) Vᵀ` (the linear model in its closed form). The reference the closed
    /// forms are tested against; valid for every `F`.
    pub fn reference<S: Real>(&self, f: &M3<S>) -> (S, M3<S>) {
        match self.model {
            Model::Linear => linear(self, f),
            _ => {
                let d = svd(f);
                let (psi, g) = self.extended(d.sigma);
                (psi, d.compose(g))
            }
        }
    }
}
