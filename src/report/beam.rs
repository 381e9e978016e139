//! The cantilever study (`eapbd report beam`): the static tip deflection of the `beam` scene under
//! its own weight, per 3D material, mesh resolution and solver setting, against the
//! Euler–Bernoulli estimate `δ = q L⁴ / (8 E I)` ([`Cantilever`]).
//!
//! Each XPBD run starts the beam straight and at rest under gravity and steps frames (compliant
//! form, Gauss-Seidel, explicit velocity damping) until the tip deflection changes by less than
//! `tolerance` (relative: max − min over the deflection) during the last `window` seconds of
//! simulated time, or until `max_time`. The tip deflection is the mean downward displacement of
//! the particles of the free end (`x = +0.5 m`) from rest.
//!
//! XPBD comes to rest where its substep returns the predicted positions `x + h² g` to `x`; with
//! too few iterations per substep that is not an equilibrium of the elastic model (too soft), and
//! XPBD's linearisation along the iterates leaves an error that falls with `h²`. So every mesh is
//! also solved directly for its static equilibrium ([`equilibrium::solve`]); a run counts as
//! converged when it settled within [`CONVERGED`] of that answer. The gap between the static
//! answer and Euler–Bernoulli is the mesh's (linear tetrahedra are too stiff in bending).

use std::collections::VecDeque;
use std::time::Instant;

use glam::{DVec3, Vec3};

pub use super::beam_output::write_outputs;
use super::cantilever::Cantilever;
use super::equilibrium::{self, Tolerances};
use crate::constraints::Form;
use crate::error::{Error, Result};
use crate::material::Model;
use crate::math::prelude::*;
use crate::scene::{self, SOLID_DENSITY, Scene, SceneOptions};
use crate::solver::{CpuSolver, Settings};

/// Floating-point precision of the solver state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    /// `f32`, as the runtime solvers.
    F32,
    /// `f64`.
    F64,
}

impl Precision {
    /// Name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
}

/// Which question a run answers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sweep {
    /// Mesh refinement at the reference solver setting.
    Resolution,
    /// Solver setting (substeps, iterations, precision, damping) at a fixed mesh.
    Solver,
}

impl Sweep {
    /// Name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Sweep::Resolution => "resolution",
            Sweep::Solver => "solver",
        }
    }
}

/// One XPBD configuration of the study.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunConfig {
    /// The table it belongs to.
    pub sweep: Sweep,
    /// The 3D material.
    pub model: Model,
    /// Cells along the beam (`--resolution`); `max(n/5, 1)` across.
    pub resolution: u32,
    /// Substeps per frame.
    pub substeps: u32,
    /// Gauss-Seidel iterations per substep.
    pub iterations: u32,
    /// Precision of the solver state.
    pub precision: Precision,
    /// Explicit velocity damping `β_v` (1/s).
    pub damping: f32,
}

/// What the study runs.
#[derive(Clone, Debug, PartialEq)]
pub struct StudyOptions {
    /// Young's modulus (Pa): small enough a deflection for every model to be in its linear range.
    pub young: f64,
    /// Poisson's ratio.
    pub poisson: f64,
    /// Frame time step (s).
    pub dt: f32,
    /// Settling window (s of simulated time).
    pub window: f64,
    /// Largest relative change of the deflection over the window that counts as settled.
    pub tolerance: f64,
    /// Longest simulated time per run (s).
    pub max_time: f64,
    /// The XPBD runs.
    pub runs: Vec<RunConfig>,
    /// Resolutions solved statically for the linear model only (no XPBD run), to show where the
    /// mesh converges.
    pub static_only: Vec<u32>,
}

/// The materials the study compares.
pub const MODELS: [Model; 3] = [Model::Linear, Model::StVK, Model::NeoHookean];

/// Young's modulus of the study (Pa): `δ_EB ≈ 3.68 mm` for the 1 m beam, a tip slope of 0.28°,
/// strains below 0.2%.
pub const YOUNG: f64 = 1.0e8;

/// The reference XPBD setting of the resolution sweep: substeps per frame, iterations (f64).
pub const REFERENCE: (u32, u32) = (400, 2);

/// A settled run within this relative distance of the static answer counts as converged.
pub const CONVERGED: f64 = 0.01;

/// Velocity damping `β_v = 2 ω₁` (1/s) that damps the Euler–Bernoulli fundamental critically
/// (129 1/s at 1e8 Pa). Every mode decays at least at `β_v / 2`; the static state is unchanged.
pub fn critical_damping(young: f64) -> f32 {
    let beam = Cantilever { length: 1.0, width: 0.2, height: 0.2, density: SOLID_DENSITY as f64, gravity: 9.81 };
    (2.0 * beam.first_frequency(young)) as f32
}

impl StudyOptions {
    fn base(runs: Vec<RunConfig>, max_time: f64, static_only: Vec<u32>) -> Self {
        StudyOptions {
            young: YOUNG,
            poisson: 0.3,
            dt: 1.0 / 60.0,
            window: 0.25,
            tolerance: 1e-4,
            max_time,
            runs,
            static_only,
        }
    }

    /// The full study (15 to 20 minutes on one core): resolutions 5 to 30 for each material at
    /// the reference setting; on the 10-cell linear beam, substeps × iterations in f32 and f64
    /// and the damping; on the 30-cell beam, fewer substeps; static solutions of the linear model
    /// up to 60 cells.
    pub fn full() -> Self {
        let beta = critical_damping(YOUNG);
        let mut runs = Vec::new();
        for model in MODELS {
            for resolution in [5, 10, 15, 20, 30] {
                runs.push(reference(model, resolution, beta));
            }
        }
        let solver = |resolution, substeps, iterations, precision, damping| RunConfig {
            sweep: Sweep::Solver,
            model: Model::Linear,
            resolution,
            substeps,
            iterations,
            precision,
            damping,
        };
        for precision in [Precision::F32, Precision::F64] {
            for (substeps, iterations) in [(10, 10), (20, 50), (40, 100), (100, 2), (400, 2)] {
                runs.push(solver(10, substeps, iterations, precision, beta));
            }
        }
        for (substeps, iterations) in [(25, 2), (50, 2), (200, 2), (100, 20), (200, 10), (400, 1)] {
            runs.push(solver(10, substeps, iterations, Precision::F64, beta));
        }
        for damping in [0.0, 20.0] {
            runs.push(solver(10, 200, 2, Precision::F64, damping));
        }
        for substeps in [100, 200] {
            runs.push(solver(30, substeps, 2, Precision::F64, beta));
        }
        Self::base(runs, 3.0, vec![40, 50, 60])
    }

    /// A run of a few seconds (CI): the 5-cell beam, each material, and two solver settings.
    pub fn quick() -> Self {
        let beta = critical_damping(YOUNG);
        let mut runs: Vec<RunConfig> = MODELS.iter().map(|&m| reference(m, 5, beta)).collect();
        for (substeps, iterations, precision) in [(10, 10, Precision::F32), (100, 2, Precision::F64)] {
            runs.push(RunConfig {
                sweep: Sweep::Solver,
                model: Model::Linear,
                resolution: 5,
                substeps,
                iterations,
                precision,
                damping: beta,
            });
        }
        Self::base(runs, 1.0, Vec::new())
    }

    /// The `(model, resolution)` pairs solved statically, in order: those of the runs, then the
    /// static-only resolutions of the linear model.
    pub fn static_cases(&self) -> Vec<(Model, u32)> {
        let mut cases: Vec<(Model, u32)> = Vec::new();
        let extra = self.static_only.iter().map(|&n| (Model::Linear, n));
        for case in self.runs.iter().map(|r| (r.model, r.resolution)).chain(extra) {
            if !cases.contains(&case) {
                cases.push(case);
            }
        }
        cases
    }

    /// Number of static solves and XPBD runs.
    pub fn steps(&self) -> usize {
        self.static_cases().len() + self.runs.len()
    }
}

fn reference(model: Model, resolution: u32, damping: f32) -> RunConfig {
    let (substeps, iterations) = REFERENCE;
    RunConfig { sweep: Sweep::Resolution, model, resolution, substeps, iterations, precision: Precision::F64, damping }
}

/// A static solution of one mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticResult {
    /// The material.
    pub model: Model,
    /// Cells along the beam.
    pub resolution: u32,
    /// Tetrahedra.
    pub tets: usize,
    /// Tip deflection (m, downwards positive).
    pub deflection: f64,
    /// Euler–Bernoulli estimate (m).
    pub euler_bernoulli: f64,
    /// Newton steps.
    pub newton_steps: u32,
    /// Conjugate-gradient iterations.
    pub cg_iterations: u32,
    /// Final force residual `‖∇E − M g‖ / ‖M g‖`.
    pub residual: f64,
    /// Wall-clock time (s).
    pub wall: f64,
}

impl StaticResult {
    /// Deflection over the Euler–Bernoulli estimate.
    pub fn ratio(&self) -> f64 {
        self.deflection / self.euler_bernoulli
    }
}

/// One XPBD run's results.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// The configuration.
    pub config: RunConfig,
    /// Cells along x, y, z.
    pub cells: [u32; 3],
    /// Tetrahedra.
    pub tets: usize,
    /// Frame time step (s).
    pub dt: f32,
    /// Tip deflection (m, downwards positive).
    pub deflection: f64,
    /// Euler–Bernoulli estimate (m).
    pub euler_bernoulli: f64,
    /// The static answer of the same mesh and material (m), once solved.
    pub static_deflection: Option<f64>,
    /// Force residual `‖∇E − M g‖ / ‖M g‖` of the final state (dominated by element-scale
    /// errors: of order 1 even when the deflection has converged).
    pub force_residual: f64,
    /// RMS XPBD residual `|C + α̃λ|` of the last substep.
    pub xpbd_residual: f64,
    /// Relative change of the deflection over the last window.
    pub window_change: f64,
    /// Whether the run settled before `max_time`.
    pub settled: bool,
    /// Whether every position stayed finite.
    pub finite: bool,
    /// Simulated time (s).
    pub simulated: f64,
    /// Wall-clock time (s).
    pub wall: f64,
}

impl RunResult {
    /// Deflection over the Euler–Bernoulli estimate.
    pub fn ratio(&self) -> f64 {
        self.deflection / self.euler_bernoulli
    }

    /// Deflection over the static answer of the same mesh (NaN before it is known).
    pub fn ratio_to_static(&self) -> f64 {
        self.static_deflection.map_or(f64::NAN, |s| self.deflection / s)
    }

    /// Settled, finite and within [`CONVERGED`] of the static answer.
    pub fn converged(&self) -> bool {
        self.settled && self.finite && (self.ratio_to_static() - 1.0).abs() <= CONVERGED
    }
}

/// Everything the study produced.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StudyResults {
    /// Static solutions, in [`StudyOptions::static_cases`] order.
    pub statics: Vec<StaticResult>,
    /// XPBD runs, in [`StudyOptions::runs`] order.
    pub runs: Vec<RunResult>,
}

impl StudyResults {
    /// The static solution of a mesh, if solved.
    pub fn static_for(&self, model: Model, resolution: u32) -> Option<&StaticResult> {
        self.statics.iter().find(|s| s.model == model && s.resolution == resolution)
    }
}

/// A finished step of [`run_study`].
#[derive(Clone, Copy, Debug)]
pub enum Step<'a> {
    /// A static solve.
    Static(&'a StaticResult),
    /// An XPBD run.
    Run(&'a RunResult),
}

/// The study's beam (the `beam` scene's shape, density and gravity).
pub fn cantilever(opts: &StudyOptions) -> Result<Cantilever> {
    Ok(Cantilever::of_scene(&beam_scene(opts, Model::Linear, 5)?, SOLID_DENSITY as f64))
}

fn beam_scene(opts: &StudyOptions, model: Model, resolution: u32) -> Result<Scene> {
    let so = SceneOptions {
        resolution: Some(resolution),
        solid: Some(model),
        young: opts.young,
        poisson: opts.poisson,
        ..SceneOptions::default()
    };
    scene::build("beam", &so)
}

/// Particles of the free end (largest rest x) and their mean rest height (m).
fn tip(scene: &Scene) -> (Vec<usize>, f64) {
    let x_max = scene.positions.iter().map(|p| p.x).fold(f32::MIN, f32::max);
    let tip: Vec<usize> = (0..scene.positions.len()).filter(|&i| scene.positions[i].x >= x_max - 1e-6).collect();
    let rest_y = tip.iter().map(|&i| scene.positions[i].y as f64).sum::<f64>() / tip.len().max(1) as f64;
    (tip, rest_y)
}

/// Mean downward displacement of the `tip` particles from `rest_y` (m).
fn deflection(tip: &[usize], rest_y: f64, x: impl Fn(usize) -> DVec3) -> f64 {
    rest_y - tip.iter().map(|&i| x(i).y).sum::<f64>() / tip.len().max(1) as f64
}

/// Solves one mesh statically.
pub fn solve_static(opts: &StudyOptions, model: Model, resolution: u32) -> Result<StaticResult> {
    let scene = beam_scene(opts, model, resolution)?;
    let t0 = Instant::now();
    let eq = equilibrium::solve(&scene, Tolerances::default())?;
    let (tip, rest_y) = tip(&scene);
    Ok(StaticResult {
        model,
        resolution,
        tets: scene.tets.as_ref().map_or(0, |f| f.len()),
        deflection: deflection(&tip, rest_y, |i| eq.positions[i]),
        euler_bernoulli: Cantilever::of_scene(&scene, SOLID_DENSITY as f64).euler_bernoulli(opts.young),
        newton_steps: eq.newton_steps,
        cg_iterations: eq.cg_iterations,
        residual: eq.residual,
        wall: t0.elapsed().as_secs_f64(),
    })
}

/// Runs one XPBD configuration (its `static_deflection` is left empty).
pub fn run_one(opts: &StudyOptions, config: RunConfig) -> Result<RunResult> {
    if !(opts.window > 0.0 && opts.max_time >= opts.window && opts.tolerance > 0.0) {
        return Err(Error::param("beam study window", opts.window, "needs 0 < window ≤ max_time and tolerance > 0"));
    }
    let scene = beam_scene(opts, config.model, config.resolution)?;
    let settings = Settings {
        dt: opts.dt,
        substeps: config.substeps,
        iterations: config.iterations,
        form: Form::Compliant,
        damping: config.damping,
        ..Settings::default()
    };
    settings.validate()?;
    match config.precision {
        Precision::F32 => settle::<Vec3>(opts, config, scene, &settings),
        Precision::F64 => settle::<DVec3>(opts, config, scene, &settings),
    }
}

fn settle<V: Vector>(opts: &StudyOptions, config: RunConfig, scene: Scene, s: &Settings) -> Result<RunResult> {
    let euler_bernoulli = Cantilever::of_scene(&scene, SOLID_DENSITY as f64).euler_bernoulli(opts.young);
    let (tip, rest_y) = tip(&scene);
    let tets = scene.tets.as_ref().map_or(0, |f| f.len());
    let across = (config.resolution / 5).max(1);
    let mut sv = CpuSolver::<V>::new(scene);
    let measure = |sv: &CpuSolver<V>| deflection(&tip, rest_y, |i| sv.particles.x[i].to_dvec3());

    let window_frames = (opts.window / opts.dt as f64).round().max(1.0) as usize;
    let max_frames = (opts.max_time / opts.dt as f64).ceil().max(1.0) as usize;
    let mut history: VecDeque<f64> = VecDeque::with_capacity(window_frames + 1);
    let (mut settled, mut finite, mut frames, mut change) = (false, true, 0, f64::INFINITY);
    let t0 = Instant::now();
    while frames < max_frames {
        sv.step_frame(s);
        frames += 1;
        let d = measure(&sv);
        if !d.is_finite() {
            finite = false;
            break;
        }
        if history.len() == window_frames + 1 {
            history.pop_front();
        }
        history.push_back(d);
        if history.len() == window_frames + 1 {
            let (lo, hi) = history.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
            // A beam that never moved (d = 0) does not count as settled.
            change = if d != 0.0 { (hi - lo) / d.abs() } else { f64::INFINITY };
            if change <= opts.tolerance {
                settled = true;
                break;
            }
        }
    }
    let wall = t0.elapsed().as_secs_f64();
    let x: Vec<DVec3> = sv.particles.x.iter().map(|v| v.to_dvec3()).collect();
    Ok(RunResult {
        config,
        cells: [config.resolution, across, across],
        tets,
        dt: opts.dt,
        deflection: measure(&sv),
        euler_bernoulli,
        static_deflection: None,
        force_residual: equilibrium::force_residual(sv.scene(), &x),
        xpbd_residual: sv.residual().0,
        window_change: change,
        settled,
        finite,
        simulated: frames as f64 * opts.dt as f64,
        wall,
    })
}

/// Solves every mesh statically, then runs every XPBD configuration, calling `progress` after
/// each step.
pub fn run_study(opts: &StudyOptions, mut progress: impl FnMut(Step<'_>)) -> Result<StudyResults> {
    let mut out = StudyResults::default();
    for (model, resolution) in opts.static_cases() {
        let s = solve_static(opts, model, resolution)?;
        progress(Step::Static(&s));
        out.statics.push(s);
    }
    for &config in &opts.runs {
        let mut r = run_one(opts, config)?;
        r.static_deflection = out.static_for(config.model, config.resolution).map(|s| s.deflection);
        progress(Step::Run(&r));
        out.runs.push(r);
    }
    Ok(out)
}
