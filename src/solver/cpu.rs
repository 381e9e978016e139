//! The CPU reference solver, generic over precision (`f32` at run time, `f64` for references).

use crate::constraints::{Element, gather};
use crate::math::prelude::*;
use crate::scene::{Family, Scene};

use super::contacts::project_contacts;
use super::jacobi;
use super::xpbd::{StepConstants, solve_element};
use super::{Method, Particles, Settings};
use crate::metrics;

/// Per-family solver state: one multiplier per constraint, and Jacobi's per-constraint scale.
#[derive(Clone, Debug, Default)]
struct FamilyState<S> {
    lambda: Vec<S>,
    jacobi_scale: Vec<S>,
}

/// The CPU reference solver: owns a scene and the particle state simulated from it.
#[derive(Clone, Debug)]
pub struct CpuSolver<V: Vector> {
    scene: Scene,
    /// Particle state.
    pub particles: Particles<V>,
    springs: FamilyState<V::S>,
    bends: FamilyState<V::S>,
    /// Jacobi's position corrections (allocated on first Jacobi step).
    dx: Vec<V>,
    jacobi_omega: Option<f32>,
    /// Constants of the last substep run (for residuals).
    last: Option<StepConstants<V::S>>,
}

impl<V: Vector> CpuSolver<V> {
    /// A solver at the scene's initial state.
    pub fn new(scene: Scene) -> Self {
        let state = |n: usize| FamilyState { lambda: vec![V::S::zero(); n], jacobi_scale: Vec::new() };
        CpuSolver {
            particles: Particles::from_scene(&scene),
            springs: state(scene.springs.as_ref().map_or(0, Family::len)),
            bends: state(scene.bends.as_ref().map_or(0, Family::len)),
            dx: Vec::new(),
            jacobi_omega: None,
            last: None,
            scene,
        }
    }

    /// The scene being simulated.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Back to the scene's initial state.
    pub fn reset(&mut self) {
        *self = CpuSolver::new(self.scene.clone());
    }

    /// Advances one frame of `settings.dt` (call [`Settings::validate`] first).
    pub fn step_frame(&mut self, s: &Settings) {
        let k = StepConstants::new(s);
        if s.method == Method::Jacobi {
            self.prepare_jacobi(s.jacobi_omega);
        }
        for _ in 0..s.substeps {
            self.substep(s, &k);
        }
        self.last = Some(k);
    }

    fn substep(&mut self, s: &Settings, k: &StepConstants<V::S>) {
        self.predict(k.h);
        self.springs.lambda.fill(V::S::zero());
        self.bends.lambda.fill(V::S::zero());
        for _ in 0..s.iterations {
            match s.method {
                Method::GaussSeidel => {
                    if let Some(f) = &self.scene.springs {
                        gauss_seidel(f, &mut self.springs.lambda, &mut self.particles, k);
                    }
                    if let Some(f) = &self.scene.bends {
                        gauss_seidel(f, &mut self.bends.lambda, &mut self.particles, k);
                    }
                }
                Method::Jacobi => self.jacobi_iteration(k),
            }
            project_contacts(&self.scene, &mut self.particles);
        }
        project_contacts(&self.scene, &mut self.particles);
        self.update_velocities(k.h, s.damping.into());
    }

    fn predict(&mut self, h: V::S) {
        let g = V::from_vec3(self.scene.gravity);
        let p = &mut self.particles;
        for i in 0..p.len() {
            p.x_prev[i] = p.x[i];
            if p.w[i] > V::S::zero() {
                p.v[i] += g * h;
                p.x[i] += p.v[i] * h;
            } else {
                p.v[i] = V::ZERO;
            }
        }
    }

    fn update_velocities(&mut self, h: V::S, damping: V::S) {
        let keep = (V::S::one() - damping * h).max(V::S::zero());
        let inv_h = V::S::one() / h;
        let p = &mut self.particles;
        for i in 0..p.len() {
            p.v[i] = if p.w[i] > V::S::zero() { (p.x[i] - p.x_prev[i]) * (inv_h * keep) } else { V::ZERO };
        }
    }

    fn prepare_jacobi(&mut self, omega: f32) {
        if self.jacobi_omega == Some(omega) {
            return;
        }
        self.jacobi_omega = Some(omega);
        let count = jacobi::constraint_counts(&self.scene);
        let omega: V::S = omega.into();
        if let Some(f) = &self.scene.springs {
            self.springs.jacobi_scale = jacobi::scales(&f.elements, &count, omega);
        }
        if let Some(f) = &self.scene.bends {
            self.bends.jacobi_scale = jacobi::scales(&f.elements, &count, omega);
        }
        self.dx = vec![V::ZERO; self.particles.len()];
    }

    fn jacobi_iteration(&mut self, k: &StepConstants<V::S>) {
        self.dx.fill(V::ZERO);
        if let Some(f) = &self.scene.springs {
            jacobi(f, &mut self.springs, &self.particles, &mut self.dx, k);
        }
        if let Some(f) = &self.scene.bends {
            jacobi(f, &mut self.bends, &self.particles, &mut self.dx, k);
        }
        for (x, d) in self.particles.x.iter_mut().zip(&self.dx) {
            *x += *d;
        }
    }

    /// RMS and maximum of the XPBD residual `|C_j + α̃ λ_j|` over all constraints, with the
    /// multipliers of the last substep (SPEC §7). `(0, 0)` before the first step.
    pub fn residual(&self) -> (f64, f64) {
        let Some(k) = &self.last else { return (0.0, 0.0) };
        metrics::residual(&self.scene, &self.particles.x, &self.springs.lambda, &self.bends.lambda, k)
    }

    /// Total material energy of every constraint family (J), accumulated in `f64`.
    pub fn elastic_energy(&self) -> f64 {
        metrics::elastic_energy(&self.scene, &self.particles.x)
    }

    /// Multipliers of the last substep: springs, bending.
    pub fn lambdas(&self) -> (&[V::S], &[V::S]) {
        (&self.springs.lambda, &self.bends.lambda)
    }

    /// Constants of the last substep run, if any.
    pub fn last_constants(&self) -> Option<&StepConstants<V::S>> {
        self.last.as_ref()
    }
}

/// One Gauss-Seidel sweep over a family's color groups, in order.
fn gauss_seidel<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    lambda: &mut [V::S],
    p: &mut Particles<V>,
    k: &StepConstants<V::S>,
) {
    let lambda = &mut lambda[..f.elements.len()];
    for range in &f.colors {
        let (lo, hi) = (range.start as usize, range.end as usize);
        for (e, l) in f.elements[lo..hi].iter().zip(&mut lambda[lo..hi]) {
            let idx = e.particles();
            let xs = gather(&p.x, idx);
            let ws = idx.map(|i| p.w[i as usize]);
            if let Some((grad, d)) = solve_element(e, &f.params, &xs, &ws, &p.x_prev, *l, k) {
                *l += d;
                for n in 0..N {
                    p.x[idx[n] as usize] = xs[n] + grad[n] * (ws[n] * d);
                }
            }
        }
    }
}

/// One Jacobi pass over a family: corrections accumulate into `dx`, scaled per constraint.
fn jacobi<E: Element<N>, V: Vector, const N: usize>(
    f: &Family<E, N>,
    st: &mut FamilyState<V::S>,
    p: &Particles<V>,
    dx: &mut [V],
    k: &StepConstants<V::S>,
) {
    for (j, e) in f.elements.iter().enumerate() {
        let idx = e.particles();
        let xs = gather(&p.x, idx);
        let ws = idx.map(|i| p.w[i as usize]);
        if let Some((grad, d)) = solve_element(e, &f.params, &xs, &ws, &p.x_prev, st.lambda[j], k) {
            let d = d * st.jacobi_scale[j];
            st.lambda[j] += d;
            for n in 0..N {
                dx[idx[n] as usize] += grad[n] * (ws[n] * d);
            }
        }
    }
}
