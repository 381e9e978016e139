//! The GPU solver against the CPU reference on the same scenes: same color order, same
//! arithmetic in f32, so trajectories agree to a small fraction of the cloth size (1 m). The GPU
//! compiler may fuse multiply-adds, so the two differ by rounding from the first frame; a cloth
//! without bending crumples chaotically under gravity and amplifies that rounding to centimetres
//! within 100 frames, so the 120-frame comparisons use the `cloth` scene, whose bending keeps the
//! motion regular. These tests need a GPU adapter (Mesa lavapipe in CI) and fail without one.

use std::sync::Arc;

use eapbd::constraints::{Form, SpringMaterial};
use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::metrics::FrameStats;
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, EnergyAware, Method, Settings};
use glam::{Vec3, Vec3A};

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
    let mut cpu = CpuSolver::<Vec3A>::new(sc.clone());
    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap();
    let mut worst = 0.0f32;
    for frame in 1..=frames {
        cpu.step_frame(s);
        gpu.step_frame(s);
        if frame % 20 == 0 || frame == frames {
            let g = gpu.read_positions().unwrap();
            let d = cpu.particles.positions().iter().zip(&g).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
            assert!(d.is_finite(), "{name}: non-finite at frame {frame}");
            worst = worst.max(d);
        }
    }
    (worst, cpu.particles.positions())
}

/// Height of the lowest particle (m).
fn lowest(x: &[Vec3]) -> f32 {
    x.iter().map(|p| p.y).fold(f32::MAX, f32::min)
}

/// Tolerance on the particle distance (m), relative to the 1 m cloth: 1e-4.
const TOLERANCE: f32 = 1e-4;

#[test]
fn cloth_matches_the_cpu_for_every_material_form_and_method() {
    // Rounding-level agreement through the fall (100 frames). The corners reach the ground soon
    // after, where a particle on either side of the static-friction threshold splits the runs;
    // contacts are held to the CPU's own sensitivity in the sphere test below.
    let ctx = context();
    let kernels = Arc::new(Kernels::new(&ctx.device));
    for material in [SpringMaterial::Hookean, SpringMaterial::StVK] {
        for form in [Form::Compliant, Form::Energy] {
            for method in [Method::GaussSeidel, Method::Jacobi] {
                let opts = SceneOptions { material, ..SceneOptions::default() };
                let s = Settings { form, method, ..Settings::default() };
                let (d, x) = compare(&ctx, &kernels, "cloth", opts, &s, 100);
                let fell = 1.2 - lowest(&x);
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
    // Through the swing down to just above the ground (25 frames): once the corners touch it,
    // static friction makes the runs chaotic (a 1e-6 m nudge of one particle of the CPU run then
    // moves the cloth by centimetres within 50 frames), which the contact test below allows for.
    let s = Settings { substeps: 2, iterations: 10, damping: 0.2, constraint_damping: 1e-3, ..Settings::default() };
    for method in [Method::GaussSeidel, Method::Jacobi] {
        let (d, x) = compare(&ctx, &kernels, "cloth", SceneOptions::default(), &Settings { method, ..s }, 25);
        let low = lowest(&x);
        println!("cloth 2x10 {method:?}: max distance {d:.3e} m, lowest particle at {low:.3} m");
        assert!(low > 0.05 && low < 0.9, "{method:?}: the cloth should have swung down, not landed");
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
    let mut cpu = CpuSolver::<Vec3A>::new(sc.clone());
    let mut perturbed = CpuSolver::<Vec3A>::new(sc.clone());
    perturbed.particles.x[800].x += 1e-6;
    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap();
    let dist = |a: &[Vec3], b: &[Vec3]| a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f32::max);
    for frame in 1..=120 {
        cpu.step_frame(&s);
        perturbed.step_frame(&s);
        gpu.step_frame(&s);
        if frame % 10 == 0 {
            let g = gpu.read_positions().unwrap();
            let d_gpu = dist(&cpu.particles.positions(), &g);
            let d_self = dist(&cpu.particles.positions(), &perturbed.particles.positions());
            println!("cloth-sphere frame {frame}: GPU {d_gpu:.2e} m, CPU perturbed {d_self:.2e} m");
            if frame <= 20 {
                assert!(d_gpu < TOLERANCE, "frame {frame}: GPU and CPU differ by {d_gpu:.3e} m before the drape");
            }
            assert!(d_gpu < 10.0 * d_self + TOLERANCE, "frame {frame}: GPU {d_gpu:.3e} m vs CPU self {d_self:.3e} m");
        }
    }
    let y_min = lowest(&gpu.read_positions().unwrap());
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

/// Like [`compare`], but also runs the CPU with one particle moved by 1e-6 m: where the
/// setting makes the motion sensitive (the local mode's switch between `C̃` and `C` flips on
/// rounding), the GPU must stay within ten times the CPU's own spread. Returns the worst ratio
/// `d_gpu / (10 d_self + TOLERANCE)` over the checkpoints, and the largest `d_gpu`.
fn compare_sensitive(
    ctx: &GpuContext,
    kernels: &Arc<Kernels>,
    opts: SceneOptions,
    s: &Settings,
    frames: u32,
) -> (f32, f32) {
    let sc = scene::build("cloth", &opts).unwrap();
    let mut cpu = CpuSolver::<Vec3A>::new(sc.clone());
    let mut perturbed = CpuSolver::<Vec3A>::new(sc.clone());
    perturbed.particles.x[sc.num_particles() / 2].x += 1e-6;
    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap();
    let dist = |a: &[Vec3], b: &[Vec3]| a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f32::max);
    let (mut ratio, mut worst) = (0.0f32, 0.0f32);
    for frame in 1..=frames {
        cpu.step_frame(s);
        perturbed.step_frame(s);
        gpu.step_frame(s);
        if frame == 1 || frame % 20 == 0 {
            let d = dist(&cpu.particles.positions(), &gpu.read_positions().unwrap());
            let d_self = dist(&cpu.particles.positions(), &perturbed.particles.positions());
            assert!(d.is_finite(), "non-finite at frame {frame}");
            ratio = ratio.max(d / (10.0 * d_self + TOLERANCE));
            worst = worst.max(d);
        }
    }
    (ratio, worst)
}

#[test]
fn energy_aware_settings_match_the_cpu() {
    // Every energy-aware setting and SOR, with both iterations, on a 21×21 cloth with bending.
    let ctx = context();
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let opts = SceneOptions { resolution: Some(21), stiffness: 1000.0, ..SceneOptions::default() };
    for (energy_aware, sor) in
        [(EnergyAware::Local, 1.0), (EnergyAware::Global, 1.0), (EnergyAware::Off, 1.5), (EnergyAware::Global, 1.5)]
    {
        for method in [Method::GaussSeidel, Method::Jacobi] {
            for form in [Form::Compliant, Form::Energy] {
                let s = Settings { energy_aware, sor, method, form, iterations: 20, ..Settings::default() };
                let (ratio, d) = compare_sensitive(&ctx, &kernels, opts, &s, 120);
                println!("{energy_aware:?} sor {sor} {method:?} {form:?}: max distance {d:.3e} m, ratio {ratio:.3}");
                assert!(ratio < 1.0, "{energy_aware:?} sor {sor} {method:?} {form:?}: GPU and CPU differ by {d:.3e} m");
            }
        }
    }
}

#[test]
fn gpu_energies_match_the_cpu() {
    // The GPU's reduction (f32, two levels) against the CPU's f64 sums of the same read-back
    // state, on the damped cloth resting on a sphere (contacts and damping dissipate work) under
    // the global balance. Against the CPU solver's own run the energies are compared until the
    // cloth settles onto the sphere (frame 15): from there the run is chaotic (the backends agree
    // bit for bit for 11 frames, then separate as fast as the CPU does from itself under a 1e-6 m
    // nudge: at frame 60 the elastic energies of the CPU, the nudged CPU and the GPU are 5.670,
    // 5.674 and 5.748 J), which the contact tests judge by the CPU's own spread.
    let ctx = context();
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let sc = scene::build("cloth-sphere", &SceneOptions { resolution: Some(21), ..SceneOptions::default() }).unwrap();
    let s = Settings { damping: 0.5, energy_aware: EnergyAware::Global, ..Settings::default() };
    let mut cpu = CpuSolver::<Vec3A>::new(sc.clone());
    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap();
    for frame in 1..=60 {
        cpu.step_frame(&s);
        gpu.step_frame(&s);
        if frame % 15 == 0 {
            let c = FrameStats::measure(&cpu, frame, 0.0);
            let own = gpu.stats(frame, 0.0).unwrap();
            let g = gpu.energies().unwrap();
            let scale = own.total().abs().max(1e-3);
            // The honest account's split, from the GPU's multipliers read back.
            println!("frame {frame} unresolved: CPU run {:.6e} J, GPU state {:.6e} J", c.unresolved, own.unresolved);
            if frame <= 15 {
                let u = c.unresolved.abs().max(own.unresolved.abs()).max(1e-3 * scale);
                assert!(
                    (c.unresolved - own.unresolved).abs() < 1e-2 * u,
                    "frame {frame} unresolved: CPU {:.6e} J, GPU {:.6e} J",
                    c.unresolved,
                    own.unresolved
                );
            }
            for (name, a, own, b) in [
                ("kinetic", c.kinetic, own.kinetic, g.kinetic),
                ("gravitational", c.gravitational, own.gravitational, g.gravitational),
                // The reduction sums the iterate's material energy, held and unresolved alike.
                ("elastic", c.material(), own.material(), g.elastic),
                ("dissipated", c.dissipated, own.dissipated, g.dissipated),
            ] {
                println!("frame {frame} {name}: CPU run {a:.6e} J, GPU reduction {b:.6e} J, its state {own:.6e} J");
                assert!(
                    (own - b).abs() < 1e-3 * scale,
                    "frame {frame} {name}: GPU reduction {b:.6e} J, its state {own:.6e} J"
                );
                if frame <= 15 {
                    assert!((a - b).abs() < 1e-3 * scale, "frame {frame} {name}: CPU {a:.6e} J, GPU {b:.6e} J");
                }
            }
        }
    }
}

/// The largest distance (m) between two CPU runs of one frame of `cloth`, one started from
/// positions moved by one unit in the last place (up or down in a fixed pattern): the CPU's own
/// response to the rounding by which two compilers of the same arithmetic may differ.
fn first_frame_sensitivity(opts: SceneOptions, s: &Settings) -> f32 {
    let sc = scene::build("cloth", &opts).unwrap();
    let mut cpu = CpuSolver::<Vec3A>::new(sc.clone());
    let mut nudged = CpuSolver::<Vec3A>::new(sc);
    for (i, p) in nudged.particles.x.iter_mut().enumerate() {
        let e = if i % 2 == 0 { f32::EPSILON } else { -f32::EPSILON };
        *p *= Vec3A::new(1.0 + e, 1.0 - e, 1.0 + e);
    }
    cpu.step_frame(s);
    nudged.step_frame(s);
    let (a, b) = (cpu.particles.positions(), nudged.particles.positions());
    a.iter().zip(&b).map(|(p, q)| p.distance(*q)).fold(0.0, f32::max)
}

#[test]
fn anisotropic_cloth_matches_the_cpu() {
    // The membrane triangles (with bending) in both forms and both iterations, stiff warp and
    // soft weft. The first frame agrees to rounding: within 1e-6 m plus ten times the CPU's own
    // response to a one-ulp nudge of the positions (the compliant form's C = √(2E/s) has a
    // gradient that turns on rounding where E ≈ 0, the flat cloth at rest, so a GPU that fuses
    // multiply-adds differs by more than lavapipe). Afterwards that sensitivity grows over the
    // fall, so the GPU is compared with the CPU's own sensitivity over 120 frames.
    let ctx = context();
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let membrane = Some(eapbd::constraints::Orthotropic::new(1e4, 1e3, None, 0.0).unwrap());
    let opts = SceneOptions { resolution: Some(21), membrane, ..SceneOptions::default() };
    for form in [Form::Compliant, Form::Energy] {
        for method in [Method::GaussSeidel, Method::Jacobi] {
            let s = Settings { form, method, substeps: 2, iterations: 10, ..Settings::default() };
            let (first, _) = compare(&ctx, &kernels, "cloth", opts, &s, 1);
            let own = first_frame_sensitivity(opts, &s);
            let (ratio, d) = compare_sensitive(&ctx, &kernels, opts, &s, 120);
            println!(
                "aniso-cloth {form:?} {method:?}: first frame {first:.3e} m (the CPU's own {own:.3e} m), \
                 max distance {d:.3e} m, ratio {ratio:.3}"
            );
            assert!(
                first < 1e-6 + 10.0 * own,
                "aniso-cloth {form:?} {method:?}: the first frame differs by {first:.3e} m (the CPU's own {own:.3e} m)"
            );
            assert!(ratio < 1.0, "aniso-cloth {form:?} {method:?}: GPU and CPU differ by {d:.3e} m");
        }
    }
}
