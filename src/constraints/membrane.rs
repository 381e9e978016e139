//! Anisotropic continuum cloth: the orthotropic St. Venant–Kirchhoff triangle (Bender et al.
//! 2014; docs/algorithm.md §3).
//!
//! Each triangle has a rest frame aligned with the cloth's warp (`u`) and weft (`v`) directions:
//! `D_m = [X₁ − X₀, X₂ − X₀]` in material coordinates (m), `F = [x₁ − x₀, x₂ − x₀] D_m⁻¹` (3×2),
//! Green strain `E = ½(FᵀF − I)` in Voigt form `ε = (E_uu, E_vv, 2E_uv)`, energy density
//! `Ψ = ½ εᵀ C_orth ε` (J/m², moduli in N/m) and element energy `A₀ Ψ` (J). The second
//! Piola–Kirchhoff stress is `S = [[s₀, s₂], [s₂, s₁]]` with `s = C_orth ε`, the first `P = F S`,
//! and the gradient `[∇x₁ ∇x₂] = A₀ P D_m⁻ᵀ`, `∇x₀ = −∇x₁ − ∇x₂`. Compliant form: `C = √(2E/s)`,
//! `α = 1/s` with `s` the larger of the warp and weft moduli.
//!
//! Green strain does not see a triangle's orientation, so a flipped triangle is no special case;
//! a triangle collapsed to a segment or a point has finite energy and gradient.

use bytemuck::{Pod, Zeroable};
use glam::Vec2;

use super::{Element, Projection, energy_root};
use crate::error::{Error, Result};
use crate::math::prelude::*;

/// Orthotropic membrane moduli (2D, N/m) and the Poisson ratio `ν_uv`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orthotropic {
    /// Warp modulus `E_u` (N/m).
    pub warp: f64,
    /// Weft modulus `E_v` (N/m).
    pub weft: f64,
    /// Shear modulus `G` (N/m).
    pub shear: f64,
    /// Poisson ratio `ν_uv`; `ν_vu = ν_uv E_v / E_u`.
    pub poisson: f64,
}

impl Orthotropic {
    /// Moduli with the shear modulus defaulting to Huber's estimate `√(E_u E_v) / (2(1 + ν))`
    /// (the isotropic `E/(2(1+ν))` when `E_u = E_v`).
    pub fn new(warp: f64, weft: f64, shear: Option<f64>, poisson: f64) -> Result<Self> {
        let positive = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 { Ok(v) } else { Err(Error::param(name, v, "must be a positive finite N/m")) }
        };
        let (warp, weft) = (positive("--warp", warp)?, positive("--weft", weft)?);
        let shear = match shear {
            Some(g) => positive("--shear", g)?,
            None => (warp * weft).sqrt() / (2.0 * (1.0 + poisson.max(0.0))),
        };
        let o = Orthotropic { warp, weft, shear, poisson };
        let nu_vu = poisson * weft / warp;
        if !(poisson.is_finite() && poisson >= 0.0 && poisson * nu_vu < 1.0) {
            return Err(Error::param(
                "--poisson",
                format!("{poisson} (here the bound √(E_u/E_v) is {:.4})", (warp / weft).sqrt()),
                "ν_uv must be ≥ 0 and below √(E_u/E_v) for the orthotropic cloth (ν_vu = ν_uv E_v/E_u)",
            ));
        }
        Ok(o)
    }

    /// `C_orth` as `[c_uu, c_uv, c_vv, c_ss]` (N/m): `c_uu = E_u/(1 − ν_uv ν_vu)`,
    /// `c_uv = E_v ν_uv/(1 − ν_uv ν_vu)`, `c_vv = E_v/(1 − ν_uv ν_vu)`, `c_ss = G`.
    pub fn stiffness(&self) -> [f64; 4] {
        let nu_vu = self.poisson * self.weft / self.warp;
        let d = 1.0 - self.poisson * nu_vu;
        [self.warp / d, self.weft * self.poisson / d, self.weft / d, self.shear]
    }
}

/// Parameters shared by the membrane triangles of a family.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MembraneParams {
    /// The moduli.
    pub moduli: Orthotropic,
    /// `C_orth` entries `[c_uu, c_uv, c_vv, c_ss]` (N/m).
    pub c: [f64; 4],
    /// Stiffness scale `s` of the compliant form (N/m), `α = 1/s`: `max(E_u, E_v)`.
    pub scale: f64,
}

impl MembraneParams {
    /// The parameters of `moduli`.
    pub fn new(moduli: Orthotropic) -> Self {
        MembraneParams { moduli, c: moduli.stiffness(), scale: moduli.warp.max(moduli.weft) }
    }
}

/// One membrane triangle. Keep in sync with `Membrane` in `shaders/solver/membranes.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Membrane {
    /// Particles.
    pub p: [u32; 3],
    /// Rest area `A₀` (m²).
    pub area: f32,
    /// `D_m⁻¹` by columns (1/m).
    pub dm_inv: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<Membrane>() == 32);

impl Membrane {
    /// A triangle at rest with material (warp, weft) coordinates `uv` (m), or `None` when it is
    /// degenerate (zero area).
    pub fn at_rest(p: [u32; 3], uv: &[Vec2]) -> Option<Self> {
        let x = p.map(|i| uv[i as usize].as_dvec2());
        let (a, b) = (x[1] - x[0], x[2] - x[0]);
        let det = a.x * b.y - a.y * b.x;
        let scale = a.length_squared().max(b.length_squared());
        if det.is_nan() || det.abs() <= 1e-12 * scale {
            return None;
        }
        // Inverse of [[a.x, b.x], [a.y, b.y]], by columns.
        let inv = [b.y / det, -a.y / det, -b.x / det, a.x / det].map(|v| v as f32);
        Some(Membrane { p, area: (0.5 * det.abs()) as f32, dm_inv: inv })
    }

    /// The columns `f_u`, `f_v` of the deformation gradient at `x`.
    fn deformation<V: Vector>(&self, x: &[V; 3]) -> [V; 2] {
        let m = self.dm_inv.map(<V::S as From<f32>>::from);
        let (d1, d2) = (x[1] - x[0], x[2] - x[0]);
        [d1 * m[0] + d2 * m[1], d1 * m[2] + d2 * m[3]]
    }

    /// Voigt Green strain `(E_uu, E_vv, 2E_uv)` of columns `f`.
    fn strain<V: Vector>(f: &[V; 2]) -> [V::S; 3] {
        let half: V::S = c(0.5);
        [(f[0].dot(f[0]) - V::S::one()) * half, (f[1].dot(f[1]) - V::S::one()) * half, f[0].dot(f[1])]
    }

    /// `C_orth ε`.
    fn stress<S: Real>(p: &MembraneParams, e: [S; 3]) -> [S; 3] {
        let k = p.c.map(S::from_f64);
        [k[0] * e[0] + k[1] * e[1], k[1] * e[0] + k[2] * e[1], k[3] * e[2]]
    }
}

impl Element<3> for Membrane {
    type Params = MembraneParams;

    #[inline]
    fn particles(&self) -> [u32; 3] {
        self.p
    }

    fn energy<V: Vector>(&self, p: &MembraneParams, x: &[V; 3]) -> V::S {
        let e = Self::strain(&self.deformation(x));
        let s = Self::stress(p, e);
        let psi = (e[0] * s[0] + e[1] * s[1] + e[2] * s[2]) * c(0.5);
        <V::S as From<f32>>::from(self.area) * psi
    }

    fn energy_gradient<V: Vector>(&self, p: &MembraneParams, x: &[V; 3]) -> [V; 3] {
        let f = self.deformation(x);
        let s = Self::stress(p, Self::strain(&f));
        // P = F S by columns.
        let (pu, pv) = (f[0] * s[0] + f[1] * s[2], f[0] * s[2] + f[1] * s[1]);
        let m = self.dm_inv.map(<V::S as From<f32>>::from);
        let a: V::S = self.area.into();
        let g1 = (pu * m[0] + pv * m[2]) * a;
        let g2 = (pu * m[1] + pv * m[3]) * a;
        [-(g1 + g2), g1, g2]
    }

    fn compliant<V: Vector>(&self, p: &MembraneParams, x: &[V; 3]) -> Projection<V, 3> {
        energy_root(self.energy(p, x), || self.energy_gradient(p, x), p.scale)
    }
}
