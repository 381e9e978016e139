//! Particle positions written by several threads at once, for the elements of one color group.
//!
//! This is the crate's one use of `unsafe`. It is sound because of the coloring: within a color
//! group no two elements share a particle ([`crate::coloring`], checked by its tests and by
//! [`crate::coloring::Coloring::validate`]), so the threads that split a group read and write
//! disjoint sets of indices, and the positions are not otherwise touched until the group joins.
#![allow(unsafe_code)]

use std::marker::PhantomData;

use crate::constraints::Positions;

/// A mutable slice shared by the workers of one color group (see the module documentation).
#[derive(Clone, Copy)]
pub(crate) struct SharedPositions<'a, V> {
    ptr: *mut V,
    len: usize,
    _borrow: PhantomData<&'a mut [V]>,
}

// SAFETY: workers only touch the particles of their own elements, disjoint within a color group.
unsafe impl<V: Send> Send for SharedPositions<'_, V> {}
// SAFETY: as above; no index is read by one worker while another writes it.
unsafe impl<V: Send> Sync for SharedPositions<'_, V> {}

impl<'a, V> SharedPositions<'a, V> {
    /// Shares `x` for the duration of the borrow.
    pub fn new(x: &'a mut [V]) -> Self {
        SharedPositions { ptr: x.as_mut_ptr(), len: x.len(), _borrow: PhantomData }
    }
}

impl<V: Copy> Positions<V> for SharedPositions<'_, V> {
    #[inline(always)]
    fn get(&self, i: usize) -> V {
        assert!(i < self.len, "particle index {i} out of range");
        // SAFETY: in bounds (checked above); no other worker writes index `i` (module docs).
        unsafe { *self.ptr.add(i) }
    }

    #[inline(always)]
    fn set(&mut self, i: usize, v: V) {
        assert!(i < self.len, "particle index {i} out of range");
        // SAFETY: in bounds (checked above); only this worker touches index `i` (module docs).
        unsafe { *self.ptr.add(i) = v }
    }
}
