//! The static equilibrium of a volumetric scene, solved directly (no time stepping): the finite
//! element answer that a converged XPBD simulation must come to rest at, so the beam study can
//! tell the solver's error from the mesh's.
//!
//! Newton's method on `∇E(x) = M g` over the free particles, in `f64`: each step solves
//! `H d = M g − ∇E(x)` by conjugate gradients, with Hessian-vector products from central
//! differences of the gradient, `H v ≈ (∇E(x + εv) − ∇E(x − εv)) / (2ε)` with `max|εv| = 1 µm`
//! (exact up to rounding for the linear model, whose energy is quadratic). The stiffness matrix is
//! never assembled.

use glam::DVec3;

use crate::constraints::{Element, gather};
use crate::error::{Error, Result};
use crate::scene::Scene;

/// A static solution.
#[derive(Clone, Debug, PartialEq)]
pub struct Equilibrium {
    /// Positions (m).
    pub positions: Vec<DVec3>,
    /// Newton steps taken.
    pub newton_steps: u32,
    /// Conjugate-gradient iterations over all steps.
    pub cg_iterations: u32,
    /// Final `‖∇E − M g‖ / ‖M g‖` over the free particles.
    pub residual: f64,
}

/// Tolerances of [`solve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    /// Stop when `‖∇E − M g‖ ≤ force · ‖M g‖`.
    pub force: f64,
    /// Most Newton steps.
    pub newton_steps: u32,
    /// Most conjugate-gradient iterations per Newton step.
    pub cg_iterations: u32,
}

impl Default for Tolerances {
    fn default() -> Self {
        Tolerances { force: 1e-10, newton_steps: 8, cg_iterations: 50_000 }
    }
}

/// Elastic forces `−∇E(x)` of the scene's tetrahedra, plus gravity on free particles; pinned
/// particles get zero (they carry the support reaction instead).
fn net_force(scene: &Scene, x: &[DVec3]) -> Vec<DVec3> {
    let mut f = vec![DVec3::ZERO; x.len()];
    if let Some(fam) = &scene.tets {
        for e in &fam.elements {
            let idx = e.particles();
            let grad = e.energy_gradient(&fam.params, &gather(x, idx));
            for (&i, g) in idx.iter().zip(grad) {
                f[i as usize] -= g;
            }
        }
    }
    let g = scene.gravity.as_dvec3();
    for (fi, &w) in f.iter_mut().zip(&scene.inv_mass) {
        *fi = if w > 0.0 { *fi + g / w as f64 } else { DVec3::ZERO };
    }
    f
}

fn dot(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a.dot(*b)).sum()
}

/// `‖f‖ / ‖M g‖` over the free particles for a net force `f` from [`net_force`].
fn relative(scene: &Scene, f: &[DVec3]) -> f64 {
    let g = scene.gravity.as_dvec3();
    let weight: f64 = scene.inv_mass.iter().filter(|&&w| w > 0.0).map(|&w| (g / w as f64).length_squared()).sum();
    if weight > 0.0 { (dot(f, f) / weight).sqrt() } else { 0.0 }
}

/// `‖∇E(x) − M g‖ / ‖M g‖` over the free particles at positions `x` (m): 1 for a body at rest
/// under gravity, 0 at static equilibrium.
pub fn force_residual(scene: &Scene, x: &[DVec3]) -> f64 {
    relative(scene, &net_force(scene, x))
}

/// A static solve that ends above this force residual is reported as a failure.
pub const STALL_LIMIT: f64 = 1e-6;

/// Solves for the static equilibrium of `scene`'s tetrahedra under gravity, starting from the
/// rest shape. Stops at the tolerance, or when a Newton step no longer halves the residual (the
/// rounding floor); fails when the scene has no tetrahedra or the residual stays above
/// [`STALL_LIMIT`].
pub fn solve(scene: &Scene, tol: Tolerances) -> Result<Equilibrium> {
    if scene.tets.is_none() {
        return Err(Error::Report(format!("scene {} has no tetrahedra to solve for", scene.name)));
    }
    let mut x: Vec<DVec3> = scene.positions.iter().map(|p| p.as_dvec3()).collect();
    let (mut newton_steps, mut cg_iterations) = (0, 0);
    let mut r = net_force(scene, &x);
    let mut residual = relative(scene, &r);
    while residual > tol.force && newton_steps < tol.newton_steps {
        // H d = r with H v = −(f(x + εv) − f(x − εv)) / (2ε), since f = M g − ∇E.
        let hessian = |v: &[DVec3]| -> Vec<DVec3> {
            let vmax = v.iter().map(|d| d.abs().max_element()).fold(0.0, f64::max).max(1e-300);
            let eps = 1e-6 / vmax;
            let plus: Vec<DVec3> = x.iter().zip(v).map(|(x, v)| *x + *v * eps).collect();
            let minus: Vec<DVec3> = x.iter().zip(v).map(|(x, v)| *x - *v * eps).collect();
            let (fp, fm) = (net_force(scene, &plus), net_force(scene, &minus));
            fp.iter().zip(&fm).map(|(a, b)| (*b - *a) / (2.0 * eps)).collect()
        };
        let (d, its) = conjugate_gradients(hessian, &r, (0.1 * tol.force / residual).max(1e-6), tol.cg_iterations);
        cg_iterations += its;
        newton_steps += 1;
        let trial: Vec<DVec3> = x.iter().zip(&d).map(|(x, d)| *x + *d).collect();
        let trial_r = net_force(scene, &trial);
        let trial_residual = relative(scene, &trial_r);
        if !trial_residual.is_finite() {
            return Err(Error::Report(format!("static solve of {}: not finite", scene.name)));
        }
        // Near the solution, a step that no longer halves the residual has reached the rounding
        // floor of the force sums (about 1e-9 of the weight): stop there. Far from it (the first
        // steps of a nonlinear model) every step is taken.
        let floor = residual <= STALL_LIMIT && trial_residual > 0.5 * residual;
        if trial_residual < residual || residual > STALL_LIMIT {
            (x, r, residual) = (trial, trial_r, trial_residual);
        }
        if floor {
            break;
        }
    }
    if residual > STALL_LIMIT {
        return Err(Error::Report(format!(
            "static solve of {}: force residual {residual:.2e} after {newton_steps} Newton steps",
            scene.name
        )));
    }
    Ok(Equilibrium { positions: x, newton_steps, cg_iterations, residual })
}

/// Conjugate gradients for `A d = b` from `d = 0`, until `‖A d − b‖ ≤ rel ‖b‖` or `max_its`;
/// `A` symmetric positive definite on the vectors it is given (pinned entries stay zero because
/// `b` and `A v` are zero there). Returns `d` and the iterations taken.
fn conjugate_gradients(a: impl Fn(&[DVec3]) -> Vec<DVec3>, b: &[DVec3], rel: f64, max_its: u32) -> (Vec<DVec3>, u32) {
    let mut d = vec![DVec3::ZERO; b.len()];
    let mut r = b.to_vec();
    let mut p = r.clone();
    let mut rr = dot(&r, &r);
    let stop = rel.max(1e-15).powi(2) * rr;
    let mut its = 0;
    while its < max_its && rr > stop {
        let ap = a(&p);
        let pap = dot(&p, &ap);
        // No descent along p (round-off near the solution, or a model that is not convex here).
        if pap <= 0.0 || !pap.is_finite() {
            break;
        }
        let step = rr / pap;
        for i in 0..d.len() {
            d[i] += p[i] * step;
            r[i] -= ap[i] * step;
        }
        let rr_new = dot(&r, &r);
        let beta = rr_new / rr;
        for i in 0..p.len() {
            p[i] = r[i] + p[i] * beta;
        }
        rr = rr_new;
        its += 1;
    }
    (d, its)
}
