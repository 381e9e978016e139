//! Jacobi's per-constraint scale `s_j = ω / max_{i∈j} nᵢ` (SPEC §1), shared by every backend.

use crate::constraints::Element;
use crate::math::prelude::*;
use crate::scene::Scene;

/// `nᵢ`: the number of constraints (all families) touching each particle.
pub fn constraint_counts(scene: &Scene) -> Vec<u32> {
    let mut count = vec![0u32; scene.num_particles()];
    crate::for_each_family!(scene, |_i, f| {
        for e in &f.elements {
            for i in e.particles() {
                count[i as usize] += 1;
            }
        }
    });
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
