//! The GPU solver against the CPU reference on the same scenes: same color order, same
//! arithmetic in f32, so trajectories agree to a small fraction of the cloth size (1 m). The GPU
//! compiler may fuse multiply-adds, so the two differ by rounding from the first frame; a cloth
//! without bending crumples chaotically under gravity and amplifies that rounding to centimetres
//! within 100 frames, so the 120-frame comparisons use the `cloth` scene, whose bending keeps the
//! motion regular. These tests need a GPU adapter (Mesa lavapipe in CI) and fail without one.

use std::sync::Arc;

use eapbd::constraints::{Form, SpringMaterial};
use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, Method, Settings};
use glam::Vec3;

fn context() -> GpuContext {
    GpuContext::new().unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"))
}

/// Runs `frames` frames on both backends; returns the largest particle distance (m) seen at the
/// checkpoints, and the CPU's final positions.
fn compare(
    ctx: &GpuContext,
    kernels: &Arc<Kernels>,
    name: &str,
    opts: SceneOptions,
    s: &Settings,
    frames: u32,
) -> (f32, Vec<Vec3>) {
    let sc = scene::build(name, &opts).unwrap();
    let mut cpu = CpuSolver::<Vec3>::new(sc.clone());
    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc);
    let mut worst = 0.0f32;
    for frame in 1..=frames {
        cpu.step_frame(s);
        gpu.step_frame(s);
        if frame % 20 == 0 || frame == frames {
            let g = gpu.read_positions().unwrap();
            let d = cpu.particles.x.iter().zip(&g).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
            assert!(d.is_finite(), "{name}: non-finite at frame {frame}");
            worst = worst.max(d);
        }
    }
    (worst, cpu.particles.x.clone())
}

/// Tolerance on the particle distance (m), relative to the 1 m cloth: 1e-4.
const TOLERANCE: f32 = 1e-4;

#[test]
fn cloth_matches_the_cpu_for_every_material_form_and_method() {
    let ctx = context();
    let kernels = Arc::new(Kernels::new(&ctx.device));
    for material in [SpringMaterial::Hookean, SpringMaterial::StVK] {
        for form in [Form::Compliant, Form::Energy] {
            for method in [Method::GaussSeidel, Method::Jacobi] {
                let opts = SceneOptions { material, ..SceneOptions::default() };
                let s = Settings { form, method, ..Settings::default() };
                let (d, x) = compare(&ctx, &kernels, "cloth", opts, &s, 120);
                let fell = 1.2 - x.iter().map(|p| p.y).fold(f32::MAX, f32::min);
                println!("{material:?} {form:?} {method:?}: max distance {d:.3e} m (cloth fell {fell:.2} m)");
                assert!(fell > 0.3, "the scene barely moved");
                assert!(d < TOLERANCE, "{material:?} {form:?} {method:?}: GPU and CPU differ by {d:.3e} m");
            }
        }
    }
}

#[test]
fn substeps_damping_and_jacobi_match_the_cpu() {
    let ctx = context();
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let s = Settings { substeps: 2, iterations: 10, damping: 0.2, constraint_damping: 1e-3, ..Settings::default() };
    for method in [Method::GaussSeidel, Method::Jacobi] {
        let (d, _) = compare(&ctx, &kernels, "cloth", SceneOptions::default(), &Settings { method, ..s }, 120);
        println!("cloth 2x10 {method:?}: max distance {d:.3e} m");
        assert!(d < TOLERANCE, "cloth {method:?}: GPU and CPU differ by {d:.3e} m");
    }
}

#[test]
fn contacts_match_the_cpu_as_closely_as_the_cpu_matches_itself() {
    // A cloth draping over a sphere with friction is chaotic: moving one particle of the CPU run
    // by 1e-6 m changes the drape by about a centimetre after 40 frames. The GPU must agree
    // with the CPU up to the impact to rounding level, and afterwards stay within ten times the
    // CPU's own sensitivity to such a perturbation.
    let ctx = context();
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let s = Settings::default();
    let sc = scene::build("cloth-sphere", &SceneOptions::default()).unwrap();
    let mut cpu = CpuSolver::<Vec3>::new(sc.clone());
    let mut perturbed = CpuSolver::<Vec3>::new(sc.clone());
    perturbed.particles.x[800].x += 1e-6;
    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc);
    let dist = |a: &[Vec3], b: &[Vec3]| a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f32::max);
    for frame in 1..=120 {
        cpu.step_frame(&s);
        perturbed.step_frame(&s);
        gpu.step_frame(&s);
        if frame % 10 == 0 {
            let g = gpu.read_positions().unwrap();
            let d_gpu = dist(&cpu.particles.x, &g);
            let d_self = dist(&cpu.particles.x, &perturbed.particles.x);
            println!("cloth-sphere frame {frame}: GPU {d_gpu:.2e} m, CPU perturbed {d_self:.2e} m");
            if frame <= 20 {
                assert!(d_gpu < TOLERANCE, "frame {frame}: GPU and CPU differ by {d_gpu:.3e} m before the drape");
            }
            assert!(d_gpu < 10.0 * d_self + TOLERANCE, "frame {frame}: GPU {d_gpu:.3e} m vs CPU self {d_self:.3e} m");
        }
    }
    let y_min = gpu.read_positions().unwrap().iter().map(|p| p.y).fold(f32::MAX, f32::min);
    assert!(y_min >= 0.0, "GPU cloth went through the ground: {y_min}");
}

#[test]
fn paper_cloth_matches_the_cpu_before_it_crumples() {
    // Springs only: rounding-level agreement for the first frames of the fall.
    let ctx = context();
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let (d, _) = compare(&ctx, &kernels, "cloth-paper", SceneOptions::default(), &Settings::default(), 20);
    assert!(d < 1e-5, "cloth-paper: GPU and CPU differ by {d:.3e} m after 20 frames");
}
