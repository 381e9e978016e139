//! What `eapbd bench` measures: the scenes, solver settings and backends of each row, and the
//! frame budgets of the quick and the full run.

use eapbd::constraints::Form;
use eapbd::mesh::Diagonals;
use eapbd::scene::SceneOptions;
use eapbd::solver::{Method, Settings};

use super::timing::Budget;

/// Spring stiffness of the peer scene (N/m).
pub const PEER_STIFFNESS: f32 = 1.0e6;
/// Dihedral bending stiffness of the peer scene (N·m/rad): soft bending, the `cloth` scene's own.
pub const PEER_BENDING: f32 = 1.0e-3;
/// Particles per side of the peer scene.
pub const PEER_RESOLUTION: u32 = 64;
/// The splits of 30 constraint projections per frame into iterations × substeps.
pub const SPLITS: [(u32, u32); 8] = [(30, 1), (15, 2), (10, 3), (6, 5), (5, 6), (3, 10), (2, 15), (1, 30)];

/// Where a row runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// The CPU solver on one thread (`threads: 1`).
    CpuSingle,
    /// The CPU solver on every core (`threads: 0`).
    CpuAll,
    /// The GPU solver, each frame submitted and waited for.
    Gpu,
}

impl Backend {
    /// Every backend, in table order.
    pub const ALL: [Backend; 3] = [Backend::CpuSingle, Backend::CpuAll, Backend::Gpu];

    /// The name in tables and CSV.
    pub fn name(self) -> &'static str {
        match self {
            Backend::CpuSingle => "cpu-1",
            Backend::CpuAll => "cpu-all",
            Backend::Gpu => "gpu",
        }
    }

    /// `Settings::threads` for the CPU backends (the GPU ignores it).
    pub fn threads(self) -> u32 {
        match self {
            Backend::CpuSingle => 1,
            Backend::CpuAll | Backend::Gpu => 0,
        }
    }
}

/// One scene and solver configuration, timed on some backends.
#[derive(Clone, Debug)]
pub struct Case {
    /// The row's name in the tables.
    pub label: String,
    /// Scene name for [`eapbd::scene::build`].
    pub scene: &'static str,
    /// Scene options.
    pub opts: SceneOptions,
    /// Constraint iterations per substep.
    pub iterations: u32,
    /// Substeps per frame.
    pub substeps: u32,
    /// Iteration method.
    pub method: Method,
    /// Projection form.
    pub form: Form,
    /// Backends to time it on.
    pub backends: Vec<Backend>,
    /// Part of the scaling series (a cloth of `--resolution N`).
    pub scaled: bool,
}

impl Case {
    /// Solver settings of this case on `backend` (dt = 1/60 s, no damping, energy-aware off).
    pub fn settings(&self, backend: Backend) -> Settings {
        Settings {
            iterations: self.iterations,
            substeps: self.substeps,
            method: self.method,
            form: self.form,
            threads: backend.threads(),
            ..Settings::default()
        }
    }
}

/// The peer scene's options: 64×64, k = 1e6 N/m, soft bending, the quads' diagonals alternating
/// as in the PositionBasedDynamics library's cloth (the mesh its figures were measured on).
pub fn peer_options() -> SceneOptions {
    SceneOptions {
        resolution: Some(PEER_RESOLUTION),
        stiffness: PEER_STIFFNESS,
        bending_stiffness: Some(PEER_BENDING),
        diagonals: Diagonals::Alternating,
        ..SceneOptions::default()
    }
}

/// A `cloth` of `n × n` particles with the scene's springs (k_s = 1e4 N/m) and bending
/// (k_b = 1e-3 N·m/rad).
pub fn scaled_options(n: u32) -> SceneOptions {
    SceneOptions { resolution: Some(n), ..SceneOptions::default() }
}

/// Everything one run measures.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The short run.
    pub quick: bool,
    /// Frame budget of every timed row.
    pub budget: Budget,
    /// Frames of each peer-scene split.
    pub peer_frames: u32,
    /// The splits measured.
    pub splits: Vec<(u32, u32)>,
    /// The rows of the main table, the scaling series among them.
    pub cases: Vec<Case>,
    /// Repetitions of each coloring case (the best is kept).
    pub coloring_reps: u32,
}

impl Plan {
    /// The full run (about ten minutes on a 2-core machine): every split, cloths from about
    /// 5,000 to 1,000,000 constraints on every backend.
    pub fn full() -> Self {
        Plan {
            quick: false,
            budget: Budget { warm_frames: 30, warm_seconds: 2.0, frames: 300, min_frames: 5, seconds: 5.0 },
            peer_frames: 120,
            splits: SPLITS.to_vec(),
            cases: cases(&[29, 41, 64, 128, 256, 410]),
            coloring_reps: 5,
        }
    }

    /// The short run CI does (well under a minute here): fewer frames, three splits, scaled
    /// cloths up to about 100,000 constraints.
    pub fn quick() -> Self {
        Plan {
            quick: true,
            budget: Budget { warm_frames: 5, warm_seconds: 0.3, frames: 40, min_frames: 3, seconds: 0.5 },
            peer_frames: 20,
            splits: vec![(30, 1), (5, 6), (1, 30)],
            cases: cases(&[29, 128]),
            coloring_reps: 1,
        }
    }

    /// Rows timed (case × backend), for progress.
    pub fn rows(&self, gpu: bool) -> usize {
        self.cases.iter().map(|c| c.backends.iter().filter(|&&b| gpu || b != Backend::Gpu).count()).sum()
    }
}

fn cases(scaled: &[u32]) -> Vec<Case> {
    let case = |label: &str, scene, opts, iterations, method, form, backends: &[Backend]| Case {
        label: label.to_string(),
        scene,
        opts,
        iterations,
        substeps: 1,
        method,
        form,
        backends: backends.to_vec(),
        scaled: false,
    };
    let (gs, jacobi) = (Method::GaussSeidel, Method::Jacobi);
    let (compliant, energy) = (Form::Compliant, Form::Energy);
    let all = &Backend::ALL;
    let paper = SceneOptions::default();
    let mut v = vec![
        case("cloth-paper", "cloth-paper", paper, 30, gs, compliant, all),
        case("cloth-paper", "cloth-paper", paper, 30, gs, energy, &[Backend::CpuSingle, Backend::CpuAll]),
        case("cloth-paper", "cloth-paper", paper, 30, jacobi, compliant, all),
        case("peer scene", "cloth", peer_options(), 30, gs, compliant, all),
        case("bunny-paper", "bunny-paper", paper, 15, gs, compliant, all),
    ];
    for &n in scaled {
        v.push(Case {
            scaled: true,
            ..case(&format!("cloth {n}"), "cloth", scaled_options(n), 30, gs, compliant, all)
        });
    }
    v
}
