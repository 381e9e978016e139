//! A family's elements slot by slot, for the SIMD kernels ([`Element::project_plain_wide`]).
//!
//! For each particle slot `n` of the elements, a run of `len` values (entry `n · len + j` for
//! element `j`): the particles' inverse masses and their byte offsets in the positions array
//! (index × the size of one position); and for each of the family's
//! [`Element::LANE_CONSTANT_COUNT`] constants ([`Element::lane_constants`]) a run of `len`
//! values too. A kernel then loads each
//! slot's masses and constants as one vector, and addresses each particle by a plain load of its
//! offset, without scaling the index or keeping it across the kernel.

use std::ops::Range;

use super::Element;
use super::simd::WIDTH;
use crate::math::Real;

/// The most per-element constants a SIMD kernel loads by lane (a spring's rest length and
/// stiffness; a tetrahedron's `D_m⁻¹` and volume); a family stores its own
/// [`Element::LANE_CONSTANT_COUNT`].
pub const LANE_CONSTANTS: usize = 10;

/// What a window's unused constant slots point at.
static NO_CONSTANTS: [f32; WIDTH] = [0.0; WIDTH];

/// A family's elements slot by slot (module documentation), built once from the elements; the
/// inverse masses are taken again whenever the particles' change ([`LaneData::set_masses`]).
/// The default holds nothing (no SIMD kernel).
#[derive(Clone, Debug, Default)]
pub struct LaneData {
    /// Elements.
    len: usize,
    /// Inverse masses (1/kg), `N · len` (empty until [`LaneData::set_masses`]).
    w: Vec<f32>,
    /// Byte offsets of the particles in the positions array, `N · len`.
    at: Vec<u32>,
    /// The elements' constants, `count · len`.
    consts: Vec<f32>,
    /// Constants per element ([`Element::LANE_CONSTANT_COUNT`]).
    count: usize,
}

impl LaneData {
    /// The offsets of `elements`' particles for positions of `stride` bytes each, and the
    /// elements' constants; empty (no SIMD kernel) where an offset would not fit 32 bits.
    pub fn new<E: Element<N>, const N: usize>(elements: &[E], stride: usize) -> Self {
        let len = elements.len();
        let fits =
            elements.iter().flat_map(|e| e.particles()).all(|p| (p as u64 + 1) * stride as u64 <= u32::MAX as u64);
        if !fits {
            return LaneData { len, ..LaneData::default() };
        }
        let mut at = vec![0; N * len];
        by_slot(&mut at, elements, |p| p * stride as u32);
        let count = E::LANE_CONSTANT_COUNT.min(LANE_CONSTANTS);
        let mut consts = vec![0.0; count * len];
        for (j, e) in elements.iter().enumerate() {
            for (m, c) in e.lane_constants().into_iter().take(count).enumerate() {
                consts[m * len + j] = c;
            }
        }
        LaneData { len, w: Vec::new(), at, consts, count }
    }

    /// Takes the inverse masses `w` (1/kg) of `elements`' particles (the elements this was built
    /// from), in `f32`.
    pub fn set_masses<E: Element<N>, S: Real, const N: usize>(&mut self, elements: &[E], w: &[S]) {
        let len = elements.len();
        if len != self.len || self.at.len() != N * len {
            return;
        }
        self.w.resize(N * len, 0.0);
        by_slot(&mut self.w, elements, |p| w[p as usize].to_f64() as f32);
    }

    /// The slices of elements `range`, where every array is complete (offsets and masses taken).
    #[inline]
    pub fn view<const N: usize>(&self, range: Range<usize>) -> Option<LaneView<'_, N>> {
        let len = self.len;
        let complete = self.w.len() == N * len && self.at.len() == N * len && self.consts.len() == self.count * len;
        (complete && range.start <= range.end && range.end <= len).then(|| LaneView {
            len: range.len(),
            w: std::array::from_fn(|n| &self.w[n * len + range.start..n * len + range.end]),
            at: std::array::from_fn(|n| &self.at[n * len + range.start..n * len + range.end]),
            consts: std::array::from_fn(|m| match m < self.count {
                true => Some(&self.consts[m * len + range.start..m * len + range.end]),
                false => None,
            }),
        })
    }

    /// `true` before [`LaneData::new`], or where the offsets would not fit.
    pub fn is_empty(&self) -> bool {
        self.at.is_empty()
    }

    /// Bytes held (masses, offsets and constants).
    pub fn bytes(&self) -> usize {
        (self.w.len() + self.at.len() + self.consts.len()) * 4
    }
}

/// Writes `value(p)` for particle `p` of slot `n` of element `j` to `out[n · len + j]`.
fn by_slot<E: Element<N>, T, const N: usize>(out: &mut [T], elements: &[E], value: impl Fn(u32) -> T) {
    let len = elements.len();
    for (j, e) in elements.iter().enumerate() {
        for (n, p) in e.particles().into_iter().enumerate() {
            out[n * len + j] = value(p);
        }
    }
}

/// Consecutive elements of a family slot by slot ([`LaneData::view`]): every slice holds one
/// value per element.
#[derive(Clone, Copy, Debug)]
pub struct LaneView<'a, const N: usize> {
    len: usize,
    w: [&'a [f32]; N],
    at: [&'a [u32]; N],
    /// The family's constants (`None` past its [`Element::LANE_CONSTANT_COUNT`]).
    consts: [Option<&'a [f32]>; LANE_CONSTANTS],
}

impl<'a, const N: usize> LaneView<'a, N> {
    /// The [`WIDTH`] elements from element `j` on (panics past the end).
    #[inline(always)]
    #[allow(unsafe_code)]
    pub fn window(&self, j: usize) -> LaneWindow<'a, N> {
        assert!(j + WIDTH <= self.len, "lanes {j}..{} past {}", j + WIDTH, self.len);
        /// # Safety
        /// `j + WIDTH <= s.len()`.
        unsafe fn at<T>(s: &[T], j: usize) -> &[T; WIDTH] {
            debug_assert!(j + WIDTH <= s.len());
            // SAFETY: in bounds (the contract), and `[T; WIDTH]` has `T`'s alignment.
            unsafe { &*s.as_ptr().add(j).cast::<[T; WIDTH]>() }
        }
        // SAFETY: every slice holds `len` values (built so by `LaneData::view`, the only
        // constructor), and `j + WIDTH <= len` (asserted above).
        unsafe {
            LaneWindow {
                w: self.w.map(|s| at(s, j)),
                at: self.at.map(|s| at(s, j)),
                consts: self.consts.map(|s| s.map_or(&NO_CONSTANTS, |s| at(s, j))),
            }
        }
    }

    /// The elements from element `j` on, fewer than [`WIDTH`] (a group's last, partial batch),
    /// each slot padded to [`WIDTH`] lanes with element `j`'s values: stand-ins that a kernel
    /// computes but neither writes nor reports ([`LaneTail::active`]).
    pub fn tail(&self, j: usize) -> LaneTail<N> {
        let n = self.len.saturating_sub(j);
        assert!(0 < n && n < WIDTH, "a tail of {n} lanes from {j} of {}", self.len);
        let pad = |l: usize| j + if l < n { l } else { 0 };
        LaneTail {
            w: self.w.map(|s| std::array::from_fn(|l| s[pad(l)])),
            at: self.at.map(|s| std::array::from_fn(|l| s[pad(l)])),
            consts: self.consts.map(|s| s.map_or([0.0; WIDTH], |s| std::array::from_fn(|l| s[pad(l)]))),
            active: (1 << n) - 1,
        }
    }

    /// Elements in the view.
    #[inline(always)]
    pub fn len(&self) -> usize {
        self.len
    }

    /// `true` when the view holds no element.
    #[inline(always)]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }
}

/// [`WIDTH`] consecutive elements slot by slot ([`LaneView::window`]), one per SIMD lane.
#[derive(Clone, Copy, Debug)]
pub struct LaneWindow<'a, const N: usize> {
    /// Inverse masses (1/kg) of particle `n` of each element.
    pub w: [&'a [f32; WIDTH]; N],
    /// Byte offsets of particle `n` of each element in the positions array.
    pub at: [&'a [u32; WIDTH]; N],
    /// Constant `m` of each element ([`Element::lane_constants`]; zeros past the family's
    /// [`Element::LANE_CONSTANT_COUNT`]).
    pub consts: [&'a [f32; WIDTH]; LANE_CONSTANTS],
}

/// A partial batch's lanes, padded to [`WIDTH`] ([`LaneView::tail`]).
#[derive(Clone, Copy, Debug)]
pub struct LaneTail<const N: usize> {
    w: [[f32; WIDTH]; N],
    at: [[u32; WIDTH]; N],
    consts: [[f32; WIDTH]; LANE_CONSTANTS],
    /// The lanes that hold an element (bit `l` for lane `l`; the first ones).
    pub active: u32,
}

impl<const N: usize> LaneTail<N> {
    /// The batch as a window for the kernels.
    #[inline(always)]
    pub fn window(&self) -> LaneWindow<'_, N> {
        LaneWindow { w: self.w.each_ref(), at: self.at.each_ref(), consts: self.consts.each_ref() }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constraints::Spring;
    use crate::constraints::spring::SpringMaterial;

    fn springs(n: u32) -> Vec<Spring> {
        (0..n)
            .map(|j| Spring::new(j, 3 * j + 1, 0.5 + j as f32, 10.0 * j as f32 + 1.0, SpringMaterial::Hookean))
            .collect()
    }

    /// Slot by slot: particle `n` of element `j` at `n · len + j`, its offset its index times the
    /// stride; the masses taken from the particles; views only where every array is complete.
    #[test]
    fn slots_hold_offsets_masses_and_constants_by_element() {
        let es = springs(WIDTH as u32 + 3);
        let len = es.len();
        let mut d = LaneData::new(&es, 16);
        assert!(d.view::<2>(0..len).is_none(), "no view before the masses");
        let w: Vec<f64> = (0..3 * len + 1).map(|i| 1.0 / (i as f64 + 1.0)).collect();
        d.set_masses(&es, &w);
        let v = d.view::<2>(0..len).expect("complete");
        assert_eq!(v.len(), len);
        assert!(d.view::<2>(0..len + 1).is_none(), "a range past the elements");
        let win = v.window(3);
        for l in 0..WIDTH {
            let e = &es[3 + l];
            assert_eq!([win.at[0][l], win.at[1][l]], [e.a * 16, e.b * 16]);
            assert_eq!([win.w[0][l], win.w[1][l]], [w[e.a as usize] as f32, w[e.b as usize] as f32]);
            assert_eq!([win.consts[0][l], win.consts[1][l]], e.lane_constants()[..2]);
            assert!(win.consts[2..].iter().all(|c| c[l] == 0.0), "a spring has two constants");
        }
        assert_eq!(d.bytes(), (2 + 2 + Spring::LANE_CONSTANT_COUNT) * len * 4);
    }

    /// Offsets that would not fit 32 bits leave the family to the scalar kernels.
    #[test]
    fn offsets_past_32_bits_give_no_lanes() {
        let es = [Spring::new(0, u32::MAX / 8, 1.0, 1.0, SpringMaterial::Hookean)];
        let mut d = LaneData::new(&es, 16);
        d.set_masses(&es, &[1.0f32; 1]);
        assert!(d.view::<2>(0..1).is_none());
    }

    #[test]
    #[should_panic(expected = "past")]
    fn a_window_past_the_end_panics() {
        let es = springs(WIDTH as u32);
        let mut d = LaneData::new(&es, 16);
        d.set_masses(&es, &[1.0f32; 3 * WIDTH]);
        let _ = d.view::<2>(1..WIDTH).expect("complete").window(0);
    }
}
