//! Signed singular value decomposition of a 3×3 matrix (Irving, Teran, Fedkiw 2004):
//! `F = U diag(σ) Vᵀ` with `U`, `V` rotations (determinant +1), `σ₁ ≥ σ₂ ≥ |σ₃|`, and `σ₃ < 0`
//! exactly when `det F < 0` (a reflected, inverted element). Computed from the eigenvectors of
//! `FᵀF` (cyclic Jacobi rotations), then `U` column by column from `F V`.

use super::mat3::M3;
use crate::math::prelude::*;

/// `F = U diag(sigma) Vᵀ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Svd<S: Real> {
    /// Left rotation.
    pub u: M3<S>,
    /// Signed singular values, `σ₁ ≥ σ₂ ≥ |σ₃|`.
    pub sigma: [S; 3],
    /// Right rotation.
    pub v: M3<S>,
}

/// Eigen-decomposition of a symmetric matrix by cyclic Jacobi rotations: eigenvalues and the
/// eigenvectors as columns.
fn symmetric_eigen<S: Real>(a: &M3<S>) -> ([S; 3], M3<S>) {
    let mut a = a.0;
    let mut v = M3::<S>::identity().0;
    let eps: S = c(1e-30);
    for _sweep in 0..32 {
        let off = a[1][0] * a[1][0] + a[2][0] * a[2][0] + a[2][1] * a[2][1];
        let diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if off <= S::epsilon() * S::epsilon() * diag || off <= eps {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            let apq = a[q][p];
            if apq.abs() <= eps {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (apq + apq);
            let t = theta.signum() / (theta.abs() + (theta * theta + S::one()).sqrt());
            let cs = S::one() / (t * t + S::one()).sqrt();
            let sn = t * cs;
            // A ← Jᵀ A J with the rotation J in the (p, q) plane.
            for k in 0..3 {
                let (akp, akq) = (a[p][k], a[q][k]);
                a[p][k] = cs * akp - sn * akq;
                a[q][k] = sn * akp + cs * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[k][p], a[k][q]);
                a[k][p] = cs * apk - sn * aqk;
                a[k][q] = sn * apk + cs * aqk;
            }
            for k in 0..3 {
                let (vkp, vkq) = (v[p][k], v[q][k]);
                v[p][k] = cs * vkp - sn * vkq;
                v[q][k] = sn * vkp + cs * vkq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], M3(v))
}

fn cross<S: Real>(a: [S; 3], b: [S; 3]) -> [S; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot<S: Real>(a: [S; 3], b: [S; 3]) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn scaled<S: Real>(a: [S; 3], s: S) -> [S; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// A unit vector orthogonal to the unit vector `a`.
fn orthogonal<S: Real>(a: [S; 3]) -> [S; 3] {
    let axis = if a[0].abs() < c(0.6) { [S::one(), S::zero(), S::zero()] } else { [S::zero(), S::one(), S::zero()] };
    let o = cross(a, axis);
    scaled(o, S::one() / dot(o, o).sqrt())
}

/// The signed SVD of `f`.
pub fn svd<S: Real>(f: &M3<S>) -> Svd<S> {
    let (mut lambda, v) = symmetric_eigen(&f.transpose().mul(f));
    let mut cols = v.0;
    // Sort by eigenvalue, largest first.
    for i in 0..3 {
        for j in (i + 1)..3 {
            if lambda[j] > lambda[i] {
                lambda.swap(i, j);
                cols.swap(i, j);
            }
        }
    }
    if M3(cols).det() < S::zero() {
        cols[2] = scaled(cols[2], -S::one());
    }
    let v = M3(cols);
    let b = f.mul(&v).0;
    let tiny: S = c(1e-20);
    let s1 = dot(b[0], b[0]).sqrt();
    let u1 = if s1 > tiny { scaled(b[0], S::one() / s1) } else { [S::one(), S::zero(), S::zero()] };
    let b2 = {
        let p = dot(b[1], u1);
        [b[1][0] - u1[0] * p, b[1][1] - u1[1] * p, b[1][2] - u1[2] * p]
    };
    let n2 = dot(b2, b2).sqrt();
    let u2 = if n2 > tiny * (S::one() + s1) { scaled(b2, S::one() / n2) } else { orthogonal(u1) };
    let s2 = dot(b[1], u2);
    let u3 = cross(u1, u2);
    let s3 = dot(b[2], u3);
    Svd { u: M3([u1, u2, u3]), sigma: [s1, s2, s3], v }
}

impl<S: Real> Svd<S> {
    /// `U diag(d) Vᵀ`.
    pub fn compose(&self, d: [S; 3]) -> M3<S> {
        self.u.mul(&M3::diag(d)).mul(&self.v.transpose())
    }
}
