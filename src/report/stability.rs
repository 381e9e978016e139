//! The stability study (`eapbd report stability`): hard cases run headless on both backends, each
//! judged pass or fail from its own run.
//!
//! A case passes when
//! 1. every measured figure stays finite;
//! 2. the energy stays bounded: the energy of motion and deformation `N = KE + E_elastic` never
//!    exceeds [`ENERGY_FACTOR`] × (`N` at the start + the largest work gravity has done so far,
//!    `GPE₀ − GPE(t)`), so a blow-up fails while ordinary motion passes;
//! 3. the body returns towards rest: the kinetic energy of the last frame is at most
//!    [`SETTLE_FRACTION`] of its peak, and the shape is back: mean relative stretch at the end at
//!    most [`STRETCH_LIMIT`], no tetrahedron inverted at the end, and for the collapsed cloth a
//!    mean edge length within [`EDGE_TOLERANCE`] of its rest value.

use std::time::Instant;

use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

use crate::constraints::Element;
use crate::error::{Error, Result};
use crate::gpu::{GpuContext, Kernels};
use crate::metrics::{FrameStats, StateView};
use crate::scene::{self, Scene, SceneOptions};
use crate::simulation::{Backend, Simulation};
use crate::solver::Settings;

pub use super::stability_cases::{cases, quick_cases};
pub use super::stability_output::{CSV_HEADER, write_outputs};

/// Bound on the energy of motion and deformation, as a multiple of what the start and gravity
/// supplied (dimensionless).
pub const ENERGY_FACTOR: f64 = 2.0;
/// Largest kinetic energy at the end as a fraction of the run's peak (dimensionless).
pub const SETTLE_FRACTION: f64 = 0.1;
/// Largest mean relative stretch at the end (dimensionless).
pub const STRETCH_LIMIT: f64 = 0.25;
/// Largest relative error of the collapsed cloth's mean edge length at the end (dimensionless).
pub const EDGE_TOLERANCE: f64 = 0.1;
/// Velocity damping `β_v` of every case (1/s): the motion of a passing case dies within a few
/// seconds, so "returns towards rest" can be measured.
pub const DAMPING: f32 = 1.0;
/// Stiffness (N/m) at which the energy of the rigid (`k = ∞`, compliance 0) cloth is measured.
pub const RIGID_MEASURE_K: f32 = 1.0e9;

/// How a case changes the scene's initial state before the solver starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Modify {
    /// The scene as built.
    None,
    /// Every spring made rigid: `k = ∞`, compliance 0.
    Rigid,
    /// Every position mirrored through the centroid's `x = const` plane: all tetrahedra inverted.
    Mirror,
    /// Every position scaled by this factor along `x` about the centroid (a stretched start).
    StretchX(f32),
    /// Every particle moved to within `radius` (m) of the centroid with a seeded random jitter.
    Collapse {
        /// Jitter radius (m).
        radius: f32,
        /// Random seed.
        seed: u64,
    },
    /// The central `side × side` block of free particles made `ratio` times heavier.
    HeavyBlock {
        /// Particles per side of the block.
        side: u32,
        /// Mass ratio block : cloth particle.
        ratio: f32,
    },
    /// Every free particle given a seeded random velocity of magnitude `speed` (m/s).
    Velocity {
        /// Speed (m/s).
        speed: f32,
        /// Random seed.
        seed: u64,
    },
}

/// One hard case.
#[derive(Clone, Debug)]
pub struct Case {
    /// Short unique name.
    pub name: &'static str,
    /// What the case stresses (the matrix's row group).
    pub group: &'static str,
    /// What is run, in words.
    pub description: String,
    /// Scene name.
    pub scene: &'static str,
    /// Scene options.
    pub options: SceneOptions,
    /// Solver settings.
    pub settings: Settings,
    /// Change to the initial state.
    pub modify: Modify,
    /// Simulated time (s).
    pub duration: f32,
    /// Backends it runs on.
    pub backends: &'static [Backend],
    /// Backends it runs on in `--quick` mode (empty: not part of it).
    pub quick: &'static [Backend],
}

impl Case {
    /// Frames to run.
    pub fn frames(&self) -> u32 {
        (self.duration / self.settings.dt).round().max(1.0) as u32
    }
}

/// One case run on one backend.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// Case name.
    pub case: &'static str,
    /// Its group.
    pub group: &'static str,
    /// Backend.
    pub backend: Backend,
    /// Frames run (fewer than planned when a value stopped being finite).
    pub frames: u32,
    /// Every measured figure finite.
    pub finite: bool,
    /// First frame with a non-finite figure.
    pub nonfinite_frame: Option<u32>,
    /// `KE + E_elastic` at the start (J).
    pub start_energy: f64,
    /// Largest work of gravity `GPE₀ − GPE(t)` seen (J).
    pub gravity_work: f64,
    /// Largest `KE + E_elastic` seen (J).
    pub peak_energy: f64,
    /// Peak kinetic energy (J).
    pub peak_kinetic: f64,
    /// Kinetic energy at the end (J).
    pub end_kinetic: f64,
    /// Mean relative stretch at the end.
    pub end_stretch: f64,
    /// Largest relative stretch at the end.
    pub end_stretch_max: f64,
    /// Mean edge length over mean rest length at the end.
    pub edge_ratio: f64,
    /// Inverted tetrahedra at the start.
    pub inverted_start: usize,
    /// Inverted tetrahedra at the end.
    pub inverted_end: usize,
    /// Wall-clock time (s).
    pub wall: f64,
    /// Whether the case was checked for the collapsed cloth's edge length.
    pub edge_check: bool,
}

impl Outcome {
    /// `peak / (start + gravity work)`: at most [`ENERGY_FACTOR`] to pass.
    pub fn energy_ratio(&self) -> f64 {
        self.peak_energy / (self.start_energy + self.gravity_work).max(1e-12)
    }

    /// End kinetic energy over its peak: at most [`SETTLE_FRACTION`] to pass.
    pub fn settle_ratio(&self) -> f64 {
        if self.peak_kinetic > 0.0 { self.end_kinetic / self.peak_kinetic } else { 0.0 }
    }

    /// Why the case fails; empty when it passes.
    pub fn failures(&self) -> Vec<String> {
        let mut f = Vec::new();
        if !self.finite {
            f.push(format!("non-finite values from frame {}", self.nonfinite_frame.unwrap_or(0)));
            return f;
        }
        if self.energy_ratio() > ENERGY_FACTOR {
            f.push(format!("energy reached {:.3e}× start + gravity work", self.energy_ratio()));
        }
        if self.settle_ratio() > SETTLE_FRACTION {
            f.push(format!("still moving: end KE {:.0}% of peak", 100.0 * self.settle_ratio()));
        }
        if self.end_stretch > STRETCH_LIMIT && !self.edge_check {
            f.push(format!("mean stretch {:.0}% at the end", 100.0 * self.end_stretch));
        }
        if self.edge_check && (self.edge_ratio - 1.0).abs() > EDGE_TOLERANCE {
            f.push(format!("mean edge length {:.3}× rest at the end", self.edge_ratio));
        }
        if self.inverted_end > 0 {
            f.push(format!("{} of the tetrahedra still inverted", self.inverted_end));
        }
        f
    }

    /// `true` when the case passes.
    pub fn passed(&self) -> bool {
        self.failures().is_empty()
    }
}

/// Edits the scene's initial state; returns the initial velocities.
fn apply(scene: &mut Scene, m: Modify) -> Vec<Vec3> {
    let n = scene.num_particles();
    let centre = scene.positions.iter().copied().sum::<Vec3>() / n.max(1) as f32;
    let mut v = vec![Vec3::ZERO; n];
    match m {
        Modify::None => {}
        Modify::Rigid => {
            if let Some(f) = &mut scene.springs {
                f.elements.iter_mut().for_each(|s| s.k = f32::INFINITY);
            }
        }
        Modify::Mirror => scene.positions.iter_mut().for_each(|p| p.x = 2.0 * centre.x - p.x),
        Modify::StretchX(s) => scene.positions.iter_mut().for_each(|p| p.x = centre.x + s * (p.x - centre.x)),
        Modify::Collapse { radius, seed } => {
            let mut rng = SmallRng::seed_from_u64(seed);
            for p in &mut scene.positions {
                let j =
                    Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
                *p = centre + radius * j / 3f32.sqrt();
            }
        }
        Modify::HeavyBlock { side, ratio } => {
            let res = (n as f64).sqrt().round() as u32;
            let lo = (res - side) / 2;
            for i in lo..lo + side {
                for j in lo..lo + side {
                    scene.inv_mass[(i * res + j) as usize] /= ratio;
                }
            }
        }
        Modify::Velocity { speed, seed } => {
            let mut rng = SmallRng::seed_from_u64(seed);
            for (vi, &w) in v.iter_mut().zip(&scene.inv_mass) {
                let d =
                    Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
                if w > 0.0 {
                    *vi = d.normalize_or(Vec3::X) * speed;
                }
            }
        }
    }
    v
}

/// Number of `scene`'s tetrahedra whose signed volume at `x` has the opposite sign of the rest
/// state's (zero-volume ones count as inverted).
fn inverted(scene: &Scene, rest: &[Vec3], x: &[Vec3]) -> usize {
    let vol = |p: &[Vec3], e: [u32; 4]| {
        let [a, b, c, d] = e.map(|i| p[i as usize]);
        (b - a).dot((c - a).cross(d - a))
    };
    scene
        .tets
        .as_ref()
        .map_or(0, |f| f.elements.iter().filter(|t| vol(rest, t.particles()) * vol(x, t.particles()) <= 0.0).count())
}

fn mean_edge(scene: &Scene, x: &[Vec3]) -> f64 {
    let sum: f64 = scene.edges.iter().map(|&[a, b]| x[a as usize].distance(x[b as usize]) as f64).sum();
    sum / scene.edges.len().max(1) as f64
}

/// Measures a simulation's state against `measure` (the scene, or its finite-stiffness copy).
fn measure(sim: &Simulation, measure: &Scene, frame: u32) -> Result<(FrameStats, Vec<Vec3>)> {
    match sim {
        Simulation::Cpu(c) => {
            Ok((FrameStats::of_state(measure, &StateView::of_solver(c), frame, 0.0), c.particles.positions()))
        }
        Simulation::Gpu(g) => {
            if std::ptr::eq(g.scene(), measure) {
                return Ok((g.stats(frame, 0.0)?, g.read_positions()?));
            }
            let st = g.read_state()?;
            let k = g.last_constants();
            Ok((FrameStats::of_state(measure, &st.view(k.as_ref()), frame, 0.0), st.x.clone()))
        }
    }
}

/// A GPU device and its kernels, created once for the study.
pub type Gpu = (GpuContext, std::sync::Arc<Kernels>);

/// Opens the GPU for the study; `None` (GPU cases skipped) when there is no adapter.
pub fn open_gpu() -> Option<Gpu> {
    let ctx = GpuContext::new().ok()?;
    let kernels = std::sync::Arc::new(Kernels::new(&ctx.device));
    Some((ctx, kernels))
}

/// Runs `case` on `backend`.
pub fn run_case(case: &Case, backend: Backend, gpu: Option<&Gpu>) -> Result<Outcome> {
    let mut scene = scene::build(case.scene, &case.options)?;
    let rest = scene.positions.clone();
    let v0 = apply(&mut scene, case.modify);
    let measure_scene = (case.modify == Modify::Rigid).then(|| {
        let mut s = scene.clone();
        if let Some(f) = &mut s.springs {
            f.elements.iter_mut().for_each(|e| e.k = RIGID_MEASURE_K);
        }
        s
    });
    case.settings.validate()?;
    let mut sim = Simulation::new(backend, scene, gpu.map(|(c, k)| (c, k)))?;
    sim.check_settings(&case.settings)?;
    sim.set_velocities(&v0)?;
    let t0 = Instant::now();
    let frames = case.frames();
    let every = (frames / 300).max(1);
    let sample = |sim: &Simulation, frame: u32| -> Result<(FrameStats, Vec<Vec3>)> {
        measure(sim, measure_scene.as_ref().unwrap_or(sim.scene()), frame)
    };
    let (s0, x0) = sample(&sim, 0)?;
    let gpe0 = s0.gravitational;
    let mut o = Outcome {
        case: case.name,
        group: case.group,
        backend,
        frames,
        finite: s0.is_finite(),
        nonfinite_frame: None,
        start_energy: s0.kinetic + s0.elastic,
        gravity_work: 0.0,
        peak_energy: s0.kinetic + s0.elastic,
        peak_kinetic: s0.kinetic,
        end_kinetic: s0.kinetic,
        end_stretch: s0.stretch_mean,
        end_stretch_max: s0.stretch_max,
        edge_ratio: 0.0,
        inverted_start: inverted(sim.scene(), &rest, &x0),
        inverted_end: 0,
        wall: 0.0,
        edge_check: matches!(case.modify, Modify::Collapse { .. }),
    };
    let mut last_x = x0;
    for frame in 1..=frames {
        sim.step_frame(&case.settings);
        if frame % every != 0 && frame != frames {
            continue;
        }
        let (s, x) = sample(&sim, frame)?;
        let finite = s.is_finite() && x.iter().all(|p| p.is_finite());
        if !finite {
            o.finite = false;
            o.nonfinite_frame = Some(frame);
            o.frames = frame;
            last_x = x;
            break;
        }
        o.gravity_work = o.gravity_work.max(gpe0 - s.gravitational);
        o.peak_energy = o.peak_energy.max(s.kinetic + s.elastic);
        o.peak_kinetic = o.peak_kinetic.max(s.kinetic);
        o.end_kinetic = s.kinetic;
        o.end_stretch = s.stretch_mean;
        o.end_stretch_max = s.stretch_max;
        last_x = x;
    }
    if let Simulation::Gpu(g) = &sim {
        g.read_positions()?;
    }
    o.wall = t0.elapsed().as_secs_f64();
    let rest_edge =
        sim.scene().edge_rest.iter().map(|&l| l as f64).sum::<f64>() / sim.scene().edge_rest.len().max(1) as f64;
    o.edge_ratio = mean_edge(sim.scene(), &last_x) / rest_edge.max(1e-30);
    o.inverted_end = if o.finite { inverted(sim.scene(), &rest, &last_x) } else { 0 };
    Ok(o)
}

/// A case's outcome, or why it was not run.
#[derive(Clone, Debug)]
pub enum Entry {
    /// It ran.
    Ran(Outcome),
    /// It was skipped (no GPU adapter).
    Skipped {
        /// Case name.
        case: &'static str,
        /// Backend.
        backend: Backend,
        /// Why.
        reason: String,
    },
}

/// Runs `cases` on their backends, calling `progress` after each run; GPU runs are skipped when
/// `gpu` is `None`.
pub fn run_study(cases: &[Case], gpu: Option<&Gpu>, mut progress: impl FnMut(&Entry)) -> Result<Vec<Entry>> {
    let mut out = Vec::new();
    for case in cases {
        for &backend in case.backends {
            let e = match (backend, gpu) {
                (Backend::Gpu, None) => Entry::Skipped { case: case.name, backend, reason: "no GPU adapter".into() },
                _ => {
                    Entry::Ran(run_case(case, backend, gpu).map_err(|e| Error::Report(format!("{}: {e}", case.name)))?)
                }
            };
            progress(&e);
            out.push(e);
        }
    }
    Ok(out)
}

/// Number of runs of `cases`.
pub fn runs(cases: &[Case]) -> usize {
    cases.iter().map(|c| c.backends.len()).sum()
}
