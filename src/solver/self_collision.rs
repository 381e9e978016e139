//! Cloth self-collision (docs/algorithm.md §3.1; after Müller's Ten-Minute Physics): particles
//! of a surface kept at least the thickness `d` apart. The CPU's stages; the GPU's twins are
//! `shaders/solver/self_collision.wgsl`, step for step.
//!
//! Once a substep, after the prediction, the candidates are checked ([`broad_phase`]): each
//! particle keeps a reference position while it stays within a margin `m = MARGIN × thickness`
//! of it (beyond the particles' mean displacement, so two moved at most `2m` towards each
//! other); one that strays takes its position as its reference, and its candidates are found
//! anew by a spatial hash of the references (counting sort of their cells: count, prefix sum,
//! scatter). Particle `i`'s candidates are every other particle whose reference is closer than
//! `r + 2m` to its own, `r = QUERY × thickness`, in increasing order, at most [`CAPACITY`] (the
//! lowest indices kept; the others counted as dropped). So every pair closer than `r` now is a
//! candidate, and a cloth in which few particles move fast keeps most of its candidates. Left
//! out: pairs whose rest distance is at most the thickness (neighbours in the mesh, which the
//! cloth's own constraints keep; to a rounding of 0.1 %) and pairs of two pinned particles.
//!
//! Every iteration then projects the candidates Jacobi-style, each particle against the same
//! iterate: a pair closer than `d` along its axis `n` gives particle `i` the share
//! `w_i / (w_i + w_j)` of the push `(d − |x_i − x_j|) n` apart, and the same share of the cut
//! of their relative tangential motion since the substep's start, at most `μ` times the depth
//! (Coulomb, as at the ground). A pair whose axis has turned by more than a right angle since
//! the substep's start, `(x_i − x_j)·(x⁰_i − x⁰_j) < 0`, has passed through itself along it: it
//! is pushed back along its start axis `n⁰` to the thickness, depth `d − (x_i − x_j)·n⁰`. Each
//! particle moves by the sum of its shares divided by `max(k / ω, 1)`, `k` its pairs in
//! contact and `ω` = [`OVER_RELAXATION`]. Both particles of a pair take their own share, so a
//! lone pair is pushed to the thickness in one pass. Particles alone stop a layer passing
//! through another while each substep's motion stays within a few thicknesses: a particle
//! passing between the four particles of a square of side `s` comes within `s/√2` of them, so a
//! thickness of at least `0.71 s` stops it, and one that passes a particle within a substep is
//! sent back by the passed-through rule.

pub mod broad_phase;
pub mod near;

pub use broad_phase::{bucket, cell, insert, inv_count, mean_shift};

use crate::math::prelude::*;
use crate::scene::SelfCollision;

/// The candidates' reach beyond the thickness within a substep, as a multiple of the thickness:
/// the room a pair has to close during one substep's iterations and still be found.
pub const QUERY: f32 = 1.25;
/// How far a particle may stray from its reference (beyond the particles' mean displacement)
/// before it takes a new one, as a multiple of the thickness. With [`QUERY`] it sets the reach
/// `r + 2m` (1.75 thicknesses), which is also the room a pair has to close within one substep:
/// at 0.125 (reach 1.5 thicknesses) the 64 × 64 `cloth-drape` at k = 1e6 N/m and one substep of
/// 30 iterations keeps 1 crossing pair (11 on the GPU) a moment after landing, where 0.25 keeps
/// none (with half the candidates to visit: 14,000 pairs against 26,600 at 30 × 1).
pub const MARGIN: f32 = 0.25;
/// When a check finds a particle beyond the margin, every particle beyond `KEEP` times the
/// margin renews its reference too, so that the particles about to stray do not each cost a
/// check of their own.
pub const KEEP: f32 = 0.5;
/// Candidates kept per particle. Within a reach of 1.75 thicknesses a particle between two
/// layers of cloth a thickness apart finds about 28 others at the default thickness (1.2 grid
/// spacings) and under 50 at the largest `--thickness` (1.5), so one that finds more is in a
/// pile denser than self-collision allows.
pub const CAPACITY: usize = 64;

/// The over-relaxation `ω` of the pass's averaging: a particle with `k` pairs in contact moves
/// by the sum of their shares divided by `max(k / ω, 1)` (Macklin et al. 2014, §4.2), never more
/// than the sum.
pub const OVER_RELAXATION: f32 = 2.0;

/// Relative tolerance on "rest distance at most the thickness" (dimensionless).
const REST_TOLERANCE: f32 = 1e-3;

/// Buckets of the hash for `n` particles: a power of two, at least twice `n` and at least 64
/// (the GPU's prefix sum splits the table into 64 equal runs).
pub fn table_size(n: usize) -> usize {
    (2 * n).next_power_of_two().max(64)
}

/// How far a particle may stray before the candidates are found anew (m): `m`.
pub fn margin(sc: &SelfCollision) -> f32 {
    MARGIN * sc.thickness
}

/// The candidates' reach when found (m): `r + 2m`.
pub fn reach(sc: &SelfCollision) -> f32 {
    QUERY * sc.thickness + 2.0 * margin(sc)
}

/// The distance below which two particles' rest positions make them mesh neighbours (m).
pub fn neighbour_distance(sc: &SelfCollision) -> f32 {
    sc.thickness * (1.0 + REST_TOLERANCE)
}

/// Each particle's candidates this substep, and the hash's scratch.
#[derive(Clone, Debug, Default)]
pub struct SelfPairs {
    /// Particle `i`'s candidates at `lists[i * CAPACITY..][..counts[i]]`, increasing.
    lists: Vec<u32>,
    counts: Vec<u32>,
    /// First entry of each hash bucket in `sorted` (one past the table: the end).
    start: Vec<u32>,
    /// Particle indices ordered by bucket.
    sorted: Vec<u32>,
    /// Their references (m) and cells, in the same order.
    sorted_at: Vec<(glam::Vec3, [i32; 3])>,
    cells: Vec<[i32; 3]>,
    /// Each particle's reference position (m; [`broad_phase`]).
    at: Vec<glam::Vec3>,
    /// The particles that strayed at the last check.
    strayed: Vec<u32>,
    /// Whether each particle strayed at the last check.
    is_strayed: Vec<bool>,
    /// Checks that renewed references (the first included).
    builds: u64,
    /// Candidates dropped beyond [`CAPACITY`] at the last finding.
    dropped: u64,
    /// Each particle's pairs in contact in the last pass.
    touching: Vec<u32>,
    /// Whether each particle moved at least half the thickness in the substep so far.
    fast: Vec<bool>,
    /// The candidate pairs `(i, j)`, `i < j`, in increasing order ([`SelfPairs::pairs`]), for
    /// the one-thread pass.
    flat: Vec<[u32; 2]>,
    /// Those of them near enough to touch, which the CPU's passes visit.
    near: near::NearPairs,
    /// The last [`SelfPairs::prepare`] found no fast particle: a pass may visit the near pairs
    /// only.
    gather_near: bool,
}

impl SelfPairs {
    /// Number of candidate pairs (each counted once).
    pub fn len(&self) -> usize {
        self.counts.iter().map(|&c| c as usize).sum::<usize>() / 2
    }

    /// `true` when there are no candidates.
    pub fn is_empty(&self) -> bool {
        self.counts.iter().all(|&c| c == 0)
    }

    /// Checks that renewed references and searched candidates anew (the first included).
    pub fn builds(&self) -> u64 {
        self.builds
    }

    /// Candidates dropped at the last finding because a particle had more than [`CAPACITY`].
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    /// Particle `i`'s candidates, in increasing order.
    pub fn of(&self, i: usize) -> &[u32] {
        &self.lists[i * CAPACITY..][..self.counts[i] as usize]
    }

    /// The candidate pairs `(i, j)`, `i < j`, in increasing order.
    pub fn pairs(&self) -> Vec<(u32, u32)> {
        self.flat.iter().map(|&[i, j]| (i, j)).collect()
    }

    /// One Jacobi pass over the candidates at positions `x` (substep start `x_prev`, inverse
    /// masses `w`) for `sc`'s thickness and friction, on one thread; `dx` is scratch. Each pair
    /// is visited once, from its lower index, and gives both particles their shares: each
    /// particle's sum then adds its pairs in increasing order of the other index, as
    /// [`SelfPairs::moves`] and the GPU's gather do, and each share is the same expression as
    /// there (negating a vector is exact), so the three agree to the bit. It visits only the
    /// [`near`] pairs while no particle moved half the thickness in the substep (the others
    /// are apart and leave the sums as they are).
    pub fn project<V: Vector>(&mut self, x: &mut [V], x_prev: &[V], w: &[V::S], sc: &SelfCollision, dx: &mut Vec<V>) {
        let pass = Pass::new(sc);
        dx.clear();
        dx.resize(x.len(), V::ZERO);
        self.touching.clear();
        self.touching.resize(x.len(), 0);
        self.prepare(x, x_prev, sc, false);
        let one = V::S::one();
        let pairs = if self.gather_near { self.near.pairs() } else { &self.flat };
        for &[i, j] in pairs {
            let (i, j) = (i as usize, j as usize);
            let d = x[i] - x[j];
            if d.dot(d) >= pass.keep2 && !self.fast[i] && !self.fast[j] {
                continue;
            }
            let Some(c) = pass.contact(d, x_prev[i] - x_prev[j], (x[i] - x_prev[i]) - (x[j] - x_prev[j])) else {
                continue;
            };
            for (a, b, sign) in [(i, j, one), (j, i, -one)] {
                if let Some(m) = c.share(w[a], w[b]) {
                    dx[a] += m * sign;
                    self.touching[a] += 1;
                }
            }
        }
        self.gather_near = false;
        for ((p, d), &k) in x.iter_mut().zip(dx.iter()).zip(&self.touching) {
            *p += pass.spread(*d, k);
        }
    }

    /// Readies a pass at positions `x` (substep start `x_prev`): marks the particles that moved
    /// at least half the thickness in the substep and, when none did, brings the [`near`] pairs
    /// up to date (with each particle's near partners when `by_particle`, for
    /// [`SelfPairs::moves`]). A pair farther apart than the thickness has passed through itself
    /// only if the two moved apart from each other by more than that (`|u_i − u_j| >
    /// |x_i − x_j|` when `(x_i − x_j)·(x⁰_i − x⁰_j) < 0`): never while both moved less than half
    /// of it, so then only the near pairs can give a move.
    pub fn prepare<V: Vector>(&mut self, x: &[V], x_prev: &[V], sc: &SelfCollision, by_particle: bool) {
        let keep = <V::S as From<f32>>::from(sc.thickness);
        let half2 = keep * keep * <V::S as From<f32>>::from(0.25);
        self.fast.clear();
        self.fast.extend(x.iter().zip(x_prev).map(|(p, q)| (*p - *q).length_squared() >= half2));
        self.gather_near = !self.fast.contains(&true);
        if self.gather_near {
            self.near.update(&self.flat, x, sc.thickness);
            if by_particle {
                self.near.by_particle(x.len());
            }
        }
    }

    /// The moves of particles `range` in one Jacobi pass at positions `x` (substep start
    /// `x_prev`, inverse masses `w`) into `out` (one per particle of `range`): each particle
    /// gathers its pairs' shares in increasing order of the other index, as the GPU's
    /// `self_project` does; the same moves as [`SelfPairs::project`] makes, range by range (for
    /// the threads of a team). Right after [`SelfPairs::prepare`] at the same positions with
    /// `by_particle`, each particle gathers over its near partners only (the same moves).
    pub fn moves<V: Vector>(
        &self,
        range: std::ops::Range<usize>,
        (x, x_prev, w): (&[V], &[V], &[V::S]),
        sc: &SelfCollision,
        out: &mut [V],
    ) {
        let pass = Pass::new(sc);
        let near = self.gather_near && self.near.by_particle_ready(self.counts.len());
        for (i, o) in range.zip(out.iter_mut()) {
            let (mut sum, mut k) = (V::ZERO, 0);
            if i < self.counts.len() && w[i] != V::S::zero() {
                let partners = if near { self.near.partners(i) } else { self.of(i) };
                for &j in partners {
                    let j = j as usize;
                    let moved = (x[i] - x_prev[i]) - (x[j] - x_prev[j]);
                    if let Some(m) =
                        pass.contact(x[i] - x[j], x_prev[i] - x_prev[j], moved).and_then(|c| c.share(w[i], w[j]))
                    {
                        sum += m;
                        k += 1;
                    }
                }
            }
            *o = pass.spread(sum, k);
        }
    }
}

/// The constants of one pass.
struct Pass<S> {
    keep: S,
    keep2: S,
    mu: S,
}

/// A pair in contact: its axis `n` (from the other particle towards this one), depth and
/// relative tangential displacement since the substep's start `t`, `|t|`.
struct Contact<V: Vector> {
    n: V,
    depth: V::S,
    t: V,
    tl: V::S,
    mu: V::S,
}

impl<S: Real> Pass<S> {
    fn new(sc: &SelfCollision) -> Self {
        let keep = <S as From<f32>>::from(sc.thickness);
        Pass { keep, keep2: keep * keep, mu: <S as From<f32>>::from(sc.friction) }
    }

    /// The contact of a pair `d = x_i − x_j` apart, `d0` at the substep's start, with relative
    /// displacement `moved` since then; `None` when apart. Passed through each other along
    /// their axis (`d·d0 < 0`): back along the start axis to the thickness.
    fn contact<V: Vector<S = S>>(&self, d: V, d0: V, moved: V) -> Option<Contact<V>> {
        let (zero, one) = (S::zero(), S::one());
        let (n, depth) = if d.dot(d0) < zero {
            let n0 = d0 * (one / d0.length());
            (n0, self.keep - d.dot(n0))
        } else {
            let dd = d.dot(d);
            if dd >= self.keep2 || dd <= zero {
                return None;
            }
            let dist = dd.sqrt();
            (d * (one / dist), self.keep - dist)
        };
        // Coulomb friction on the relative motion since the substep's start.
        let t = moved - n * moved.dot(n);
        Some(Contact { n, depth, tl: t.length(), t, mu: self.mu })
    }

    /// A particle's move from the sum `sum` of its `k` pairs' shares: `sum / max(k / ω, 1)`.
    fn spread<V: Vector<S = S>>(&self, sum: V, k: u32) -> V {
        if k == 0 {
            return V::ZERO;
        }
        let rho = <S as From<f32>>::from(1.0 / OVER_RELAXATION);
        sum * (S::one() / (<S as From<f32>>::from(k as f32) * rho).max(S::one()))
    }
}

impl<V: Vector> Contact<V> {
    /// The share of the particle of inverse mass `wa` (the other's `wb`): `n d wa/(wa + wb)` less
    /// the same share of the friction's cut `min(μ d, |t|)` along `t`; `None` when pinned.
    fn share(&self, wa: V::S, wb: V::S) -> Option<V> {
        let zero = V::S::zero();
        if wa == zero {
            return None;
        }
        let share = wa / (wa + wb);
        let mut c = self.n * (self.depth * share);
        if self.tl > zero {
            c -= self.t * ((self.mu * self.depth).min(self.tl) / self.tl * share);
        }
        Some(c)
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
        let found = pairs.pairs();
        assert_eq!(found, brute);
        assert_eq!(pairs.dropped(), 0);
        for i in 0..x.len() {
            assert!(pairs.of(i).windows(2).all(|p| p[0] < p[1]), "increasing");
            assert!(pairs.of(i).iter().all(|&j| pairs.of(j as usize).contains(&(i as u32))), "both ways");
        }
        assert!(found.iter().any(|&(i, j)| i < n * n && j >= n * n), "pairs across the layers");
        assert!(found.iter().all(|&(i, j)| sc.rest[i as usize].distance(sc.rest[j as usize]) > s), "no mesh neighbour");
    }

    #[test]
    fn the_gather_by_ranges_moves_every_particle_as_the_pass_does() {
        let (n, s) = (6u32, 0.1f32);
        let layer = (n * n) as usize;
        let rest = [sheet(n, s, 0.0), sheet(n, s, 1.0)].concat();
        let sc = SelfCollision { thickness: s, friction: 0.3, rest };
        // The upper layer 0.06 m above the lower, shifted, coming down from 0.2 m; three of its
        // particles started below the lower layer; one particle pinned, one heavier.
        let upper = |y: f32| sheet(n, s, y).into_iter().map(|p| p + Vec3::new(0.03, 0.0, 0.02));
        let x: Vec<Vec3A> = sheet(n, s, 0.0).into_iter().chain(upper(0.06)).map(Vec3A::from).collect();
        let mut x_prev: Vec<Vec3A> = sheet(n, s, 0.0).into_iter().chain(upper(0.2)).map(Vec3A::from).collect();
        for k in [7, 8, 14] {
            x_prev[layer + k].y = -0.05;
        }
        let mut w = vec![1.0f32; x.len()];
        (w[0], w[layer + 1]) = (0.0, 0.5);
        let mut pairs = SelfPairs::default();
        pairs.update(&x, &w, &sc);
        let mut moved = vec![Vec3A::ZERO; x.len()];
        let (low, high) = moved.split_at_mut(7);
        pairs.moves(0..7, (&x, &x_prev, &w), &sc, low);
        pairs.moves(7..x.len(), (&x, &x_prev, &w), &sc, high);
        let mut y = x.clone();
        pairs.project(&mut y, &x_prev, &w, &sc, &mut Vec::new());
        for i in 0..x.len() {
            assert_eq!(
                (x[i] + moved[i]).to_array().map(f32::to_bits),
                y[i].to_array().map(f32::to_bits),
                "particle {i}"
            );
        }
        assert_eq!(moved[0], Vec3A::ZERO, "pinned");
        assert!(moved.iter().filter(|m| m.length() > 1e-3).count() > 2 * layer - 4, "every free particle pushed");
        // The three came up through the lower layer within the substep: sent back down to their
        // side; the others are pushed up.
        assert!([7, 8, 14].iter().all(|&k| moved[layer + k].y < 0.0), "{:?}", &moved[layer..]);
        assert!([20, 21, 27].iter().all(|&k| moved[layer + k].y > 0.0), "{:?}", &moved[layer..]);
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
        pairs.project(&mut x, &prev, &w, &sc, &mut Vec::new());
        assert!((x[0].distance(x[1]) - 0.1).abs() < 1e-6);
        // The lighter particle (w = 3) moves three times as far.
        assert!((x[0].x + 0.015).abs() < 1e-6 && (x[1].x - 0.085).abs() < 1e-6, "{x:?}");
        // The push moved each particle 0.03 m from the mean shift (margin 0.025 m): both renew
        // their references; then they stand until one strays that far from the mean shift
        // again (moving one by 4 cm strays each by 2 cm from the mean shift, by 6 cm 3 cm).
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
