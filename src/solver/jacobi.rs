//! Jacobi's per-constraint scale `s_j = ω / max_{i∈j} nᵢ` (docs/algorithm.md §1), shared by every backend.

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

/// Every family's scales at `omega`, indexed as in [`crate::for_each_family`] (empty where the
/// scene has no such family): what both backends upload or keep.
pub fn family_scales<S: Real>(scene: &Scene, omega: S) -> [Vec<S>; crate::scene::FAMILY_COUNT] {
    let count = constraint_counts(scene);
    let mut out: [Vec<S>; crate::scene::FAMILY_COUNT] = Default::default();
    crate::for_each_family!(scene, |i, f| out[i] = scales(&f.elements, &count, omega));
    out
}

/// Where the team puts each element's Jacobi corrections before the particles add them up: one
/// slot per particle of every element, family after family in solve order, and for each particle
/// the slots that touch it in that same order, the order in which the one-thread pass adds them
/// (so the sums, and the positions, are the same bits).
#[derive(Clone, Debug, Default)]
pub(crate) struct Slots {
    /// First slot of each family: its element `j`'s particle `n` has slot `base[i] + N j + n`.
    pub base: [usize; crate::scene::FAMILY_COUNT],
    /// Particle `p`'s slots are `incident[offsets[p]..offsets[p + 1]]`.
    pub offsets: Vec<u32>,
    /// Slot indices grouped by particle.
    pub incident: Vec<u32>,
    /// Slots in all.
    pub total: usize,
}

impl Slots {
    /// The slots of every family of `scene`.
    pub fn new(scene: &Scene) -> Self {
        let count = constraint_counts(scene);
        let mut offsets = Vec::with_capacity(count.len() + 1);
        offsets.push(0u32);
        for c in &count {
            offsets.push(offsets[offsets.len() - 1] + c);
        }
        let mut fill: Vec<u32> = offsets[..count.len()].to_vec();
        let mut incident = vec![0u32; offsets[count.len()] as usize];
        let (mut base, mut next) = ([0; crate::scene::FAMILY_COUNT], 0usize);
        crate::for_each_family!(scene, |i, f| {
            base[i] = next;
            for e in &f.elements {
                for p in e.particles() {
                    incident[fill[p as usize] as usize] = next as u32;
                    fill[p as usize] += 1;
                    next += 1;
                }
            }
        });
        Slots { base, offsets, incident, total: next }
    }

    /// The slots of particle `p`.
    #[inline]
    pub fn of(&self, p: usize) -> &[u32] {
        &self.incident[self.offsets[p] as usize..self.offsets[p + 1] as usize]
    }
}
