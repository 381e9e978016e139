//! The energy-momentum projection (`--energy-aware project`) on the GPU: its invariants on the
//! GPU's own run (energy, both momenta, a body at rest) and its parity with the CPU's. These
//! tests need a GPU adapter (Mesa lavapipe in CI) and fail without one.

mod common;

use std::sync::Arc;

use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::metrics::FrameStats;
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::projection::{momenta, momentum_scales};
use eapbd::solver::{CpuSolver, EnergyAware, Settings};
use glam::{Vec3, Vec3A};

fn settings(substeps: u32, iterations: u32, energy_aware: EnergyAware) -> Settings {
    Settings { substeps, iterations, energy_aware, threads: 1, ..Settings::default() }
}

/// The hanging cloth: 41×41, k = 10⁴ N/m, bending 10⁻³ N·m/rad.
fn hanging_cloth() -> scene::Scene {
    let opts = SceneOptions { stiffness: 1e4, bending_stiffness: Some(1e-3), ..SceneOptions::default() };
    scene::build("cloth", &opts).unwrap()
}

fn gpu_solver(ctx: &GpuContext, kernels: &Arc<Kernels>, sc: scene::Scene) -> GpuSolver {
    GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, sc).unwrap()
}

/// The honest total (J) and kinetic energy of the GPU's state.
fn measure(gpu: &GpuSolver, frame: u32) -> FrameStats {
    gpu.stats(frame, 0.0).unwrap()
}

#[test]
fn the_free_cloth_keeps_both_momenta_and_its_energy_on_the_gpu() {
    let (ctx, kernels) = common::gpu();
    let opts = SceneOptions { resolution: Some(21), stiffness: 1e4, ..SceneOptions::default() };
    let sc = scene::build("cloth-free", &opts).unwrap();
    // Set the cloth drifting and spinning, so both momenta are far from zero.
    let v: Vec<Vec3> =
        sc.positions.iter().map(|x| Vec3::new(0.3, -0.1, 0.2) + Vec3::new(0.0, 2.0, 0.5).cross(*x)).collect();
    let mut gpu = gpu_solver(&ctx, &kernels, sc);
    gpu.set_velocities(&v).unwrap();
    let s = settings(3, 10, EnergyAware::Project);
    gpu.step_frame(&s);
    let first = gpu.read_state().unwrap();
    let (p0, l0) = momenta(&first.x, &first.v, &first.w);
    let start = measure(&gpu, 1).total();
    for frame in 2..=600 {
        gpu.step_frame(&s);
        if frame % 50 != 0 {
            continue;
        }
        let st = gpu.read_state().unwrap();
        let (p1, l1) = momenta(&st.x, &st.v, &st.w);
        let (scale_p, scale_l) = momentum_scales(&st.x, &st.v, &st.w);
        assert!((p1 - p0).length() <= 1e-4 * scale_p, "frame {frame}: P {p0} -> {p1} (scale {scale_p:.3e})");
        assert!((l1 - l0).length() <= 1e-4 * scale_l, "frame {frame}: L {l0} -> {l1} (scale {scale_l:.3e})");
        let e = measure(&gpu, frame).total();
        assert!((e - start).abs() <= 0.02 * start, "frame {frame}: {e:.5} J against {start:.5} J");
    }
    let p = gpu.projection_state().unwrap().expect("the projection ran");
    println!("free cloth on the GPU: {start:.5} J after frame 1, budget {:.5} J, last scale {}", p.budget, p.scale);
    assert!((p.budget as f64 - start).abs() <= 0.01 * start, "the budget {} J against {start:.5} J", p.budget);
}

#[test]
fn the_hanging_cloth_keeps_its_energy_and_swing_on_the_gpu_as_on_the_cpu() {
    let (ctx, kernels) = common::gpu();
    let s = settings(10, 3, EnergyAware::Project);
    let mut cpu = CpuSolver::<Vec3A>::new(hanging_cloth());
    let mut gpu = gpu_solver(&ctx, &kernels, hanging_cloth());
    let (mut early, mut late) = ([0.0; 2], [0.0; 2]);
    let mut start = [0.0; 2];
    for frame in 1..=600u32 {
        cpu.step_frame(&s);
        gpu.step_frame(&s);
        if frame % 10 != 0 && frame != 1 {
            continue;
        }
        let (c, g) = (FrameStats::measure(&cpu, frame, 0.0), measure(&gpu, frame));
        if frame == 1 {
            start = [c.total(), g.total()];
        }
        for (i, st) in [c, g].iter().enumerate() {
            // Held to the start within 2%: n within 1 ± 0.05 (the fall makes 4.9 J of 11.8 J available).
            assert!(
                (st.total() - start[i]).abs() <= 0.02 * start[i],
                "{} frame {frame}: {:.4} J against {:.4} J",
                ["cpu", "gpu"][i],
                st.total(),
                start[i]
            );
            if frame <= 120 {
                early[i] += st.kinetic;
            } else if frame > 480 {
                late[i] += st.kinetic;
            }
        }
        if frame == 60 {
            // The same swing on both backends while the motion is regular: the projection's
            // scale differs by the f32 and f64 sums' rounding.
            let (x, y) = (cpu.particles.positions(), gpu.read_positions().unwrap());
            let d = x.iter().zip(&y).map(|(a, b)| a.distance(*b)).fold(0.0, f32::max);
            println!("hanging cloth, frame 60: CPU and GPU within {d:.2e} m");
            assert!(d <= 2e-3, "the GPU's cloth is {d:.2e} m from the CPU's after 1 s");
        }
    }
    for i in 0..2 {
        let ratio = late[i] / early[i];
        println!("{}: kinetic energy over the last 2 s / the first 2 s = {ratio:.3}", ["cpu", "gpu"][i]);
        assert!(ratio >= 0.5, "{}: the swing died ({ratio:.3})", ["cpu", "gpu"][i]);
    }
}

#[test]
fn a_cloth_at_rest_stays_at_rest_on_the_gpu() {
    let (ctx, kernels) = common::gpu();
    let mut gpu = gpu_solver(&ctx, &kernels, hanging_cloth());
    let damped = Settings { damping: 5.0, ..settings(10, 3, EnergyAware::Off) };
    for _ in 0..900 {
        gpu.step_frame(&damped);
    }
    let before = measure(&gpu, 0).kinetic;
    let s = settings(10, 3, EnergyAware::Project);
    let mut peak: f64 = 0.0;
    for frame in 1..=300 {
        gpu.step_frame(&s);
        if frame % 10 == 0 {
            peak = peak.max(measure(&gpu, frame).kinetic);
        }
    }
    println!("at rest on the GPU: kinetic energy {before:.3e} J before, at most {peak:.3e} J over 5 s");
    assert!(peak <= 1e-3, "the cloth at rest reached {peak:.3e} J of kinetic energy");
}

#[test]
fn the_gpu_holds_what_the_cpu_holds() {
    // The reduction's held elastic energy (the family kernels with the multipliers) against the
    // CPU's honest account on the same state.
    let (ctx, kernels) = common::gpu();
    let mut gpu = gpu_solver(&ctx, &kernels, hanging_cloth());
    let s = settings(3, 10, EnergyAware::Off);
    for _ in 0..40 {
        gpu.step_frame(&s);
    }
    let reduced = gpu.energies().unwrap();
    let account = measure(&gpu, 40);
    println!(
        "held: reduction {:.5} J, account {:.5} J; material {:.4} J",
        reduced.held, account.elastic, reduced.elastic
    );
    assert!(account.unresolved > account.elastic, "the frame leaves stretch unresolved");
    assert!((reduced.held - account.elastic).abs() <= 0.01 * account.elastic, "{reduced:?} against {account:?}");
}

#[test]
fn the_dropped_bunny_loses_what_its_contacts_take_on_the_gpu() {
    let (ctx, kernels) = common::gpu();
    let opts = SceneOptions { lattice: Some(8), ..SceneOptions::default() };
    let mut gpu = gpu_solver(&ctx, &kernels, scene::build("bunny", &opts).unwrap());
    let s = settings(3, 10, EnergyAware::Project);
    gpu.step_frame(&s);
    let first = measure(&gpu, 1);
    let mut peak = f64::MIN;
    for frame in 2..=150 {
        gpu.step_frame(&s);
        if frame % 10 == 0 {
            peak = peak.max(measure(&gpu, frame).total());
        }
    }
    let last = measure(&gpu, 150);
    let (lost, work) = (first.total() - last.total(), first.dissipated - last.dissipated);
    println!(
        "bunny on the GPU: start {:.4} J, peak {peak:.4} J, lost {lost:.4} J, contact work {work:.4} J",
        first.total()
    );
    assert!(work > 0.1 * first.total(), "the landing did contact work: {work:.4} J");
    assert!(peak <= 1.05 * first.total(), "the honest total rose to {peak:.4} J from {:.4} J", first.total());
    assert!((lost - work).abs() <= 0.05 * work, "lost {lost:.4} J against {work:.4} J of contact work");
}
