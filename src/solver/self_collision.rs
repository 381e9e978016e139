//! Cloth self-collision on the CPU (docs/algorithm.md §3.1; after Müller's Ten-Minute Physics):
//! particles of a surface kept at least the thickness `d` apart.
//!
//! Once a substep, after the prediction, the candidate pairs are checked: they hold while no
//! particle has moved more than a margin `m = MARGIN × thickness` since they were found (beyond
//! the particles' mean displacement, so two moved at most `2m` towards each other), else a
//! spatial hash of the particles (counting sort of their cells: count, prefix sum, scatter)
//! finds them anew, every pair closer than `r + 2m` with `r = QUERY × thickness`. So every pair
//! closer than `r` now was found, and a cloth that moves slowly keeps its pairs for many
//! substeps. Left out: pairs whose rest distance is at most the thickness (neighbours in the
//! mesh, which the cloth's own constraints keep; to a rounding of 0.1 %) and pairs of two pinned
//! particles. Every iteration then projects the candidates in order, Gauss-Seidel: a pair closer
//! than `d` is pushed apart along its axis `n` by `d − |x_i − x_j|`, shared by inverse mass, and
//! its relative tangential motion since the substep's start is cut by at most `μ` times that
//! depth (Coulomb, as at the ground). Many substeps keep each substep's motion well under the thickness, which
//! is what lets particles alone stop a layer passing through another: a particle passing between
//! the four particles of a square of side `s` comes within `s/√2` of them, so a thickness of at
//! least `0.71 s` stops it.

use crate::math::prelude::*;
use crate::scene::SelfCollision;

/// The candidates' reach beyond the thickness within a substep, as a multiple of the thickness:
/// the room a pair has to close during one substep's iterations and still be found.
pub const QUERY: f32 = 1.25;
/// How far a particle may move before the pairs are found anew, as a multiple of the thickness.
pub const MARGIN: f32 = 0.25;

/// Relative tolerance on "rest distance at most the thickness" (dimensionless).
const REST_TOLERANCE: f32 = 1e-3;

/// A candidate pair (particle indices, `i < j`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pair {
    i: u32,
    j: u32,
}

/// The candidate pairs of the current substep and the hash's scratch.
#[derive(Clone, Debug, Default)]
pub struct SelfPairs {
    pairs: Vec<Pair>,
    /// First entry of each hash bucket in `sorted` (one past the table: the end).
    start: Vec<u32>,
    /// Particle indices ordered by bucket.
    sorted: Vec<u32>,
    cells: Vec<[i32; 3]>,
    /// The positions the pairs were found at (m).
    at: Vec<glam::Vec3>,
    /// Times the pairs were found.
    builds: u64,
}

/// The bucket of cell `c` in a table of `size` buckets (a power of two).
fn bucket(c: [i32; 3], size: usize) -> usize {
    let h = (c[0].wrapping_mul(92837111)) ^ (c[1].wrapping_mul(689287499)) ^ (c[2].wrapping_mul(283923481));
    (h as u32 as usize) & (size - 1)
}

impl SelfPairs {
    /// Number of candidate pairs this substep.
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// `true` when there are no candidates.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// Times the pairs have been found (the broad phase's runs).
    pub fn builds(&self) -> u64 {
        self.builds
    }

    /// Makes the pairs valid at positions `x`: found anew where some particle has moved more
    /// than the margin since they were found, not counting the mean displacement (a common
    /// translation moves no pair closer).
    pub fn update<V: Vector>(&mut self, x: &[V], w: &[V::S], sc: &SelfCollision) {
        let m = MARGIN * sc.thickness;
        let stale = self.at.len() != x.len() || {
            let shift: glam::Vec3 =
                x.iter().zip(&self.at).map(|(p, q)| p.to_vec3() - *q).sum::<glam::Vec3>() / x.len().max(1) as f32;
            x.iter().zip(&self.at).any(|(p, q)| (p.to_vec3() - *q - shift).length_squared() > m * m)
        };
        if stale {
            self.find(x, w, sc, QUERY * sc.thickness + 2.0 * m);
            self.at.clear();
            self.at.extend(x.iter().map(|p| p.to_vec3()));
            self.builds += 1;
        }
    }

    /// The candidate pairs at positions `x` (the broad phase): those closer than `r` (m), each
    /// once, `i < j`, in increasing order of `i`.
    fn find<V: Vector>(&mut self, x: &[V], w: &[V::S], sc: &SelfCollision, r: f32) {
        let n = x.len();
        let size = (2 * n.max(1)).next_power_of_two();
        self.cells.clear();
        self.cells.extend(x.iter().map(|p| {
            let p = p.to_vec3() / r;
            [p.x.floor() as i32, p.y.floor() as i32, p.z.floor() as i32]
        }));
        // Counting sort by bucket.
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
        self.pairs.clear();
        let (r2, zero) = (r * r, V::S::zero());
        // Rest distances up to the thickness, to rounding (a grid's neighbours at the default
        // thickness, its spacing, sit exactly there).
        let neighbour = sc.thickness * (1.0 + REST_TOLERANCE);
        for i in 0..n {
            let c = self.cells[i];
            let xi = x[i].to_vec3();
            for dz in -1..=1 {
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        let cell = [c[0] + dx, c[1] + dy, c[2] + dz];
                        let b = bucket(cell, size);
                        for &j in &self.sorted[self.start[b] as usize..self.start[b + 1] as usize] {
                            let j = j as usize;
                            // Each pair once: from its lower index, and only in the cell the
                            // other particle is in (a bucket holds other cells' particles too).
                            if j <= i
                                || self.cells[j] != cell
                                || (w[i] == zero && w[j] == zero)
                                || xi.distance_squared(x[j].to_vec3()) >= r2
                            {
                                continue;
                            }
                            if sc.rest[i].distance(sc.rest[j]) > neighbour {
                                self.pairs.push(Pair { i: i as u32, j: j as u32 });
                            }
                        }
                    }
                }
            }
        }
    }

    /// One Gauss-Seidel pass over the candidates at positions `x` (substep start `x_prev`,
    /// inverse masses `w`) for `sc`'s thickness and friction.
    pub fn project<V: Vector>(&self, x: &mut [V], x_prev: &[V], w: &[V::S], sc: &SelfCollision) {
        let mu = <V::S as From<f32>>::from(sc.friction);
        let keep = <V::S as From<f32>>::from(sc.thickness);
        for p in &self.pairs {
            let (i, j) = (p.i as usize, p.j as usize);
            let d = x[i] - x[j];
            let dist = d.length();
            if dist >= keep || dist <= V::S::zero() {
                continue;
            }
            let ws = w[i] + w[j];
            let n = d * (V::S::one() / dist);
            let depth = keep - dist;
            let (ai, aj) = (w[i] / ws, w[j] / ws);
            x[i] += n * (depth * ai);
            x[j] -= n * (depth * aj);
            // Coulomb friction on the relative motion since the substep's start.
            let rel = (x[i] - x_prev[i]) - (x[j] - x_prev[j]);
            let t = rel - n * rel.dot(n);
            let tl = t.length();
            if tl > V::S::zero() {
                let cut = t * ((mu * depth).min(tl) / tl);
                x[i] -= cut * ai;
                x[j] += cut * aj;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec3, Vec3A};

    fn sheet(n: u32, spacing: f32, y: f32) -> Vec<Vec3> {
        (0..n * n).map(|k| Vec3::new((k % n) as f32 * spacing, y, (k / n) as f32 * spacing)).collect()
    }

    #[test]
    fn the_broad_phase_finds_every_close_pair_of_two_layers_and_no_neighbour() {
        let (n, s) = (6u32, 0.1f32);
        let rest = [sheet(n, s, 0.0), sheet(n, s, 1.0)].concat();
        let sc = SelfCollision { thickness: s, friction: 0.0, rest };
        // The upper layer lowered to 0.05 m above the lower, shifted by a quarter cell.
        let x: Vec<Vec3A> =
            [sheet(n, s, 0.0), sheet(n, s, 0.05).iter().map(|p| *p + Vec3::new(0.025, 0.0, 0.0)).collect()]
                .concat()
                .into_iter()
                .map(Vec3A::from)
                .collect();
        let w = vec![1.0f32; x.len()];
        let mut pairs = SelfPairs::default();
        pairs.update(&x, &w, &sc);
        let r = (QUERY + 2.0 * MARGIN) * s;
        let mut brute = Vec::new();
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                if x[i].distance(x[j]) < r && sc.rest[i].distance(sc.rest[j]) > s * (1.0 + REST_TOLERANCE) {
                    brute.push((i as u32, j as u32));
                }
            }
        }
        let mut found: Vec<(u32, u32)> = pairs.pairs.iter().map(|p| (p.i, p.j)).collect();
        found.sort_unstable();
        assert_eq!(found, brute);
        assert!(found.iter().any(|&(i, j)| i < n * n && j >= n * n), "pairs across the layers");
        assert!(found.iter().all(|&(i, j)| sc.rest[i as usize].distance(sc.rest[j as usize]) > s), "no mesh neighbour");
    }

    #[test]
    fn a_close_pair_is_pushed_to_the_thickness_by_inverse_mass() {
        let sc = SelfCollision { thickness: 0.1, friction: 0.0, rest: vec![Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)] };
        let mut x = vec![Vec3A::ZERO, Vec3A::new(0.04, 0.0, 0.0)];
        let prev = x.clone();
        let w = vec![1.0f32, 3.0];
        let mut pairs = SelfPairs::default();
        pairs.update(&x, &w, &sc);
        assert_eq!(pairs.len(), 1);
        pairs.project(&mut x, &prev, &w, &sc);
        assert!((x[0].distance(x[1]) - 0.1).abs() < 1e-6);
        // The lighter particle (w = 3) moves three times as far.
        assert!((x[0].x + 0.015).abs() < 1e-6 && (x[1].x - 0.085).abs() < 1e-6, "{x:?}");
        // The push moved the particles 0.03 m apart beyond their mean shift (margin 0.025 m):
        // found anew; then they stand until one strays that far from the mean shift again.
        pairs.update(&x, &w, &sc);
        assert_eq!(pairs.builds(), 2);
        x[1].x += 0.04;
        pairs.update(&x, &w, &sc);
        assert_eq!(pairs.builds(), 2);
        x[1].x += 0.02;
        pairs.update(&x, &w, &sc);
        assert_eq!(pairs.builds(), 3);
    }
}
