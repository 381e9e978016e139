//! Mesh coloring: valid partitions on the cloth and on random graphs, and the solve order.

use eapbd::coloring::{self, Incidence};
use eapbd::mesh::{Diagonals, dihedral_pairs, grid, unique_edges};
use eapbd::scene::{self, SceneOptions};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

#[test]
fn cloth_springs_and_bending_are_validly_colored() {
    for diagonals in [Diagonals::Uniform, Diagonals::Alternating] {
        let mesh = grid(41, 1.0, 0.0, diagonals);
        let n = mesh.positions.len();
        let edges = unique_edges(&mesh.triangles);
        assert_eq!(edges.len(), 4880, "the paper's cloth has 4880 edges");
        let c = coloring::color(n, &edges);
        c.validate(n, &edges).unwrap();
        let s = c.stats();
        // Interior particles touch 6 springs (uniform) or alternately 4 and 8 (alternating), so
        // at least 6 or 8 colors are needed.
        match diagonals {
            Diagonals::Uniform => {
                assert!((6..=8).contains(&s.colors), "{s}");
                assert!(s.max_group - s.min_group <= s.max_group / 10, "unbalanced groups: {s}");
            }
            Diagonals::Alternating => assert!((8..=10).contains(&s.colors), "{s}"),
        }

        let hinges = dihedral_pairs(&mesh.triangles);
        assert_eq!(hinges.len(), 4880 - 4 * 40, "one hinge per interior edge");
        let c = coloring::color(n, &hinges);
        c.validate(n, &hinges).unwrap();
    }
}

#[test]
fn alternating_diagonals_form_a_checkerboard_facing_up() {
    let n = 5u32;
    let mesh = grid(n, 1.0, 0.0, Diagonals::Alternating);
    let edges = unique_edges(&mesh.triangles);
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = i + n * j;
            let (b, c, d) = (a + 1, a + n, a + n + 1);
            let has = |p: u32, q: u32| edges.contains(&[p.min(q), p.max(q)]);
            // Quad (i, j): the diagonal b–c where i + j is even, a–d where it is odd, never both.
            let odd = (i + j) % 2 == 1;
            assert_eq!((has(b, c), has(a, d)), (!odd, odd), "quad ({i}, {j})");
        }
    }
    for t in &mesh.triangles {
        let [p, q, r] = t.map(|k| mesh.positions[k as usize]);
        let normal = (q - p).cross(r - p);
        assert!(normal.y > 0.0 && normal.x.abs() < 1e-6 && normal.z.abs() < 1e-6, "triangle {t:?} faces {normal}");
    }
    // The scene builds it on request, and only for cloth scenes.
    let o = SceneOptions { resolution: Some(n), diagonals: Diagonals::Alternating, ..SceneOptions::default() };
    assert_eq!(scene::build("cloth", &o).unwrap().triangles, mesh.triangles);
    let err = scene::build("beam", &o).unwrap_err().to_string();
    assert!(err.contains("--diagonals"), "{err}");
}

#[test]
fn random_graphs_are_validly_colored() {
    let mut rng = SmallRng::seed_from_u64(11);
    for (np, ne) in [(10usize, 40usize), (1000, 20_000), (5000, 20_000)] {
        let edges: Vec<[u32; 2]> = (0..ne)
            .map(|_| {
                let a = rng.random_range(0..np as u32);
                [a, (a + rng.random_range(1..np as u32)) % np as u32]
            })
            .collect();
        let c = coloring::color(np, &edges);
        c.validate(np, &edges).unwrap();
        // Every element in exactly one group of the solve order.
        let (perm, ranges) = c.order();
        let mut seen = vec![0u32; ne];
        for (color, r) in ranges.iter().enumerate() {
            for &j in &perm[r.start as usize..r.end as usize] {
                assert_eq!(c.color_of[j as usize], color as u32);
                seen[j as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&s| s == 1), "an element is missing or repeated in the order");
        // First fit never needs more than max degree + 1 colors.
        let inc = Incidence::new(np, &edges);
        let max_deg = (0..np).map(|p| inc.degree(p)).max().unwrap_or(0);
        assert!(c.num_colors <= max_deg + 1, "{} colors for max degree {max_deg}", c.num_colors);
    }
}

#[test]
fn dense_graph_needs_more_than_64_colors_and_gets_them() {
    // A complete graph on 80 particles needs 80 colors (one layer of masks holds 64).
    let np = 80u32;
    let edges: Vec<[u32; 2]> = (0..np).flat_map(|a| (a + 1..np).map(move |b| [a, b])).collect();
    let c = coloring::color(np as usize, &edges);
    c.validate(np as usize, &edges).unwrap();
    assert!(c.num_colors >= 79, "{} colors", c.num_colors);
}

#[test]
fn validate_reports_a_conflict() {
    let edges = [[0u32, 1], [1, 2]];
    let bad = coloring::Coloring { color_of: vec![0, 0], num_colors: 1 };
    let err = bad.validate(3, &edges).unwrap_err();
    assert!(err.contains("share particle 1"), "{err}");
}

/// Asserts that `ranges` cover `idx` from 0 to its end and no range has a particle twice.
fn assert_color_groups(name: &str, idx: &[Vec<u32>], ranges: &[std::ops::Range<u32>]) {
    assert_eq!(ranges.first().map(|r| r.start), Some(0), "{name}");
    assert_eq!(ranges.last().map(|r| r.end as usize), Some(idx.len()), "{name}");
    for r in ranges {
        let mut used = std::collections::HashSet::new();
        for e in &idx[r.start as usize..r.end as usize] {
            for p in e {
                assert!(used.insert(*p), "{name}: particle {p} twice in one color group");
            }
        }
    }
}

#[test]
fn scene_families_are_stored_in_color_order() {
    // Every family kind: springs and bending (cloth), membrane triangles (aniso-cloth),
    // volumetric and centroid tetrahedra (cube).
    let s = scene::build("cloth", &SceneOptions::default()).unwrap();
    let f = s.springs.as_ref().unwrap();
    assert_color_groups("springs", &f.elements.iter().map(|e| vec![e.a, e.b]).collect::<Vec<_>>(), &f.colors);
    let f = s.bends.as_ref().unwrap();
    assert_color_groups("bending", &f.elements.iter().map(|e| e.p.to_vec()).collect::<Vec<_>>(), &f.colors);
    let membrane = Some(eapbd::constraints::Orthotropic::new(1e3, 1e2, None, 0.2).unwrap());
    let s = scene::build("cloth", &SceneOptions { membrane, ..SceneOptions::default() }).unwrap();
    let f = s.membranes.as_ref().unwrap();
    assert_color_groups("membranes", &f.elements.iter().map(|e| e.p.to_vec()).collect::<Vec<_>>(), &f.colors);
    for tets in [scene::TetMode::Volume, scene::TetMode::Centroid] {
        let s = scene::build("cube", &SceneOptions { tets, ..SceneOptions::default() }).unwrap();
        let f = s.tets.as_ref().unwrap();
        let idx: Vec<Vec<u32>> = f.elements.iter().map(|e| e.p.to_vec()).collect();
        assert_color_groups(&format!("{tets:?} tetrahedra"), &idx, &f.colors);
    }
}
