//! `eapbd report ...`: studies written as CSV, Markdown and PNG.

use std::path::PathBuf;

use clap::{Args, Subcommand};
use eapbd::report::{beam, energy, error_time, splits, stability};

use super::{MaterialArg, material};

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
    /// The hanging cloth at 1 × 30, 3 × 10, 10 × 3 and 30 × 1 (substeps × iterations) under each
    /// energy-aware setting: energy normalised by the energy available for motion, motion kept,
    /// stretch, unresolved stretch and cost; the free cloth's energy and momenta.
    Splits(SplitsArgs),
    /// Static tip deflection of the cantilever (linear, StVK, Neo-Hookean) against Euler–Bernoulli,
    /// over mesh resolution and solver settings, with the static finite-element answer of each mesh.
    Beam(BeamArgs),
    /// Hard cases (stiffness, time step, iterations, mass ratio, inversion, collapse, Poisson 0.49,
    /// huge velocities) on the CPU and GPU backends, each with pass or fail and its figures.
    Stability(StabilityArgs),
    /// Error against a converged f64 reference (1000 substeps per frame) and wall-clock time for
    /// every solver variant (CPU/GPU, Gauss-Seidel/Jacobi, forms, energy-aware, SOR) over
    /// iterations × substeps budgets, and error against frame number.
    ErrorVsTime(ErrorArgs),
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

/// Arguments of `eapbd report splits`.
#[derive(Args, Debug)]
pub struct SplitsArgs {
    /// Output directory.
    #[arg(long, default_value = "docs/energy-splits")]
    pub out: PathBuf,
    /// An 11×11 cloth for 2 s (seconds) instead of the full study (about a minute).
    #[arg(long)]
    pub quick: bool,
}

/// Arguments of `eapbd report beam`.
#[derive(Args, Debug)]
pub struct BeamArgs {
    /// Output directory.
    #[arg(long, default_value = "docs/beam")]
    pub out: PathBuf,
    /// The 5-cell beam only (seconds) instead of the full study (15 to 20 minutes).
    #[arg(long)]
    pub quick: bool,
}

/// Arguments of `eapbd report stability`.
#[derive(Args, Debug)]
pub struct StabilityArgs {
    /// Output directory.
    #[arg(long, default_value = "docs/stability")]
    pub out: PathBuf,
    /// The cheap subset of the cases (under a minute) instead of all of them (minutes).
    #[arg(long)]
    pub quick: bool,
    /// Run on the CPU only (GPU cases are listed as skipped).
    #[arg(long)]
    pub cpu_only: bool,
}

/// Arguments of `eapbd report error-vs-time`.
#[derive(Args, Debug)]
pub struct ErrorArgs {
    /// Scene: cloth (hanging, mid-fall), bunny (volumetric Neo-Hookean, just after landing) or any
    /// other scene name.
    #[arg(long, default_value = "cloth")]
    pub scene: String,
    /// Material: hookean or stvk-spring (cloth scenes); linear, stvk, neo-hookean, mooney-rivlin
    /// or arruda-boyce (volumetric scenes).
    #[arg(long, value_parser = material)]
    pub material: Option<MaterialArg>,
    /// Small-strain spring stiffness k_s (N/m).
    #[arg(long, allow_negative_numbers = true, default_value_t = 1.0e4)]
    pub stiffness: f32,
    /// Young's modulus of volumetric scenes (Pa).
    #[arg(long, allow_negative_numbers = true, default_value_t = 2.0e6)]
    pub young: f64,
    /// Poisson's ratio of volumetric scenes.
    #[arg(long, allow_negative_numbers = true, default_value_t = 0.3)]
    pub poisson: f64,
    /// Particles per side of a cloth (default 41).
    #[arg(long)]
    pub resolution: Option<u32>,
    /// Volumetric bunny: lattice cells along the longest side (default 8 in this report).
    #[arg(long)]
    pub lattice: Option<u32>,
    /// Dihedral bending stiffness k_b (N·m/rad) of cloth scenes; 0 disables.
    #[arg(long, allow_negative_numbers = true)]
    pub bending_stiffness: Option<f32>,
    /// Frames K after which the error is measured (default 10; 5 with --quick).
    #[arg(long)]
    pub frames: Option<u32>,
    /// Frames run before the start state is taken (default: 20 for the cloth, 12 for the bunny).
    #[arg(long)]
    pub start_frame: Option<u32>,
    /// Substeps per frame of the f64 reference (default 1000; 200 with --quick).
    #[arg(long)]
    pub reference_substeps: Option<u32>,
    /// Output directory (default docs/error/SCENE).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Fewer budgets, splits and frames and a cheaper reference (under a minute) instead of the
    /// full study (5 to 10 minutes).
    #[arg(long)]
    pub quick: bool,
    /// Run the CPU variants only (GPU variants are listed as skipped).
    #[arg(long)]
    pub cpu_only: bool,
}

impl ErrorArgs {
    /// The study these arguments select.
    pub fn options(&self) -> anyhow::Result<error_time::StudyOptions> {
        let (material, solid) = match self.material {
            Some(MaterialArg::Spring(m)) => (m, None),
            Some(MaterialArg::Solid(m)) => (eapbd::constraints::SpringMaterial::Hookean, Some(m)),
            Some(MaterialArg::AnisoCloth) => anyhow::bail!("--material aniso-cloth is not offered by this report"),
            None => (eapbd::constraints::SpringMaterial::Hookean, None),
        };
        let scene_options = eapbd::scene::SceneOptions {
            resolution: self.resolution,
            stiffness: self.stiffness,
            material,
            bending_stiffness: self.bending_stiffness,
            solid,
            young: self.young,
            poisson: self.poisson,
            lattice: self.lattice,
            ..Default::default()
        };
        let mut o = if self.quick {
            error_time::StudyOptions::quick(&self.scene, scene_options)
        } else {
            error_time::StudyOptions::full(&self.scene, scene_options)
        };
        if let Some(k) = self.frames {
            o.frames = k;
            o.track_frames = o.track_frames.max(k);
        }
        if let Some(f) = self.start_frame {
            o.start_frame = f;
        }
        if let Some(n) = self.reference_substeps {
            o.reference_substeps = n;
        }
        if self.cpu_only {
            o.variants.retain(|v| v.backend == eapbd::simulation::Backend::Cpu);
        }
        eapbd::scene::build(&o.scene, &o.options)?;
        o.validate()?;
        Ok(o)
    }
}

/// Runs the command.
pub fn run(a: &ReportArgs) -> anyhow::Result<()> {
    match &a.report {
        Report::Energy(e) => energy(e),
        Report::Splits(e) => splits_report(e),
        Report::Beam(b) => beam(b),
        Report::Stability(s) => stability(s),
        Report::ErrorVsTime(e) => error_vs_time(e),
    }
}

fn splits_report(a: &SplitsArgs) -> anyhow::Result<()> {
    let opts = if a.quick { splits::SplitsOptions::quick() } else { splits::SplitsOptions::full() };
    let (reference, runs, free) = splits::run_study(&opts, |line| say!("{line}"))?;
    splits::write_outputs(&a.out, &opts, &reference, &runs, &free)?;
    say!("wrote {}", a.out.join("splits.md").display());
    Ok(())
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
    let opts = if a.quick { energy::StudyOptions::quick(scenes) } else { energy::StudyOptions::full(scenes) };
    let bar = indicatif::ProgressBar::new(opts.runs() as u64);
    let results = energy::run_study(&opts, |r| {
        bar.suspend(|| {
            say!(
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
    energy::write_outputs(&a.out, &opts, &results)?;
    wrote(&bar, &a.out.join("energy.md"))
}

fn beam(a: &BeamArgs) -> anyhow::Result<()> {
    let opts = if a.quick { beam::StudyOptions::quick() } else { beam::StudyOptions::full() };
    let bar = indicatif::ProgressBar::new(opts.steps() as u64);
    let results = beam::run_study(&opts, |step| {
        bar.suspend(|| match step {
            beam::Step::Static(st) => say!(
                "static {:12} n {:2}  {:5} tets  δ {:.4} mm = {:.3} δ_EB  ({} Newton, {} CG, {:.1} s)",
                st.model.name(),
                st.resolution,
                st.tets,
                st.deflection * 1e3,
                st.ratio(),
                st.newton_steps,
                st.cg_iterations,
                st.wall
            ),
            beam::Step::Run(r) => say!(
                "xpbd   {:12} n {:2}  {:5} tets  {} {:3}×{:<3} β {:3.0}  δ {:.4} mm = {:.3} δ_EB = {:.4} static{}  \
                 ({:.2} s simulated, {:.1} s)",
                r.config.model.name(),
                r.config.resolution,
                r.tets,
                r.config.precision.name(),
                r.config.substeps,
                r.config.iterations,
                r.config.damping,
                r.deflection * 1e3,
                r.ratio(),
                r.ratio_to_static(),
                if r.settled { "" } else { "  NOT SETTLED" },
                r.simulated,
                r.wall
            ),
        });
        bar.inc(1);
    })?;
    beam::write_outputs(&a.out, &opts, &results)?;
    wrote(&bar, &a.out.join("beam.md"))
}

fn stability(a: &StabilityArgs) -> anyhow::Result<()> {
    let cases = if a.quick { stability::quick_cases() } else { stability::cases() };
    let gpu = if a.cpu_only { None } else { stability::open_gpu() };
    if gpu.is_none() && !a.cpu_only {
        eprintln!("no GPU adapter: GPU cases are skipped");
    }
    let bar = indicatif::ProgressBar::new(stability::runs(&cases) as u64);
    let started = std::time::Instant::now();
    let entries = stability::run_study(&cases, gpu.as_ref(), |e| {
        bar.suspend(|| match e {
            stability::Entry::Ran(o) => say!(
                "{:24} {}  {:4}  E {:9.3e}  KE {:9.3e}  stretch {:9.3e}  edge {:.3}  inverted {}→{}  {:6.2} s{}",
                o.case,
                o.backend.name(),
                if o.passed() { "pass" } else { "FAIL" },
                o.energy_ratio(),
                o.settle_ratio(),
                o.end_stretch,
                o.edge_ratio,
                o.inverted_start,
                o.inverted_end,
                o.wall,
                if o.passed() { String::new() } else { format!("  ({})", o.failures().join("; ")) }
            ),
            stability::Entry::Skipped { case, backend, reason } => {
                say!("{case:24} {}  skipped ({reason})", backend.name())
            }
        });
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    stability::write_outputs(&a.out, &cases, &entries, a.quick)?;
    say!("wrote {} ({:.1} s)", a.out.join("stability.md").display(), started.elapsed().as_secs_f64());
    Ok(())
}

fn error_vs_time(a: &ErrorArgs) -> anyhow::Result<()> {
    use error_time::Progress;
    let opts = a.options()?;
    let out = a.out.clone().unwrap_or_else(|| PathBuf::from("docs/error").join(&opts.scene));
    let wants_gpu = opts.variants.iter().any(|v| v.backend == eapbd::simulation::Backend::Gpu);
    let gpu = if wants_gpu { stability::open_gpu() } else { None };
    if gpu.is_none() && wants_gpu {
        eprintln!("no GPU adapter: GPU variants are skipped");
    }
    let bar = indicatif::ProgressBar::new(opts.steps() as u64);
    let study = error_time::run_study(&opts, gpu.as_ref(), |p| {
        match p {
            Progress::Reference { frame, of, check } => {
                bar.set_message(format!("{}reference frame {frame}/{of}", if check { "half-substep " } else { "" }));
            }
            Progress::Sweep(r) => bar.suspend(|| {
                say!(
                    "{:34} {:3} it × {:3} sub  e {:9.3e}  {:8.2} ms/frame{}",
                    r.variant.name(),
                    r.iterations,
                    r.substeps,
                    r.error,
                    r.seconds_per_frame * 1e3,
                    if r.finite() { "" } else { "  NOT FINITE" }
                )
            }),
            Progress::Track(points) => bar.suspend(|| {
                if let (Some(first), Some(last)) = (points.first(), points.last()) {
                    say!(
                        "{:34} {:3} it × {:3} sub  e over {} frames: {:9.3e} … {:9.3e}",
                        first.variant.name(),
                        first.iterations,
                        first.substeps,
                        last.frame,
                        first.error,
                        last.error
                    )
                }
            }),
        }
        bar.inc(1);
    })?;
    bar.finish_and_clear();
    say!(
        "reference: {} substeps, {:.2} s/frame, half-substep check e = {:.2e}",
        study.reference.substeps,
        study.reference.seconds_per_frame,
        study.reference.check_error
    );
    error_time::write_outputs(&out, &study)?;
    say!("wrote {} ({:.1} s)", out.join("error_vs_time.md").display(), study.wall);
    Ok(())
}

/// Clears a study's progress bar and says where its report went.
fn wrote(bar: &indicatif::ProgressBar, report: &std::path::Path) -> anyhow::Result<()> {
    bar.finish_and_clear();
    say!("wrote {}", report.display());
    Ok(())
}
