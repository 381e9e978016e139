//! Particle state as a struct of arrays.

use crate::math::prelude::*;
use crate::scene::Scene;

/// Particle state: positions, positions at the start of the substep, velocities, inverse
/// masses. Pinned particles have inverse mass 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Particles<V: Vector> {
    /// Positions `x` (m).
    pub x: Vec<V>,
    /// Positions at the start of the current substep (m).
    pub x_prev: Vec<V>,
    /// Velocities `v` (m/s).
    pub v: Vec<V>,
    /// Inverse masses `w` (1/kg).
    pub w: Vec<V::S>,
}

impl<V: Vector> Particles<V> {
    /// The scene's initial state, at rest.
    pub fn from_scene(scene: &Scene) -> Self {
        let x: Vec<V> = scene.positions.iter().map(|&p| V::from_vec3(p)).collect();
        Particles {
            x_prev: x.clone(),
            v: vec![V::ZERO; x.len()],
            w: scene.inv_mass.iter().map(|&w| <V::S as From<f32>>::from(w)).collect(),
            x,
        }
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// `true` when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Mass of particle `i` (kg), 0 for a pinned particle (left out of mass-weighted sums).
    pub fn mass(&self, i: usize) -> V::S {
        if self.w[i] > V::S::zero() { V::S::one() / self.w[i] } else { V::S::zero() }
    }
}
