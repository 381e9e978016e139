//! Springs between two particles: Hookean and St. Venant–Kirchhoff (docs/algorithm.md §3, "2D").
//!
//! With `d = x₂ − x₁` and rest length `l₀`:
//! - Hookean: `E = ½ k (|d| − l₀)²`, `∇x₂ E = k (|d| − l₀) d/|d|`; compliant form
//!   `C = |d| − l₀`, `α = 1/k`.
//! - StVK: `E = ½ k (|d|² − l₀²)²`, `∇x₂ E = 2 k (|d|² − l₀²) d`; compliant form
//!   `C = |d|² − l₀²`, `α = 1/k`. Its small-strain stiffness is `4 k l₀²`, so a spring built from a
//!   small-strain constant `k_s` (N/m) stores `k = k_s / (4 l₀²)` (N/m³).
//!
//! `∇x₁ = −∇x₂` in every case. A zero-length spring has no direction: its gradient is zero and
//! the solver skips it for that iteration.

use bytemuck::{Pod, Zeroable};

use super::{Element, LANE_CONSTANTS, LaneWindow, Positions, Projection, simd};
use crate::math::prelude::*;

/// The spring energy model.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SpringMaterial {
    /// `E = ½ k (|d| − l₀)²`.
    #[default]
    Hookean,
    /// `E = ½ k (|d|² − l₀²)²`.
    StVK,
}

impl SpringMaterial {
    /// The per-spring constant `k` that gives the small-strain stiffness `k_s` (N/m) at rest
    /// length `l₀` (m): `k_s` for Hookean, `k_s / (4 l₀²)` for StVK.
    pub fn spring_constant(self, k_s: f32, rest: f32) -> f32 {
        match self {
            SpringMaterial::Hookean => k_s,
            SpringMaterial::StVK => k_s / (4.0 * rest * rest),
        }
    }
}

/// Parameters shared by every spring of a family.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SpringParams {
    /// The energy model.
    pub material: SpringMaterial,
}

/// One spring. Keep in sync with `Spring` in the WGSL sources.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Spring {
    /// First particle.
    pub a: u32,
    /// Second particle.
    pub b: u32,
    /// Rest length `l₀` in metres.
    pub rest: f32,
    /// Spring constant `k`: N/m (Hookean) or N/m³ (StVK).
    pub k: f32,
}

const _: () = assert!(std::mem::size_of::<Spring>() == 16);

impl Spring {
    /// A spring of small-strain stiffness `k_s` (N/m) for the given material.
    pub fn new(a: u32, b: u32, rest: f32, k_s: f32, material: SpringMaterial) -> Self {
        Spring { a, b, rest, k: material.spring_constant(k_s, rest) }
    }

    #[inline(always)]
    fn split<V: Vector>(&self, x: &[V; 2]) -> (V, V::S, V::S) {
        let d = x[1] - x[0];
        (d, d.length(), <V::S as From<f32>>::from(self.rest))
    }
}

impl Element<2> for Spring {
    type Params = SpringParams;

    #[inline(always)]
    fn particles(&self) -> [u32; 2] {
        [self.a, self.b]
    }

    #[inline(always)]
    fn energy<V: Vector>(&self, p: &SpringParams, x: &[V; 2]) -> V::S {
        let (_, len, l0) = self.split(x);
        let k: V::S = self.k.into();
        let half: V::S = c(0.5);
        match p.material {
            SpringMaterial::Hookean => half * k * (len - l0).powi(2),
            SpringMaterial::StVK => half * k * (len * len - l0 * l0).powi(2),
        }
    }

    #[inline(always)]
    fn energy_gradient<V: Vector>(&self, p: &SpringParams, x: &[V; 2]) -> [V; 2] {
        let (d, len, l0) = self.split(x);
        let k: V::S = self.k.into();
        let g = match p.material {
            SpringMaterial::Hookean => {
                if len <= tiny::<V::S>() {
                    return [V::ZERO; 2];
                }
                d * (k * (len - l0) / len)
            }
            SpringMaterial::StVK => d * (c::<V::S>(2.0) * k * (len * len - l0 * l0)),
        };
        [-g, g]
    }

    #[inline(always)]
    fn compliant<V: Vector>(&self, p: &SpringParams, x: &[V; 2]) -> Projection<V, 2> {
        let (d, len, l0) = self.split(x);
        let k: V::S = self.k.into();
        let alpha = V::S::one() / k;
        let (cv, g) = match p.material {
            SpringMaterial::Hookean => {
                let g = if len <= tiny::<V::S>() { V::ZERO } else { d * (V::S::one() / len) };
                (len - l0, g)
            }
            SpringMaterial::StVK => (len * len - l0 * l0, d * c::<V::S>(2.0)),
        };
        Projection { c: cv, grad: [-g, g], alpha }
    }

    /// Hookean: `C = |d| − l₀`, `∇C = ±d/|d|` so `Σ w|∇C|² = w_a + w_b`, and the correction
    /// `Δλ/|d|` scales `d` directly (one square root, one division on the dependency chain).
    #[inline(always)]
    fn project_plain<V: Vector, P: Positions<V> + ?Sized>(
        &self,
        p: &SpringParams,
        x: &mut P,
        w: &[V::S],
        lambda: &mut V::S,
        inv_h2: V::S,
        sor: V::S,
    ) -> bool {
        if p.material != SpringMaterial::Hookean {
            return false;
        }
        let (a, b) = (self.a as usize, self.b as usize);
        let (xa, xb) = (x.get(a), x.get(b));
        let (wa, wb) = (w[a], w[b]);
        let d = xb - xa;
        let len = d.dot_madd(d).sqrt();
        if len.is_nan() || len <= tiny::<V::S>() {
            return false;
        }
        let alpha_tilde = inv_h2 / <V::S as From<f32>>::from(self.k);
        let denom = wa + wb + alpha_tilde;
        if denom.is_nan() || denom <= c(1e-20) {
            return false;
        }
        let l0: V::S = self.rest.into();
        // One division on the dependency chain: `s = Δλ/|d|`, then `Δλ = s |d|`.
        let s = alpha_tilde.madd(-*lambda, l0 - len) * sor / (denom * len);
        *lambda = s.madd(len, *lambda);
        x.set(a, d.madd(-(wa * s), xa));
        x.set(b, d.madd(wb * s, xb));
        true
    }

    /// `[l₀, k]`.
    #[inline(always)]
    fn lane_constants(&self) -> [f32; LANE_CONSTANTS] {
        let mut c = [0.0; LANE_CONSTANTS];
        (c[0], c[1]) = (self.rest, self.k);
        c
    }

    const LANE_CONSTANT_COUNT: usize = 2;

    /// [`Spring::project_plain`] lane by lane, operation for operation.
    const PLAIN_WIDE: bool = true;

    #[inline(always)]
    fn project_plain_wide<V: Vector, P: Positions<V> + ?Sized>(
        lanes: LaneWindow<'_, 2>,
        p: &SpringParams,
        x: &mut P,
        lambda: &mut [V::S],
        inv_h2: V::S,
        sor: V::S,
        active: u32,
    ) -> u32 {
        use simd::{Lanes, madd};
        if p.material != SpringMaterial::Hookean {
            return active;
        }
        let [ia, ib] = lanes.at;
        let (xa, xb) = (simd::gather(x, ia), simd::gather(x, ib));
        let (wa, wb) = (simd::load(lanes.w[0]), simd::load(lanes.w[1]));
        let (l0, k) = (simd::load(lanes.consts[0]), simd::load(lanes.consts[1]));
        let d = xb - xa;
        let len = d.length_squared().sqrt();
        let alpha_tilde = Lanes::splat(inv_h2.to_f64() as f32) / k;
        let denom = wa + wb + alpha_tilde;
        let ok = len.simd_gt(Lanes::splat(1e-12)) & denom.simd_gt(Lanes::splat(1e-20));
        let lam = simd::lanes(lambda);
        let sor = Lanes::splat(sor.to_f64() as f32);
        let s = ok.select(madd(alpha_tilde, -lam, l0 - len) * sor / (denom * len), Lanes::ZERO);
        let mask = ok.to_bitmask() & active;
        simd::store_masked(lambda, madd(s, len, lam), mask);
        simd::scatter(x, ia, d.madd(-(wa * s), xa), mask);
        simd::scatter(x, ib, d.madd(wb * s, xb), mask);
        !mask & active
    }
}

/// Lengths below this are treated as zero (no direction).
#[inline(always)]
pub(crate) fn tiny<S: Real>() -> S {
    c(1e-12)
}
