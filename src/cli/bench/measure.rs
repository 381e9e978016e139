//! One row of the main table: a case timed on one backend, with its throughput, dispatches and
//! memory.

use std::mem::size_of;
use std::sync::Arc;

use eapbd::constraints::{Element, Form};
use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::scene::{Family, Scene};
use eapbd::solver::{CpuSolver, Method};
use glam::Vec3A;

use super::cases::{Backend, Case};
use super::timing::{Budget, Timing, time_frames, time_interleaved};

/// Memory a solver holds for a scene (bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Memory {
    /// Everything counted.
    pub total: u64,
    /// Per-particle arrays.
    pub particles: u64,
    /// Per-constraint arrays (elements, multipliers, Jacobi's scales and slots).
    pub constraints: u64,
}

/// A case timed on one backend.
#[derive(Clone, Debug)]
pub struct Row {
    /// The case's name.
    pub label: String,
    /// Scene name.
    pub scene: String,
    /// Particles per side of a cloth (`None`: the scene's own).
    pub resolution: Option<u32>,
    /// Where it ran.
    pub backend: Backend,
    /// Iteration method.
    pub method: Method,
    /// Projection form.
    pub form: Form,
    /// Constraint iterations per substep.
    pub iterations: u32,
    /// Substeps per frame.
    pub substeps: u32,
    /// Particles.
    pub particles: usize,
    /// Constraints over every family.
    pub constraints: usize,
    /// Color groups over every family.
    pub colors: usize,
    /// Frames measured and the median time of one.
    pub timing: Timing,
    /// Compute dispatches per frame (GPU only).
    pub dispatches: Option<u64>,
    /// Memory held.
    pub memory: Memory,
    /// Part of the scaling series.
    pub scaled: bool,
}

impl Row {
    /// Constraint projections per frame.
    pub fn projections(&self) -> f64 {
        self.constraints as f64 * (self.iterations * self.substeps) as f64
    }

    /// Constraint projections per second (1/s).
    pub fn projections_per_s(&self) -> f64 {
        self.projections() / (self.timing.median_ms * 1e-3)
    }

    /// Wall time per constraint projection (ns).
    pub fn ns_per_projection(&self) -> f64 {
        self.timing.median_ms * 1e6 / self.projections()
    }

    /// Per-particle memory divided by the particle count (bytes).
    pub fn bytes_per_particle(&self) -> f64 {
        self.memory.particles as f64 / self.particles.max(1) as f64
    }

    /// Per-constraint memory divided by the constraint count (bytes).
    pub fn bytes_per_constraint(&self) -> f64 {
        self.memory.constraints as f64 / self.constraints.max(1) as f64
    }
}

/// A row with the scene's counts, before timing.
fn row(case: &Case, scene: &Scene, backend: Backend) -> Row {
    let colors = scene.num_color_groups();
    Row {
        label: case.label.clone(),
        scene: case.scene.to_string(),
        resolution: case.opts.resolution,
        backend,
        method: case.method,
        form: case.form,
        iterations: case.iterations,
        substeps: case.substeps,
        particles: scene.num_particles(),
        constraints: scene.num_constraints(),
        colors,
        timing: Timing { frames: 0, median_ms: f64::NAN },
        dispatches: None,
        memory: Memory::default(),
        scaled: case.scaled,
    }
}

/// Times `case` on the CPU solver on each of `backends` (which pick the thread count), in turns
/// of a few frames ([`time_interleaved`]), so that one thread and every core are measured under
/// the same conditions; one row per backend, in order.
pub fn cpu_rows(case: &Case, scene: &Scene, backends: &[Backend], budget: &Budget) -> anyhow::Result<Vec<Row>> {
    let mut runs: Vec<_> = backends
        .iter()
        .map(|&b| (row(case, scene, b), case.settings(b), CpuSolver::<Vec3A>::new(scene.clone())))
        .collect();
    let mut frames: Vec<_> = runs
        .iter_mut()
        .map(|(_, s, solver)| {
            move || -> anyhow::Result<()> {
                solver.step_frame(s);
                Ok(())
            }
        })
        .collect();
    let timings = time_interleaved(budget, &mut frames)?;
    drop(frames);
    Ok(runs
        .into_iter()
        .zip(timings)
        .map(|((mut r, _, solver), timing)| {
            r.timing = timing;
            r.memory = cpu_memory(&solver, case.method);
            r
        })
        .collect())
}

/// The arrays the CPU solver works on (bytes, from their lengths): particle state (`x`,
/// `x_prev`, `v`, `w`), the elements of every family and one `f32` multiplier per constraint; the
/// SIMD kernels' copy of the elements slot by slot, with the inverse masses after a frame of plain
/// Gauss-Seidel ([`CpuSolver::lane_bytes`]); with Jacobi its per-constraint scale and per-particle
/// correction.
pub fn cpu_memory(solver: &CpuSolver<Vec3A>, method: Method) -> Memory {
    let p = &solver.particles;
    let (seen, lanes) = solver.lane_bytes();
    let mut particles = ((p.x.len() + p.x_prev.len() + p.v.len()) * size_of::<Vec3A>() + p.w.len() * 4 + seen) as u64;
    let scene = solver.scene();
    let mut constraints = 0u64;
    eapbd::for_each_family!(scene, |_i, f| constraints += element_bytes(f));
    let m = scene.num_constraints() as u64;
    constraints += m * size_of::<f32>() as u64 + lanes as u64;
    if method == Method::Jacobi {
        constraints += m * size_of::<f32>() as u64;
        particles += (p.len() * size_of::<Vec3A>()) as u64;
    }
    Memory { total: particles + constraints, particles, constraints }
}

fn element_bytes<E: Element<N>, const N: usize>(f: &Family<E, N>) -> u64 {
    (f.elements.len() * size_of::<E>()) as u64
}

/// The GPU device and its compiled kernels, opened once per run.
pub struct Gpu {
    ctx: GpuContext,
    kernels: Arc<Kernels>,
}

impl Gpu {
    /// Opens the default adapter and compiles the kernels.
    pub fn open() -> eapbd::Result<Self> {
        let ctx = GpuContext::new()?;
        let kernels = Arc::new(Kernels::new(&ctx.device));
        Ok(Gpu { ctx, kernels })
    }

    /// The adapter, for the report.
    pub fn describe(&self) -> String {
        self.ctx.describe()
    }

    /// Times `case` on the GPU solver: each frame recorded, submitted and waited for.
    pub fn row(&self, case: &Case, scene: Scene, budget: &Budget) -> anyhow::Result<Row> {
        let mut r = row(case, &scene, Backend::Gpu);
        let s = case.settings(Backend::Gpu);
        let mut g = GpuSolver::new(self.kernels.clone(), &self.ctx.device, &self.ctx.queue, scene)?;
        r.timing = time_frames(budget, || {
            g.step_frame(&s);
            Ok(self.ctx.wait()?)
        })?;
        r.dispatches = Some(g.dispatches_per_frame(&s));
        let m = g.memory();
        r.memory = Memory { total: m.total(), particles: m.particles, constraints: m.constraints + m.jacobi };
        Ok(r)
    }
}
