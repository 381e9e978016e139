//! Dihedral bending between two triangles sharing an edge (Müller et al. 2007, with the signed
//! angle of Bridson et al. 2003 so the gradient is defined at the flat rest state).
//!
//! Particles `[x₀, x₁, x₂, x₃]`: the shared edge is `x₀ → x₁`, `x₂` is the wing of triangle
//! `(x₀, x₁, x₂)` and `x₃` the wing of triangle `(x₁, x₀, x₃)` (both consistently oriented).
//! With `e = x₁ − x₀`, `n₁ = e × (x₂ − x₀)`, `n₂ = (x₃ − x₀) × e`:
//!
//! `θ = atan2((n₁ × n₂)·ê, n₁·n₂)` (0 when flat), `E = ½ k_b (θ − θ₀)²` with `k_b` in N·m/rad.
//!
//! Gradient of θ: `∇x₂ θ = −|e| n₁/|n₁|²`, `∇x₃ θ = −|e| n₂/|n₂|²`, and with the wings' positions
//! along the edge `tᵢ = (xᵢ − x₀)·e/|e|²`: `∇x₀ θ = −(1 − t₂)∇x₂ θ − (1 − t₃)∇x₃ θ`,
//! `∇x₁ θ = −t₂ ∇x₂ θ − t₃ ∇x₃ θ`. Compliant form: `C = θ − θ₀`, `α = 1/k_b`.
//! A degenerate triangle or edge gives a zero gradient (skipped for that iteration).

use bytemuck::{Pod, Zeroable};

use super::spring::tiny;
use super::{Element, LANE_CONSTANTS, LaneWindow, Positions, Projection, simd};
use crate::math::prelude::*;

/// Parameters shared by all bending elements (none yet: stiffness is per element).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct BendParams;

/// One bending element. Keep in sync with `Bend` in the WGSL sources.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Bend {
    /// `[x₀, x₁, x₂, x₃]`: shared edge, then the two wings.
    pub p: [u32; 4],
    /// Rest dihedral angle `θ₀` in radians.
    pub rest_angle: f32,
    /// Bending stiffness `k_b` in N·m/rad.
    pub k: f32,
}

const _: () = assert!(std::mem::size_of::<Bend>() == 24);

/// The signed dihedral angle and its gradient (zero gradient when degenerate).
#[inline(always)]
pub fn dihedral<V: Vector>(x: &[V; 4]) -> (V::S, [V; 4]) {
    let e = x[1] - x[0];
    let n1 = e.cross(x[2] - x[0]);
    let n2 = (x[3] - x[0]).cross(e);
    let e2 = e.length_squared();
    let (n1s, n2s) = (n1.length_squared(), n2.length_squared());
    let el = e2.sqrt();
    let small = tiny::<V::S>();
    if e2 <= small || n1s <= small * e2 || n2s <= small * e2 {
        let theta = if e2 <= small { V::S::zero() } else { angle(n1, n2, e * (V::S::one() / el)) };
        return (theta, [V::ZERO; 4]);
    }
    let theta = angle(n1, n2, e * (V::S::one() / el));
    let g2 = n1 * (-el / n1s);
    let g3 = n2 * (-el / n2s);
    let t2 = (x[2] - x[0]).dot(e) / e2;
    let t3 = (x[3] - x[0]).dot(e) / e2;
    let one = V::S::one();
    let g0 = -(g2 * (one - t2)) - g3 * (one - t3);
    let g1 = -(g2 * t2) - g3 * t3;
    (theta, [g0, g1, g2, g3])
}

#[inline(always)]
fn angle<V: Vector>(n1: V, n2: V, e_hat: V) -> V::S {
    n1.cross(n2).dot(e_hat).fast_atan2(n1.dot(n2))
}

/// `θ − θ₀` wrapped into `(−π, π]`.
#[inline(always)]
fn wrapped<S: Real>(theta: S, rest: S) -> S {
    let pi: S = c(std::f64::consts::PI);
    let two_pi = pi + pi;
    let mut d = theta - rest;
    if d > pi {
        d -= two_pi;
    } else if d <= -pi {
        d += two_pi;
    }
    d
}

impl Bend {
    /// A bending element with its rest angle measured from `x` (rest positions).
    pub fn at_rest(p: [u32; 4], x: &[glam::Vec3], k: f32) -> Self {
        let xs = p.map(|i| x[i as usize]);
        let (theta, _) = dihedral(&xs);
        Bend { p, rest_angle: theta, k }
    }
}

impl Element<4> for Bend {
    type Params = BendParams;

    #[inline(always)]
    fn particles(&self) -> [u32; 4] {
        self.p
    }

    /// The hinge: the shared edge `x₀ → x₁`.
    fn outline(&self) -> Vec<[u32; 2]> {
        vec![[self.p[0], self.p[1]]]
    }

    #[inline(always)]
    fn energy<V: Vector>(&self, _: &BendParams, x: &[V; 4]) -> V::S {
        let (theta, _) = dihedral(x);
        let d = wrapped(theta, self.rest_angle.into());
        c::<V::S>(0.5) * <V::S as From<f32>>::from(self.k) * d * d
    }

    #[inline(always)]
    fn energy_gradient<V: Vector>(&self, _: &BendParams, x: &[V; 4]) -> [V; 4] {
        let (theta, g) = dihedral(x);
        let s = <V::S as From<f32>>::from(self.k) * wrapped(theta, self.rest_angle.into());
        g.map(|gi| gi * s)
    }

    #[inline(always)]
    fn compliant<V: Vector>(&self, _: &BendParams, x: &[V; 4]) -> Projection<V, 4> {
        let (theta, grad) = dihedral(x);
        Projection {
            c: wrapped(theta, self.rest_angle.into()),
            grad,
            alpha: V::S::one() / <V::S as From<f32>>::from(self.k),
        }
    }

    /// [`dihedral`] written for a short dependency chain: `θ = atan2((n₁ × n₂)·e, (n₁·n₂)|e|)`
    /// (both arguments scaled by `|e|`, so no `ê`), `|∇x₂θ|² = |e|²/|n₁|²`, `|∇x₃θ|² = |e|²/|n₂|²`,
    /// and the divisions independent of each other; every product that feeds a sum through
    /// [`Real::madd`] (fused where the build has FMA), as the SIMD kernel does.
    #[inline(always)]
    fn project_plain<V: Vector, P: Positions<V> + ?Sized>(
        &self,
        _: &BendParams,
        x: &mut P,
        w: &[V::S],
        lambda: &mut V::S,
        inv_h2: V::S,
        sor: V::S,
    ) -> bool {
        let [i0, i1, i2, i3] = [self.p[0] as usize, self.p[1] as usize, self.p[2] as usize, self.p[3] as usize];
        let (x0, x1, x2, x3) = (x.get(i0), x.get(i1), x.get(i2), x.get(i3));
        let e = x1 - x0;
        let (a, b) = (x2 - x0, x3 - x0);
        let n1 = e.cross_madd(a);
        let n2 = b.cross_madd(e);
        let e2 = e.dot_madd(e);
        let (n1s, n2s) = (n1.dot_madd(n1), n2.dot_madd(n2));
        let small = tiny::<V::S>();
        if !(e2 > small && n1s > small * e2 && n2s > small * e2) {
            return false;
        }
        let el = e2.sqrt();
        let theta = n1.cross_madd(n2).dot_madd(e).fast_atan2(n1.dot_madd(n2) * el);
        let inv_e2 = V::S::one() / e2;
        let (q1, q2) = (el / n1s, el / n2s);
        let (t2, t3) = (a.dot_madd(e) * inv_e2, b.dot_madd(e) * inv_e2);
        let g2 = n1 * -q1;
        let g3 = n2 * -q2;
        let one = V::S::one();
        let g0 = g3.madd(-(one - t3), -(g2 * (one - t2)));
        let g1 = g3.madd(-t3, -(g2 * t2));
        let [w0, w1, w2, w3] = [w[i0], w[i1], w[i2], w[i3]];
        let sum = w3.madd(q2, w2 * q1).madd(el, w1.madd(g1.dot_madd(g1), w0 * g0.dot_madd(g0)));
        let alpha_tilde = inv_h2 / <V::S as From<f32>>::from(self.k);
        let denom = sum + alpha_tilde;
        if denom.is_nan() || denom <= c(1e-20) {
            return false;
        }
        let cval = wrapped(theta, self.rest_angle.into());
        let dl = alpha_tilde.madd(-*lambda, -cval) / denom * sor;
        *lambda += dl;
        x.set(i0, g0.madd(w0 * dl, x0));
        x.set(i1, g1.madd(w1 * dl, x1));
        x.set(i2, g2.madd(w2 * dl, x2));
        x.set(i3, g3.madd(w3 * dl, x3));
        true
    }

    /// `[θ₀, k_b]`.
    #[inline(always)]
    fn lane_constants(&self) -> [f32; LANE_CONSTANTS] {
        let mut c = [0.0; LANE_CONSTANTS];
        (c[0], c[1]) = (self.rest_angle, self.k);
        c
    }

    const LANE_CONSTANT_COUNT: usize = 2;

    /// [`Bend::project_plain`] lane by lane, operation for operation.
    const PLAIN_WIDE: bool = true;

    #[inline(always)]
    fn project_plain_wide<V: Vector, P: Positions<V> + ?Sized>(
        lanes: LaneWindow<'_, 4>,
        _: &BendParams,
        x: &mut P,
        lambda: &mut [V::S],
        inv_h2: V::S,
        sor: V::S,
        active: u32,
    ) -> u32 {
        use simd::{Lanes, madd};
        let at = lanes.at;
        let xs = [simd::gather(x, at[0]), simd::gather(x, at[1]), simd::gather(x, at[2]), simd::gather(x, at[3])];
        let ws = lanes.w.map(simd::load);
        let (rest, k) = (simd::load(lanes.consts[0]), simd::load(lanes.consts[1]));
        let e = xs[1] - xs[0];
        let (a, b) = (xs[2] - xs[0], xs[3] - xs[0]);
        let n1 = e.cross(a);
        let n2 = b.cross(e);
        let e2 = e.length_squared();
        let (n1s, n2s) = (n1.length_squared(), n2.length_squared());
        let small = Lanes::splat(1e-12);
        let mut ok = e2.simd_gt(small) & n1s.simd_gt(small * e2) & n2s.simd_gt(small * e2);
        let elen = e2.sqrt();
        let (theta, covered) = simd::atan2(n1.cross(n2).dot(e), n1.dot(n2) * elen);
        ok &= covered;
        let one = Lanes::ONE;
        let inv_e2 = one / e2;
        let (q1, q2) = (elen / n1s, elen / n2s);
        let (t2, t3) = (a.dot(e) * inv_e2, b.dot(e) * inv_e2);
        let g2 = n1 * -q1;
        let g3 = n2 * -q2;
        let g0 = g3.madd(-(one - t3), -(g2 * (one - t2)));
        let g1 = g3.madd(-t3, -(g2 * t2));
        let sum =
            madd(madd(ws[3], q2, ws[2] * q1), elen, madd(ws[1], g1.length_squared(), ws[0] * g0.length_squared()));
        let alpha_tilde = Lanes::splat(inv_h2.to_f64() as f32) / k;
        let denom = sum + alpha_tilde;
        ok &= denom.simd_gt(Lanes::splat(1e-20));
        let pi = Lanes::splat(std::f64::consts::PI as f32);
        let two_pi = pi + pi;
        let d = theta - rest;
        let d = d.simd_gt(pi).select(d - two_pi, d);
        let cval = d.simd_le(-pi).select(d + two_pi, d);
        let lam = simd::lanes(lambda);
        let sor = Lanes::splat(sor.to_f64() as f32);
        let dl = ok.select(madd(alpha_tilde, -lam, -cval) / denom * sor, Lanes::ZERO);
        let mask = ok.to_bitmask() & active;
        simd::store_masked(lambda, lam + dl, mask);
        simd::scatter(x, at[0], g0.madd(ws[0] * dl, xs[0]), mask);
        simd::scatter(x, at[1], g1.madd(ws[1] * dl, xs[1]), mask);
        simd::scatter(x, at[2], g2.madd(ws[2] * dl, xs[2]), mask);
        simd::scatter(x, at[3], g3.madd(ws[3] * dl, xs[3]), mask);
        !mask & active
    }
}
