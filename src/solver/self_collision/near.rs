//! The CPU passes' near pairs: the candidates that can touch before any particle moves
//! [`NEAR_MARGIN`] thicknesses from where they were taken (beyond the particles' mean
//! displacement since then). Most candidates are a reach of 1.75 thicknesses apart and cannot
//! touch for many substeps; the pass visits only the near ones while they hold.
//!
//! Taken at positions `b`, the near pairs are the candidates with `|b_i − b_j| < d + 2m'`
//! (`d` the thickness, `m' = NEAR_MARGIN d`). While every particle is within `m'` of `b_i + T`
//! (`T` the mean of `x − b`), any other candidate is at least `d` apart, `|x_i − x_j| ≥
//! |b_i − b_j| − 2m'`, so the pass finds it apart and leaves it: visiting the near pairs only,
//! in the candidates' order, gives the same sums to the bit. A pair farther apart can still
//! have passed through itself within the substep; that needs a particle that moved at least
//! half the thickness in it, and then the pass visits every candidate.

use crate::math::prelude::*;

/// How far a particle may move from where the near pairs were taken (beyond the mean
/// displacement since then) before they are taken again, as a multiple of the thickness. The
/// near pairs' reach, `1.125 d`, stays below a flat sheet's diagonal neighbours at the default
/// thickness (`√2 h = 1.18 d` at `d = 1.2 h`), which are most of the candidates: on the 64 × 64
/// `cloth-drape` at 30 × 1, once it lies, the pass visits about 1,400 of 26,600 (the near pairs
/// taken about 8 times a frame over 300 frames). An eighth of the thickness takes the diagonals
/// in (about 9,000 pairs) and measured slower; a sixteenth and a thirty-second alike.
pub const NEAR_MARGIN: f32 = 0.0625;

/// Relative room on the near pairs' reach for the rounding of `f32` positions.
const ROUNDING: f32 = 1e-3;

/// The candidates near enough to touch, and where they were taken.
#[derive(Clone, Debug, Default)]
pub struct NearPairs {
    /// Positions when the near pairs were taken (m).
    at: Vec<glam::Vec3>,
    /// The candidates closer than `d + 2m'` then, in the candidates' order.
    pairs: Vec<[u32; 2]>,
    /// Whether the candidates changed since.
    stale: bool,
    /// Times the near pairs were taken.
    takes: u64,
    /// Each particle's near partners, increasing, at `partners[offsets[i]..offsets[i + 1]]`
    /// (for the threads of a team, which gather particle by particle); out of date while
    /// `by_particle_stale`.
    offsets: Vec<u32>,
    partners: Vec<u32>,
    by_particle_stale: bool,
}

impl NearPairs {
    /// Marks the near pairs out of date (the candidates changed).
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// Times the near pairs were taken.
    pub fn takes(&self) -> u64 {
        self.takes
    }

    /// Makes the near pairs those of `candidates` that can touch at positions `x` for thickness
    /// `d` (m): taken again when the candidates changed or a particle strayed more than `m'`
    /// from where they were taken, beyond the mean displacement.
    pub fn update<V: Vector>(&mut self, candidates: &[[u32; 2]], x: &[V], d: f32) {
        let m = NEAR_MARGIN * d;
        if self.stale || self.at.len() != x.len() || self.strayed(x, m) {
            self.take(candidates, x, d + 2.0 * m);
        }
    }

    /// The near pairs `(i, j)`, `i < j`, in the candidates' order.
    pub fn pairs(&self) -> &[[u32; 2]] {
        &self.pairs
    }

    /// Sorts the near pairs into each of `n` particles' partners ([`NearPairs::partners`]).
    /// The candidates come in increasing order of `(i, j)`, so a particle meets its partners
    /// below it (from their rows) before those above it (from its own), each in increasing order.
    pub fn by_particle(&mut self, n: usize) {
        if self.by_particle_ready(n) {
            return;
        }
        self.offsets.clear();
        self.offsets.resize(n + 1, 0);
        for &[i, j] in &self.pairs {
            self.offsets[i as usize + 1] += 1;
            self.offsets[j as usize + 1] += 1;
        }
        for k in 0..n {
            self.offsets[k + 1] += self.offsets[k];
        }
        self.partners.resize(self.offsets[n] as usize, 0);
        // Each particle's next free slot: `offsets` moved on by one particle as it fills.
        for &[i, j] in &self.pairs {
            for (a, b) in [(i, j), (j, i)] {
                let slot = &mut self.offsets[a as usize];
                self.partners[*slot as usize] = b;
                *slot += 1;
            }
        }
        // Every particle's slot ended at the next one's start: shift back.
        self.offsets.copy_within(0..n, 1);
        self.offsets[0] = 0;
        self.by_particle_stale = false;
    }

    /// Whether each of `n` particles' partners are sorted out for the near pairs as they are.
    pub fn by_particle_ready(&self, n: usize) -> bool {
        !self.by_particle_stale && self.offsets.len() == n + 1
    }

    /// Particle `i`'s near partners, increasing ([`NearPairs::by_particle`] first).
    pub fn partners(&self, i: usize) -> &[u32] {
        &self.partners[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Whether some particle is farther than `m` (m) from where the pairs were taken, beyond
    /// the mean displacement.
    fn strayed<V: Vector>(&self, x: &[V], m: f32) -> bool {
        let sum = x.iter().zip(&self.at).fold(glam::Vec3::ZERO, |s, (p, a)| s + (p.to_vec3() - *a));
        let shift = sum / x.len().max(1) as f32;
        let m2 = m * m * (1.0 - ROUNDING);
        x.iter().zip(&self.at).any(|(p, a)| (p.to_vec3() - *a - shift).length_squared() > m2)
    }

    /// Takes the candidates closer than `reach` (m) at `x`.
    fn take<V: Vector>(&mut self, candidates: &[[u32; 2]], x: &[V], reach: f32) {
        self.at.clear();
        self.at.extend(x.iter().map(|p| p.to_vec3()));
        let r2 = (reach * (1.0 + ROUNDING)).powi(2);
        let at = &self.at;
        self.pairs.clear();
        self.pairs.extend(candidates.iter().filter(|&&[i, j]| (at[i as usize] - at[j as usize]).length_squared() < r2));
        self.stale = false;
        self.by_particle_stale = true;
        self.takes += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::super::SelfPairs;
    use crate::scene::SelfCollision;
    use glam::{Vec3, Vec3A};
    use rand::rngs::SmallRng;
    use rand::{Rng, SeedableRng};

    #[test]
    fn the_passes_over_the_near_pairs_move_every_particle_as_the_pass_over_all_candidates() {
        // Two 8 × 8 sheets, spacing and thickness 0.1 m, 0.09 m apart and shifted: pairs across
        // them touch. They wander by up to 4 mm a step (less than half the thickness), so the
        // near pairs are taken again now and then, and the candidates renewed.
        let sheet = |y: f32| (0..64).map(move |k| Vec3::new((k % 8) as f32 * 0.1, y, (k / 8) as f32 * 0.1));
        let rest: Vec<Vec3> = sheet(0.0).chain(sheet(1.0)).collect();
        let sc = SelfCollision { thickness: 0.1, friction: 0.2, rest };
        let mut x: Vec<Vec3A> =
            sheet(0.0).chain(sheet(0.09).map(|p| p + Vec3::new(0.03, 0.0, 0.02))).map(Vec3A::from).collect();
        let mut w = vec![1.0f32; x.len()];
        (w[0], w[70]) = (0.0, 0.5);
        let mut rng = SmallRng::seed_from_u64(7);
        let mut pairs = SelfPairs::default();
        let (mut visited, mut candidates, mut pushed, mut near_gathers) = (0, 0, 0, 0);
        for step in 0..60 {
            let x_prev = x.clone();
            for p in &mut x {
                *p += Vec3A::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0))
                    * 0.0023;
            }
            pairs.update(&x, &w, &sc);
            let mut all = vec![Vec3A::ZERO; x.len()];
            pairs.moves(0..x.len(), (&x, &x_prev, &w), &sc, &mut all);
            let mut y = x.clone();
            pairs.project(&mut y, &x_prev, &w, &sc, &mut Vec::new());
            // A team's threads: readied, then each particle over its near partners.
            pairs.prepare(&x, &x_prev, &sc, true);
            near_gathers += usize::from(pairs.gather_near);
            let mut gathered = vec![Vec3A::ZERO; x.len()];
            pairs.moves(0..x.len(), (&x, &x_prev, &w), &sc, &mut gathered);
            for i in 0..x.len() {
                let expected = (x[i] + all[i]).to_array().map(f32::to_bits);
                assert_eq!(y[i].to_array().map(f32::to_bits), expected, "step {step}, particle {i}");
                assert_eq!(gathered[i].to_array().map(f32::to_bits), all[i].to_array().map(f32::to_bits), "{i}");
            }
            pushed += x.iter().zip(&y).filter(|(a, b)| a != b).count();
            visited += pairs.near.pairs.len();
            candidates += pairs.flat.len();
            x = y;
        }
        assert!(pushed > 60 * 10, "pushed {pushed}");
        assert_eq!(near_gathers, 60, "no particle moved half the thickness");
        assert!(pairs.near.takes() > 5 && pairs.near.takes() < 60, "taken {} times", pairs.near.takes());
        assert!(pairs.builds() > 2, "renewed {} times", pairs.builds());
        assert!(2 * visited < candidates, "visited {visited} of {candidates}");
    }
}
