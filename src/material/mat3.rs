//! A small 3×3 matrix over any [`Real`], stored by columns (`m[c][r]`).

use crate::math::prelude::*;

/// A 3×3 matrix, `m[column][row]`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct M3<S: Real>(pub [[S; 3]; 3]);

impl<S: Real> M3<S> {
    /// The identity.
    #[inline(always)]
    pub fn identity() -> Self {
        let (o, z) = (S::one(), S::zero());
        M3([[o, z, z], [z, o, z], [z, z, o]])
    }

    /// The zero matrix.
    #[inline(always)]
    pub fn zero() -> Self {
        M3([[S::zero(); 3]; 3])
    }

    /// From three column vectors.
    #[inline(always)]
    pub fn from_cols<V: Vector<S = S>>(a: V, b: V, c: V) -> Self {
        let col = |v: V| [v.get(0), v.get(1), v.get(2)];
        M3([col(a), col(b), col(c)])
    }

    /// Entry at row `r`, column `c`.
    #[inline(always)]
    pub fn at(&self, r: usize, c: usize) -> S {
        self.0[c][r]
    }

    /// Column `c` as a vector.
    #[inline(always)]
    pub fn col<V: Vector<S = S>>(&self, c: usize) -> V {
        V::new(self.0[c][0], self.0[c][1], self.0[c][2])
    }

    /// `selfᵀ`.
    #[inline(always)]
    pub fn transpose(&self) -> Self {
        let mut t = Self::zero();
        for c in 0..3 {
            for r in 0..3 {
                t.0[r][c] = self.0[c][r];
            }
        }
        t
    }

    /// `self · o`.
    #[inline(always)]
    pub fn mul(&self, o: &Self) -> Self {
        let mut m = Self::zero();
        for c in 0..3 {
            for r in 0..3 {
                let mut s = S::zero();
                for k in 0..3 {
                    s += self.at(r, k) * o.at(k, c);
                }
                m.0[c][r] = s;
            }
        }
        m
    }

    /// `self + o`.
    #[inline(always)]
    pub fn add(&self, o: &Self) -> Self {
        let mut m = *self;
        for c in 0..3 {
            for r in 0..3 {
                m.0[c][r] += o.0[c][r];
            }
        }
        m
    }

    /// `s · self`.
    #[inline(always)]
    pub fn scale(&self, s: S) -> Self {
        let mut m = *self;
        for c in 0..3 {
            for r in 0..3 {
                m.0[c][r] = m.0[c][r] * s;
            }
        }
        m
    }

    /// Trace.
    #[inline(always)]
    pub fn trace(&self) -> S {
        self.0[0][0] + self.0[1][1] + self.0[2][2]
    }

    /// Determinant.
    #[inline(always)]
    pub fn det(&self) -> S {
        let m = |r, c| self.at(r, c);
        m(0, 0) * (m(1, 1) * m(2, 2) - m(1, 2) * m(2, 1)) - m(0, 1) * (m(1, 0) * m(2, 2) - m(1, 2) * m(2, 0))
            + m(0, 2) * (m(1, 0) * m(2, 1) - m(1, 1) * m(2, 0))
    }

    /// Inverse, or `None` when the determinant vanishes.
    #[inline(always)]
    pub fn inverse(&self) -> Option<Self> {
        let d = self.det();
        if d.abs() <= S::min_positive_value() || !d.is_finite() {
            return None;
        }
        let m = |r, c| self.at(r, c);
        let cof = |r0: usize, r1: usize, c0: usize, c1: usize| m(r0, c0) * m(r1, c1) - m(r0, c1) * m(r1, c0);
        let inv_d = S::one() / d;
        // inverse = adjugate / det; adj[r][c] = cofactor(c, r).
        let mut out = Self::zero();
        let rows = [(1, 2), (0, 2), (0, 1)];
        for r in 0..3 {
            for c in 0..3 {
                let (r0, r1) = rows[c];
                let (c0, c1) = rows[r];
                let sign = if (r + c) % 2 == 0 { S::one() } else { -S::one() };
                out.0[c][r] = sign * cof(r0, r1, c0, c1) * inv_d;
            }
        }
        Some(out)
    }

    /// Frobenius inner product `Σ aᵢⱼ bᵢⱼ`.
    #[inline(always)]
    pub fn ddot(&self, o: &Self) -> S {
        let mut s = S::zero();
        for c in 0..3 {
            for r in 0..3 {
                s += self.0[c][r] * o.0[c][r];
            }
        }
        s
    }

    /// `diag(d)`.
    #[inline(always)]
    pub fn diag(d: [S; 3]) -> Self {
        let z = S::zero();
        M3([[d[0], z, z], [z, d[1], z], [z, z, d[2]]])
    }
}
