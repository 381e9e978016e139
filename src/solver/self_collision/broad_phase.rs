//! The self-collision's broad phase (docs/algorithm.md §3.1): each particle's reference
//! position, the check of the references against the positions once a substep, and the spatial
//! hash (counting sort of the references' cells) that finds the candidates.
//!
//! The candidates are a function of the references alone: particle `i`'s are every `j` with
//! `|a_i − a_j| < r + 2m` (no mesh neighbour, not both pinned), the lowest [`CAPACITY`] kept.
//! A check computes the particles' mean displacement from their references `T`; when some
//! particle strayed, `|x_i − a_i − T| > m`, every particle beyond [`KEEP`] times the margin
//! takes the reference `a_i = x_i − T`. Every particle is then within `m` of its reference
//! shifted by `T`, so two particles closer than `r` have references closer than `r + 2m`: every
//! pair that can touch within the substep is a candidate. Only the renewed particles change
//! their candidates, so one thread looks up just their cells (and edits their partners' lists),
//! where finding every particle's takes the whole table; the GPU finds them all again (one
//! invocation per particle), the same lists.
//! `T` is summed in the GPU's order and scaled by the same `1/n`, and every other step is one
//! correctly rounded operation, so the references agree to the bit on both backends.

use super::{CAPACITY, KEEP, SelfPairs, margin, neighbour_distance, reach, table_size};
use crate::math::prelude::*;
use crate::scene::SelfCollision;

/// Lanes of the GPU's check (`self_check`'s workgroup): lane `l` sums particles `l, l + 64, …`.
const LANES: usize = 64;

/// The 27 cells around a particle's, as offsets: its own first, then the 13 after it in
/// (z, y, x) order, then the 13 before. The first 14 are the whole search's stencil: the other
/// half finds the particle from theirs.
const AROUND: [[i32; 3]; 27] = {
    let mut s = [[0; 3]; 27];
    let mut k = 0;
    while k < 27 {
        // The cell at linear index `o` of the 3 × 3 × 3 block around (13 in its middle).
        let o = (13 + k as i32) % 27;
        s[k] = [o % 3 - 1, o / 3 % 3 - 1, o / 9 - 1];
        k += 1;
    }
    s
};

/// The whole search's cells ([`AROUND`]'s first 14).
const STENCIL: &[[i32; 3]] = AROUND.split_at(14).0;

/// The squared reach (m²) and the rest distance of mesh neighbours (m).
fn limits(sc: &SelfCollision) -> (f32, f32) {
    let r = reach(sc);
    (r * r, neighbour_distance(sc))
}

/// The bucket of cell `c` in a table of `size` buckets (a power of two).
pub fn bucket(c: [i32; 3], size: usize) -> usize {
    let h = (c[0].wrapping_mul(92837111)) ^ (c[1].wrapping_mul(689287499)) ^ (c[2].wrapping_mul(283923481));
    (h as u32 as usize) & (size - 1)
}

/// The hash cell of position `p` for cells of side `1 / inv_r` (m).
pub fn cell(p: glam::Vec3, inv_r: f32) -> [i32; 3] {
    let q = p * inv_r;
    [q.x.floor() as i32, q.y.floor() as i32, q.z.floor() as i32]
}

/// The particles' mean displacement from their references (m), `T = (Σ_i (x_i − a_i)) · inv_n`,
/// summed as the GPU's `self_check` does: lane `l` of 64 over particles `l, l + 64, …` in turn,
/// then the lanes in halving pairs (`reduce_workgroup`), so both backends get the same bits.
pub fn mean_shift<V: Vector>(x: &[V], at: &[glam::Vec3], inv_n: f32) -> glam::Vec3 {
    let mut lanes = [glam::Vec3::ZERO; LANES];
    for (k, (p, a)) in x.iter().zip(at).enumerate() {
        lanes[k % LANES] += p.to_vec3() - *a;
    }
    let mut s = LANES / 2;
    while s > 0 {
        for l in 0..s {
            lanes[l] += lanes[l + s];
        }
        s /= 2;
    }
    lanes[0] * inv_n
}

/// `1/n` as both backends scale the mean shift.
pub fn inv_count(n: usize) -> f32 {
    1.0 / n.max(1) as f32
}

/// Inserts `j` into the increasing `list` of `*count` entries (at most [`CAPACITY`]), keeping
/// the lowest indices; returns `true` when an index was dropped.
pub fn insert(list: &mut [u32], count: &mut u32, j: u32) -> bool {
    let c = *count as usize;
    let full = c == CAPACITY;
    if full && j >= list[CAPACITY - 1] {
        return true;
    }
    let mut k = if full { CAPACITY - 1 } else { c };
    while k > 0 && list[k - 1] > j {
        list[k] = list[k - 1];
        k -= 1;
    }
    list[k] = j;
    if !full {
        *count += 1;
    }
    full
}

/// Appends `j` to `list` of `*count` entries (in no order) while it has room; a full list is
/// put in increasing order and kept to the lowest [`CAPACITY`] indices ([`insert`]). Returns
/// `true` when an index was dropped. Sorted at the end, the list holds the same indices as
/// [`insert`] gives, in any order of arrival.
fn push(list: &mut [u32], count: &mut u32, j: u32) -> bool {
    let c = *count as usize;
    if c < CAPACITY {
        list[c] = j;
        *count += 1;
        return false;
    }
    list.sort_unstable();
    insert(list, count, j)
}

/// Removes `j` from the increasing `list` of `*count` entries, if there.
fn remove(list: &mut [u32], count: &mut u32, j: u32) {
    let c = *count as usize;
    if let Ok(k) = list[..c].binary_search(&j) {
        list.copy_within(k + 1..c, k);
        *count -= 1;
    }
}

impl SelfPairs {
    /// Makes the candidates valid at positions `x` (inverse masses `w`): when some particle
    /// strayed more than the margin from its reference (beyond the particles' mean
    /// displacement, [`mean_shift`]), the references of every particle beyond [`KEEP`] times
    /// the margin move to their positions, and their candidates are found anew (everyone's at
    /// the first call).
    pub fn update<V: Vector>(&mut self, x: &[V], w: &[V::S], sc: &SelfCollision) {
        if self.at.len() != x.len() {
            self.at.clear();
            self.at.extend(x.iter().map(|p| p.to_vec3()));
            self.find(w, sc);
            self.builds += 1;
            return;
        }
        let m = margin(sc);
        let shift = mean_shift(x, &self.at, inv_count(x.len()));
        self.strayed.clear();
        // How far a particle is from its reference beyond the shift, squared (m²).
        let strayed2 = |p: &V, a: &glam::Vec3| {
            let d = p.to_vec3() - *a - shift;
            d.dot(d)
        };
        if x.iter().zip(&self.at).any(|(p, a)| strayed2(p, a) > m * m) {
            let k = m * m * (KEEP * KEEP);
            for (i, (p, a)) in x.iter().zip(self.at.iter_mut()).enumerate() {
                if strayed2(p, a) > k {
                    *a = p.to_vec3() - shift;
                    self.strayed.push(i as u32);
                }
            }
        }
        if !self.strayed.is_empty() {
            if !self.refind(w, sc) {
                self.find(w, sc);
            }
            self.builds += 1;
        }
    }

    /// The references' cells sorted into the hash's buckets.
    fn hash(&mut self, sc: &SelfCollision) {
        let n = self.at.len();
        let size = table_size(n);
        let inv_r = 1.0 / reach(sc);
        self.cells.clear();
        self.cells.extend(self.at.iter().map(|&p| cell(p, inv_r)));
        self.start.clear();
        self.start.resize(size + 1, 0);
        for &c in &self.cells {
            self.start[bucket(c, size) + 1] += 1;
        }
        for b in 0..size {
            self.start[b + 1] += self.start[b];
        }
        self.sorted.clear();
        self.sorted.resize(n, 0);
        let mut fill = self.start.clone();
        for (i, &c) in self.cells.iter().enumerate() {
            let b = bucket(c, size);
            self.sorted[fill[b] as usize] = i as u32;
            fill[b] += 1;
        }
        // The references and cells in bucket order, read in sequence by the searches.
        self.sorted_at.clear();
        self.sorted_at.extend(self.sorted.iter().map(|&i| (self.at[i as usize], self.cells[i as usize])));
    }

    /// Whether `i` and `j` (references `a_i`, `a_j` in `cell_j`, searched in `cell`) make a
    /// candidate pair: `j` in that cell (a bucket holds other cells' particles too), closer than
    /// the reach, not both pinned, no mesh neighbours.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn pairs_up<S: Real>(
        sc: &SelfCollision,
        (i, j): (usize, usize),
        (a_i, a_j): (glam::Vec3, glam::Vec3),
        (cell_j, cell): ([i32; 3], [i32; 3]),
        w: &[S],
        r2: f32,
        neighbour: f32,
    ) -> bool {
        // Combined without branches: most tests fail, unpredictably.
        let same = (cell_j[0] == cell[0]) & (cell_j[1] == cell[1]) & (cell_j[2] == cell[2]);
        same & ((a_i - a_j).length_squared() < r2)
            && !(w[i] == S::zero() && w[j] == S::zero())
            && (sc.rest[i] - sc.rest[j]).length() > neighbour
    }

    /// Every particle's candidates from the references.
    fn find<S: Real>(&mut self, w: &[S], sc: &SelfCollision) {
        self.hash(sc);
        let n = self.at.len();
        let size = table_size(n);
        self.lists.resize(n * CAPACITY, 0);
        self.counts.clear();
        self.counts.resize(n, 0);
        self.dropped = 0;
        let (r2, neighbour) = limits(sc);
        // Each pair once, into both lists (each list ends with the same lowest indices in
        // increasing order whatever the order they come in): from each particle, its own cell
        // for the particles above it, and half of the 26 cells around it (the other half finds
        // it from theirs). Particles are taken in bucket order, so a run of particles of one
        // cell looks its stencil's buckets up once.
        let mut runs = [([0; 3], (0, 0)); 14];
        let mut last = None;
        for k in 0..n {
            let i = self.sorted[k] as usize;
            let (a_i, c) = self.sorted_at[k];
            if last != Some(c) {
                last = Some(c);
                for (run, d) in runs.iter_mut().zip(STENCIL) {
                    let cell = [c[0] + d[0], c[1] + d[1], c[2] + d[2]];
                    let b = bucket(cell, size);
                    *run = (cell, (self.start[b] as usize, self.start[b + 1] as usize));
                }
            }
            for (o, &(cell, (from, to))) in runs.iter().enumerate() {
                for (&j, &(a_j, cell_j)) in self.sorted[from..to].iter().zip(&self.sorted_at[from..to]) {
                    let ju = j as usize;
                    if (o == 0 && ju <= i) || !Self::pairs_up(sc, (i, ju), (a_i, a_j), (cell_j, cell), w, r2, neighbour)
                    {
                        continue;
                    }
                    for (a, b) in [(i, j), (ju, i as u32)] {
                        let list = &mut self.lists[a * CAPACITY..][..CAPACITY];
                        self.dropped += push(list, &mut self.counts[a], b) as u64;
                    }
                }
            }
        }
        for i in 0..n {
            self.lists[i * CAPACITY..][..self.counts[i] as usize].sort_unstable();
        }
        self.flatten();
    }

    /// The candidates of the particles that strayed found anew, each taken out of its old
    /// partners' lists and put into its new partners'; every other pair stands, as its
    /// references do. `false`, leaving the lists to [`SelfPairs::find`], where a list was or
    /// would be full (the lowest indices kept then depend on the candidates dropped).
    fn refind<S: Real>(&mut self, w: &[S], sc: &SelfCollision) -> bool {
        if self.dropped > 0 {
            return false;
        }
        self.hash(sc);
        let n = self.at.len();
        let size = table_size(n);
        self.is_strayed.clear();
        self.is_strayed.resize(n, false);
        for &i in &self.strayed {
            self.is_strayed[i as usize] = true;
        }
        for &i in &self.strayed {
            let i = i as usize;
            for k in 0..self.counts[i] as usize {
                let p = self.lists[i * CAPACITY + k] as usize;
                if !self.is_strayed[p] {
                    remove(&mut self.lists[p * CAPACITY..][..CAPACITY], &mut self.counts[p], i as u32);
                }
            }
        }
        for &i in &self.strayed {
            self.counts[i as usize] = 0;
        }
        let (r2, neighbour) = limits(sc);
        // A pair of two strayed particles once, from the lower index.
        for &i in &self.strayed {
            let i = i as usize;
            let (a_i, c) = (self.at[i], self.cells[i]);
            for d in &AROUND {
                let cell = [c[0] + d[0], c[1] + d[1], c[2] + d[2]];
                let b = bucket(cell, size);
                let (from, to) = (self.start[b] as usize, self.start[b + 1] as usize);
                for (&j, &(a_j, cell_j)) in self.sorted[from..to].iter().zip(&self.sorted_at[from..to]) {
                    let ju = j as usize;
                    if ju == i
                        || (self.is_strayed[ju] && ju < i)
                        || !Self::pairs_up(sc, (i, ju), (a_i, a_j), (cell_j, cell), w, r2, neighbour)
                    {
                        continue;
                    }
                    let mine = push(&mut self.lists[i * CAPACITY..][..CAPACITY], &mut self.counts[i], j);
                    let theirs = &mut self.lists[ju * CAPACITY..][..CAPACITY];
                    let other = if self.is_strayed[ju] {
                        push(theirs, &mut self.counts[ju], i as u32)
                    } else {
                        insert(theirs, &mut self.counts[ju], i as u32)
                    };
                    if mine || other {
                        return false;
                    }
                }
            }
        }
        for &i in &self.strayed {
            let i = i as usize;
            self.lists[i * CAPACITY..][..self.counts[i] as usize].sort_unstable();
        }
        self.flatten();
        true
    }

    /// The pairs `(i, j)`, `i < j`, in increasing order, from the lists.
    fn flatten(&mut self) {
        self.near.invalidate();
        self.gather_near = false;
        self.flat.clear();
        for i in 0..self.counts.len() {
            let list = &self.lists[i * CAPACITY..][..self.counts[i] as usize];
            self.flat.extend(list.iter().filter(|&&j| j as usize > i).map(|&j| [i as u32, j]));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stencil_holds_each_neighbouring_cell_or_its_mirror_once() {
        assert_eq!(STENCIL[0], [0, 0, 0]);
        for d in STENCIL[1..].iter() {
            let mirror = d.map(|v| -v);
            assert_eq!(STENCIL.iter().filter(|s| *s == d || **s == mirror).count(), 1, "{d:?}");
        }
        let mut all: Vec<_> = STENCIL.iter().flat_map(|d| [*d, d.map(|v| -v)]).collect();
        all.sort();
        all.dedup();
        assert_eq!(all.len(), 27);
    }

    #[test]
    fn a_full_list_keeps_the_lowest_indices_in_order() {
        let (mut list, mut count) = ([0u32; CAPACITY], 0u32);
        let mut dropped = 0;
        for j in (0..CAPACITY as u32 + 10).rev() {
            dropped += insert(&mut list, &mut count, 2 * j) as u32;
        }
        assert_eq!(count as usize, CAPACITY);
        assert_eq!(dropped, 10);
        assert!(list.iter().enumerate().all(|(k, &j)| j == 2 * k as u32), "{list:?}");
        assert!(insert(&mut list, &mut count, 1000), "beyond the kept ones: dropped");
        assert!(insert(&mut list, &mut count, 1) && list[1] == 1 && list[CAPACITY - 1] == 2 * (CAPACITY as u32 - 2));
        // Pushed in any order and sorted, the same list.
        let (mut pushed, mut n) = ([0u32; CAPACITY], 0u32);
        let mut dropped = 0;
        for j in (0..CAPACITY as u32 + 10).map(|j| (j * 5) % (CAPACITY as u32 + 10)) {
            dropped += push(&mut pushed, &mut n, 2 * j) as u32;
        }
        pushed.sort_unstable();
        assert_eq!((n as usize, dropped), (CAPACITY, 10));
        assert!(pushed.iter().enumerate().all(|(k, &j)| j == 2 * k as u32), "{pushed:?}");
        remove(&mut pushed, &mut n, 6);
        remove(&mut pushed, &mut n, 7);
        assert_eq!((n as usize, &pushed[2..4]), (CAPACITY - 1, &[4, 8][..]));
    }

    #[test]
    fn renewing_a_few_references_gives_the_lists_of_a_full_finding() {
        // Two 8 × 8 sheets 0.05 m apart, spacing 0.1 m; thickness 0.1 m (margin 0.0125 m).
        let sheet = |y: f32| (0..64).map(move |k| glam::Vec3::new((k % 8) as f32 * 0.1, y, (k / 8) as f32 * 0.1));
        let rest: Vec<glam::Vec3> = sheet(0.0).chain(sheet(1.0)).collect();
        let sc = SelfCollision { thickness: 0.1, friction: 0.0, rest };
        let x0: Vec<glam::Vec3A> = sheet(0.0).chain(sheet(0.05)).map(Into::into).collect();
        let w = vec![1.0f32; x0.len()];
        let mut pairs = SelfPairs::default();
        pairs.update(&x0, &w, &sc);
        // All moved by a common 0.3 m, a few by more than the margin besides, one of them by a
        // whole cell.
        let x1: Vec<glam::Vec3A> = x0
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let far = match i {
                    3 | 70 => glam::Vec3A::new(0.02, 0.0, -0.01),
                    100 => glam::Vec3A::new(0.0, -0.3, 0.0),
                    _ => glam::Vec3A::ZERO,
                };
                p + glam::Vec3A::splat(0.3) + far
            })
            .collect();
        pairs.update(&x1, &w, &sc);
        assert_eq!((pairs.builds(), pairs.strayed.len()), (2, 3));
        let mut full = SelfPairs { at: pairs.at.clone(), ..SelfPairs::default() };
        full.find(&w, &sc);
        assert_eq!(pairs.pairs(), full.pairs());
        for i in 0..x1.len() {
            assert_eq!(pairs.of(i), full.of(i), "particle {i}");
        }
        assert!(pairs.of(100).iter().all(|&j| j < 64), "particle 100 went down to the lower sheet");
    }

    #[test]
    fn the_mean_shift_is_summed_in_the_gpus_order() {
        let n = 200;
        let x: Vec<glam::Vec3A> = (0..n).map(|k| glam::Vec3A::splat(0.1 + k as f32 * 1e-3)).collect();
        let at = vec![glam::Vec3::ZERO; n];
        let mut lanes = [0.0f32; LANES];
        for (k, p) in x.iter().enumerate() {
            lanes[k % LANES] += p.x;
        }
        for s in [32, 16, 8, 4, 2, 1] {
            for l in 0..s {
                lanes[l] += lanes[l + s];
            }
        }
        let t = mean_shift(&x, &at, inv_count(n));
        assert_eq!(t.x.to_bits(), (lanes[0] * (1.0 / n as f32)).to_bits());
        assert!((t.x - (0.1 + 0.0995)).abs() < 1e-5, "{t}");
    }
}
