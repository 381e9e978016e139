//! `eapbd bench`: time per frame, throughput, dispatches and memory of the CPU solver (one
//! thread and every core) and the GPU solver on `cloth-paper`, the peer scene, `bunny-paper` and
//! cloths from about 5,000 to 1,000,000 constraints; the peer scene's splits of 30 projections into
//! iterations × substeps with their stretch; the scaling of time with constraint count; the cost
//! of mesh coloring. Prints Markdown on stdout and writes `bench.csv`, `scaling.csv`, `peer.csv`,
//! `scaling.png` and `bench.md`.

mod cases;
mod coloring;
mod measure;
mod output;
mod peer;
mod scaling;
pub(super) mod timing;

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use eapbd::scene;

use cases::{Backend, Plan};
use measure::Gpu;
use output::Results;

/// Arguments of `eapbd bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// A short run (under a minute on 2 cores): fewer frames, three splits of the peer scene and
    /// cloths up to about 100,000 constraints.
    #[arg(long)]
    pub quick: bool,
    /// Output directory (default: docs/bench; target/bench-quick with --quick, target/bench-gpu
    /// with --gpu-only).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Leave out the GPU path.
    #[arg(long, conflicts_with = "gpu_only")]
    pub cpu_only: bool,
    /// Time the GPU path alone (every case's GPU row; no CPU rows, splits or coloring): the
    /// short run for a machine lent with a GPU.
    #[arg(long)]
    pub gpu_only: bool,
}

/// Runs the command.
pub fn run(a: &BenchArgs) -> anyhow::Result<()> {
    let started = Instant::now();
    let plan = if a.quick { Plan::quick() } else { Plan::full() };
    let out = a.out.clone().unwrap_or_else(|| {
        PathBuf::from(match (a.quick, a.gpu_only) {
            (_, true) => "target/bench-gpu",
            (true, false) => "target/bench-quick",
            (false, false) => "docs/bench",
        })
    });
    let total = |gpu: bool| {
        if a.gpu_only { plan.rows(true) - plan.rows(false) + 1 } else { plan.rows(gpu) + 2 * plan.splits.len() + 1 }
    } as u64;
    let bar = indicatif::ProgressBar::new(total(!a.cpu_only));
    if let Ok(style) = indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed_precise} {msg}") {
        bar.set_style(style);
    }

    // Every CPU measurement first, the GPU last: lavapipe runs its work on worker threads of
    // its own on the same cores, and a CPU team measured next to them pays for it.
    let mut rows = Vec::new();
    let mut scenes = Vec::with_capacity(plan.cases.len());
    for (c, case) in plan.cases.iter().enumerate() {
        bar.set_message(format!("building {}", case.label));
        let scene = scene::build(case.scene, &case.opts)?;
        // The CPU backends, timed together; each row keeps its backend's index in the case.
        let (index, backends): (Vec<usize>, Vec<Backend>) =
            case.backends.iter().copied().enumerate().filter(|(_, b)| *b != Backend::Gpu && !a.gpu_only).unzip();
        let names: Vec<&str> = backends.iter().map(|b| b.name()).collect();
        bar.set_message(format!("{} ({} constraints) on {}", case.label, scene.num_constraints(), names.join(" and ")));
        for (b, row) in index.into_iter().zip(measure::cpu_rows(case, &scene, &backends, &plan.budget)?) {
            rows.push((c, b, row));
            bar.inc(1);
        }
        scenes.push(scene);
    }

    let mut splits = Vec::new();
    for &(iterations, substeps) in plan.splits.iter().filter(|_| !a.gpu_only) {
        bar.set_message(format!("peer scene {iterations} × {substeps}"));
        splits.extend(peer::run_split(iterations, substeps, &[Backend::CpuSingle, Backend::CpuAll], plan.peer_frames)?);
        bar.inc(2);
    }

    let gpu = if a.cpu_only {
        None
    } else {
        match Gpu::open() {
            Ok(g) => Some(g),
            Err(e) if a.gpu_only => return Err(e.into()),
            Err(e) => {
                eprintln!("GPU path not measured: {e}");
                bar.set_length(total(false));
                None
            }
        }
    };
    let gpu_name = gpu.as_ref().map_or("none".to_string(), Gpu::describe);
    if let Some(g) = &gpu {
        for (c, (case, scene)) in plan.cases.iter().zip(scenes).enumerate() {
            let Some(b) = case.backends.iter().position(|b| *b == Backend::Gpu) else { continue };
            bar.set_message(format!("{} ({} constraints) on gpu", case.label, scene.num_constraints()));
            rows.push((c, b, g.row(case, scene, &plan.budget)?));
            bar.inc(1);
        }
    }
    // Back in the tables' order: by case, then backend.
    rows.sort_by_key(|(c, b, _)| (*c, *b));
    let rows: Vec<_> = rows.into_iter().map(|(_, _, row)| row).collect();

    bar.set_message("mesh coloring");
    let coloring = if a.gpu_only { Vec::new() } else { coloring::run(plan.coloring_reps) };
    bar.inc(1);
    bar.finish_and_clear();

    let scaling = scaling::series(&rows);
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let command = match (plan.quick, a.gpu_only) {
        (true, true) => "eapbd bench --quick --gpu-only",
        (true, false) => "eapbd bench --quick",
        (false, true) => "eapbd bench --gpu-only",
        (false, false) => "eapbd bench",
    };
    let header = format!(
        "# Benchmarks ({})\n\nCommand: `cargo run --release -- {}`. {threads} CPU threads available; GPU adapter: {gpu_name}. \
         f32, dt = 1/60 s, Gauss-Seidel over color groups unless stated.\n\n",
        if plan.quick { "quick run" } else { "full run" },
        command.trim_start_matches("eapbd "),
    );
    let results = Results {
        header,
        rows,
        splits,
        split_frames: plan.peer_frames,
        scaling,
        coloring,
        coloring_reps: plan.coloring_reps,
    };
    let mut md = output::markdown(&results);
    let wall = started.elapsed().as_secs_f64();
    md.push_str(&format!("\nRun time: {wall:.0} s.\n"));
    put!("{md}");
    output::write_files(&out, &results)?;
    output::write(&out, "bench.md", &md)?;
    scaling::plot(&out.join("scaling.png"), &results.scaling, &gpu_name)?;
    say!("\nwrote {} (bench.csv, scaling.csv, peer.csv, scaling.png)", out.join("bench.md").display());
    Ok(())
}
