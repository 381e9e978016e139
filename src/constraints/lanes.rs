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
    /// The color groups' last, partial batches ([`LaneView::tail`]), [`WIDTH`] lanes each (the
    /// batch's elements, then copies of its first as stand-ins), slot by slot like the family's:
    /// built with the rest, so a sweep copies nothing.
    tails: Option<Box<LaneData>>,
    /// The family's element in each lane of `tails`.
    tail_elements: Vec<u32>,
    /// Where each of `tails`' batches starts in the family's order (increasing).
    tail_starts: Vec<usize>,
}

impl LaneData {
    /// The offsets of `elements`' particles for positions of `stride` bytes each, the elements'
    /// constants, and the last, partial batch of each of the color groups `groups` (ranges of
    /// `elements`, whole batches counted from each group's start); empty (no SIMD kernel) where
    /// an offset would not fit 32 bits.
    pub fn new<E: Element<N>, const N: usize>(elements: &[E], groups: &[Range<u32>], stride: usize) -> Self {
        let len = elements.len();
        let fits =
            elements.iter().flat_map(|e| e.particles()).all(|p| (p as u64 + 1) * stride as u64 <= u32::MAX as u64);
        if !fits {
            return LaneData { len, ..LaneData::default() };
        }
        let (mut tail_elements, mut tail_starts) = (Vec::new(), Vec::new());
        for g in groups.iter().filter(|g| g.end as usize <= len) {
            let n = g.len() % WIDTH;
            if n > 0 {
                let start = g.end - n as u32;
                tail_starts.push(start as usize);
                tail_elements.extend((0..WIDTH as u32).map(|l| start + if (l as usize) < n { l } else { 0 }));
            }
        }
        let tails = (!tail_starts.is_empty()).then(|| {
            let padded: Vec<E> = tail_elements.iter().map(|&j| elements[j as usize]).collect();
            Box::new(LaneData::new(&padded, &[], stride))
        });
        let mut at = vec![0; N * len];
        by_slot(&mut at, elements, |p| p * stride as u32);
        let count = E::LANE_CONSTANT_COUNT.min(LANE_CONSTANTS);
        let mut consts = vec![0.0; count * len];
        for (j, e) in elements.iter().enumerate() {
            for (m, c) in e.lane_constants().into_iter().take(count).enumerate() {
                consts[m * len + j] = c;
            }
        }
        LaneData { len, w: Vec::new(), at, consts, count, tails, tail_elements, tail_starts }
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
        if let Some(tails) = &mut self.tails {
            let padded: Vec<E> = self.tail_elements.iter().map(|&j| elements[j as usize]).collect();
            tails.set_masses(&padded, w);
        }
    }

    /// The slices of elements `range`, where every array is complete (offsets and masses taken).
    #[inline]
    pub fn view<const N: usize>(&self, range: Range<usize>) -> Option<LaneView<'_, N>> {
        let len = self.len;
        let complete = self.w.len() == N * len && self.at.len() == N * len && self.consts.len() == self.count * len;
        (complete && range.start <= range.end && range.end <= len).then(|| LaneView {
            start: range.start,
            data: self,
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

    /// Bytes held (masses, offsets and constants, the partial batches' too).
    pub fn bytes(&self) -> usize {
        let tails = self.tails.as_ref().map_or(0, |t| t.bytes() + self.tail_elements.len() * 4);
        (self.w.len() + self.at.len() + self.consts.len()) * 4 + tails + self.tail_starts.len() * size_of::<usize>()
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
    /// The view's first element in the family's order.
    start: usize,
    /// The store the view is of (for its partial batches).
    data: &'a LaneData,
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

    /// The elements from element `j` on, fewer than [`WIDTH`], where they are a color group's
    /// last, partial batch ([`LaneData::new`]): its window, each slot padded to [`WIDTH`] lanes
    /// with the batch's first element (stand-ins that a kernel computes but neither writes nor
    /// reports), and the mask of the lanes that hold the elements. `None` elsewhere, or before
    /// the masses are taken.
    #[inline]
    pub fn tail(&self, j: usize) -> Option<(LaneWindow<'a, N>, u32)> {
        let n = self.len.checked_sub(j).filter(|n| (1..WIDTH).contains(n))?;
        let data = self.data;
        let k = data.tail_starts.binary_search(&(self.start + j)).ok()?;
        // The batch is the view's last `n` elements exactly: lane `n − 1` its last, lane `n` a
        // stand-in.
        let lanes = &data.tail_elements[k * WIDTH..(k + 1) * WIDTH];
        let exact = lanes[n - 1] as usize == self.start + self.len - 1 && lanes[n] as usize == data.tail_starts[k];
        let window = data.tails.as_ref()?.view::<N>(k * WIDTH..(k + 1) * WIDTH)?.window(0);
        exact.then_some((window, (1 << n) - 1))
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
    /// stride; the masses taken from the particles; views only where every array is complete; the
    /// group's last three elements also as a partial batch, padded with copies of its first.
    #[test]
    fn slots_hold_offsets_masses_and_constants_by_element() {
        let es = springs(WIDTH as u32 + 3);
        let len = es.len();
        let mut d = LaneData::new(&es, std::slice::from_ref(&(0..len as u32)), 16);
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
        let (tail, active) = v.tail(WIDTH).expect("the group's partial batch");
        assert_eq!(active, 0b111);
        for l in 0..WIDTH {
            let e = &es[WIDTH + if l < 3 { l } else { 0 }];
            assert_eq!([tail.at[0][l], tail.at[1][l]], [e.a * 16, e.b * 16]);
            assert_eq!([tail.w[0][l], tail.w[1][l]], [w[e.a as usize] as f32, w[e.b as usize] as f32]);
            assert_eq!([tail.consts[0][l], tail.consts[1][l]], e.lane_constants()[..2]);
        }
        assert!(v.tail(WIDTH + 1).is_none() && v.tail(0).is_none(), "only the group's last batch");
        let per_element = (2 + 2 + Spring::LANE_CONSTANT_COUNT) * 4;
        assert_eq!(d.bytes(), per_element * (len + WIDTH) + 4 * WIDTH + size_of::<usize>());
    }

    /// Offsets that would not fit 32 bits leave the family to the scalar kernels.
    #[test]
    fn offsets_past_32_bits_give_no_lanes() {
        let es = [Spring::new(0, u32::MAX / 8, 1.0, 1.0, SpringMaterial::Hookean)];
        let mut d = LaneData::new(&es, std::slice::from_ref(&(0..1)), 16);
        d.set_masses(&es, &[1.0f32; 1]);
        assert!(d.view::<2>(0..1).is_none());
    }

    #[test]
    #[should_panic(expected = "past")]
    fn a_window_past_the_end_panics() {
        let es = springs(WIDTH as u32);
        let mut d = LaneData::new(&es, std::slice::from_ref(&(0..WIDTH as u32)), 16);
        d.set_masses(&es, &[1.0f32; 3 * WIDTH]);
        let _ = d.view::<2>(1..WIDTH).expect("complete").window(0);
    }
}
