//! `eapbd report ...`: studies written as CSV, Markdown and PNG.

use std::path::PathBuf;

use clap::{Args, Subcommand};
use eapbd::report::energy::{StudyOptions, run_study, write_outputs};

/// Arguments of `eapbd report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// Which report.
    #[command(subcommand)]
    pub report: Report,
}

/// The reports.
#[derive(Subcommand, Debug)]
pub enum Report {
    /// Total energy, drift, stretch, residual and cost of each energy-aware setting and SOR over
    /// iteration counts and time steps.
    Energy(EnergyArgs),
}

/// Arguments of `eapbd report energy`.
#[derive(Args, Debug)]
pub struct EnergyArgs {
    /// Scenes to study (repeat the flag); default: cloth (pinned, gravity, k_s = 1000 N/m) and
    /// cloth-free (stretched, no gravity, k_s = 10 N/m).
    #[arg(long = "scene")]
    pub scenes: Vec<String>,
    /// Spring stiffness k_s (N/m) of scenes named with --scene.
    #[arg(long, default_value_t = 1000.0)]
    pub stiffness: f32,
    /// Output directory.
    #[arg(long, default_value = "docs/energy")]
    pub out: PathBuf,
    /// A small, short run (seconds) instead of the full study (minutes).
    #[arg(long)]
    pub quick: bool,
}

/// Runs the command.
pub fn run(a: &ReportArgs) -> anyhow::Result<()> {
    match &a.report {
        Report::Energy(e) => energy(e),
    }
}

fn energy(a: &EnergyArgs) -> anyhow::Result<()> {
    let scenes: Vec<(String, f32)> = if a.scenes.is_empty() {
        vec![("cloth".to_string(), 1000.0), ("cloth-free".to_string(), 10.0)]
    } else {
        a.scenes.iter().map(|s| (s.clone(), a.stiffness)).collect()
    };
    for (s, k) in &scenes {
        eapbd::scene::build(s, &eapbd::scene::SceneOptions { stiffness: *k, ..Default::default() })?;
    }
    let opts = if a.quick { StudyOptions::quick(scenes) } else { StudyOptions::full(scenes) };
    let bar = indicatif::ProgressBar::new(opts.runs() as u64);
    let results = run_study(&opts, |r| {
        bar.suspend(|| {
            println!(
                "{:12} dt 1/{:<3} {:3} it  {:8}  drift {:+7.1}%  stretch {:.4}  {:.2} ms/frame{}",
                r.scene,
                (1.0 / r.dt).round(),
                r.iterations,
                r.variant.name(),
                100.0 * r.drift(),
                r.stretch_mean,
                r.ms_per_frame,
                if r.finite { "" } else { "  NOT FINITE" }
            )
        });
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    write_outputs(&a.out, &opts, &results)?;
    println!("wrote {}", a.out.join("energy.md").display());
    Ok(())
}
