//! # eapbd
//!
//! Position-based simulation of elastic models (XPBD, Macklin et al. 2016) with the energy-aware
//! Gauss-Seidel iteration and two-step mesh coloring of Cetinaslan (Computer Graphics Forum 2019):
//! a CPU reference solver, a wgpu compute solver with the same stage list, cloth (springs,
//! bending, an anisotropic membrane) and solids (five hyperelastic models on tetrahedra).
//! SI units throughout: metres, kilograms, seconds; stiffnesses in N/m (springs, 2D moduli),
//! N·m/rad (bending) and Pa (3D moduli).
//!
//! ## A tour
//!
//! A run has three parts: a [`scene::Scene`] (particles, constraint families already sorted
//! into color groups, colliders, gravity), built by name with [`scene::build`] from
//! [`scene::SceneOptions`]; [`solver::Settings`] (time step, substeps, iterations, projection
//! form, Gauss-Seidel or Jacobi, energy-aware mode, SOR, damping), which may change between
//! frames; and a solver that owns a copy of the scene's state and advances it one frame at a
//! time:
//!
//! ```rust
//! use eapbd::{metrics::FrameStats, scene, solver::{CpuSolver, Settings}};
//!
//! let scene = scene::build("cloth", &scene::SceneOptions::default())?;
//! let settings = Settings { substeps: 10, iterations: 3, ..Settings::default() };
//! settings.validate()?;
//! // `Vec3A` (16-byte particles) is the fast f32 storage; `Vec3` gives the same bits, `DVec3` f64.
//! let mut solver = CpuSolver::<glam::Vec3A>::new(scene);
//! for frame in 1..=60 {
//!     solver.step_frame(&settings);
//!     let stats = FrameStats::measure(&solver, frame, 0.0);
//!     println!("{stats}"); // residual, stretch, kinetic, gravitational, elastic energy
//! }
//! # Ok::<(), eapbd::Error>(())
//! ```
//!
//! The GPU solver takes the same scene and settings: open a [`gpu::GpuContext`], build the
//! pipelines once per device with [`gpu::Kernels`], upload the scene into a [`gpu::GpuSolver`],
//! call [`gpu::GpuSolver::step_frame`] (records and submits, never waits) and read back with
//! [`gpu::GpuSolver::read_positions`] or [`gpu::GpuSolver::stats`] when needed.
//! [`simulation::Simulation`] wraps either backend behind one interface, and
//! [`render::Snapshotter`] draws one offscreen into a PNG. Every fallible function returns
//! [`Result`] with the library's [`Error`], whose messages name the parameter or file at fault.
//!
//! Runnable programs are in `examples/` (`cargo run --release --example hanging_cloth`,
//! `gpu_cloth`, `bunny_materials`, `render_png`); the command line and every scene, material and
//! setting are described in `docs/guide.md`.
//!
//! ## Modules
//!
//! | module | what it holds |
//! |---|---|
//! | [`scene`] | scene builders ([`scene::SCENES`]: cloths, beam, cube, bunny), options, colliders |
//! | [`solver`] | [`solver::Settings`], the CPU reference solver [`solver::CpuSolver`] (generic over `f32`/`f64`), the XPBD update, Jacobi scaling, the energy-aware balance |
//! | [`gpu`] | the wgpu solver: device context, compute pipelines, per-scene buffers, read-back |
//! | [`simulation`] | a scene on either backend behind one interface |
//! | [`constraints`] | the constraint families (springs, dihedral bending, tetrahedra, membranes): energy, gradient and both projection forms |
//! | [`material`] | 3×3 matrices, the signed SVD, hyperdual numbers and the five 3D models with inversion handling |
//! | [`coloring`] | two-step mesh coloring and the one solve-order policy |
//! | [`mesh`] | triangle and tetrahedral meshes: cloth grids, boxes, lattices with embedded surfaces, topology, OBJ and TetGen input, OBJ export |
//! | [`metrics`] | residual, stretch and energy measures ([`metrics::FrameStats`]) |
//! | [`render`] | camera, pipelines, scene draw data, offscreen targets and PNG output |
//! | `report` | the studies behind `eapbd report` (energy, beam, stability) and their plots (feature `studies`) |
//! | `viewer` | the interactive window (winit, egui) on the solver's device (feature `viewer`) |
//! | [`math`] | the precision-generic [`math::Vector`] and [`math::Real`] traits over glam |
//! | [`error`] | [`Error`] and [`Result`] |
//!
//! Every module but `report` and `viewer` is the simulation core, which depends on neither the
//! window system, the plotting library nor the command line. The layers above it are features:
//! `viewer` (the window) and `studies` (`report`), both on by default; the `eapbd` binary
//! (feature `cli`) adds the command line and the bench.

pub mod coloring;
pub mod compare;
pub mod constraints;
pub mod error;
pub mod gpu;
pub mod material;
pub mod math;
pub mod mesh;
pub mod metrics;
pub mod render;
#[cfg(feature = "studies")]
pub mod report;
pub mod scene;
pub mod simulation;
pub mod solver;
#[cfg(feature = "viewer")]
pub mod viewer;

pub use error::{Error, Result};
