//! Particle positions and multipliers written by several threads at once, for the elements of one
//! color group.
//!
//! This is the crate's one use of `unsafe`. It is sound because of the coloring: within a color
//! group no two elements share a particle ([`crate::coloring`], checked by its tests and by
//! [`crate::coloring::Coloring::validate`]), so the threads that split a group read and write
//! disjoint sets of particle indices; each thread takes a disjoint range of the group's elements
//! ([`super::barrier::share`]) and so of their multipliers, and of the particles in the
//! per-particle passes; and a particle that two threads touch in different steps is touched by
//! the later one only after the earlier one has published that step
//! ([`super::barrier::Progress`], the team's plan in `cpu/plan.rs`) or after both have passed a
//! barrier ([`super::barrier::SpinBarrier`]). An array is read whole only in a phase in which
//! no thread writes it (the substep-start positions during the sweeps). The same file holds
//! [`Prechecked`], the positions the sweeps' lean kernels read and write without a bounds check
//! once the sweep has checked its family's particle indices.
#![allow(unsafe_code)]

use std::marker::PhantomData;

use crate::constraints::Positions;

/// A mutable slice shared by the workers of one color group (see the module documentation):
/// positions indexed by particle, or multipliers indexed by element.
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

impl<V> SharedPositions<'_, V> {
    /// The elements `range` as a slice of their own, for the one worker that owns that range in
    /// the current group (no other worker's range overlaps it; module docs).
    pub fn range_mut(&mut self, range: std::ops::Range<usize>) -> &mut [V] {
        assert!(range.start <= range.end && range.end <= self.len, "range {range:?} out of 0..{}", self.len);
        // SAFETY: in bounds (checked above); the range is this worker's alone until the barrier.
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(range.start), range.len()) }
    }
}

impl<V> SharedPositions<'_, V> {
    /// The whole array for reading, in a phase in which no worker writes it (module docs).
    pub fn read_all(&self) -> &[V] {
        // SAFETY: the pointer and length come from a live `&mut [V]`; nothing writes it meanwhile.
        unsafe { std::slice::from_raw_parts(self.ptr, self.len) }
    }

    /// Number of items.
    pub fn len(&self) -> usize {
        self.len
    }
}

impl<V: Copy> Positions<V> for SharedPositions<'_, V> {
    #[inline(always)]
    fn get(&self, i: usize) -> V {
        if i >= self.len {
            out_of_range(i, self.len);
        }
        // SAFETY: in bounds (checked above); no other worker writes index `i` (module docs).
        unsafe { *self.ptr.add(i) }
    }

    #[inline(always)]
    fn set(&mut self, i: usize, v: V) {
        if i >= self.len {
            out_of_range(i, self.len);
        }
        // SAFETY: in bounds (checked above); only this worker touches index `i` (module docs).
        unsafe { *self.ptr.add(i) = v }
    }
}

/// Positions read and written without a bounds check, for the lean kernels of a sweep: the sweep
/// checks once that every particle index of its family lies below the array's length
/// ([`crate::solver::cpu`]'s `FamilyState::bound`) and hands this view only to kernels that touch
/// the particles of the elements they are given, so each gather and scatter saves a compare and a
/// branch per particle (a tenth of the peer scene's instructions).
pub(crate) struct Prechecked<'a, V> {
    ptr: *mut V,
    len: usize,
    _borrow: PhantomData<&'a mut [V]>,
}

impl<'a, V> Prechecked<'a, V> {
    /// `x` without bounds checks.
    ///
    /// # Safety
    /// While the view lives, [`Positions::get`] and [`Positions::set`] are called only with
    /// indices below `x.len()`, and [`Positions::get_at`] and [`Positions::set_at`] only with such
    /// an index times the size of `V`.
    pub unsafe fn slice(x: &'a mut [V]) -> Self {
        Prechecked { ptr: x.as_mut_ptr(), len: x.len(), _borrow: PhantomData }
    }

    /// The shared positions `x` without bounds checks.
    ///
    /// # Safety
    /// As [`Prechecked::slice`] for `x.len()`, and the view is used as `x` would be (module
    /// documentation: only the particles of this worker's elements of the current group).
    pub unsafe fn shared(x: &'a mut SharedPositions<'_, V>) -> Self {
        Prechecked { ptr: x.ptr, len: x.len, _borrow: PhantomData }
    }
}

impl<V: Copy> Positions<V> for Prechecked<'_, V> {
    #[inline(always)]
    fn get(&self, i: usize) -> V {
        debug_assert!(i < self.len, "particle index {i} out of range 0..{}", self.len);
        // SAFETY: `i < len` (the constructor's contract); a shared array as in `SharedPositions`.
        unsafe { *self.ptr.add(i) }
    }

    #[inline(always)]
    fn set(&mut self, i: usize, v: V) {
        debug_assert!(i < self.len, "particle index {i} out of range 0..{}", self.len);
        // SAFETY: as in `get`.
        unsafe { *self.ptr.add(i) = v }
    }

    #[inline(always)]
    fn get_at(&self, at: u32) -> V {
        let at = at as usize;
        debug_assert!(at.is_multiple_of(size_of::<V>()) && at / size_of::<V>() < self.len, "offset {at} out of range");
        // SAFETY: `at` is the offset of a particle index below `len` (the constructor's contract),
        // so the address is in bounds and aligned.
        unsafe { *self.ptr.cast::<u8>().add(at).cast::<V>() }
    }

    #[inline(always)]
    fn set_at(&mut self, at: u32, v: V) {
        let at = at as usize;
        debug_assert!(at.is_multiple_of(size_of::<V>()) && at / size_of::<V>() < self.len, "offset {at} out of range");
        // SAFETY: as in `get_at`.
        unsafe { *self.ptr.cast::<u8>().add(at).cast::<V>() = v }
    }
}

/// The panic of an index past the end, kept out of line: a formatted `assert!` in `get` and `set`
/// put its panic code inside every gather and scatter of the kernels, which made the team's sweeps
/// about a quarter slower than the same kernels on a slice.
#[cold]
#[inline(never)]
fn out_of_range(i: usize, len: usize) -> ! {
    panic!("particle index {i} out of range 0..{len}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_and_writes_in_bounds() {
        let mut x = [1.0f32, 2.0, 3.0];
        let mut s = SharedPositions::new(&mut x);
        s.set(2, s.get(0) + s.get(1) + 7.0);
        assert_eq!(s.read_all(), &[1.0, 2.0, 10.0]);
        s.set(0, 5.0);
        assert_eq!(x, [5.0, 2.0, 10.0]);
    }

    #[test]
    #[should_panic(expected = "particle index 3 out of range 0..3")]
    fn an_index_past_the_end_panics() {
        let mut x = [0.0f32; 3];
        let s = SharedPositions::new(&mut x);
        let _ = s.get(3);
    }
}
