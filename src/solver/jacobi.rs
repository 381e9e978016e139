//! Jacobi's per-constraint scale `s_j = ω / max_{i∈j} nᵢ` (SPEC §1), shared by every backend.

use crate::constraints::Element;
use crate::math::prelude::*;
use crate::scene::Scene;

/// `nᵢ`: the number of constraints (all families) touching each particle.
pub fn constraint_counts(scene: &Scene) -> Vec<u32> {
    let mut count = vec![0u32; scene.num_particles()];
    let mut tally = |idx: &[u32]| idx.iter().for_each(|&i| count[i as usize] += 1);
    if let Some(f) = &scene.springs {
        f.elements.iter().for_each(|e| tally(&e.particles()));
    }
    if let Some(f) = &scene.bends {
        f.elements.iter().for_each(|e| tally(&e.particles()));
    }
    if let Some(f) = &scene.tets {
        f.elements.iter().for_each(|e| tally(&e.particles()));
    }
    count
}

/// `s_j = ω / max_{i∈j} nᵢ` for each element.
pub fn scales<E: Element<N>, S: Real, const N: usize>(elements: &[E], count: &[u32], omega: S) -> Vec<S> {
    elements
        .iter()
        .map(|e| {
            let n = e.particles().iter().map(|&i| count[i as usize]).max().unwrap_or(1).max(1);
            omega / c::<S>(n as f64)
        })
        .collect()
}
