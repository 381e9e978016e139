//! A colored constraint family: elements stored in the solver's color order.

use std::ops::Range;

use crate::coloring::{self, ColorStats};
use crate::constraints::Element;

/// The elements of one constraint family, sorted so that each color group is a contiguous range
/// (groups in increasing color, elements of a group in their original order: the one color-order
/// policy, shared by every backend).
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
        let (perm, colors) = coloring.order();
        Family {
            params,
            elements: perm.iter().map(|&j| elements[j as usize]).collect(),
            colors,
            stats: coloring.stats(),
        }
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
