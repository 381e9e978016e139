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

mod elastic_account {
    use eapbd::constraints::Form;
    use eapbd::metrics::FrameStats;
    use eapbd::scene::{self, SceneOptions};
    use eapbd::solver::{CpuSolver, Settings};
    use glam::Vec3A;

    /// A 5×5 hanging cloth (k = 1000 N/m) after 200 frames of one substep.
    fn hanging(iterations: u32, form: Form) -> FrameStats {
        let opts = SceneOptions { resolution: Some(5), stiffness: 1e3, ..SceneOptions::default() };
        let mut sv = CpuSolver::<Vec3A>::new(scene::build("cloth", &opts).unwrap());
        let s = Settings { iterations, form, threads: 1, ..Settings::default() };
        for _ in 0..200 {
            sv.step_frame(&s);
        }
        FrameStats::measure(&sv, 200, 0.0)
    }

    #[test]
    fn a_converged_solve_leaves_nothing_unresolved() {
        let s = hanging(500, Form::Compliant);
        println!("500 iterations: held {:.4e} J, unresolved {:.4e} J", s.elastic, s.unresolved);
        assert!(s.elastic > 0.0);
        assert!(s.unresolved < 1e-4 * s.elastic, "held {:.4e} J, unresolved {:.4e} J", s.elastic, s.unresolved);
    }

    #[test]
    fn one_iteration_leaves_most_of_the_stretch_unresolved_and_out_of_the_total() {
        let s = hanging(1, Form::Compliant);
        println!("1 iteration: held {:.4e} J, unresolved {:.4e} J", s.elastic, s.unresolved);
        assert!(s.unresolved > 10.0 * s.elastic, "held {:.4e} J, unresolved {:.4e} J", s.elastic, s.unresolved);
        assert_eq!(s.total(), s.kinetic + s.gravitational + s.elastic);
        assert!((s.material() - (s.elastic + s.unresolved)).abs() <= 1e-12 * s.material());
    }

    #[test]
    fn the_energy_form_is_split_too() {
        let (converged, few) = (hanging(500, Form::Energy), hanging(2, Form::Energy));
        println!(
            "energy form: 500 iterations held {:.4e} J unresolved {:.4e} J; 2 iterations held {:.4e} J unresolved {:.4e} J",
            converged.elastic, converged.unresolved, few.elastic, few.unresolved
        );
        assert!(converged.is_finite() && few.is_finite());
        assert!(converged.unresolved < 0.2 * converged.material());
        assert!(few.unresolved > 0.9 * few.material());
    }

    #[test]
    fn before_a_step_everything_counts_as_held() {
        let opts = SceneOptions { resolution: Some(5), stiffness: 1e3, ..SceneOptions::default() };
        let sv = CpuSolver::<Vec3A>::new(scene::build("cloth-free", &opts).unwrap());
        let s = FrameStats::measure(&sv, 0, 0.0);
        assert!(s.elastic > 0.0, "cloth-free starts stretched");
        assert_eq!(s.unresolved, 0.0);
    }
}
