//! Precision-generic vector math.
//!
//! The runtime solvers use `f32` ([`glam::Vec3`]); finite-difference tests and converged reference
//! solves use `f64` ([`glam::DVec3`]). Constraint math and the CPU solver are written once against
//! the [`Vector`] trait, which both glam types implement.

use std::fmt::Debug;
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

use glam::{DVec3, Vec3, Vec3A};
use num_traits::Float;

/// A floating-point scalar: `f32` or `f64`.
pub trait Real:
    num_traits::Float + From<f32> + AddAssign + SubAssign + Debug + Default + Send + Sync + 'static
{
    /// Widens to `f64` (for reports and accumulations).
    fn to_f64(self) -> f64;
    /// Narrows or keeps an `f64` constant.
    fn from_f64(v: f64) -> Self;
    /// `atan2(self, x)` (rad): the angle of the point `(x, self)`. `f32` uses a rational
    /// reduction and a degree-9 odd polynomial (Cephes `atanf`, within 2 ulp of the library
    /// function on every quadrant) instead of the library call, which costs several times more in
    /// the bending kernel; `f64` calls the library.
    #[inline(always)]
    fn fast_atan2(self, x: Self) -> Self {
        self.atan2(x)
    }
    /// `self·b + c`, rounded once where the build targets FMA ([`FUSED`]), else the product
    /// and the sum each rounded (`self * b + c`). The in-place kernels (`project_plain` and
    /// their SIMD twins) use it for every product that feeds a sum, so that both give the same
    /// bits in either build.
    #[inline(always)]
    fn madd(self, b: Self, c: Self) -> Self {
        if FUSED { self.mul_add(b, c) } else { self * b + c }
    }
}

/// `true` where the build targets x86-64 FMA (`target-cpu=native` on any x86-64 CPU since about
/// 2013, which the project's `.cargo/config.toml` selects): [`Real::madd`] and its vector and SIMD
/// forms then fuse, and the in-place kernels' results differ in the last bits from a build
/// without FMA (`tests/plain_regression.rs` keeps a checksum set for each).
pub const FUSED: bool = cfg!(target_feature = "fma");

impl Real for f32 {
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn from_f64(v: f64) -> Self {
        v as f32
    }
    #[inline(always)]
    fn fast_atan2(self, x: f32) -> f32 {
        atan2_f32(self, x)
    }
}

/// `atan2(y, x)` in `f32` without a library call: with `lo = min(|x|,|y|)`, `hi = max(|x|,|y|)`,
/// `t = lo/hi` in `[0, 1]`, or `(lo − hi)/(lo + hi)` with `π/4` added above `tan(π/8)`; then the
/// Cephes polynomial `atan t ≈ t + t³ P(t²)` (Horner's steps through [`Real::madd`]), and the
/// quadrant restored. One division and no data-dependent branch (the selects compile to blends),
/// since bending angles change sign and octant unpredictably. Zero, infinite and NaN inputs take
/// the library call, so every edge case matches it.
#[inline(always)]
fn atan2_f32(y: f32, x: f32) -> f32 {
    use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let swap = ay > ax;
    let (lo, hi) = if swap { (ax, ay) } else { (ay, ax) };
    if !(hi > 0.0 && hi < f32::INFINITY && lo <= hi) {
        return y.atan2(x);
    }
    let big = lo > 0.414_213_57 * hi;
    let t = if big { lo - hi } else { lo } / if big { lo + hi } else { hi };
    let base = if big { FRAC_PI_4 } else { 0.0 };
    let z = t * t;
    let poly = 8.053_744_5e-2f32.madd(z, -1.387_768_6e-1).madd(z, 1.997_771_1e-1).madd(z, -3.333_295e-1) * z;
    let r = base + t.madd(poly, t);
    let r = if swap { FRAC_PI_2 - r } else { r };
    let r = if x < 0.0 { PI - r } else { r };
    r.copysign(y)
}

impl Real for f64 {
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn from_f64(v: f64) -> Self {
        v
    }
}

/// A 3D vector over a [`Real`] scalar.
pub trait Vector:
    Copy
    + Debug
    + Default
    + PartialEq
    + Send
    + Sync
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + Mul<<Self as Vector>::S, Output = Self>
{
    /// The scalar type.
    type S: Real;
    /// The zero vector.
    const ZERO: Self;
    /// Builds a vector from its components.
    fn new(x: Self::S, y: Self::S, z: Self::S) -> Self;
    /// Converts from the `f32` storage type.
    fn from_vec3(v: Vec3) -> Self;
    /// Converts to the `f32` storage type.
    fn to_vec3(self) -> Vec3;
    /// Converts to `f64`.
    fn to_dvec3(self) -> DVec3;
    /// The components as the `f32` SIMD lanes `[x, y, z, 0]` (the SIMD kernels' gather; one
    /// register move for the padded [`Vec3A`]).
    #[inline(always)]
    fn to_quad(self) -> wide::f32x4 {
        let v = self.to_vec3();
        wide::f32x4::new([v.x, v.y, v.z, 0.0])
    }
    /// The vector of lanes `[x, y, z, 0]` (the SIMD kernels' scatter).
    #[inline(always)]
    fn from_quad(q: wide::f32x4) -> Self {
        let a = q.to_array();
        Self::from_vec3(Vec3::new(a[0], a[1], a[2]))
    }
    /// Dot product.
    fn dot(self, o: Self) -> Self::S;
    /// Cross product.
    fn cross(self, o: Self) -> Self;
    /// Euclidean length.
    fn length(self) -> Self::S {
        self.dot(self).sqrt()
    }
    /// Squared length.
    fn length_squared(self) -> Self::S {
        self.dot(self)
    }
    /// `z z' + (y y' + x x')` through [`Real::madd`]: the dot product of the in-place kernels
    /// (the same bits as [`Vector::dot`] without FMA).
    #[inline(always)]
    fn dot_madd(self, o: Self) -> Self::S {
        self.get(2).madd(o.get(2), self.get(1).madd(o.get(1), self.get(0) * o.get(0)))
    }
    /// The cross product of the in-place kernels: component `x` is `a.y b.z − b.y a.z` as
    /// `madd(a.y, b.z, −(b.y a.z))`, and so on (the same bits as [`Vector::cross`] without FMA).
    #[inline(always)]
    fn cross_madd(self, o: Self) -> Self {
        let (a, b) = (self, o);
        let m = |i: usize, j: usize| a.get(i).madd(b.get(j), -(b.get(i) * a.get(j)));
        Self::new(m(1, 2), m(2, 0), m(0, 1))
    }
    /// `self · s + c` component by component through [`Real::madd`].
    #[inline(always)]
    fn madd(self, s: Self::S, c: Self) -> Self {
        Self::new(self.get(0).madd(s, c.get(0)), self.get(1).madd(s, c.get(1)), self.get(2).madd(s, c.get(2)))
    }
    /// Component `i` (0 = x, 1 = y, 2 = z).
    fn get(self, i: usize) -> Self::S;
    /// `true` when every component is finite.
    fn is_finite(self) -> bool;
}

macro_rules! impl_vector {
    ($v:ty, $s:ty $(, $extra:item)*) => {
        impl Vector for $v {
            $($extra)*
            type S = $s;
            const ZERO: Self = <$v>::ZERO;
            #[inline]
            fn new(x: $s, y: $s, z: $s) -> Self {
                <$v>::new(x, y, z)
            }
            #[inline]
            fn from_vec3(v: Vec3) -> Self {
                <$v>::new(v.x as $s, v.y as $s, v.z as $s)
            }
            #[inline]
            fn to_vec3(self) -> Vec3 {
                Vec3::new(self.x as f32, self.y as f32, self.z as f32)
            }
            #[inline]
            fn to_dvec3(self) -> DVec3 {
                DVec3::new(self.x as f64, self.y as f64, self.z as f64)
            }
            #[inline]
            fn dot(self, o: Self) -> $s {
                <$v>::dot(self, o)
            }
            #[inline]
            fn cross(self, o: Self) -> Self {
                cross(self, o)
            }
            #[inline]
            fn get(self, i: usize) -> $s {
                self[i]
            }
            #[inline]
            fn is_finite(self) -> bool {
                <$v>::is_finite(self)
            }
        }
    };
}

impl_vector!(Vec3, f32);
impl_vector!(
    Vec3A,
    f32,
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn to_quad(self) -> wide::f32x4 {
        bytemuck::cast(std::arch::x86_64::__m128::from(self))
    },
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn from_quad(q: wide::f32x4) -> Self {
        Vec3A::from(bytemuck::cast::<_, std::arch::x86_64::__m128>(q))
    }
);
impl_vector!(DVec3, f64);

/// `a × b` as `(a.y b.z − b.y a.z, a.z b.x − b.z a.x, a.x b.y − b.x a.y)`, each product rounded
/// on its own (glam's `Vec3A::cross` fuses them where the target has FMA, which would make the
/// padded solver differ from the unpadded one and from the GPU).
#[inline(always)]
fn cross<V: std::ops::Index<usize, Output = S> + Vector<S = S>, S: Real>(a: V, b: V) -> V {
    V::new(a[1] * b[2] - b[1] * a[2], a[2] * b[0] - b[2] * a[0], a[0] * b[1] - b[0] * a[1])
}

/// Shorthand for a scalar constant in any precision.
#[inline]
pub fn c<S: Real>(v: f64) -> S {
    S::from_f64(v)
}

/// Traits whose methods the generic math calls (`sqrt`, `atan2`, `zero`, `one`, ...).
pub mod prelude {
    pub use super::{FUSED, Real, Vector, c};
    pub use num_traits::{Float, One, Zero};
}
