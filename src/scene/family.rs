//! A colored constraint family: elements stored in the solver's color order.

use std::ops::Range;

use crate::coloring::{self, ColorStats};
use crate::constraints::Element;

/// The elements of one constraint family, sorted so that each color group is a contiguous range
/// (groups in increasing color, elements of a group by lowest particle index, then original
/// order: the one color-order policy, shared by every backend).
#[derive(Clone, Debug)]
pub struct Family<E: Element<N>, const N: usize> {
    /// Parameters shared by the family.
    pub params: E::Params,
    /// Elements in color order.
    pub elements: Vec<E>,
    /// Range of `elements` each color group occupies, in solve order.
    pub colors: Vec<Range<u32>>,
    /// Color count and balance.
    pub stats: ColorStats,
}

impl<E: Element<N>, const N: usize> Family<E, N> {
    /// Colors `elements` over `n_particles` particles and stores them in color order.
    pub fn new(params: E::Params, elements: Vec<E>, n_particles: usize) -> Self {
        let idx: Vec<[u32; N]> = elements.iter().map(|e| e.particles()).collect();
        let coloring = coloring::color(n_particles, &idx);
        let (mut perm, colors) = coloring.order();
        // Within a group, by lowest particle index: the threads that split a group in consecutive
        // shares then write mostly disjoint stretches of the position array (no cache line
        // passed back and forth), whatever order the mesh listed its elements in. The elements of
        // a group are independent, so their order does not change the result.
        for r in &colors {
            perm[r.start as usize..r.end as usize].sort_by_key(|&j| idx[j as usize].iter().min().copied());
        }
        Family {
            params,
            elements: perm.iter().map(|&j| elements[j as usize]).collect(),
            colors,
            stats: coloring.stats(),
        }
    }

    /// `true` when no two elements of a color group share a particle (what lets the threads of a
    /// group write positions without ordering). `Family::new` guarantees it; a family assembled
    /// by hand is checked before the CPU solver splits its groups. O(elements).
    pub fn groups_disjoint(&self, n_particles: usize) -> bool {
        let mut owner = vec![u32::MAX; n_particles];
        for range in &self.colors {
            let Some(group) = self.elements.get(range.start as usize..range.end as usize) else { return false };
            for (j, e) in group.iter().enumerate() {
                let j = range.start + j as u32;
                for p in e.particles() {
                    match owner.get_mut(p as usize) {
                        Some(o) if *o == u32::MAX || *o < range.start || *o == j => *o = j,
                        _ => return false,
                    }
                }
            }
        }
        true
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// `true` when the family has no elements.
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }
}
