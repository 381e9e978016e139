//! The cost of mesh coloring on a million elements.

use std::time::Instant;

use eapbd::coloring;
use eapbd::mesh::{Diagonals, grid, unique_edges};
use rand::{Rng, SeedableRng};

/// One coloring case: the best time of some repetitions.
#[derive(Clone, Debug, PartialEq)]
pub struct ColoringRow {
    /// What was colored.
    pub name: String,
    /// Elements (2-particle edges).
    pub elements: usize,
    /// Particles.
    pub particles: usize,
    /// Colors used.
    pub colors: u32,
    /// Smallest and largest color group.
    pub groups: (u32, u32),
    /// Best wall time (ms).
    pub ms: f64,
}

/// The grid edges of a 578×578 cloth (999,941 edges) and a random graph of 1,000,000 edges over
/// 200,000 particles, each colored `reps` times.
pub fn run(reps: u32) -> Vec<ColoringRow> {
    let cloth = grid(578, 1.0, 0.0, Diagonals::Uniform);
    let edges = unique_edges(&cloth.triangles);
    let mut out = vec![case("cloth grid edges (578×578 grid)", cloth.positions.len(), &edges, reps)];
    let mut rng = rand::rngs::SmallRng::seed_from_u64(7);
    let np = 200_000u32;
    let random: Vec<[u32; 2]> = (0..1_000_000)
        .map(|_| {
            let a = rng.random_range(0..np);
            let b = (a + rng.random_range(1..np)) % np;
            [a, b]
        })
        .collect();
    out.push(case("random graph edges", np as usize, &random, reps));
    out
}

fn case(name: &str, particles: usize, elements: &[[u32; 2]], reps: u32) -> ColoringRow {
    let mut best = f64::INFINITY;
    let mut stats = None;
    for _ in 0..reps.max(1) {
        let t0 = Instant::now();
        let c = coloring::color(particles, elements);
        best = best.min(t0.elapsed().as_secs_f64() * 1e3);
        stats = Some(c.stats());
    }
    let (colors, groups) = stats.map_or((0, (0, 0)), |s| (s.colors, (s.min_group, s.max_group)));
    ColoringRow { name: name.to_string(), elements: elements.len(), particles, colors, groups, ms: best }
}
