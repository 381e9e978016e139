//! Particle positions and multipliers written by several threads at once, for the elements of one
//! color group.
//!
//! [`SharedPositions`] is a raw view that every thread of a team ([`super::cpu`]'s `team`) holds a
//! copy of. Making one is `unsafe`: the team promises the rules below, which make each access
//! through a copy sound.
//! 1. **Disjoint writes.** Within a step, the threads write disjoint sets of indices: within a
//!    color group no two elements share a particle ([`crate::coloring`], checked by its tests and
//!    by [`crate::coloring::Coloring::validate`]; a family whose groups were not checked disjoint
//!    runs on one thread), each thread takes a disjoint range of the group's elements and so of
//!    their multipliers ([`super::barrier::share`]), and disjoint ranges of the particles in the
//!    per-particle passes.
//! 2. **Ordered steps.** An index that two threads touch in different steps is touched by the
//!    later one only after the earlier one has published that step ([`super::barrier::Progress`],
//!    the team's plan in `cpu/plan.rs`) or after both have passed a barrier
//!    ([`super::barrier::SpinBarrier`]); both publish with release and wait with acquire, so the
//!    writes happen before the reads.
//! 3. **No reference over another thread's writes.** A shared slice (`&[V]`) covers only indices
//!    that no thread writes while it lives: [`SharedPositions::read_range`] a range this thread's
//!    step owns, [`SharedPositions::read_all`] a whole array only in a phase between two barriers
//!    in which no thread writes that array (the local mode's snapshots, Jacobi's positions and
//!    corrections, the work rows at the frame's end). Everything else is read element by element
//!    ([`Positions::get`]), which creates no reference.
//!
//! The team's tests run under Miri (`solver::cpu::team_tests`; README, "Threads"), which checks the
//! accesses for data races and aliasing. The same file holds [`Prechecked`], the positions the
//! sweeps' lean kernels read and write without a bounds check once the sweep has checked its
//! family's particle indices.
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

// SAFETY: the view is a pointer into a `&mut [V]` borrowed for `'a`; sending a copy to another
// thread is sound because every access through it follows the rules its constructor's caller
// promised (module documentation): disjoint writes, ordered steps, no reference over writes.
unsafe impl<V: Send> Send for SharedPositions<'_, V> {}
// SAFETY: as for `Send`; `&self` methods only read, under the same rules.
unsafe impl<V: Send> Sync for SharedPositions<'_, V> {}

impl<'a, V> SharedPositions<'a, V> {
    /// Shares `x` for the duration of the borrow.
    ///
    /// # Safety
    /// While the view or any copy of it lives, every access through them follows the module
    /// documentation's three rules: no index is written by one thread while another thread reads
    /// or writes it unless a published step or a barrier orders the two, and no slice returned by
    /// [`SharedPositions::read_range`], [`SharedPositions::read_all`] or
    /// [`SharedPositions::range_mut`] covers an index another thread writes while it lives.
    pub unsafe fn new(x: &'a mut [V]) -> Self {
        SharedPositions { ptr: x.as_mut_ptr(), len: x.len(), _borrow: PhantomData }
    }
}

impl<V> SharedPositions<'_, V> {
    /// The elements `range` as a slice of their own, for the one worker that owns that range in
    /// the current step (rule 1: no other worker reads or writes it until the step is published).
    pub fn range_mut(&mut self, range: std::ops::Range<usize>) -> &mut [V] {
        assert!(range.start <= range.end && range.end <= self.len, "range {range:?} out of 0..{}", self.len);
        // SAFETY: in bounds (checked above), inside the live `&mut [V]` of the constructor; the
        // range is this worker's alone while the slice lives (the constructor's contract, rule 1).
        unsafe { std::slice::from_raw_parts_mut(self.ptr.add(range.start), range.len()) }
    }
}

impl<V> SharedPositions<'_, V> {
    /// The elements `range` for reading: a range no thread writes while the slice lives (rule 3;
    /// this thread's own range of a per-particle step, or one whose writers have published).
    pub fn read_range(&self, range: std::ops::Range<usize>) -> &[V] {
        assert!(range.start <= range.end && range.end <= self.len, "range {range:?} out of 0..{}", self.len);
        // SAFETY: in bounds (checked above), inside the live `&mut [V]` of the constructor; no
        // thread writes the range while the slice lives (the constructor's contract, rule 3).
        unsafe { std::slice::from_raw_parts(self.ptr.add(range.start), range.len()) }
    }

    /// The whole array for reading, in a phase between two barriers in which no thread writes it
    /// (rule 3).
    pub fn read_all(&self) -> &[V] {
        self.read_range(0..self.len)
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
        // SAFETY: in bounds (checked above); a read of one element, creating no reference, that
        // no other thread's write to `i` races with (the constructor's contract, rules 1 and 2).
        unsafe { *self.ptr.add(i) }
    }

    #[inline(always)]
    fn set(&mut self, i: usize, v: V) {
        if i >= self.len {
            out_of_range(i, self.len);
        }
        // SAFETY: in bounds (checked above); only this worker touches index `i` in this step
        // (the constructor's contract, rules 1 and 2).
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
        // SAFETY: one thread, no slice held across a write.
        let mut s = unsafe { SharedPositions::new(&mut x) };
        s.set(2, s.get(0) + s.get(1) + 7.0);
        assert_eq!(s.read_all(), &[1.0, 2.0, 10.0]);
        s.set(0, 5.0);
        assert_eq!(x, [5.0, 2.0, 10.0]);
    }

    #[test]
    #[should_panic(expected = "particle index 3 out of range 0..3")]
    fn an_index_past_the_end_panics() {
        let mut x = [0.0f32; 3];
        // SAFETY: one thread.
        let s = unsafe { SharedPositions::new(&mut x) };
        let _ = s.get(3);
    }
}
