//! The error-against-run-time study (`eapbd report error-vs-time`, docs/algorithm.md §7).
//!
//! 1. **Start state.** The scene runs `start_frame` frames with a well-converged solver (CPU,
//!    f32, Gauss-Seidel, compliant form, [`WARMUP_SUBSTEPS`] substeps × 1 iteration); its
//!    positions `x_start` and velocities `v_start` are the common start of every run.
//! 2. **Reference.** From that state, the same scene runs in f64 (`CpuSolver<DVec3>`),
//!    Gauss-Seidel, compliant form, `reference_substeps` substeps × 1 iteration per frame: the
//!    time-continuous solution that every compliant-form variant approaches as its budget grows.
//!    A second reference with half the substeps, compared with it after `K` frames, estimates the
//!    reference's own error ([`Reference::check_error`]).
//! 3. **Sweep.** Each [`Variant`] runs the same `K` frames from the start state for every
//!    iterations × substeps shape of a budget `B = iterations × substeps` (projection sweeps per
//!    frame, so equal `B` means equal work per frame) and of a [`Split`]; its error is
//!    `e = ‖x − x_ref‖ / ‖x_ref − x_start‖` after `K` frames (norms over all particles, m/m),
//!    and its cost the measured wall-clock seconds per frame (the median over the `K` frames; on
//!    the GPU each frame is submitted and waited for).
//! 4. **Track.** Each variant at one mid budget runs `track_frames ≥ K` frames, its error taken
//!    after every frame against the reference advanced frame by frame.
//!
//! Energy-form variants converge to another model (XPBD minimises `E² / (2α)`), so their error
//! against the compliant reference is model error and is expected to plateau.

use std::time::Instant;

use glam::{DVec3, Vec3, Vec3A};

use super::stability::Gpu;
use crate::constraints::Form;
use crate::error::{Error, Result};
use crate::scene::{self, Scene, SceneOptions};
use crate::simulation::{Backend, Simulation};
use crate::solver::{CpuSolver, EnergyAware, Method, Settings};

pub use super::error_time_output::{FRAME_CSV_HEADER, SWEEP_CSV_HEADER, write_outputs};

/// Substeps per frame of the run to the start state (1 iteration each).
pub const WARMUP_SUBSTEPS: u32 = 100;
/// Lattice cells along the bunny's longest side in this study (648 tetrahedra): the scene's
/// default 16 (4998 tetrahedra) makes the 1000-substep reference cost minutes per frame here.
pub const BUNNY_LATTICE: u32 = 8;
/// SOR factor `ω` of the SOR variant.
pub const SOR_OMEGA: f32 = 1.5;

/// One solver variant: backend, iteration, form, energy-aware setting and SOR factor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Variant {
    /// Backend.
    pub backend: Backend,
    /// Gauss-Seidel or Jacobi (ω = 1).
    pub method: Method,
    /// Projection form.
    pub form: Form,
    /// Energy-aware setting.
    pub energy_aware: EnergyAware,
    /// SOR factor `ω` (1 = plain).
    pub sor: f32,
}

impl Variant {
    const fn new(backend: Backend, method: Method, form: Form, energy_aware: EnergyAware, sor: f32) -> Self {
        Variant { backend, method, form, energy_aware, sor }
    }

    /// Every variant of the full study, in the order of tables and legends.
    pub const ALL: [Variant; 11] = {
        use Backend::{Cpu, Gpu};
        use EnergyAware::{Global, Local, Off, Project};
        use Form::{Compliant, Energy};
        use Method::{GaussSeidel as Gs, Jacobi};
        [
            Variant::new(Cpu, Gs, Compliant, Off, 1.0),
            Variant::new(Cpu, Gs, Compliant, Off, SOR_OMEGA),
            Variant::new(Cpu, Gs, Compliant, Local, 1.0),
            Variant::new(Cpu, Gs, Compliant, Global, 1.0),
            Variant::new(Cpu, Gs, Compliant, Project, 1.0),
            Variant::new(Cpu, Jacobi, Compliant, Off, 1.0),
            Variant::new(Cpu, Gs, Energy, Off, 1.0),
            Variant::new(Cpu, Gs, Energy, Local, 1.0),
            Variant::new(Gpu, Gs, Compliant, Off, 1.0),
            Variant::new(Gpu, Jacobi, Compliant, Off, 1.0),
            Variant::new(Gpu, Gs, Compliant, Global, 1.0),
        ]
    };

    /// Name in tables, legends and the CSV, e.g. `cpu GS compliant SOR 1.5`, `gpu Jacobi
    /// compliant`, `cpu GS energy local`.
    pub fn name(&self) -> String {
        let method = match self.method {
            Method::GaussSeidel => "GS",
            Method::Jacobi => "Jacobi",
        };
        let mut s = format!("{} {method} {}", self.backend.name(), self.form.name());
        if self.energy_aware != EnergyAware::Off {
            s = format!("{s} {}", self.energy_aware.name());
        }
        if self.sor != 1.0 {
            s = format!("{s} SOR {}", self.sor);
        }
        s
    }

    /// Index in [`Variant::ALL`] (the plot colour), or `ALL.len()` for another variant.
    pub fn index(&self) -> usize {
        Variant::ALL.iter().position(|v| v == self).unwrap_or(Variant::ALL.len())
    }

    /// The solver settings of this variant at `iterations` × `substeps` per frame of `dt` (s).
    pub fn settings(&self, dt: f32, iterations: u32, substeps: u32) -> Settings {
        Settings {
            dt,
            iterations,
            substeps,
            form: self.form,
            method: self.method,
            energy_aware: self.energy_aware,
            sor: self.sor,
            ..Settings::default()
        }
    }
}

/// How a budget `B` of projection sweeps per frame is split into iterations × substeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    /// This many iterations per substep, `B / it` substeps (only where `it` divides `B`).
    PerSubstep(u32),
    /// One substep of `B` iterations (converges to one implicit-Euler step of the whole frame).
    OneSubstep,
}

impl Split {
    /// Name in tables and legends.
    pub fn name(self) -> String {
        match self {
            Split::PerSubstep(1) => "1 iteration/substep".into(),
            Split::PerSubstep(i) => format!("{i} iterations/substep"),
            Split::OneSubstep => "1 substep".into(),
        }
    }

    /// `(iterations, substeps)` of budget `b`, if this split has one.
    pub fn shape(self, b: u32) -> Option<(u32, u32)> {
        match self {
            Split::PerSubstep(i) => (i > 0 && b >= i && b.is_multiple_of(i)).then(|| (i, b / i)),
            Split::OneSubstep => (b > 0).then_some((b, 1)),
        }
    }

    /// Whether `(iterations, substeps)` belongs to this split.
    pub fn contains(self, iterations: u32, substeps: u32) -> bool {
        match self {
            Split::PerSubstep(i) => iterations == i,
            Split::OneSubstep => substeps == 1,
        }
    }
}

/// What the study runs.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyOptions {
    /// Scene name.
    pub scene: String,
    /// Scene options.
    pub options: SceneOptions,
    /// Frame time step (s).
    pub dt: f32,
    /// Frames run before the start state is taken.
    pub start_frame: u32,
    /// Frames `K` of the sweep.
    pub frames: u32,
    /// Substeps per frame of the f64 reference (1 iteration each).
    pub reference_substeps: u32,
    /// Budgets `B` (projection sweeps per frame).
    pub budgets: Vec<u32>,
    /// Splits of each budget.
    pub splits: Vec<Split>,
    /// Variants.
    pub variants: Vec<Variant>,
    /// Frames of the error-against-frame runs (at least `frames`).
    pub track_frames: u32,
    /// Budget of the error-against-frame runs.
    pub track_budget: u32,
    /// Splits of the error-against-frame runs.
    pub track_splits: Vec<Split>,
    /// Written by `--quick`.
    pub quick: bool,
}

/// Frames before the start state by default: the cloth mid-fall (frame 20 of its swing), the
/// bunny just after it lands (it touches the ground near frame 10), 20 otherwise.
pub fn default_start_frame(scene: &str) -> u32 {
    match scene {
        "bunny" => 12,
        _ => 20,
    }
}

impl StudyOptions {
    /// The full study (about 5 to 10 minutes per scene on 2 cores): budgets 4 … 128, splits of
    /// 1 and 4 iterations per substep and one substep, every variant of [`Variant::ALL`],
    /// `K` = 10 frames, a 1000-substep reference, and 60 frames of error against frame number at
    /// budget 32.
    pub fn full(scene: &str, options: SceneOptions) -> Self {
        StudyOptions {
            scene: scene.to_string(),
            options: study_scene_options(scene, options),
            dt: 1.0 / 60.0,
            start_frame: default_start_frame(scene),
            frames: 10,
            reference_substeps: 1000,
            budgets: vec![4, 8, 16, 32, 64, 128],
            splits: vec![Split::PerSubstep(1), Split::PerSubstep(4), Split::OneSubstep],
            variants: Variant::ALL.to_vec(),
            track_frames: 60,
            track_budget: 32,
            track_splits: vec![Split::PerSubstep(1), Split::OneSubstep],
            quick: false,
        }
    }

    /// The CI run (under a minute per scene): budgets 2, 8, 32, splits of 1 iteration per
    /// substep and one substep, every variant, `K` = 5 frames, a 200-substep reference, 15
    /// frames of error against frame number at budget 8.
    pub fn quick(scene: &str, options: SceneOptions) -> Self {
        StudyOptions {
            frames: 5,
            reference_substeps: 200,
            budgets: vec![2, 8, 32],
            splits: vec![Split::PerSubstep(1), Split::OneSubstep],
            track_frames: 15,
            track_budget: 8,
            track_splits: vec![Split::PerSubstep(1)],
            quick: true,
            ..StudyOptions::full(scene, options)
        }
    }

    /// The distinct `(iterations, substeps)` of every budget and split, by budget then
    /// iterations.
    pub fn shapes(&self) -> Vec<(u32, u32)> {
        let mut out: Vec<(u32, u32)> =
            self.budgets.iter().flat_map(|&b| self.splits.iter().filter_map(move |s| s.shape(b))).collect();
        out.sort_by_key(|&(i, s)| (i * s, i));
        out.dedup();
        out
    }

    /// The `(iterations, substeps)` of the error-against-frame runs.
    pub fn track_shapes(&self) -> Vec<(u32, u32)> {
        let mut out: Vec<(u32, u32)> = self.track_splits.iter().filter_map(|s| s.shape(self.track_budget)).collect();
        out.dedup();
        out
    }

    /// Progress steps of [`run_study`]: reference frames, check frames, sweep runs, track runs.
    pub fn steps(&self) -> usize {
        self.track_frames.max(self.frames) as usize
            + self.frames as usize
            + self.variants.len() * (self.shapes().len() + self.track_shapes().len())
    }

    /// Rejects options that cannot give a study.
    pub fn validate(&self) -> Result<()> {
        if self.frames == 0 || self.track_frames < self.frames {
            return Err(Error::param("--frames", self.frames, "must be at least 1 and at most the tracked frames"));
        }
        if self.reference_substeps < 2 {
            return Err(Error::param("--reference-substeps", self.reference_substeps, "must be at least 2"));
        }
        if self.budgets.is_empty() || self.shapes().is_empty() {
            return Err(Error::Report("no budget has a shape in the chosen splits".into()));
        }
        for &(it, sub) in self.shapes().iter().chain(&self.track_shapes()) {
            for v in &self.variants {
                v.settings(self.dt, it, sub).validate()?;
            }
        }
        Ok(())
    }
}

/// The scene options the study uses: the bunny's lattice defaults to [`BUNNY_LATTICE`].
pub fn study_scene_options(scene: &str, mut options: SceneOptions) -> SceneOptions {
    if scene == "bunny" && options.lattice.is_none() {
        options.lattice = Some(BUNNY_LATTICE);
    }
    options
}

/// The common start state.
#[derive(Clone, Debug)]
pub struct Start {
    /// The scene with its initial positions replaced by `x_start` (m).
    pub scene: Scene,
    /// Velocities `v_start` (m/s).
    pub velocities: Vec<Vec3>,
    /// Wall-clock time of the run to the start state (s).
    pub wall: f64,
}

/// Runs `opts.start_frame` frames of the scene with the warm-up solver and returns that state.
pub fn start_state(opts: &StudyOptions) -> Result<Start> {
    let mut scene = scene::build(&opts.scene, &opts.options)?;
    let t0 = Instant::now();
    let warmup = Settings { dt: opts.dt, substeps: WARMUP_SUBSTEPS, iterations: 1, ..Settings::default() };
    warmup.validate()?;
    let mut sv = CpuSolver::<Vec3A>::new(scene.clone());
    for _ in 0..opts.start_frame {
        sv.step_frame(&warmup);
    }
    if !sv.particles.x.iter().chain(&sv.particles.v).all(|p| p.is_finite()) {
        return Err(Error::Report(format!("the start state of {} is not finite", opts.scene)));
    }
    scene.positions = sv.particles.positions();
    Ok(Start { scene, velocities: sv.particles.velocities(), wall: t0.elapsed().as_secs_f64() })
}

/// The f64 reference trajectory.
#[derive(Clone, Debug)]
pub struct Reference {
    /// Positions after each frame `0..=track_frames` (frame 0 is `x_start`), m.
    pub positions: Vec<Vec<DVec3>>,
    /// Substeps per frame.
    pub substeps: u32,
    /// Wall-clock time per frame (s).
    pub seconds_per_frame: f64,
    /// Error of the half-substep reference after `K` frames against this one (dimensionless, as
    /// [`relative_error`]): an estimate of the reference's own error.
    pub check_error: f64,
    /// `‖x_ref − x_start‖` after `K` frames (m), the error's denominator.
    pub displacement: f64,
    /// RMS displacement `‖x_ref − x_start‖ / √n` over the `n` free particles after `K` frames (m).
    pub displacement_rms: f64,
}

impl Reference {
    /// `x_start`.
    pub fn start(&self) -> &[DVec3] {
        &self.positions[0]
    }
}

fn f64_solver(start: &Start) -> CpuSolver<DVec3> {
    let mut sv = CpuSolver::<DVec3>::new(start.scene.clone());
    sv.particles.v = start.velocities.iter().map(|v| v.as_dvec3()).collect();
    sv
}

/// `‖x − x_ref‖ / ‖x_ref − x_start‖` (norms over all particles; dimensionless) and the RMS
/// distance `‖x − x_ref‖ / √n` over the `n` free particles (m). Non-finite positions give NaN.
pub fn relative_error(x: &[Vec3], reference: &[DVec3], start: &[DVec3], w: &[f32]) -> (f64, f64) {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for ((p, r), s) in x.iter().zip(reference).zip(start) {
        let p = p.as_dvec3();
        if !p.is_finite() {
            return (f64::NAN, f64::NAN);
        }
        num += p.distance_squared(*r);
        den += r.distance_squared(*s);
    }
    let free = w.iter().filter(|&&w| w > 0.0).count().max(1) as f64;
    (num.sqrt() / den.sqrt().max(1e-300), (num / free).sqrt())
}

fn as_f32(x: &[DVec3]) -> Vec<Vec3> {
    x.iter().map(|p| p.as_vec3()).collect()
}

/// One variant at one shape: the sweep's row.
#[derive(Clone, Debug)]
pub struct Row {
    /// Variant.
    pub variant: Variant,
    /// Iterations per substep.
    pub iterations: u32,
    /// Substeps per frame.
    pub substeps: u32,
    /// Median wall-clock time per frame (s).
    pub seconds_per_frame: f64,
    /// Relative error after `K` frames ([`relative_error`]).
    pub error: f64,
    /// RMS distance to the reference after `K` frames (m).
    pub rms: f64,
}

impl Row {
    /// `iterations × substeps`: projection sweeps per frame.
    pub fn budget(&self) -> u32 {
        self.iterations * self.substeps
    }

    /// Whether the error is finite.
    pub fn finite(&self) -> bool {
        self.error.is_finite()
    }
}

/// One variant's error after one frame of a track run.
#[derive(Clone, Debug)]
pub struct TrackPoint {
    /// Variant.
    pub variant: Variant,
    /// Iterations per substep.
    pub iterations: u32,
    /// Substeps per frame.
    pub substeps: u32,
    /// Frame after the start (1 …).
    pub frame: u32,
    /// Relative error against the reference at this frame.
    pub error: f64,
    /// RMS distance to the reference (m).
    pub rms: f64,
}

/// What [`run_study`] reports as it goes.
#[derive(Clone, Debug)]
pub enum Progress<'a> {
    /// The reference (or its half-substep check, `check = true`) finished a frame.
    Reference {
        /// Frame finished.
        frame: u32,
        /// Frames to run.
        of: u32,
        /// The half-substep check run.
        check: bool,
    },
    /// A sweep run finished.
    Sweep(&'a Row),
    /// A track run finished (its points).
    Track(&'a [TrackPoint]),
}

/// Everything the study measured.
#[derive(Clone, Debug)]
pub struct Study {
    /// What was run.
    pub options: StudyOptions,
    /// Particles of the scene.
    pub particles: usize,
    /// Constraints of the scene.
    pub constraints: usize,
    /// The reference.
    pub reference: Reference,
    /// The sweep, by variant then shape.
    pub rows: Vec<Row>,
    /// The error-against-frame runs.
    pub track: Vec<TrackPoint>,
    /// GPU adapter used, if any.
    pub gpu: Option<String>,
    /// Variants skipped (no GPU adapter).
    pub skipped: Vec<Variant>,
    /// Wall-clock time of the whole study (s).
    pub wall: f64,
}

fn reference(opts: &StudyOptions, start: &Start, progress: &mut dyn FnMut(Progress)) -> Result<Reference> {
    let s = Settings { dt: opts.dt, substeps: opts.reference_substeps, iterations: 1, ..Settings::default() };
    s.validate()?;
    let frames = opts.track_frames.max(opts.frames);
    let mut sv = f64_solver(start);
    let mut positions = vec![sv.particles.x.clone()];
    let t0 = Instant::now();
    for frame in 1..=frames {
        sv.step_frame(&s);
        if !sv.particles.x.iter().all(|p| p.is_finite()) {
            return Err(Error::Report(format!("the reference is not finite at frame {frame}")));
        }
        positions.push(sv.particles.x.clone());
        progress(Progress::Reference { frame, of: frames, check: false });
    }
    let seconds_per_frame = t0.elapsed().as_secs_f64() / frames as f64;
    let half = Settings { substeps: opts.reference_substeps / 2, ..s };
    let mut check = f64_solver(start);
    for frame in 1..=opts.frames {
        check.step_frame(&half);
        progress(Progress::Reference { frame, of: opts.frames, check: true });
    }
    let k = opts.frames as usize;
    let (check_error, _) =
        relative_error(&as_f32(&check.particles.x), &positions[k], &positions[0], &start.scene.inv_mass);
    let displacement = positions[k].iter().zip(&positions[0]).map(|(a, b)| a.distance_squared(*b)).sum::<f64>().sqrt();
    let free = start.scene.inv_mass.iter().filter(|&&w| w > 0.0).count().max(1) as f64;
    Ok(Reference {
        positions,
        substeps: opts.reference_substeps,
        seconds_per_frame,
        check_error,
        displacement,
        displacement_rms: displacement / free.sqrt(),
    })
}

/// Positions (m) after a frame (numbered from 1).
type FramePositions = (u32, Vec<Vec3>);

/// Runs `variant` at `iterations × substeps` for `frames` frames from the start state. Returns
/// the median wall-clock seconds per frame and, for each frame in `1..=frames` when `every_frame`
/// (else for the last only), the positions.
fn run_variant(
    start: &Start,
    gpu: Option<&Gpu>,
    s: &Settings,
    backend: Backend,
    frames: u32,
    every_frame: bool,
) -> Result<(f64, Vec<FramePositions>)> {
    let mut sim = Simulation::new(backend, start.scene.clone(), gpu.map(|(c, k)| (c, k)))?;
    sim.check_settings(s)?;
    sim.set_velocities(&start.velocities)?;
    let mut times = Vec::with_capacity(frames as usize);
    let mut out = Vec::new();
    for frame in 1..=frames {
        let t0 = Instant::now();
        sim.step_frame(s);
        if let (Simulation::Gpu(_), Some((ctx, _))) = (&sim, gpu) {
            ctx.wait()?;
        }
        times.push(t0.elapsed().as_secs_f64());
        if every_frame || frame == frames {
            out.push((frame, sim.positions()?));
        }
    }
    times.sort_by(f64::total_cmp);
    Ok((times[times.len() / 2], out))
}

/// Runs the study: start state, reference, sweep and track, calling `progress` as it goes. GPU
/// variants are skipped (listed in [`Study::skipped`]) when `gpu` is `None`.
pub fn run_study(opts: &StudyOptions, gpu: Option<&Gpu>, mut progress: impl FnMut(Progress)) -> Result<Study> {
    opts.validate()?;
    let t0 = Instant::now();
    let start = start_state(opts)?;
    let reference = reference(opts, &start, &mut progress)?;
    let w = &start.scene.inv_mass;
    let x_start = reference.start().to_vec();
    let (variants, skipped): (Vec<Variant>, Vec<Variant>) =
        opts.variants.iter().partition(|v| v.backend == Backend::Cpu || gpu.is_some());
    let k = opts.frames;
    let mut rows = Vec::new();
    for v in &variants {
        for &(it, sub) in &opts.shapes() {
            let s = v.settings(opts.dt, it, sub);
            let (sec, xs) = run_variant(&start, gpu, &s, v.backend, k, false)?;
            let (error, rms) = relative_error(&xs[0].1, &reference.positions[k as usize], &x_start, w);
            let row = Row { variant: *v, iterations: it, substeps: sub, seconds_per_frame: sec, error, rms };
            progress(Progress::Sweep(&row));
            rows.push(row);
        }
    }
    let mut track = Vec::new();
    for v in &variants {
        for &(it, sub) in &opts.track_shapes() {
            let s = v.settings(opts.dt, it, sub);
            let (_, xs) = run_variant(&start, gpu, &s, v.backend, opts.track_frames, true)?;
            let points: Vec<TrackPoint> = xs
                .iter()
                .map(|(frame, x)| {
                    let (error, rms) = relative_error(x, &reference.positions[*frame as usize], &x_start, w);
                    TrackPoint { variant: *v, iterations: it, substeps: sub, frame: *frame, error, rms }
                })
                .collect();
            progress(Progress::Track(&points));
            track.extend(points);
        }
    }
    Ok(Study {
        options: opts.clone(),
        particles: start.scene.num_particles(),
        constraints: start.scene.num_constraints(),
        reference,
        rows,
        track,
        gpu: gpu.map(|(c, _)| c.describe()),
        skipped,
        wall: t0.elapsed().as_secs_f64(),
    })
}
