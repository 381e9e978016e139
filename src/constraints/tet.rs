//! Tetrahedral elements with the 3D elastic models of [`crate::material`] (docs/algorithm.md §3).
//!
//! Particles `[x₀, x₁, x₂, x₃]`; `D_s = [x₁ − x₀, x₂ − x₀, x₃ − x₀]`, `F = D_s D_m⁻¹`, energy
//! `E = V₀ Ψ(F)` (J), gradient `[∇x₁ ∇x₂ ∇x₃] = V₀ P(F) D_m⁻ᵀ`, `∇x₀ = −Σ`. Compliant form:
//! `C = √(2 V₀ Ψ / s)` with `α = 1/s` for the stiffness scale `s` (Young's modulus, Pa), so
//! `E = C²/(2α)`; `∇C = ∇E / (s C)`, and the element is skipped for the iteration when `C`
//! vanishes (at rest, where its gradient is undefined).

use bytemuck::{Pod, Zeroable};

use super::{Element, Form, LANE_CONSTANTS, LaneWindow, Positions, Projection, energy_root, simd};
use crate::material::{Elastic, M3, Model, SIGMA_MIN};
use crate::math::prelude::*;

/// Parameters shared by the tetrahedra of a family.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TetParams {
    /// The model and its constants.
    pub elastic: Elastic,
    /// Stiffness scale `s` of the compliant form (Pa), `α = 1/s`.
    pub scale: f64,
}

/// One tetrahedron. Keep in sync with `Tet` in the WGSL sources.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Tet {
    /// Particles.
    pub p: [u32; 4],
    /// `D_m⁻¹` by columns.
    pub dm_inv: [f32; 9],
    /// Rest volume `V₀` (m³).
    pub volume: f32,
    /// Padding.
    pub pad: [u32; 2],
}

const _: () = assert!(std::mem::size_of::<Tet>() == 64);

impl Tet {
    /// A tetrahedron at rest at positions `x`, or `None` when it is degenerate (zero volume).
    pub fn at_rest(p: [u32; 4], x: &[glam::Vec3]) -> Option<Self> {
        let xs = p.map(|i| x[i as usize].as_dvec3());
        let dm = M3::from_cols(xs[1] - xs[0], xs[2] - xs[0], xs[3] - xs[0]);
        let volume = dm.det() / 6.0;
        let inv = dm.inverse()?;
        if volume.abs() < 1e-15 {
            return None;
        }
        let mut dm_inv = [0.0f32; 9];
        for c in 0..3 {
            for r in 0..3 {
                dm_inv[3 * c + r] = inv.0[c][r] as f32;
            }
        }
        Some(Tet { p, dm_inv, volume: volume.abs() as f32, pad: [0; 2] })
    }

    fn dm_inv<S: Real>(&self) -> M3<S> {
        let mut m = M3::zero();
        for c in 0..3 {
            for r in 0..3 {
                m.0[c][r] = self.dm_inv[3 * c + r].into();
            }
        }
        m
    }

    /// Energy `V₀ Ψ(F)` (J) and its gradient (N) at `x`, from one evaluation of the model
    /// ([`Elastic::energy_stress`](crate::material::Elastic::energy_stress)).
    #[inline(always)]
    pub fn energy_and_gradient<V: Vector>(&self, p: &TetParams, x: &[V; 4]) -> (V::S, [V; 4]) {
        let dm_inv = self.dm_inv::<V::S>();
        let f = M3::from_cols(x[1] - x[0], x[2] - x[0], x[3] - x[0]).mul(&dm_inv);
        let (psi, stress) = p.elastic.energy_stress(&f);
        let volume: V::S = self.volume.into();
        let h = stress.mul(&dm_inv.transpose()).scale(volume);
        let (g1, g2, g3) = (h.col::<V>(0), h.col::<V>(1), h.col::<V>(2));
        (volume * psi, [-(g1 + g2 + g3), g1, g2, g3])
    }

    /// The deformation gradient at `x`.
    pub fn deformation<V: Vector>(&self, x: &[V; 4]) -> M3<V::S> {
        M3::from_cols(x[1] - x[0], x[2] - x[0], x[3] - x[0]).mul(&self.dm_inv())
    }
}

impl Element<4> for Tet {
    type Params = TetParams;

    #[inline]
    fn particles(&self) -> [u32; 4] {
        self.p
    }

    fn energy<V: Vector>(&self, p: &TetParams, x: &[V; 4]) -> V::S {
        <V::S as From<f32>>::from(self.volume) * p.elastic.energy_density(&self.deformation(x))
    }

    fn energy_gradient<V: Vector>(&self, p: &TetParams, x: &[V; 4]) -> [V; 4] {
        self.energy_and_gradient(p, x).1
    }

    /// Both forms from one evaluation of the model ([`Tet::energy_and_gradient`]).
    #[inline(always)]
    fn constraint<V: Vector>(
        &self,
        p: &TetParams,
        x: &[V; 4],
        form: Form,
        energy_compliance: V::S,
    ) -> Projection<V, 4> {
        match form {
            Form::Energy => {
                let (e, grad) = self.energy_and_gradient(p, x);
                Projection { c: e, grad, alpha: energy_compliance }
            }
            Form::Compliant => self.compliant(p, x),
        }
    }

    #[inline(always)]
    fn compliant<V: Vector>(&self, p: &TetParams, x: &[V; 4]) -> Projection<V, 4> {
        let (e, grad) = self.energy_and_gradient(p, x);
        energy_root(e, || grad, p.scale)
    }

    /// `D_m⁻¹` by columns, then `V₀`.
    #[inline(always)]
    fn lane_constants(&self) -> [f32; LANE_CONSTANTS] {
        let mut c = [0.0; LANE_CONSTANTS];
        c[..9].copy_from_slice(&self.dm_inv);
        c[9] = self.volume;
        c
    }

    const LANE_CONSTANT_COUNT: usize = 10;

    const PLAIN_WIDE: bool = true;

    /// [`super::SIMD_WIDTH`] regular tetrahedra of one color group (every model) projected at
    /// once, one per lane, in the compliant form above with the closed forms of
    /// [`crate::material::invariants`] (the same formulas; `ln` and `exp` are `wide`'s, so a lane
    /// agrees with the general update within rounding, not bit for bit: `tests/kernels.rs`). A
    /// lane is declined, and its element left to the general update, where the element is not
    /// regular (`J ≤ 0` or `J² < σ_min² I₂(C)`; the linear model is regular everywhere), its
    /// constraint vanishes, or the denominator does. The team's shares and the one-thread sweep
    /// batch a group alike (whole batches from the group's start, the last one partial), so
    /// which elements take this kernel does not depend on the thread count.
    #[inline(always)]
    fn project_plain_wide<V: Vector, P: Positions<V> + ?Sized>(
        lanes: LaneWindow<'_, 4>,
        p: &TetParams,
        x: &mut P,
        lambda: &mut [V::S],
        inv_h2: V::S,
        sor: V::S,
        active: u32,
    ) -> u32 {
        use simd::{Lanes, V3, madd};
        /// `a · s` for a 3-vector of lanes.
        #[inline(always)]
        fn mul(a: V3, s: Lanes) -> V3 {
            a * s
        }
        let e = &p.elastic;
        let k = |v: f64| Lanes::splat(v as f32);
        let at = lanes.at;
        let xs = [simd::gather(x, at[0]), simd::gather(x, at[1]), simd::gather(x, at[2]), simd::gather(x, at[3])];
        let ws = lanes.w.map(simd::load);
        let m: [Lanes; 9] = std::array::from_fn(|i| simd::load(lanes.consts[i]));
        let volume = simd::load(lanes.consts[9]);
        let d = [xs[1] - xs[0], xs[2] - xs[0], xs[3] - xs[0]];
        // F = D_s D_m⁻¹ by columns (D_m⁻¹ by columns: m[3c + r] is row r of column c).
        let f: [V3; 3] =
            std::array::from_fn(|c| mul(d[0], m[3 * c]) + mul(d[1], m[3 * c + 1]) + mul(d[2], m[3 * c + 2]));
        let cof = [f[1].cross(f[2]), f[2].cross(f[0]), f[0].cross(f[1])];
        let j = f[0].dot(cof[0]);
        // C = FᵀF, C_ab = f_a · f_b.
        let (c00, c11, c22) = (f[0].dot(f[0]), f[1].dot(f[1]), f[2].dot(f[2]));
        let (c01, c02, c12) = (f[0].dot(f[1]), f[0].dot(f[2]), f[1].dot(f[2]));
        let i1 = c00 + c11 + c22;
        let cc = c00 * c00 + c11 * c11 + c22 * c22 + k(2.0) * (c01 * c01 + c02 * c02 + c12 * c12);
        let i2 = (i1 * i1 - cc) * k(0.5);
        let mut ok = match e.model {
            Model::Linear => Lanes::ONE.simd_gt(Lanes::ZERO),
            _ => j.simd_gt(Lanes::ZERO) & (j * j).simd_ge(k(SIGMA_MIN * SIGMA_MIN) * i2),
        };
        let (psi, stress) = match e.model {
            Model::Linear => {
                // ε = ½(F + Fᵀ) − I, Ψ = μ ε:ε + (λ/2) tr²ε, P = 2με + λ tr ε I (F_rc: row r of f[c]).
                let fm = f.map(|v| [v.x, v.y, v.z]);
                let eps: [[Lanes; 3]; 3] = std::array::from_fn(|r| {
                    std::array::from_fn(|c| {
                        (fm[c][r] + fm[r][c]) * k(0.5) - if r == c { Lanes::ONE } else { Lanes::ZERO }
                    })
                });
                let tr = eps[0][0] + eps[1][1] + eps[2][2];
                let mut ee = Lanes::ZERO;
                for row in &eps {
                    for v in row {
                        ee += *v * *v;
                    }
                }
                let psi = k(e.mu) * ee + k(0.5 * e.lambda) * tr * tr;
                let (two_mu, diag) = (k(2.0 * e.mu), k(e.lambda) * tr);
                let p = |r: usize, c: usize| two_mu * eps[r][c] + if r == c { diag } else { Lanes::ZERO };
                (psi, std::array::from_fn::<V3, 3, _>(|c| V3 { x: p(0, c), y: p(1, c), z: p(2, c) }))
            }
            Model::NeoHookean => {
                // Ψ = (μ/2)(I₁ − 3) − μ log J + (λ/2) log² J, P = μF + (λ log J − μ) cof F / J.
                let l = ok.select(j, Lanes::ONE).ln();
                let psi = k(0.5 * e.mu) * (i1 - k(3.0)) - k(e.mu) * l + k(0.5 * e.lambda) * l * l;
                let s = (k(e.lambda) * l - k(e.mu)) / j;
                (psi, std::array::from_fn::<V3, 3, _>(|c| mul(f[c], k(e.mu)) + mul(cof[c], s)))
            }
            Model::MooneyRivlin | Model::ArrudaBoyce => {
                // Ĵ = J^{−2/3} = exp(−⅔ log J).
                let jh = (ok.select(j, Lanes::ONE).ln() * k(-2.0 / 3.0)).exp();
                let jm = j - Lanes::ONE;
                if e.model == Model::MooneyRivlin {
                    // Ψ = (μ₀₁/2)(a Ĵ² − 6) + μ₁₀(I₁ Ĵ − 3) + ν₁(J − 1)², a = I₁² − C:C;
                    // P = (μ₀₁/2) Ĵ² (4(I₁F − FC) − (4/3) a cof F / J) + μ₁₀ Ĵ (2F − (2/3) I₁ cof F / J)
                    //   + 2ν₁(J − 1) cof F.
                    let jh2 = jh * jh;
                    let a = i1 * i1 - cc;
                    let psi =
                        k(0.5 * e.mu01) * (a * jh2 - k(6.0)) + k(e.mu10) * (i1 * jh - k(3.0)) + k(e.nu1) * jm * jm;
                    let cm = [[c00, c01, c02], [c01, c11, c12], [c02, c12, c22]];
                    let (ta, tb) = (k(4.0 / 3.0) * a / j, k(2.0 / 3.0) * i1 / j);
                    let (wa, wb, wc) = (k(0.5 * e.mu01) * jh2, k(e.mu10) * jh, k(2.0 * e.nu1) * jm);
                    let stress = std::array::from_fn::<V3, 3, _>(|c| {
                        let fc = mul(f[0], cm[0][c]) + mul(f[1], cm[1][c]) + mul(f[2], cm[2][c]);
                        let da = mul(mul(f[c], i1) - fc, k(4.0));
                        mul(da - mul(cof[c], ta), wa) + mul(mul(f[c], k(2.0)) - mul(cof[c], tb), wb) + mul(cof[c], wc)
                    });
                    (psi, stress)
                } else {
                    // Ī₁ = Ĵ I₁, Ψ = Σᵢ αᵢ(Ī₁ⁱ − 3ⁱ) + (κ/2)(J − 1)²,
                    // P = (Σᵢ i αᵢ Ī₁ⁱ⁻¹)(2ĴF − (2/3) Ī₁ cof F / J) + κ(J − 1) cof F.
                    let ib = jh * i1;
                    let (mut psi, mut dpsi, mut pow) = (k(0.5 * e.kappa) * jm * jm, Lanes::ZERO, Lanes::ONE);
                    for (n, alpha) in e.arruda_boyce_alphas().into_iter().enumerate() {
                        dpsi += k((n + 1) as f64 * alpha) * pow;
                        pow *= ib;
                        psi += k(alpha) * (pow - k(3f64.powi(n as i32 + 1)));
                    }
                    let (t, wk) = (k(2.0 / 3.0) * ib / j, k(e.kappa) * jm);
                    let stress = std::array::from_fn::<V3, 3, _>(|c| {
                        mul(mul(f[c], k(2.0) * jh) - mul(cof[c], t), dpsi) + mul(cof[c], wk)
                    });
                    (psi, stress)
                }
            }
            _ => {
                // StVK: E = ½(C − I), S = 2μE + λ tr E I, Ψ = μ E:E + (λ/2) tr²E, P = F S.
                let half = k(0.5);
                let (e00, e11, e22) = ((c00 - Lanes::ONE) * half, (c11 - Lanes::ONE) * half, (c22 - Lanes::ONE) * half);
                let (e01, e02, e12) = (c01 * half, c02 * half, c12 * half);
                let tr = (i1 - k(3.0)) * half;
                let ee = e00 * e00 + e11 * e11 + e22 * e22 + k(2.0) * (e01 * e01 + e02 * e02 + e12 * e12);
                let psi = k(e.mu) * ee + k(0.5 * e.lambda) * tr * tr;
                let (two_mu, diag) = (k(2.0 * e.mu), k(e.lambda) * tr);
                let s = [
                    [two_mu * e00 + diag, two_mu * e01, two_mu * e02],
                    [two_mu * e01, two_mu * e11 + diag, two_mu * e12],
                    [two_mu * e02, two_mu * e12, two_mu * e22 + diag],
                ];
                (psi, std::array::from_fn::<V3, 3, _>(|c| mul(f[0], s[0][c]) + mul(f[1], s[1][c]) + mul(f[2], s[2][c])))
            }
        };
        // ∇E = V₀ P D_m⁻ᵀ by columns (particles 1..3), particle 0 the negative sum.
        let h: [V3; 3] = std::array::from_fn(|c| {
            mul(mul(stress[0], m[c]) + mul(stress[1], m[3 + c]) + mul(stress[2], m[6 + c]), volume)
        });
        let g = [-(h[0] + h[1] + h[2]), h[0], h[1], h[2]];
        // Compliant form: C = √(2E/s), ∇C = ∇E/(s C), α̃ = 1/(s h²).
        let scale = k(p.scale);
        let cval = (k(2.0) * (volume * psi).max(Lanes::ZERO) / scale).sqrt();
        ok &= cval.simd_gt(k(1e-12));
        let kc = Lanes::ONE / (scale * cval);
        let sum = (ws[0] * g[0].length_squared()
            + ws[1] * g[1].length_squared()
            + ws[2] * g[2].length_squared()
            + ws[3] * g[3].length_squared())
            * (kc * kc);
        let alpha_tilde = Lanes::splat(inv_h2.to_f64() as f32) / scale;
        let denom = sum + alpha_tilde;
        ok &= denom.simd_gt(k(1e-20));
        let lam = simd::lanes(lambda);
        let sor = Lanes::splat(sor.to_f64() as f32);
        let dl = ok.select(madd(alpha_tilde, -lam, -cval) / denom * sor, Lanes::ZERO);
        let mask = ok.to_bitmask() & active;
        simd::store_masked(lambda, lam + dl, mask);
        for n in 0..4 {
            simd::scatter(x, at[n], g[n].madd(ws[n] * kc * dl, xs[n]), mask);
        }
        !mask & active
    }
}
