//! [`WIDTH`] elements at once in SIMD for the in-place Gauss-Seidel kernels: 3-vectors of
//! [`WIDTH`] lanes, gathers and scatters through [`Positions`], and `atan2` lane by lane.
//!
//! The width is chosen when the crate is compiled: 8 lanes (`wide::f32x8`, one AVX register)
//! where the target has AVX, which the project's `.cargo/config.toml` enables on machines that
//! have it (`target-cpu=native`), else 4 (`wide::f32x4`, SSE2 on x86-64, NEON on ARM).
//!
//! Every operation is the one the scalar kernels perform, in the same order (glam's `dot` and
//! `cross`, [`Real::fast_atan2`]), so a lane gives the same bits as the scalar kernel on that
//! element, at either width. The kernels run on `f32` only; the conversions below are the
//! identity there.

use std::ops::{Add, Mul, Neg, Sub};

use super::Positions;
use crate::math::prelude::*;

/// One SIMD register of `f32` lanes.
#[cfg(target_feature = "avx")]
pub(crate) type Lanes = wide::f32x8;
/// One SIMD register of `f32` lanes.
#[cfg(not(target_feature = "avx"))]
pub(crate) type Lanes = wide::f32x4;

/// Elements per SIMD kernel call: the `f32` lanes of one SIMD register (8 where the target has
/// AVX, else 4).
pub const WIDTH: usize = std::mem::size_of::<Lanes>() / 4;

/// A 3-vector per lane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct V3 {
    pub x: Lanes,
    pub y: Lanes,
    pub z: Lanes,
}

impl V3 {
    /// `(x·x') + (y·y') + (z·z')`, glam's order.
    #[inline(always)]
    pub fn dot(self, o: V3) -> Lanes {
        (self.x * o.x) + (self.y * o.y) + (self.z * o.z)
    }

    /// glam's cross product, term for term.
    #[inline(always)]
    pub fn cross(self, o: V3) -> V3 {
        V3 { x: self.y * o.z - o.y * self.z, y: self.z * o.x - o.z * self.x, z: self.x * o.y - o.x * self.y }
    }

    /// Squared length.
    #[inline(always)]
    pub fn length_squared(self) -> Lanes {
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

impl Mul<Lanes> for V3 {
    type Output = V3;
    #[inline(always)]
    fn mul(self, s: Lanes) -> V3 {
        V3 { x: self.x * s, y: self.y * s, z: self.z * s }
    }
}

/// `true` when the scalar type is `f32`, the one precision the SIMD kernels serve.
#[inline(always)]
pub(crate) fn is_f32<S: Real>() -> bool {
    std::any::TypeId::of::<S>() == std::any::TypeId::of::<f32>()
}

/// Lane `l` from `f(l)`.
#[inline(always)]
pub(crate) fn per_lane(f: impl Fn(usize) -> f32) -> Lanes {
    let mut a = [0.0f32; WIDTH];
    for (l, v) in a.iter_mut().enumerate() {
        *v = f(l);
    }
    Lanes::new(a)
}

/// Scalars as lanes.
#[inline(always)]
pub(crate) fn lanes<S: Real>(v: &[S]) -> Lanes {
    per_lane(|l| v[l].to_f64() as f32)
}

/// The first [`WIDTH`] values of `v` as lanes, in one load.
#[inline(always)]
pub(crate) fn load(v: &[f32]) -> Lanes {
    let a: [f32; WIDTH] = v[..WIDTH].try_into().expect("one value per lane");
    Lanes::from(a)
}

/// The particle indices of `el` by slot: `slots(el)[n][l]` is particle `n` of element `l`.
#[inline(always)]
pub(crate) fn slots<E: super::Element<N>, const N: usize>(el: &[E; WIDTH]) -> [[usize; WIDTH]; N] {
    let mut s = [[0; WIDTH]; N];
    for (l, e) in el.iter().enumerate() {
        for (n, p) in e.particles().into_iter().enumerate() {
            s[n][l] = p as usize;
        }
    }
    s
}

/// Lanes back as scalars.
#[inline(always)]
pub(crate) fn unlanes<S: Real>(v: Lanes) -> [S; WIDTH] {
    let a = v.to_array();
    let mut out = [S::zero(); WIDTH];
    for (o, a) in out.iter_mut().zip(a) {
        *o = S::from_f64(a as f64);
    }
    out
}

/// Writes lane `l` of `v` to `out[l]` for every lane set in `mask` (the multipliers of the
/// elements a kernel did not decline).
#[inline(always)]
pub(crate) fn store_masked<S: Real>(out: &mut [S], v: Lanes, mask: u32) {
    let v: [S; WIDTH] = unlanes(v);
    if mask == (1 << WIDTH) - 1 {
        out[..WIDTH].copy_from_slice(&v);
        return;
    }
    for (l, (o, v)) in out.iter_mut().zip(v).enumerate() {
        if mask & (1 << l) != 0 {
            *o = v;
        }
    }
}

/// Quarters of [`Lanes`] (one SSE register each).
const QUARTERS: usize = WIDTH / 4;

/// Lanes from their quarters, lowest first.
#[inline(always)]
fn join(q: [wide::f32x4; QUARTERS]) -> Lanes {
    bytemuck::cast(q)
}

/// The quarters of `v`, lowest first.
#[inline(always)]
fn split(v: Lanes) -> [wide::f32x4; QUARTERS] {
    bytemuck::cast(v)
}

/// The positions of particles `idx`, one per lane: each four particles' `[x, y, z, 0]`
/// ([`Vector::to_quad`], one 16-byte load for [`glam::Vec3A`]) transposed into lanes.
#[inline(always)]
pub(crate) fn gather<V: Vector, P: Positions<V> + ?Sized>(x: &P, idx: &[usize; WIDTH]) -> V3 {
    let mut c = [[wide::f32x4::ZERO; QUARTERS]; 3];
    for q in 0..QUARTERS {
        let i = &idx[4 * q..4 * q + 4];
        let t = wide::f32x4::transpose([
            x.get(i[0]).to_quad(),
            x.get(i[1]).to_quad(),
            x.get(i[2]).to_quad(),
            x.get(i[3]).to_quad(),
        ]);
        (c[0][q], c[1][q], c[2][q]) = (t[0], t[1], t[2]);
    }
    V3 { x: join(c[0]), y: join(c[1]), z: join(c[2]) }
}

/// Writes lane `l` of `v` to particle `idx[l]` for every lane set in `mask` (the transpose of
/// [`gather`]).
#[inline(always)]
pub(crate) fn scatter<V: Vector, P: Positions<V> + ?Sized>(x: &mut P, idx: &[usize; WIDTH], v: V3, mask: u32) {
    let (vx, vy, vz) = (split(v.x), split(v.y), split(v.z));
    if mask == (1 << WIDTH) - 1 {
        for q in 0..QUARTERS {
            let t = wide::f32x4::transpose([vx[q], vy[q], vz[q], wide::f32x4::ZERO]);
            for (l, t) in t.into_iter().enumerate() {
                x.set(idx[4 * q + l], V::from_quad(t));
            }
        }
        return;
    }
    for q in 0..QUARTERS {
        let t = wide::f32x4::transpose([vx[q], vy[q], vz[q], wide::f32x4::ZERO]);
        for (l, t) in t.into_iter().enumerate() {
            if mask & (1 << (4 * q + l)) != 0 {
                x.set(idx[4 * q + l], V::from_quad(t));
            }
        }
    }
}

/// `atan2(y, x)` lane by lane with the operations of the scalar `f32` `fast_atan2`, and a mask of
/// the lanes it covers: the others (zero, infinite or NaN inputs) are left to the scalar path.
#[inline(always)]
pub(crate) fn atan2(y: Lanes, x: Lanes) -> (Lanes, Lanes) {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let swap = ay.simd_gt(ax);
    let (lo, hi) = (swap.select(ax, ay), swap.select(ay, ax));
    let ok = hi.simd_gt(Lanes::ZERO) & hi.simd_lt(Lanes::splat(f32::INFINITY)) & lo.simd_le(hi);
    let big = lo.simd_gt(Lanes::splat(0.414_213_57) * hi);
    let t = big.select(lo - hi, lo) / big.select(lo + hi, hi);
    let base = big.select(Lanes::splat(FRAC_PI_4), Lanes::ZERO);
    let z = t * t;
    let poly = (((Lanes::splat(8.053_744_5e-2) * z - Lanes::splat(1.387_768_6e-1)) * z + Lanes::splat(1.997_771_1e-1))
        * z
        - Lanes::splat(3.333_295e-1))
        * z;
    let r = base + (t + t * poly);
    let r = swap.select(Lanes::splat(FRAC_PI_2) - r, r);
    let r = x.simd_lt(Lanes::ZERO).select(Lanes::splat(PI) - r, r);
    (r | (y & Lanes::splat(-0.0)), ok)
}
