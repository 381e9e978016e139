//! The stretch measures of the benchmark: the grid edges of a cloth, without its diagonals.

use eapbd::metrics::{axis_aligned_edges, stretch};
use eapbd::scene::{self, SceneOptions};

#[test]
fn axis_aligned_edges_are_the_warp_and_weft_of_the_grid() {
    for n in [41u32, 64] {
        let s = scene::build("cloth", &SceneOptions { resolution: Some(n), ..SceneOptions::default() }).unwrap();
        let (edges, rest) = axis_aligned_edges(&s);
        let n = n as usize;
        // n rows and n columns of n − 1 edges; the scene's edges add one diagonal per quad.
        assert_eq!(edges.len(), 2 * n * (n - 1));
        assert_eq!(s.edges.len(), 2 * n * (n - 1) + (n - 1) * (n - 1));
        let spacing = 1.0 / (n - 1) as f32;
        for (&[a, b], &l0) in edges.iter().zip(&rest) {
            assert!((l0 - spacing).abs() < 1e-6 * spacing.max(1.0), "edge {a}-{b}: rest {l0}, spacing {spacing}");
            let (a, b) = (a as usize, b as usize);
            assert!(a.abs_diff(b) == 1 || a.abs_diff(b) == n, "edge {a}-{b} is not a grid edge");
        }
    }
}

#[test]
fn grid_stretch_leaves_out_the_diagonals() {
    let s = scene::build("cloth", &SceneOptions { resolution: Some(3), ..SceneOptions::default() }).unwrap();
    let (edges, rest) = axis_aligned_edges(&s);
    // Stretch the grid by 10% along x only: warp edges stretch 10%, weft edges not at all.
    let x: Vec<glam::Vec3> = s.positions.iter().map(|p| glam::Vec3::new(p.x * 1.1, p.y, p.z)).collect();
    let (mean, max) = stretch(&edges, &rest, &x);
    assert!((mean - 0.05).abs() < 1e-6, "mean grid stretch {mean}");
    assert!((max - 0.1).abs() < 1e-6, "max grid stretch {max}");
    // Over every edge the diagonals' partial stretch enters the mean.
    let (all, _) = stretch(&s.edges, &s.edge_rest, &x);
    assert!((all - mean).abs() > 1e-4, "every edge {all}, grid edges {mean}");
}
