//! [`WIDTH`] elements at once in SIMD for the in-place Gauss-Seidel kernels: 3-vectors of
//! [`WIDTH`] lanes, gathers and scatters through [`Positions`], and `atan2` lane by lane.
//!
//! The width is chosen when the crate is compiled: 8 lanes (`wide::f32x8`, one AVX register)
//! where the target has AVX, which the project's `.cargo/config.toml` enables on machines that
//! have it (`target-cpu=native`), else 4 (`wide::f32x4`, SSE2 on x86-64, NEON on ARM).
//!
//! Every operation is the one the scalar kernels perform, in the same order ([`Vector::dot_madd`],
//! [`Vector::cross_madd`], [`Real::madd`], [`Real::fast_atan2`]), so a lane gives the same bits as
//! the scalar kernel on that element, at either width, with FMA or without. The kernels run on
//! `f32` only; the conversions below are the identity there.

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
    /// [`Vector::dot_madd`] lane by lane: `z z' + (y y' + x x')` through [`madd`].
    #[inline(always)]
    pub fn dot(self, o: V3) -> Lanes {
        madd(self.z, o.z, madd(self.y, o.y, self.x * o.x))
    }

    /// [`Vector::cross_madd`] lane by lane: `x = madd(y, o.z, −(o.y z))`, and so on.
    #[inline(always)]
    pub fn cross(self, o: V3) -> V3 {
        V3 {
            x: madd(self.y, o.z, -(o.y * self.z)),
            y: madd(self.z, o.x, -(o.z * self.x)),
            z: madd(self.x, o.y, -(o.x * self.y)),
        }
    }

    /// [`Vector::madd`] lane by lane: `self · s + c`.
    #[inline(always)]
    pub fn madd(self, s: Lanes, c: V3) -> V3 {
        V3 { x: madd(self.x, s, c.x), y: madd(self.y, s, c.y), z: madd(self.z, s, c.z) }
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

/// [`Real::madd`] lane by lane: `a·b + c`, rounded once where the build targets FMA
/// ([`FUSED`]), else the product and the sum each rounded.
#[inline(always)]
pub(crate) fn madd(a: Lanes, b: Lanes, c: Lanes) -> Lanes {
    if FUSED { a.mul_add(b, c) } else { a * b + c }
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

/// [`WIDTH`] values as lanes, in one load.
#[inline(always)]
pub(crate) fn load(v: &[f32; WIDTH]) -> Lanes {
    Lanes::from(*v)
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

/// The positions of the particles at byte offsets `at[l]` ([`Positions::get_at`]), one per lane
/// `l`: each particle's `[x, y, z, 0]` ([`Vector::to_quad`], one 16-byte load for
/// [`glam::Vec3A`]) transposed into lanes.
#[inline(always)]
pub(crate) fn gather<V: Vector, P: Positions<V> + ?Sized>(x: &P, at: &[u32; WIDTH]) -> V3 {
    let [x, y, z] = transpose::to_lanes(std::array::from_fn(|l| x.get_at(at[l]).to_quad()));
    V3 { x, y, z }
}

/// Writes lane `l` of `v` to the particle at byte offset `at[l]` for every lane set in `mask`
/// (the transpose of [`gather`]).
#[inline(always)]
pub(crate) fn scatter<V: Vector, P: Positions<V> + ?Sized>(x: &mut P, at: &[u32; WIDTH], v: V3, mask: u32) {
    if mask == (1 << WIDTH) - 1 {
        transpose::to_quads([v.x, v.y, v.z], |l, q| x.set_at(at[l], V::from_quad(q)));
        return;
    }
    transpose::to_quads([v.x, v.y, v.z], |l, q| {
        if mask & (1 << l) != 0 {
            x.set_at(at[l], V::from_quad(q));
        }
    });
}

/// Particles' `[x, y, z, w]` quads to lanes of `x`, `y` and `z` (`w` ignored) and back (`w = 0`).
#[cfg(target_feature = "avx")]
mod transpose {
    use safe_arch::{
        cast_to_m128_from_m256, extract_m128_from_m256, m128, m256, set_m128_m256, shuffle_m256, unpack_hi_m256,
        unpack_lo_m256, zeroed_m256,
    };

    use super::{Lanes, WIDTH};

    /// Quads `l` and `l + 4` in the low and high halves of one register: the two 4 × 4
    /// transposes then run side by side, in 256-bit shuffles.
    #[inline(always)]
    pub fn to_lanes(q: [wide::f32x4; WIDTH]) -> [Lanes; 3] {
        let pair = |l: usize| set_m128_m256(bytemuck::cast::<_, m128>(q[l + 4]), bytemuck::cast(q[l]));
        let (r0, r1, r2, r3) = (pair(0), pair(1), pair(2), pair(3));
        // [x0 x1 y0 y1 | x4 x5 y4 y5], [z0 z1 w0 w1 | …], and the same for particles 2, 3 (6, 7).
        let (a, b) = (unpack_lo_m256(r0, r1), unpack_hi_m256(r0, r1));
        let (c, d) = (unpack_lo_m256(r2, r3), unpack_hi_m256(r2, r3));
        let x = shuffle_m256::<0b01_00_01_00>(a, c);
        let y = shuffle_m256::<0b11_10_11_10>(a, c);
        let z = shuffle_m256::<0b01_00_01_00>(b, d);
        [x, y, z].map(bytemuck::cast)
    }

    /// The transpose of [`to_lanes`], with `w = 0`: `put(l, quad)` for each lane `l`.
    #[inline(always)]
    pub fn to_quads(v: [Lanes; 3], mut put: impl FnMut(usize, wide::f32x4)) {
        let [x, y, z] = v.map(bytemuck::cast::<_, m256>);
        // [x0 y0 x1 y1 | x4 y4 x5 y5], [x2 y2 x3 y3 | …], [z0 0 z1 0 | …], [z2 0 z3 0 | …].
        let (a, b) = (unpack_lo_m256(x, y), unpack_hi_m256(x, y));
        let (c, d) = (unpack_lo_m256(z, zeroed_m256()), unpack_hi_m256(z, zeroed_m256()));
        let r = [
            shuffle_m256::<0b01_00_01_00>(a, c),
            shuffle_m256::<0b11_10_11_10>(a, c),
            shuffle_m256::<0b01_00_01_00>(b, d),
            shuffle_m256::<0b11_10_11_10>(b, d),
        ];
        for (l, r) in r.into_iter().enumerate() {
            put(l, bytemuck::cast(cast_to_m128_from_m256(r)));
            put(l + 4, bytemuck::cast(extract_m128_from_m256::<1>(r)));
        }
    }
}

/// Particles' `[x, y, z, w]` quads to lanes of `x`, `y` and `z` (`w` ignored) and back (`w = 0`).
#[cfg(not(target_feature = "avx"))]
mod transpose {
    use super::{Lanes, WIDTH};

    #[inline(always)]
    pub fn to_lanes(q: [wide::f32x4; WIDTH]) -> [Lanes; 3] {
        let t = wide::f32x4::transpose(q);
        [t[0], t[1], t[2]]
    }

    #[inline(always)]
    pub fn to_quads(v: [Lanes; 3], mut put: impl FnMut(usize, wide::f32x4)) {
        for (l, q) in wide::f32x4::transpose([v[0], v[1], v[2], wide::f32x4::ZERO]).into_iter().enumerate() {
            put(l, q);
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
    let poly = madd(Lanes::splat(8.053_744_5e-2), z, Lanes::splat(-1.387_768_6e-1));
    let poly = madd(madd(poly, z, Lanes::splat(1.997_771_1e-1)), z, Lanes::splat(-3.333_295e-1)) * z;
    let r = base + madd(t, poly, t);
    let r = swap.select(Lanes::splat(FRAC_PI_2) - r, r);
    let r = x.simd_lt(Lanes::ZERO).select(Lanes::splat(PI) - r, r);
    (r | (y & Lanes::splat(-0.0)), ok)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec3, Vec3A};

    /// Lane `l` of a gather is particle `idx[l]` (at its byte offset), and a scatter writes
    /// exactly the lanes of its mask back, for the padded and the packed storage.
    #[test]
    fn gather_and_scatter_are_transposes_lane_by_lane() {
        let x: Vec<Vec3> = (0..20).map(|i| Vec3::new(i as f32, 100.0 + i as f32, -(i as f32) - 0.5)).collect();
        let idx: [usize; WIDTH] = std::array::from_fn(|l| (7 * l + 3) % 20);
        let (at, at_a) = (idx.map(|i| (i * size_of::<Vec3>()) as u32), idx.map(|i| (i * size_of::<Vec3A>()) as u32));
        let v = gather(&x[..], &at);
        let va = gather(&x.iter().map(|&p| Vec3A::from(p)).collect::<Vec<_>>()[..], &at_a);
        for (l, &i) in idx.iter().enumerate() {
            let lane = |c: Lanes| c.to_array()[l];
            assert_eq!(Vec3::new(lane(v.x), lane(v.y), lane(v.z)), x[i], "lane {l}");
            assert_eq!(Vec3::new(lane(va.x), lane(va.y), lane(va.z)), x[i], "padded lane {l}");
        }
        for mask in [(1u32 << WIDTH) - 1, 0b0110_1001 & ((1 << WIDTH) - 1)] {
            let mut out = vec![Vec3::ZERO; 20];
            let mut out_a = vec![Vec3A::ZERO; 20];
            scatter(&mut out[..], &at, v, mask);
            scatter(&mut out_a[..], &at_a, v, mask);
            for (l, &i) in idx.iter().enumerate() {
                let expected = if mask & (1 << l) != 0 { x[i] } else { Vec3::ZERO };
                assert_eq!(out[i], expected, "mask {mask:b}, lane {l}");
                assert_eq!(Vec3::from(out_a[i]), expected, "padded, mask {mask:b}, lane {l}");
            }
            let written = out.iter().filter(|p| **p != Vec3::ZERO).count();
            assert_eq!(written, mask.count_ones() as usize);
        }
    }
}
