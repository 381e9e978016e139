//! Tetrahedra on the GPU against the CPU reference: the cantilever beam with every 3D model, both
//! forms and both iterations, the energy-aware settings, the GPU's energy reduction, and the
//! mirrored cube. Needs a GPU adapter (Mesa lavapipe in CI).

mod common;

use std::sync::Arc;

use eapbd::constraints::Form;
use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::material::Model;
use eapbd::metrics::FrameStats;
use eapbd::scene::{self, Scene, SceneOptions};
use eapbd::solver::{CpuSolver, EnergyAware, Method, Settings};
use glam::{Vec3, Vec3A};

fn beam(model: Model) -> Scene {
    scene::build("beam", &SceneOptions { solid: Some(model), ..SceneOptions::default() }).unwrap()
}

fn max_distance(a: &[Vec3], b: &[Vec3]) -> f32 {
    a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f32::max)
}

/// Runs `frames` frames of `sc` on both backends, and the CPU also with one particle moved by
/// 1e-6 m and with every position moved by one unit in the last place (the rounding by which two
/// compilations of the same arithmetic differ: the CPU's SIMD kernels and the GPU's round
/// differently from the general update); returns the largest GPU–CPU particle distance (m) at the
/// checkpoints, the largest ratio of it to `10 d_self + TOLERANCE` (`d_self`: the CPU's larger
/// spread under the two perturbations), and the CPU's largest displacement from the start (m). Where a setting makes
/// the motion sensitive (the local mode's switch between `C̃` and `C` flips on rounding) only
/// the ratio is meaningful.
fn compare(ctx: &GpuContext, kernels: &Arc<Kernels>, sc: Scene, s: &Settings, frames: u32) -> (f32, f32, f32) {
    let start = sc.positions.clone();
    let mut cpu = CpuSolver::<Vec3A>::new(sc.clone());
    let mut perturbed = CpuSolver::<Vec3A>::new(sc.clone());
    perturbed.particles.x[sc.num_particles() - 1].y += 1e-6;
    let mut nudged = CpuSolver::<Vec3A>::new(sc.clone());
    for (i, p) in nudged.particles.x.iter_mut().enumerate() {
        let e = if i % 2 == 0 { f32::EPSILON } else { -f32::EPSILON };
        *p *= Vec3A::new(1.0 + e, 1.0 - e, 1.0 + e);
    }
    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap();
    let (mut worst, mut ratio) = (0.0f32, 0.0f32);
    for frame in 1..=frames {
        cpu.step_frame(s);
        perturbed.step_frame(s);
        nudged.step_frame(s);
        gpu.step_frame(s);
        if frame % 20 == 0 || frame == frames {
            let d = max_distance(&cpu.particles.positions(), &gpu.read_positions().unwrap());
            let c = cpu.particles.positions();
            let d_self =
                max_distance(&c, &perturbed.particles.positions()).max(max_distance(&c, &nudged.particles.positions()));
            assert!(d.is_finite(), "non-finite at frame {frame}");
            worst = worst.max(d);
            ratio = ratio.max(d / (10.0 * d_self + TOLERANCE));
        }
    }
    (worst, ratio, max_distance(&cpu.particles.positions(), &start))
}

/// Tolerance on the particle distance (m) for the 1 m beam: 1e-4 m, a 1e-4 fraction of its
/// length. Both backends run the same f32 arithmetic in the same color order; they differ by the
/// GPU compiler's fused multiply-adds and transcendental functions.
const TOLERANCE: f32 = 1e-4;

#[test]
fn the_beam_matches_the_cpu_for_every_model_and_form() {
    let (ctx, kernels) = common::gpu();
    let s = Settings { substeps: 2, iterations: 10, ..Settings::default() };
    for model in Model::ALL {
        for form in [Form::Compliant, Form::Energy] {
            let (d, _, moved) = compare(&ctx, &kernels, beam(model), &Settings { form, ..s }, 120);
            println!("beam {model:?} {form:?}: max distance {d:.3e} m (tip moved {moved:.3} m)");
            assert!(moved > 0.01, "{model:?} {form:?}: the beam barely moved");
            assert!(d < TOLERANCE, "{model:?} {form:?}: GPU and CPU differ by {d:.3e} m");
        }
    }
}

#[test]
fn jacobi_damping_and_energy_aware_modes_match_the_cpu_on_the_beam() {
    // The energy-aware modes are compared with the CPU's own sensitivity (see `compare`): the
    // local mode's switch flips on rounding, and the global balance's σ comes from f32 sums on
    // the GPU. Plain Jacobi is held to the tolerance.
    let (ctx, kernels) = common::gpu();
    let base = Settings { substeps: 2, iterations: 10, damping: 0.5, constraint_damping: 1e-3, ..Settings::default() };
    for (method, energy_aware) in [
        (Method::Jacobi, EnergyAware::Off),
        (Method::GaussSeidel, EnergyAware::Local),
        (Method::GaussSeidel, EnergyAware::Global),
        (Method::Jacobi, EnergyAware::Global),
    ] {
        let s = Settings { method, energy_aware, ..base };
        let (d, ratio, moved) = compare(&ctx, &kernels, beam(Model::NeoHookean), &s, 120);
        println!("beam {method:?} {energy_aware:?}: max distance {d:.3e} m, ratio {ratio:.3} (moved {moved:.3} m)");
        if energy_aware != EnergyAware::Off {
            assert!(ratio < 1.0, "{method:?} {energy_aware:?}: GPU and CPU differ by {d:.3e} m");
        } else {
            assert!(d < TOLERANCE, "{method:?} {energy_aware:?}: GPU and CPU differ by {d:.3e} m");
        }
    }
}

#[test]
fn gpu_tet_energies_match_the_cpu() {
    let (ctx, kernels) = common::gpu();
    let sc = beam(Model::StVK);
    let s = Settings { substeps: 2, iterations: 10, ..Settings::default() };
    let mut cpu = CpuSolver::<Vec3A>::new(sc.clone());
    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap();
    for _ in 0..40 {
        cpu.step_frame(&s);
        gpu.step_frame(&s);
    }
    let c = FrameStats::measure(&cpu, 40, 0.0);
    let g = gpu.energies().unwrap();
    // The GPU reduction sums the iterate's material energy, held and unresolved alike.
    let c = c.material();
    println!("elastic: CPU {:.6e} J, GPU {:.6e} J", c, g.elastic);
    assert!(c > 0.0);
    assert!((c - g.elastic).abs() < 1e-3 * c, "CPU {:.6e} J, GPU {:.6e} J", c, g.elastic);
}

/// The GPU twin of `tests/solids.rs`' bunny recovery: the stability study's cases that tangle
/// the bunny end with no inverted tetrahedron on this backend too.
#[test]
fn the_bunny_recovers_from_every_disturbance_of_the_stability_study_on_the_gpu() {
    use eapbd::report::stability::{cases, run_case};
    use eapbd::simulation::Backend;
    let gpu = common::gpu();
    for name in ["bunny-dt1e-1", "bunny-velocity-100", "bunny-inverted"] {
        let case = cases().into_iter().find(|c| c.name == name).unwrap();
        let o = run_case(&case, Backend::Gpu, Some(&gpu)).unwrap();
        assert_eq!(o.inverted_end, 0, "{name}: {} of the tetrahedra still inverted", o.inverted_end);
        assert!(o.passed(), "{name}: {:?}", o.failures());
    }
}

#[test]
fn a_mirrored_cube_regains_positive_volume_on_the_gpu() {
    let (ctx, kernels) = common::gpu();
    for model in [Model::StVK, Model::NeoHookean, Model::MooneyRivlin, Model::ArrudaBoyce] {
        let mut sc = scene::build("cube", &SceneOptions { solid: Some(model), ..SceneOptions::default() }).unwrap();
        for p in &mut sc.positions {
            p.x = -p.x;
        }
        let tets = sc.tets.clone().unwrap();
        let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap();
        let s = Settings { substeps: 2, iterations: 10, damping: 2.0, ..Settings::default() };
        for _ in 0..100 {
            gpu.step_frame(&s);
        }
        let x = gpu.read_positions().unwrap();
        assert!(x.iter().all(|p| p.is_finite()), "{model:?}: not finite");
        let inverted = tets.elements.iter().filter(|t| t.deformation(&t.p.map(|i| x[i as usize])).det() <= 0.0).count();
        assert_eq!(inverted, 0, "{model:?}: {inverted} of {} tetrahedra still inverted", tets.len());
    }
}

#[test]
fn centroid_tetrahedra_match_the_cpu() {
    // The paper's surface-plus-centroid tetrahedra: every element shares the centroid, so each
    // is its own color group (192 of them), and the GPU sweeps them all in one dispatch per
    // iteration; 30 frames of the falling cube.
    let (ctx, kernels) = common::gpu();
    let opts = SceneOptions { tets: scene::TetMode::Centroid, ..SceneOptions::default() };
    let s = Settings { substeps: 2, iterations: 10, ..Settings::default() };
    let sc = scene::build("cube", &opts).unwrap();
    assert_eq!(sc.tets.as_ref().unwrap().colors.len(), 192);
    let gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap();
    // Per substep: predict, clear, 10 × one sweep, 9 contact passes, finish.
    assert_eq!(gpu.dispatches_per_frame(&s), 2 * (1 + 1 + 10 + 9 + 1));
    drop(gpu);
    // Before it lands (at about frame 17), to the tolerance; through the impact, within the
    // CPU's own sensitivity to a 1e-6 m perturbation.
    let (d, _, _) = compare(&ctx, &kernels, scene::build("cube", &opts).unwrap(), &s, 12);
    let (d_all, ratio, moved) = compare(&ctx, &kernels, scene::build("cube", &opts).unwrap(), &s, 30);
    println!("centroid cube: {d:.3e} m in the fall, {d_all:.3e} m (ratio {ratio:.3}) through the impact");
    assert!(moved > 0.05, "the cube barely moved");
    assert!(d < TOLERANCE, "GPU and CPU differ by {d:.3e} m in the fall");
    assert!(ratio < 1.0, "GPU and CPU differ by {d_all:.3e} m through the impact");
}

#[test]
fn the_volumetric_bunny_and_its_embedded_surface_match_the_cpu() {
    // 60 frames of the dropped bunny (default lattice, 4998 tetrahedra), then the GPU's embed
    // pass against the CPU's barycentric placement on the same particle positions.
    let (ctx, kernels) = common::gpu();
    let sc = scene::build("bunny", &SceneOptions::default()).unwrap();
    let embedding = sc.embedding.clone().unwrap();
    let s = Settings { substeps: 2, iterations: 10, ..Settings::default() };
    let (d, ratio, moved) = compare(&ctx, &kernels, sc.clone(), &s, 60);
    println!("bunny: max distance {d:.3e} m, ratio {ratio:.3} (moved {moved:.3} m)");
    assert!(moved > 0.1, "the bunny barely moved");
    assert!(ratio < 1.0, "GPU and CPU differ by {d:.3e} m");

    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap();
    for _ in 0..20 {
        gpu.step_frame(&s);
    }
    let embedder = eapbd::render::Embedder::new(&ctx.device, &embedding, &gpu.x);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    embedder.encode(&mut encoder);
    ctx.queue.submit([encoder.finish()]);
    let on_gpu: Vec<glam::Vec4> = eapbd::gpu::read_buffer(&ctx.device, &ctx.queue, &embedder.positions).unwrap();
    let on_cpu = embedding.positions(&gpu.read_positions().unwrap());
    let worst = on_cpu.iter().zip(&on_gpu).map(|(a, b)| a.distance(b.truncate())).fold(0.0, f32::max);
    println!("embedded surface: GPU and CPU placement differ by {worst:.3e} m");
    assert_eq!(on_gpu.len(), on_cpu.len());
    assert!(worst < 1e-6, "embedded vertices differ by {worst:.3e} m");
}
