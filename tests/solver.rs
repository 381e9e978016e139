//! The CPU reference solver: convergence, Jacobi against Gauss-Seidel, long-run stability,
//! pins, contacts and settings validation.

use eapbd::constraints::{Form, SpringMaterial};
use eapbd::metrics::FrameStats;
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, Method, Settings};
use glam::{DVec3, Vec3};

fn solver<V: eapbd::math::Vector>(name: &str, opts: SceneOptions) -> CpuSolver<V> {
    CpuSolver::new(scene::build(name, &opts).expect("scene builds"))
}

#[test]
fn gauss_seidel_residual_decreases_with_iterations() {
    // From the same mid-fall state, one frame with more iterations leaves a smaller residual.
    // The default cloth is stiff (slow convergence); the soft one shows the rate.
    for (stiffness, factor) in [(1.0e4, 1.0), (100.0, 0.8)] {
        let mut base = solver::<Vec3>("cloth-paper", SceneOptions { stiffness, ..SceneOptions::default() });
        let s = Settings::default();
        for _ in 0..20 {
            base.step_frame(&s);
        }
        let mut last = f64::INFINITY;
        for iterations in [10, 30, 100] {
            let mut sv = base.clone();
            sv.step_frame(&Settings { iterations, ..s });
            let (rms, _) = sv.residual();
            assert!(rms < last * factor, "k {stiffness}, {iterations} iterations: residual {rms:.3e} vs {last:.3e}");
            last = rms;
        }
    }
}

/// Max distance between two position sets, relative to the cloth size (1 m).
fn max_distance(a: &[DVec3], b: &[DVec3]) -> f64 {
    a.iter().zip(b).map(|(a, b)| a.distance(*b)).fold(0.0, f64::max)
}

#[test]
fn jacobi_and_gauss_seidel_converge_to_the_same_step() {
    // One frame of a small, soft cloth in f64, from a swinging state. Both iterations drive the
    // residual C + α̃λ to zero. XPBD evaluates ∇C at each iterate, so the converged positions
    // depend slightly on the path; they agree to a small fraction of the step's correction.
    let opts = SceneOptions { resolution: Some(9), stiffness: 200.0, ..SceneOptions::default() };
    for form in [Form::Compliant, Form::Energy] {
        let mut base = solver::<DVec3>("cloth", opts);
        let s = Settings { form, substeps: 10, ..Settings::default() };
        for _ in 0..15 {
            base.step_frame(&s);
        }
        let run = |method, iterations| {
            let mut sv = base.clone();
            sv.step_frame(&Settings { method, iterations, jacobi_omega: 1.0, ..s });
            (sv.particles.x.clone(), sv.residual().0)
        };
        let (gs, r_gs) = run(Method::GaussSeidel, 3000);
        let (jac, r_jac) = run(Method::Jacobi, 10000);
        let (free, _) = run(Method::GaussSeidel, 0);
        assert!(r_gs < 1e-12 && r_jac < 1e-12, "{form:?}: residuals {r_gs:.2e} (GS), {r_jac:.2e} (Jacobi)");
        let correction = max_distance(&gs, &free);
        let d = max_distance(&gs, &jac);
        assert!(
            d < 0.1 * correction,
            "{form:?}: Jacobi and Gauss-Seidel differ by {d:.3e} m, correction {correction:.3e} m"
        );
        // Jacobi's partial iterates approach that point.
        let (jac_short, _) = run(Method::Jacobi, 10);
        assert!(max_distance(&jac_short, &gs) > 5.0 * d, "{form:?}: the test scene is too easy");
    }
}

#[test]
fn cloth_stays_finite_with_bounded_stretch_for_600_frames() {
    for material in [SpringMaterial::Hookean, SpringMaterial::StVK] {
        for form in [Form::Compliant, Form::Energy] {
            let mut sv = solver::<Vec3>("cloth-paper", SceneOptions { material, ..SceneOptions::default() });
            let s = Settings { form, ..Settings::default() };
            let mut worst = 0.0f64;
            for frame in 1..=600 {
                sv.step_frame(&s);
                if frame % 20 == 0 {
                    let st = FrameStats::measure(&sv, frame, 0.0);
                    assert!(st.is_finite(), "{material:?} {form:?}: non-finite at frame {frame}");
                    assert!(st.stretch_mean < 0.15, "{material:?} {form:?}: mean stretch {:.3}", st.stretch_mean);
                    worst = worst.max(st.stretch_max);
                }
            }
            assert!(sv.particles.x.iter().all(|x| x.is_finite()));
            // Unconverged Gauss-Seidel concentrates stretch at the pins (up to about 6 in the
            // energy form, 4 in the compliant form); a blow-up would be far beyond this bound.
            assert!(worst < 15.0, "{material:?} {form:?}: max stretch {worst:.2}");
        }
    }
}

#[test]
fn more_substeps_reduce_stretch() {
    let run = |substeps, iterations| {
        let mut sv = solver::<Vec3>("cloth-paper", SceneOptions::default());
        let s = Settings { substeps, iterations, ..Settings::default() };
        for _ in 0..120 {
            sv.step_frame(&s);
        }
        FrameStats::measure(&sv, 120, 0.0).stretch_mean
    };
    let (coarse, fine) = (run(1, 30), run(30, 1));
    assert!(fine < coarse / 3.0, "30x1 stretch {fine:.4} vs 1x30 {coarse:.4}");
}

#[test]
fn pinned_particles_never_move() {
    for method in [Method::GaussSeidel, Method::Jacobi] {
        let mut sv = solver::<Vec3>("cloth", SceneOptions::default());
        let pinned: Vec<usize> = (0..sv.particles.len()).filter(|&i| sv.particles.w[i] == 0.0).collect();
        assert_eq!(pinned.len(), 2);
        let start: Vec<Vec3> = pinned.iter().map(|&i| sv.particles.x[i]).collect();
        let s = Settings { method, damping: 0.5, constraint_damping: 0.01, ..Settings::default() };
        for _ in 0..200 {
            sv.step_frame(&s);
            for (k, &i) in pinned.iter().enumerate() {
                assert_eq!(sv.particles.x[i], start[k], "{method:?}: pinned particle {i} moved");
                assert_eq!(sv.particles.v[i], Vec3::ZERO);
            }
        }
    }
}

#[test]
fn cloth_rests_on_the_sphere_and_the_ground() {
    let mut sv = solver::<Vec3>("cloth-sphere", SceneOptions::default());
    let s = Settings::default();
    for _ in 0..300 {
        sv.step_frame(&s);
    }
    let sc = sv.scene().clone();
    let sphere = sc.spheres[0];
    for x in &sv.particles.x {
        assert!(x.y >= sc.contact_offset - 1e-4, "particle below the ground: {x}");
        assert!(
            x.distance(sphere.center) >= sphere.radius + sc.contact_offset - 1e-3,
            "particle inside the sphere: {x}"
        );
    }
    let top = sv.particles.x.iter().map(|x| x.y).fold(f32::MIN, f32::max);
    assert!((top - (2.0 * sphere.radius + sc.contact_offset)).abs() < 0.02, "cloth top at {top} m");
    let st = FrameStats::measure(&sv, 300, 0.0);
    assert!(st.kinetic < 1e-2, "cloth still moving: KE {}", st.kinetic);
}

#[test]
fn velocity_damping_removes_energy() {
    let run = |damping| {
        let mut sv = solver::<Vec3>("cloth-paper", SceneOptions::default());
        let s = Settings { damping, ..Settings::default() };
        for _ in 0..60 {
            sv.step_frame(&s);
        }
        FrameStats::measure(&sv, 60, 0.0).kinetic
    };
    assert!(run(5.0) < 0.5 * run(0.0));
}

#[test]
fn absurd_settings_and_options_are_rejected_with_a_reason() {
    let bad = [
        Settings { dt: -1.0, ..Settings::default() },
        Settings { dt: f32::NAN, ..Settings::default() },
        Settings { substeps: 0, ..Settings::default() },
        Settings { jacobi_omega: 2.5, ..Settings::default() },
        Settings { damping: -1.0, ..Settings::default() },
        Settings { energy_compliance: 0.0, ..Settings::default() },
    ];
    for s in bad {
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("invalid parameter --"), "{e}");
    }
    let e = scene::build("cloth", &SceneOptions { stiffness: -3.0, ..SceneOptions::default() }).unwrap_err();
    assert!(e.to_string().contains("--stiffness"), "{e}");
    let e = scene::build("cloth", &SceneOptions { resolution: Some(1), ..SceneOptions::default() }).unwrap_err();
    assert!(e.to_string().contains("--resolution"), "{e}");
    let e = scene::build("drape", &SceneOptions::default()).unwrap_err().to_string();
    assert!(e.contains("unknown scene 'drape'") && e.contains("cloth-paper"), "{e}");
}
