//! `eapbd bench`: time per frame of the CPU solver and the cost of mesh coloring.

use std::time::Instant;

use clap::Args;
use std::sync::Arc;

use eapbd::coloring;
use eapbd::constraints::Form;
use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::mesh::{grid, unique_edges};
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, Method, Settings};
use glam::Vec3;
use rand::{Rng, SeedableRng};

/// Arguments of `eapbd bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// A short run of a few seconds (fewer frames and repetitions).
    #[arg(long)]
    pub quick: bool,
}

/// Runs the command.
pub fn run(a: &BenchArgs) -> anyhow::Result<()> {
    let (warm, frames, reps) = if a.quick { (10, 40, 1) } else { (30, 300, 5) };
    println!("CPU solver, single thread, f32 (median of {frames} frames after {warm} warm-up frames)");
    println!("| scene | solver | form | iterations x substeps | constraints | colors | ms/frame | projections/s |");
    println!("|---|---|---|---|---|---|---|---|");
    let cases = [
        (Method::GaussSeidel, Form::Compliant),
        (Method::GaussSeidel, Form::Energy),
        (Method::Jacobi, Form::Compliant),
    ];
    for (method, form) in cases {
        let scene = scene::build("cloth-paper", &SceneOptions::default())?;
        let colors = scene.springs.as_ref().map_or(0, |f| f.stats.colors);
        let n = scene.num_constraints();
        let settings = Settings { iterations: 30, substeps: 1, method, form, ..Settings::default() };
        let ms = median_frame_ms(CpuSolver::<Vec3>::new(scene), &settings, warm, frames);
        let proj = (n as f64 * 30.0) / (ms * 1e-3);
        println!(
            "| cloth-paper | {} | {} | 30 x 1 | {n} | {colors} | {ms:.3} | {:.1} M |",
            method.name(),
            form.name(),
            proj / 1e6
        );
    }
    peer_rows(if a.quick { 20 } else { 120 })?;
    gpu_rows(warm, frames)?;
    println!();
    println!("Mesh coloring (best of {reps})");
    println!("| elements | particles | colors | group sizes | ms |");
    println!("|---|---|---|---|---|");
    let cloth = grid(578, 1.0, 0.0);
    let edges = unique_edges(&cloth.triangles);
    coloring_case("cloth grid edges", cloth.positions.len(), &edges, reps);
    let mut rng = rand::rngs::SmallRng::seed_from_u64(7);
    let np = 200_000u32;
    let random: Vec<[u32; 2]> = (0..1_000_000)
        .map(|_| {
            let a = rng.random_range(0..np);
            let b = (a + rng.random_range(1..np)) % np;
            [a, b]
        })
        .collect();
    coloring_case("random graph", np as usize, &random, reps);
    Ok(())
}

/// The peer scene of the performance issue: 64×64 cloth, 1 m, 1 kg, two corners pinned,
/// k = 1e6 N/m springs on grid edges and one diagonal per quad plus dihedral bending on interior
/// edges (23,814 constraints), gravity, dt = 1/60; mean time per frame and time-averaged mean
/// stretch over `frames` frames.
fn peer_rows(frames: u32) -> anyhow::Result<()> {
    println!(
        "\nPeer scene: cloth --resolution 64 --stiffness 1e6 (springs + bending), {frames} frames, CPU, one thread"
    );
    println!("| iterations x substeps | constraints | ms/frame (mean) | mean stretch (time average) |");
    println!("|---|---|---|---|");
    for (iterations, substeps) in [(30, 1), (1, 30)] {
        let opts = SceneOptions { resolution: Some(64), stiffness: 1.0e6, ..SceneOptions::default() };
        let scene = scene::build("cloth", &opts)?;
        let n = scene.num_constraints();
        let mut sv = CpuSolver::<Vec3>::new(scene);
        let s = Settings { iterations, substeps, ..Settings::default() };
        let (mut ms, mut stretch) = (0.0, 0.0);
        for frame in 1..=frames {
            let t0 = Instant::now();
            sv.step_frame(&s);
            ms += t0.elapsed().as_secs_f64() * 1e3;
            stretch += eapbd::metrics::FrameStats::measure(&sv, frame, 0.0).stretch_mean;
        }
        println!("| {iterations} x {substeps} | {n} | {:.2} | {:.4} |", ms / frames as f64, stretch / frames as f64);
    }
    Ok(())
}

/// The GPU solver on `cloth-paper` (each frame submitted and waited for).
fn gpu_rows(warm: u32, frames: u32) -> anyhow::Result<()> {
    let ctx = match GpuContext::new() {
        Ok(c) => c,
        Err(e) => {
            println!("\nGPU solver: not measured ({e})");
            return Ok(());
        }
    };
    let kernels = Arc::new(Kernels::new(&ctx.device));
    println!("\nGPU solver on {} (median of {frames} frames, each submitted and waited for)", ctx.describe());
    println!("| scene | solver | form | iterations x substeps | dispatches/frame | ms/frame |");
    println!("|---|---|---|---|---|---|");
    for (method, form) in [(Method::GaussSeidel, Form::Compliant), (Method::Jacobi, Form::Compliant)] {
        let scene = scene::build("cloth-paper", &SceneOptions::default())?;
        let s = Settings { iterations: 30, substeps: 1, method, form, ..Settings::default() };
        let mut g = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, scene)?;
        let mut t = Vec::with_capacity(frames as usize);
        for i in 0..warm + frames {
            let t0 = Instant::now();
            g.step_frame(&s);
            ctx.wait()?;
            if i >= warm {
                t.push(t0.elapsed().as_secs_f64() * 1e3);
            }
        }
        t.sort_by(f64::total_cmp);
        println!(
            "| cloth-paper | {} | {} | 30 x 1 | {} | {:.3} |",
            method.name(),
            form.name(),
            g.dispatches_per_frame(&s),
            t[t.len() / 2]
        );
    }
    Ok(())
}

fn median_frame_ms(mut solver: CpuSolver<Vec3>, s: &Settings, warm: u32, frames: u32) -> f64 {
    for _ in 0..warm {
        solver.step_frame(s);
    }
    let mut t: Vec<f64> = (0..frames)
        .map(|_| {
            let t0 = Instant::now();
            solver.step_frame(s);
            t0.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[t.len() / 2]
}

fn coloring_case(name: &str, particles: usize, elements: &[[u32; 2]], reps: u32) {
    let mut best = f64::INFINITY;
    let mut stats = None;
    for _ in 0..reps {
        let t0 = Instant::now();
        let c = coloring::color(particles, elements);
        best = best.min(t0.elapsed().as_secs_f64() * 1e3);
        stats = Some(c.stats());
    }
    if let Some(s) = stats {
        println!(
            "| {} {name} | {particles} | {} | {}..{} | {best:.1} |",
            elements.len(),
            s.colors,
            s.min_group,
            s.max_group
        );
    }
}
