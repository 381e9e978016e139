//! Second-order forward differentiation in three variables: a value with its gradient and
//! Hessian. The isotropic energies are written once as formulas in the singular values and this
//! type delivers their exact first and second derivatives (the second ones are needed only by
//! the inversion extension).

use std::ops::{Add, Mul, Neg, Sub};

use crate::math::prelude::*;

/// `f`, `∇f` and `∇²f` with respect to three variables.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hd<S: Real> {
    /// Value.
    pub v: S,
    /// Gradient.
    pub g: [S; 3],
    /// Hessian (symmetric).
    pub h: [[S; 3]; 3],
}

impl<S: Real> Hd<S> {
    /// A constant.
    pub fn constant(v: S) -> Self {
        Hd { v, g: [S::zero(); 3], h: [[S::zero(); 3]; 3] }
    }

    /// The `i`-th variable at value `v`.
    pub fn var(i: usize, v: S) -> Self {
        let mut x = Self::constant(v);
        x.g[i] = S::one();
        x
    }

    /// `f(self)` from `f(v)`, `f'(v)`, `f''(v)`.
    fn chain(self, f: S, df: S, ddf: S) -> Self {
        let mut out = Self::constant(f);
        for i in 0..3 {
            out.g[i] = df * self.g[i];
            for j in 0..3 {
                out.h[i][j] = df * self.h[i][j] + ddf * self.g[i] * self.g[j];
            }
        }
        out
    }

    /// Natural logarithm (for positive values).
    pub fn ln(self) -> Self {
        let inv = S::one() / self.v;
        self.chain(self.v.ln(), inv, -inv * inv)
    }

    /// `self^p` (for positive values).
    pub fn powf(self, p: S) -> Self {
        let one = S::one();
        let vp = self.v.powf(p);
        self.chain(vp, p * vp / self.v, p * (p - one) * vp / (self.v * self.v))
    }

    /// `self^n` for a small integer `n ≥ 1`.
    pub fn powi(self, n: u32) -> Self {
        (1..n).fold(self, |acc, _| acc * self)
    }

    /// `s · self`.
    pub fn scale(self, s: S) -> Self {
        self.chain(self.v * s, s, S::zero())
    }
}

impl<S: Real> Add for Hd<S> {
    type Output = Self;
    fn add(mut self, o: Self) -> Self {
        self.v += o.v;
        for i in 0..3 {
            self.g[i] += o.g[i];
            for j in 0..3 {
                self.h[i][j] += o.h[i][j];
            }
        }
        self
    }
}

impl<S: Real> Neg for Hd<S> {
    type Output = Self;
    fn neg(self) -> Self {
        self.scale(-S::one())
    }
}

impl<S: Real> Sub for Hd<S> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        self + (-o)
    }
}

impl<S: Real> Mul for Hd<S> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        let mut out = Self::constant(self.v * o.v);
        for i in 0..3 {
            out.g[i] = self.g[i] * o.v + self.v * o.g[i];
            for j in 0..3 {
                out.h[i][j] = self.h[i][j] * o.v + self.v * o.h[i][j] + self.g[i] * o.g[j] + o.g[i] * self.g[j];
            }
        }
        out
    }
}

impl<S: Real> Add<S> for Hd<S> {
    type Output = Self;
    fn add(mut self, s: S) -> Self {
        self.v += s;
        self
    }
}

impl<S: Real> Mul<S> for Hd<S> {
    type Output = Self;
    fn mul(self, s: S) -> Self {
        self.scale(s)
    }
}
