//! Four elements at once in 4-wide SIMD (`wide::f32x4`, SSE2 on x86-64) for the in-place
//! Gauss-Seidel kernels: 3-vectors of four lanes, gathers and scatters through [`Positions`], and
//! `atan2` lane by lane.
//!
//! Every operation is the one the scalar kernels perform, in the same order (glam's `dot` and
//! `cross`, [`Real::fast_atan2`]), so a lane gives the same bits as the scalar kernel on that
//! element. The kernels run on `f32` only; the conversions below are the identity there.

use std::ops::{Add, Mul, Neg, Sub};

use glam::Vec3;
use wide::f32x4;

use super::Positions;
use crate::math::prelude::*;

/// A 3-vector per lane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct V3 {
    pub x: f32x4,
    pub y: f32x4,
    pub z: f32x4,
}

impl V3 {
    /// `(x·x') + (y·y') + (z·z')`, glam's order.
    #[inline(always)]
    pub fn dot(self, o: V3) -> f32x4 {
        (self.x * o.x) + (self.y * o.y) + (self.z * o.z)
    }

    /// glam's cross product, term for term.
    #[inline(always)]
    pub fn cross(self, o: V3) -> V3 {
        V3 { x: self.y * o.z - o.y * self.z, y: self.z * o.x - o.z * self.x, z: self.x * o.y - o.x * self.y }
    }

    /// Squared length.
    #[inline(always)]
    pub fn length_squared(self) -> f32x4 {
        self.dot(self)
    }
}

impl Add for V3 {
    type Output = V3;
    #[inline(always)]
    fn add(self, o: V3) -> V3 {
        V3 { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }
}

impl Sub for V3 {
    type Output = V3;
    #[inline(always)]
    fn sub(self, o: V3) -> V3 {
        V3 { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }
}

impl Neg for V3 {
    type Output = V3;
    #[inline(always)]
    fn neg(self) -> V3 {
        V3 { x: -self.x, y: -self.y, z: -self.z }
    }
}

impl Mul<f32x4> for V3 {
    type Output = V3;
    #[inline(always)]
    fn mul(self, s: f32x4) -> V3 {
        V3 { x: self.x * s, y: self.y * s, z: self.z * s }
    }
}

/// `true` when the scalar type is `f32`, the one precision the SIMD kernels serve.
#[inline(always)]
pub(crate) fn is_f32<S: Real>() -> bool {
    std::any::TypeId::of::<S>() == std::any::TypeId::of::<f32>()
}

/// Four scalars as lanes.
#[inline(always)]
pub(crate) fn lanes<S: Real>(v: [S; 4]) -> f32x4 {
    f32x4::new([v[0].to_f64() as f32, v[1].to_f64() as f32, v[2].to_f64() as f32, v[3].to_f64() as f32])
}

/// Lanes back as scalars.
#[inline(always)]
pub(crate) fn unlanes<S: Real>(v: f32x4) -> [S; 4] {
    let a = v.to_array();
    [S::from_f64(a[0] as f64), S::from_f64(a[1] as f64), S::from_f64(a[2] as f64), S::from_f64(a[3] as f64)]
}

/// The positions of particles `idx`, one per lane.
#[inline(always)]
pub(crate) fn gather<V: Vector, P: Positions<V> + ?Sized>(x: &P, idx: [usize; 4]) -> V3 {
    let p = [x.get(idx[0]).to_vec3(), x.get(idx[1]).to_vec3(), x.get(idx[2]).to_vec3(), x.get(idx[3]).to_vec3()];
    V3 {
        x: f32x4::new([p[0].x, p[1].x, p[2].x, p[3].x]),
        y: f32x4::new([p[0].y, p[1].y, p[2].y, p[3].y]),
        z: f32x4::new([p[0].z, p[1].z, p[2].z, p[3].z]),
    }
}

/// Writes lane `l` of `v` to particle `idx[l]` for every lane set in `mask`.
#[inline(always)]
pub(crate) fn scatter<V: Vector, P: Positions<V> + ?Sized>(x: &mut P, idx: [usize; 4], v: V3, mask: u32) {
    let (vx, vy, vz) = (v.x.to_array(), v.y.to_array(), v.z.to_array());
    for l in 0..4 {
        if mask & (1 << l) != 0 {
            x.set(idx[l], V::from_vec3(Vec3::new(vx[l], vy[l], vz[l])));
        }
    }
}

/// `atan2(y, x)` lane by lane with the operations of the scalar `f32` `fast_atan2`, and a mask of
/// the lanes it covers: the others (zero, infinite or NaN inputs) are left to the scalar path.
#[inline(always)]
pub(crate) fn atan2(y: f32x4, x: f32x4) -> (f32x4, f32x4) {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let swap = ay.simd_gt(ax);
    let (lo, hi) = (swap.select(ax, ay), swap.select(ay, ax));
    let ok = hi.simd_gt(f32x4::ZERO) & hi.simd_lt(f32x4::splat(f32::INFINITY)) & lo.simd_le(hi);
    let big = lo.simd_gt(f32x4::splat(0.414_213_57) * hi);
    let t = big.select(lo - hi, lo) / big.select(lo + hi, hi);
    let base = big.select(f32x4::splat(FRAC_PI_4), f32x4::ZERO);
    let z = t * t;
    let poly = (((f32x4::splat(8.053_744_5e-2) * z - f32x4::splat(1.387_768_6e-1)) * z + f32x4::splat(1.997_771_1e-1))
        * z
        - f32x4::splat(3.333_295e-1))
        * z;
    let r = base + (t + t * poly);
    let r = swap.select(f32x4::splat(FRAC_PI_2) - r, r);
    let r = x.simd_lt(f32x4::ZERO).select(f32x4::splat(PI) - r, r);
    (r | (y & f32x4::splat(-0.0)), ok)
}
