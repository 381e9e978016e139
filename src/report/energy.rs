//! The energy study (`eapbd report energy`): each energy-aware setting and SOR at several
//! iteration counts and time steps, on a pinned cloth under gravity and on the free stretched
//! cloth without gravity; total energy against time, drift, stretch, residual and cost.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;
use std::time::Instant;

use glam::Vec3A;

use super::plot::{Legend, Line, Panel, save_panels};
use crate::error::{Error, Result};
use crate::metrics::FrameStats;
use crate::scene::{self, SceneOptions};
use crate::solver::{CpuSolver, EnergyAware, Settings};

/// A solver variant compared by the study.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// Plain XPBD.
    Off,
    /// `--energy-aware local`.
    Local,
    /// `--energy-aware global`.
    Global,
    /// Plain XPBD with SOR ω = 1.5.
    Sor,
}

impl Variant {
    /// All variants, in the order of tables and legends.
    pub const ALL: [Variant; 4] = [Variant::Off, Variant::Local, Variant::Global, Variant::Sor];

    /// Name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Variant::Off => "off",
            Variant::Local => "local",
            Variant::Global => "global",
            Variant::Sor => "SOR 1.5",
        }
    }

    /// The solver settings of this variant.
    pub fn settings(self, base: Settings) -> Settings {
        match self {
            Variant::Off => Settings { energy_aware: EnergyAware::Off, ..base },
            Variant::Local => Settings { energy_aware: EnergyAware::Local, ..base },
            Variant::Global => Settings { energy_aware: EnergyAware::Global, ..base },
            Variant::Sor => Settings { energy_aware: EnergyAware::Off, sor: 1.5, ..base },
        }
    }
}

/// What the study runs.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyOptions {
    /// Scenes with their spring stiffness `k_s` (N/m), e.g. `cloth` with gravity at 1000 N/m
    /// and `cloth-free` without gravity at 10 N/m (the prototype's settings).
    pub scenes: Vec<(String, f32)>,
    /// Particles per side of the cloth.
    pub resolution: u32,
    /// Simulated time per run (s).
    pub duration: f32,
    /// Iteration counts.
    pub iterations: Vec<u32>,
    /// Time steps (s).
    pub steps: Vec<f32>,
}

impl StudyOptions {
    /// The full study: 4 iteration counts × 3 time steps × 4 variants per scene, 10 s each.
    pub fn full(scenes: Vec<(String, f32)>) -> Self {
        StudyOptions {
            scenes,
            resolution: 21,
            duration: 10.0,
            iterations: vec![5, 15, 30, 100],
            steps: vec![1.0 / 30.0, 1.0 / 60.0, 1.0 / 120.0],
        }
    }

    /// A run of a few seconds (CI).
    pub fn quick(scenes: Vec<(String, f32)>) -> Self {
        StudyOptions { scenes, resolution: 11, duration: 1.0, iterations: vec![5, 30], steps: vec![1.0 / 60.0] }
    }

    /// Number of runs.
    pub fn runs(&self) -> usize {
        self.scenes.len() * self.iterations.len() * self.steps.len() * Variant::ALL.len()
    }
}

/// One run's results.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// Scene name.
    pub scene: String,
    /// Spring stiffness (N/m).
    pub stiffness: f32,
    /// Variant.
    pub variant: Variant,
    /// Iterations per substep.
    pub iterations: u32,
    /// Time step (s).
    pub dt: f32,
    /// Frames run.
    pub frames: u32,
    /// Total energy at the start (J).
    pub start_total: f64,
    /// Total energy at the end (J).
    pub end_total: f64,
    /// Lowest and highest total energy seen (J).
    pub min_total: f64,
    /// Highest total energy seen (J).
    pub max_total: f64,
    /// Time average of the mean stretch.
    pub stretch_mean: f64,
    /// Largest stretch seen.
    pub stretch_max: f64,
    /// Time average of the RMS residual.
    pub residual: f64,
    /// Mean solve time per frame (ms).
    pub ms_per_frame: f64,
    /// Whether every value stayed finite.
    pub finite: bool,
    /// Sampled frames `(time s, stats)`.
    pub series: Vec<(f64, FrameStats)>,
}

impl RunResult {
    /// `(end − start) / |start|`.
    pub fn drift(&self) -> f64 {
        (self.end_total - self.start_total) / self.start_total.abs().max(1e-12)
    }
}

/// Runs one configuration.
pub fn run_one(
    opts: &StudyOptions,
    (scene_name, stiffness): (&str, f32),
    variant: Variant,
    iterations: u32,
    dt: f32,
) -> Result<RunResult> {
    let so = SceneOptions { resolution: Some(opts.resolution), stiffness, ..SceneOptions::default() };
    let mut sv = CpuSolver::<Vec3A>::new(scene::build(scene_name, &so)?);
    let s = variant.settings(Settings { dt, iterations, ..Settings::default() });
    s.validate()?;
    let frames = (opts.duration / dt).round().max(1.0) as u32;
    let sample_every = (frames / 200).max(1);
    let (mut series, mut time_ms) = (Vec::new(), 0.0);
    let (mut min_total, mut max_total, mut stretch_sum, mut stretch_max, mut residual_sum) =
        (f64::MAX, f64::MIN, 0.0, 0.0f64, 0.0);
    let mut last = FrameStats::measure(&sv, 0, 0.0);
    let start_total = last.total();
    series.push((0.0, last));
    for frame in 1..=frames {
        let t0 = Instant::now();
        sv.step_frame(&s);
        let ms = t0.elapsed().as_secs_f64() * 1e3;
        time_ms += ms;
        last = FrameStats::measure(&sv, frame, ms);
        min_total = min_total.min(last.total());
        max_total = max_total.max(last.total());
        stretch_sum += last.stretch_mean;
        stretch_max = stretch_max.max(last.stretch_max);
        residual_sum += last.residual_rms;
        if frame % sample_every == 0 {
            series.push((frame as f64 * dt as f64, last));
        }
        if !last.is_finite() {
            break;
        }
    }
    Ok(RunResult {
        scene: scene_name.to_string(),
        stiffness,
        variant,
        iterations,
        dt,
        frames,
        start_total,
        end_total: last.total(),
        min_total,
        max_total,
        stretch_mean: stretch_sum / frames as f64,
        stretch_max,
        residual: residual_sum / frames as f64,
        ms_per_frame: time_ms / frames as f64,
        finite: last.is_finite(),
        series,
    })
}

/// Runs every configuration, calling `progress` after each.
pub fn run_study(opts: &StudyOptions, mut progress: impl FnMut(&RunResult)) -> Result<Vec<RunResult>> {
    let mut out = Vec::with_capacity(opts.runs());
    for (scene_name, stiffness) in &opts.scenes {
        for &dt in &opts.steps {
            for &iterations in &opts.iterations {
                for variant in Variant::ALL {
                    let r = run_one(opts, (scene_name, *stiffness), variant, iterations, dt)?;
                    progress(&r);
                    out.push(r);
                }
            }
        }
    }
    Ok(out)
}

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io { path: path.to_path_buf(), source }
}

fn fps(dt: f32) -> u32 {
    (1.0 / dt).round() as u32
}

/// Writes `energy_runs.csv`, `energy_series.csv`, `energy.md` and one PNG per scene and time step
/// into `dir`.
pub fn write_outputs(dir: &Path, opts: &StudyOptions, results: &[RunResult]) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let runs = dir.join("energy_runs.csv");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&runs).map_err(io(&runs))?);
    writeln!(f, "scene,stiffness,variant,iterations,dt_s,frames,start_total_j,end_total_j,drift,min_total_j,max_total_j,stretch_mean,stretch_max,residual_rms,ms_per_frame,finite").map_err(io(&runs))?;
    for r in results {
        writeln!(
            f,
            "{},{},{},{},{:.6},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.4},{}",
            r.scene,
            r.stiffness,
            r.variant.name(),
            r.iterations,
            r.dt,
            r.frames,
            r.start_total,
            r.end_total,
            r.drift(),
            r.min_total,
            r.max_total,
            r.stretch_mean,
            r.stretch_max,
            r.residual,
            r.ms_per_frame,
            r.finite
        )
        .map_err(io(&runs))?;
    }
    f.flush().map_err(io(&runs))?;

    let series = dir.join("energy_series.csv");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&series).map_err(io(&series))?);
    writeln!(f, "scene,variant,iterations,dt_s,time_s,kinetic_j,gravitational_j,elastic_j,total_j,dissipated_j,stretch_mean,stretch_max,unresolved_j")
        .map_err(io(&series))?;
    for r in results {
        for (t, s) in &r.series {
            writeln!(
                f,
                "{},{},{},{:.6},{:.4},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e}",
                r.scene,
                r.variant.name(),
                r.iterations,
                r.dt,
                t,
                s.kinetic,
                s.gravitational,
                s.elastic,
                s.total(),
                s.dissipated,
                s.stretch_mean,
                s.stretch_max,
                s.unresolved
            )
            .map_err(io(&series))?;
        }
    }
    f.flush().map_err(io(&series))?;

    for (scene_name, stiffness) in &opts.scenes {
        for &dt in &opts.steps {
            let panels: Vec<Panel> = opts
                .iterations
                .iter()
                .map(|&it| Panel {
                    title: format!("{it} iterations"),
                    x_label: "time (s)".into(),
                    y_label: "total energy (J)".into(),
                    lines: results
                        .iter()
                        .filter(|r| &r.scene == scene_name && r.dt == dt && r.iterations == it)
                        .map(|r| Line {
                            label: r.variant.name().into(),
                            points: r.series.iter().map(|(t, s)| (*t, s.total())).collect(),
                            color: Variant::ALL.iter().position(|v| *v == r.variant).unwrap_or(0),
                            markers: false,
                        })
                        .collect(),
                    legend: Legend::LowerLeft,
                })
                .collect();
            let path = dir.join(format!("energy_{scene_name}_dt{}.png", fps(dt)));
            let title = format!("{scene_name}, k = {stiffness} N/m: total energy, dt = 1/{} s", fps(dt));
            save_panels(&path, &title, &panels, 2, (520, 340))?;
        }
    }

    let md = dir.join("energy.md");
    std::fs::write(&md, markdown(opts, results)).map_err(io(&md))
}

fn markdown(opts: &StudyOptions, results: &[RunResult]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Energy study\n");
    let _ = writeln!(
        s,
        "Produced by `eapbd report energy`: {}×{} cloth, {} s per run, CPU solver (f32), \
         Gauss-Seidel, compliant form, one substep per frame. Drift is (end − start) / |start| of the total \
         energy (kinetic + gravitational from the ground + elastic); min/max are relative to the start. \
         Stretch is the time average of the mean relative stretch and the largest stretch seen; \
         the residual is the time average of the RMS of |C + α̃λ|.\n",
        opts.resolution, opts.resolution, opts.duration
    );
    for (scene_name, stiffness) in &opts.scenes {
        let _ = writeln!(s, "## {scene_name}, k_s = {stiffness} N/m\n");
        let _ = writeln!(
            s,
            "| dt (s) | iterations | variant | drift | min | max | stretch mean | stretch max | residual | ms/frame | finite |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
        for r in results.iter().filter(|r| &r.scene == scene_name) {
            let rel = |v: f64| 100.0 * (v - r.start_total) / r.start_total.abs().max(1e-12);
            let _ = writeln!(
                s,
                "| 1/{} | {} | {} | {:+.1}% | {:+.1}% | {:+.1}% | {:.4} | {:.3} | {:.2e} | {:.2} | {} |",
                fps(r.dt),
                r.iterations,
                r.variant.name(),
                100.0 * r.drift(),
                rel(r.min_total),
                rel(r.max_total),
                r.stretch_mean,
                r.stretch_max,
                r.residual,
                r.ms_per_frame,
                if r.finite { "yes" } else { "NO" }
            );
        }
        let _ = writeln!(s);
        for &dt in &opts.steps {
            let _ = writeln!(s, "![{scene_name}, dt = 1/{}](energy_{scene_name}_dt{}.png)\n", fps(dt), fps(dt));
        }
    }
    s
}
