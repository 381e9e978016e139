//! The per-scene state of the GPU solver and the recording of a frame.

use std::ops::Range;
use std::sync::Arc;

use glam::{Vec3, Vec4};
use wgpu::util::DeviceExt;

use super::kernels::{FamilyKernels, FamilyKind, Kernels, PARTIAL_SLOTS, groups, reduce_groups};
use super::layout::{DispatchRange, GpuLedger, GpuProjection, GpuSphere, SimParams};
use super::memory::GpuMemory;
use super::readback::read_buffer;
use crate::constraints::Element;
use crate::error::{Error, Result};
use crate::metrics::{FrameStats, StateView};
use crate::scene::{FAMILY_COUNT, Family, Scene};
use crate::solver::stages::{self, FrameStart, Stage};
use crate::solver::{EnergyAware, Method, Settings, StepConstants, jacobi};

/// Stride of the dispatch-range table (the uniform offset alignment).
const RANGE_STRIDE: u64 = 256;

/// Buffers of one constraint family on the GPU.
#[derive(Debug)]
struct GpuFamily {
    kind: FamilyKind,
    elements: wgpu::Buffer,
    lambda: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// How each color group's sweep is recorded, in order.
    sweeps: Vec<SweepDispatch>,
    /// Dynamic offset of the whole-family range entry.
    all_offset: u32,
    len: u32,
    /// First Jacobi correction slot.
    slot_base: u32,
    jacobi: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    /// Local mode: group 3 (snapshots, start energies).
    local: Option<wgpu::BindGroup>,
}

/// How the GPU records the Gauss-Seidel sweep of one color group.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct SweepDispatch {
    /// Dynamic offset of the group's range entry.
    offset: u32,
    /// Elements in the group.
    size: u32,
    /// The group's place in a run of one-element groups.
    run: Run,
}

/// A color group's place in a run of two or more consecutive one-element groups (centroid meshes
/// have one group per element). A frame records a run as one dispatch of one invocation that
/// projects the run's elements in their order: the same updates as one dispatch per group.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Run {
    /// Not in a run.
    None,
    /// The run's first group, the run's range entry at this dynamic offset.
    First(u32),
    /// A later group of the run, recorded with the first.
    Inside,
}

/// The sweeps of color groups `colors`, their range entries (each group's, then each run's)
/// appended to `ranges`.
fn sweep_dispatches(colors: &[Range<u32>], slot_base: u32, ranges: &mut Vec<DispatchRange>) -> Vec<SweepDispatch> {
    let mut entry = |start: u32, count: u32| {
        ranges.push(DispatchRange { start, count, slot_base, pad: 0 });
        ((ranges.len() as u64 - 1) * RANGE_STRIDE) as u32
    };
    let mut out: Vec<SweepDispatch> = colors
        .iter()
        .map(|r| SweepDispatch { offset: entry(r.start, r.len() as u32), size: r.len() as u32, run: Run::None })
        .collect();
    let mut c = 0;
    while c < colors.len() {
        let run = colors[c..].iter().take_while(|r| r.len() == 1).count();
        if run >= 2 {
            out[c].run = Run::First(entry(colors[c].start, run as u32));
            out[c + 1..c + run].iter_mut().for_each(|d| d.run = Run::Inside);
        }
        c += run.max(1);
    }
    out
}

mod energy;
mod jacobi_buffers;
mod projection;
mod self_collision;
mod stage;

use energy::EnergyBuffers;
pub use energy::GpuEnergies;
use jacobi_buffers::JacobiBuffers;
pub use self_collision::GpuSelfPairs;
use self_collision::SelfBuffers;

/// State read back from the GPU.
#[derive(Clone, Debug, Default)]
pub struct GpuState {
    /// Positions (m).
    pub x: Vec<Vec3>,
    /// Velocities (m/s).
    pub v: Vec<Vec3>,
    /// Inverse masses (1/kg).
    pub w: Vec<f32>,
    /// Multipliers of the last substep, per family in solve order (empty where absent).
    pub lambdas: [Vec<f32>; FAMILY_COUNT],
    /// Work of physical dissipation since the start (J), summed over particles.
    pub dissipated: f64,
}

impl GpuState {
    /// The state to measure, with the constants of the substep that produced it (if known).
    pub fn view<'a>(&'a self, constants: Option<&'a StepConstants<f32>>) -> StateView<'a, Vec3> {
        StateView {
            x: &self.x,
            v: &self.v,
            w: &self.w,
            lambdas: std::array::from_fn(|i| self.lambdas[i].as_slice()),
            constants,
            dissipated: self.dissipated,
        }
    }
}

/// One scene on the GPU: particle buffers (`x` is `STORAGE | VERTEX`, read by the renderer), the
/// buffers of the families the scene has and nothing else, and the recorded stage list.
#[derive(Debug)]
pub struct GpuSolver {
    kernels: Arc<Kernels>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    scene: Scene,
    /// Positions (xyz, m) and inverse masses (w, 1/kg), one `vec4<f32>` per particle.
    pub x: wgpu::Buffer,
    /// The substep's start positions (xyz, m), one `vec4<f32>` per particle.
    x_prev: wgpu::Buffer,
    v: wgpu::Buffer,
    params: wgpu::Buffer,
    particles_bind_group: wgpu::BindGroup,
    range_bind_group: wgpu::BindGroup,
    /// The scene's families, in solve order.
    families: Vec<GpuFamily>,
    jacobi: Option<JacobiBuffers>,
    energy: Option<EnergyBuffers>,
    /// Local mode: group 3 of the per-particle kernels (snapshots).
    local: Option<wgpu::BindGroup>,
    /// The self-collision's buffers, where the scene has it.
    self_collision: Option<SelfBuffers>,
    /// Whether the ledger holds the energy at the start of the next substep.
    ledger_valid: bool,
    /// The settings (thread count aside) the projection's budget was carried under, and whether
    /// the budget is set on the GPU.
    projected_with: Option<Settings>,
    budget_set: bool,
    /// Offsets of the range entries selecting the final reduction's mode (init, balance, measure).
    total_offsets: [u32; 3],
    /// Constant from the balance's gravitational reference to the ground's (J).
    gravity_shift: f64,
    last: Option<Settings>,
    /// The frame's pulled particle, whose inverse mass in [`GpuSolver::x`] is the soft grab's
    /// effective one during the substeps ([`crate::solver::Pull`]), and its own inverse mass
    /// (one `f32`), copied back after them.
    pulled: Option<u32>,
    pull_w: wgpu::Buffer,
    n: u32,
    /// Sizes of the buffers created so far.
    memory: GpuMemory,
    /// Each family's color groups ([`stages::color_counts`]).
    colors: [usize; FAMILY_COUNT],
    /// The last frame's stages (kept, so a frame allocates none).
    stages: Vec<Stage>,
}

/// `−M g·(x_com − x_floor)`: converts gravitational energy about the rest centre of mass into
/// heights from the ground (J).
fn gravity_shift(scene: &Scene) -> f64 {
    let com = scene.rest_center_of_mass().as_dvec3();
    let floor = glam::DVec3::new(0.0, scene.ground.map_or(0.0, |g| g.height as f64), 0.0);
    let mass: f64 = scene.inv_mass.iter().filter(|&&w| w > 0.0).map(|&w| 1.0 / w as f64).sum();
    -mass * scene.gravity.as_dvec3().dot(com - floor)
}

fn storage_buffer(device: &wgpu::Device, label: &str, data: &[u8], extra: wgpu::BufferUsages) -> wgpu::Buffer {
    // wgpu rejects zero-sized bindings: keep at least one element.
    let data = if data.is_empty() { &[0u8; 64][..] } else { data };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: data,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST | extra,
    })
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
}

impl GpuSolver {
    /// Uploads `scene` to the device of `kernels`; `Err` naming the buffer when the scene needs
    /// one larger than the device allows ([`super::check_fits`]).
    pub fn new(kernels: Arc<Kernels>, device: &wgpu::Device, queue: &wgpu::Queue, scene: Scene) -> Result<Self> {
        super::memory::check_fits(&scene, None, &device.limits())?;
        let n = scene.num_particles() as u32;
        let x4: Vec<Vec4> = scene.positions.iter().zip(&scene.inv_mass).map(|(p, &w)| p.extend(w)).collect();
        let bytes = bytemuck::cast_slice(&x4);
        let x = storage_buffer(device, "x", bytes, wgpu::BufferUsages::VERTEX);
        let x_prev = storage_buffer(device, "x_prev", bytes, wgpu::BufferUsages::empty());
        let v = storage_buffer(device, "v", &vec![0u8; bytes.len()], wgpu::BufferUsages::empty());
        let spheres: Vec<GpuSphere> = scene.spheres.iter().map(GpuSphere::from).collect();
        let spheres = storage_buffer(device, "spheres", bytemuck::cast_slice(&spheres), wgpu::BufferUsages::empty());
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::bytes_of(&SimParams::new(&scene, &Settings::default())),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let particles_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("particles"),
            layout: &kernels.particles_layout,
            entries: &[entry(0, &x), entry(1, &x_prev), entry(2, &v), entry(3, &params), entry(4, &spheres)],
        });

        // The dispatch-range table: each family's color groups, then the whole family.
        let mut ranges: Vec<DispatchRange> = Vec::new();
        let mut slot_base = 0u32;
        let mut constraint_bytes = 0u64;
        let mut family = |kind: FamilyKind, len: usize, colors: &[std::ops::Range<u32>], bytes: &[u8]| {
            let label = kind.name();
            let elements = storage_buffer(device, label, bytes, wgpu::BufferUsages::empty());
            let lambda = storage_buffer(device, "lambda", &vec![0u8; len * 4], wgpu::BufferUsages::empty());
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &kernels.family_layout,
                entries: &[entry(0, &elements), entry(1, &lambda)],
            });
            constraint_bytes += elements.size() + lambda.size();
            let sweeps = sweep_dispatches(colors, slot_base, &mut ranges);
            let all_offset = (ranges.len() as u64 * RANGE_STRIDE) as u32;
            ranges.push(DispatchRange { start: 0, count: len as u32, slot_base, pad: 0 });
            let f = GpuFamily {
                kind,
                elements,
                lambda,
                bind_group,
                sweeps,
                all_offset,
                len: len as u32,
                slot_base,
                jacobi: None,
                local: None,
            };
            slot_base += kind.arity() * len as u32;
            f
        };
        let mut families: Vec<GpuFamily> = Vec::with_capacity(FamilyKind::ALL.len());
        crate::for_each_family!(scene, |i, f| {
            let (len, colors, bytes) = upload(f);
            families.push(family(FamilyKind::ALL[i], len, colors, bytes));
        });
        let total_offsets = [0u32, 1, 2].map(|mode| {
            ranges.push(DispatchRange { start: mode, count: 0, slot_base: 0, pad: 0 });
            ((ranges.len() as u64 - 1) * RANGE_STRIDE) as u32
        });
        let mut table = vec![0u8; (ranges.len().max(1) as u64 * RANGE_STRIDE) as usize];
        for (i, r) in ranges.iter().enumerate() {
            let at = i * RANGE_STRIDE as usize;
            table[at..at + 16].copy_from_slice(bytemuck::bytes_of(r));
        }
        let range_table = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dispatch ranges"),
            contents: &table,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let range_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("range"),
            layout: &kernels.range_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &range_table,
                    offset: 0,
                    size: wgpu::BufferSize::new(16),
                }),
            }],
        });
        let gravity_shift = gravity_shift(&scene);
        let memory = GpuMemory {
            particles: x.size() + x_prev.size() + v.size(),
            constraints: constraint_bytes,
            fixed: params.size() + spheres.size() + range_table.size(),
            ..GpuMemory::default()
        };
        let colors = stages::color_counts(&scene);
        let self_collision = scene.self_collision.as_ref().map(|sc| SelfBuffers::new(device, &kernels, sc, n as usize));
        let memory = GpuMemory { self_collision: self_collision.as_ref().map_or(0, |b| b.bytes), ..memory };
        Ok(GpuSolver {
            kernels,
            device: device.clone(),
            queue: queue.clone(),
            scene,
            x,
            x_prev,
            v,
            params,
            particles_bind_group,
            range_bind_group,
            families,
            jacobi: None,
            energy: None,
            local: None,
            self_collision,
            ledger_valid: false,
            projected_with: None,
            budget_set: false,
            total_offsets,
            gravity_shift,
            last: None,
            pulled: None,
            pull_w: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("pulled particle's inverse mass"),
                size: 16,
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            n,
            memory,
            colors,
            stages: Vec::new(),
        })
    }

    /// `Ok` when frames under `s` fit this device: the buffers a frame first needs (Jacobi's
    /// corrections, the local mode's snapshots) within its limits ([`super::check_fits`]).
    /// Call it before stepping under new settings; a frame whose buffers do not fit fails inside
    /// wgpu.
    pub fn check_settings(&self, s: &Settings) -> Result<()> {
        super::memory::check_fits(&self.scene, Some(s), &self.device.limits())
    }

    /// The scene being simulated.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Velocities (xyz, m/s; w: the particle's dissipated work, J), one `vec4<f32>` per particle
    /// (`STORAGE | COPY_SRC | COPY_DST`), for copies on the device.
    pub fn velocities(&self) -> &wgpu::Buffer {
        &self.v
    }

    /// Each family's multipliers as `(family index in solve order, buffer, element count)`.
    pub fn lambda_buffers(&self) -> impl Iterator<Item = (usize, &wgpu::Buffer, u32)> {
        self.families.iter().map(|f| (f.kind as usize, &f.lambda, f.len))
    }

    /// Sizes of the device buffers this solver holds, by purpose (bytes).
    pub fn memory(&self) -> GpuMemory {
        self.memory
    }

    /// Total size of the device buffers this solver holds (bytes): the sum of the sizes of every
    /// buffer it created and still keeps.
    pub fn memory_bytes(&self) -> u64 {
        self.memory.total()
    }

    /// The settings of the last recorded frame.
    pub fn last_settings(&self) -> Option<&Settings> {
        self.last.as_ref()
    }

    /// Records one frame of `settings.dt` into `encoder` (one compute pass, no read-back).
    /// Call [`Settings::validate`] first.
    pub fn encode_frame(&mut self, encoder: &mut wgpu::CommandEncoder, s: &Settings) {
        let projection = self.plan_projection(s);
        self.prepare(s);
        let global = s.energy_aware == EnergyAware::Global;
        if !global {
            self.ledger_valid = false;
        }
        let start = FrameStart {
            projection_start: projection.is_some_and(|p| p.start_before),
            balance_start: global && !self.ledger_valid,
            self_collision: self.self_collision.is_some(),
        };
        self.ledger_valid = global;
        let mut list = std::mem::take(&mut self.stages);
        stages::frame_into(&mut list, &self.colors, s, start);
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("frame"), timestamp_writes: None });
        pass.set_bind_group(0, &self.particles_bind_group, &[]);
        let start_after = projection.is_some_and(|p| p.start_after);
        let pulled = self.pulled.take();
        let families = self.with_kernels();
        let substeps = stages::substeps(&list);
        for &stage in &list[..substeps.end] {
            self.encode_stage(&mut pass, &families, stage, s, (start_after, true));
        }
        if let Some(i) = pulled {
            // The pulled particle's own inverse mass back for the stages after the substeps.
            drop(pass);
            encoder.copy_buffer_to_buffer(&self.pull_w, 0, &self.x, i as u64 * 16 + 12, 4);
            pass = encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("frame"), timestamp_writes: None });
            pass.set_bind_group(0, &self.particles_bind_group, &[]);
        }
        for &stage in &list[substeps.end..] {
            self.encode_stage(&mut pass, &families, stage, s, (start_after, true));
        }
        drop(pass);
        drop(families);
        self.stages = list;
    }

    /// The soft grab's particle takes its effective inverse mass for the frame's substeps
    /// ([`crate::solver::Pull::effective_inverse_mass`]), one `f32` written; its own goes to
    /// `pull_w`, which [`GpuSolver::encode_frame`] copies back after the substeps.
    fn prepare_pull(&mut self, s: &Settings) {
        self.pulled = None;
        let Some(p) = s.pull.filter(|p| p.particle < self.n) else { return };
        let own = self.scene.inv_mass[p.particle as usize];
        let w = p.effective_inverse_mass(own, s.h());
        self.queue.write_buffer(&self.x, p.particle as u64 * 16 + 12, bytemuck::bytes_of(&w));
        self.queue.write_buffer(&self.pull_w, 0, bytemuck::bytes_of(&own));
        self.pulled = Some(p.particle);
    }

    /// What a frame under `s` needs before its stages: the parameters uploaded, Jacobi's
    /// buffers, the energy reduction's, the local mode's.
    fn prepare(&mut self, s: &Settings) {
        self.prepare_pull(s);
        if self.last.as_ref() != Some(s) {
            self.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&SimParams::new(&self.scene, s)));
            self.last = Some(*s);
        }
        if s.method == Method::Jacobi {
            self.prepare_jacobi(s.jacobi_omega);
        }
        if matches!(s.energy_aware, EnergyAware::Global | EnergyAware::Project) {
            self.prepare_energy();
        }
        if s.energy_aware == EnergyAware::Local {
            self.prepare_local();
        }
    }

    /// Dispatches `pipeline` in `workgroups` groups over the whole of family `f`: its elements and
    /// multipliers as bind group 1, its whole range as group 2, and `group3` where given.
    fn dispatch_family(
        &self,
        pass: &mut wgpu::ComputePass<'_>,
        pipeline: &wgpu::ComputePipeline,
        f: &GpuFamily,
        group3: Option<&wgpu::BindGroup>,
        workgroups: u32,
    ) {
        pass.set_pipeline(pipeline);
        pass.set_bind_group(1, &f.bind_group, &[]);
        pass.set_bind_group(2, &self.range_bind_group, &[f.all_offset]);
        if let Some(g) = group3 {
            pass.set_bind_group(3, g, &[]);
        }
        pass.dispatch_workgroups(workgroups, 1, 1);
    }

    /// The scene's families with their kernels.
    fn with_kernels(&self) -> Vec<(&GpuFamily, &FamilyKernels)> {
        self.families.iter().map(|f| (f, self.kernels.family(f.kind))).collect()
    }

    /// Allocates the local mode's snapshots and start energies (once).
    fn prepare_local(&mut self) {
        if self.local.is_some() {
            return;
        }
        let snapshots =
            storage_buffer(&self.device, "snapshots", &vec![0u8; self.n as usize * 32], wgpu::BufferUsages::empty());
        self.memory.local = snapshots.size();
        self.local = Some(self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("local particles"),
            layout: &self.kernels.local_particles_layout,
            entries: &[entry(0, &snapshots)],
        }));
        for f in &mut self.families {
            let start = storage_buffer(
                &self.device,
                "energy at start",
                &vec![0u8; f.len as usize * 4],
                wgpu::BufferUsages::empty(),
            );
            self.memory.local += start.size();
            f.local = Some(self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("local family"),
                layout: &self.kernels.local_family_layout,
                entries: &[entry(0, &snapshots), entry(1, &start)],
            }));
        }
    }

    /// Dispatches one frame needs under `s` (for reports): the sum over its stages
    /// ([`stages::frame`], once the projection's budget and the balance's energy have started).
    pub fn dispatches_per_frame(&self, s: &Settings) -> u64 {
        let start = FrameStart { self_collision: self.self_collision.is_some(), ..FrameStart::default() };
        let list = stages::frame(&self.colors, s, start);
        list.iter().map(|&stage| self.stage_dispatches(stage, s)).sum()
    }

    /// Records and submits one frame, without waiting.
    pub fn step_frame(&mut self, s: &Settings) {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        self.encode_frame(&mut encoder, s);
        self.queue.submit([encoder.finish()]);
    }

    /// Reads positions, velocities and multipliers back (waits for the GPU).
    pub fn read_state(&self) -> Result<GpuState> {
        let x: Vec<Vec4> = read_buffer(&self.device, &self.queue, &self.x)?;
        let v: Vec<Vec4> = read_buffer(&self.device, &self.queue, &self.v)?;
        let mut lambdas: [Vec<f32>; FAMILY_COUNT] = Default::default();
        for f in &self.families {
            let mut l: Vec<f32> = read_buffer(&self.device, &self.queue, &f.lambda)?;
            l.truncate(f.len as usize);
            lambdas[f.kind as usize] = l;
        }
        Ok(GpuState {
            w: x.iter().map(|p| p.w).collect(),
            x: x.iter().map(|p| p.truncate()).collect(),
            v: v.iter().map(|p| p.truncate()).collect(),
            dissipated: v.iter().map(|p| p.w as f64).sum(),
            lambdas,
        })
    }

    /// Replaces the velocities (m/s, one per particle), e.g. to start a scene moving; the
    /// dissipation ledger restarts at zero.
    pub fn set_velocities(&mut self, v: &[Vec3]) -> Result<()> {
        if v.len() != self.n as usize {
            return Err(Error::Gpu(format!("{} velocities for {} particles", v.len(), self.n)));
        }
        let v4: Vec<Vec4> = v.iter().map(|v| v.extend(0.0)).collect();
        self.queue.write_buffer(&self.v, 0, bytemuck::cast_slice(&v4));
        self.restart_budgets();
        Ok(())
    }

    /// Reads the positions back (waits for the GPU).
    pub fn read_positions(&self) -> Result<Vec<Vec3>> {
        let x: Vec<Vec4> = read_buffer(&self.device, &self.queue, &self.x)?;
        Ok(x.iter().map(|p| p.truncate()).collect())
    }

    /// Measures the current state (reads it back).
    pub fn stats(&self, frame: u32, time_ms: f64) -> Result<FrameStats> {
        let st = self.read_state()?;
        let k = self.last_constants();
        Ok(FrameStats::of_state(&self.scene, &st.view(k.as_ref()), frame, time_ms))
    }

    /// Constants of the last frame's substeps, if a frame has run (for residuals and the
    /// honest energy account's split).
    pub fn last_constants(&self) -> Option<StepConstants<f32>> {
        self.last.as_ref().map(StepConstants::<f32>::new)
    }
}

/// A family's length, color ranges and element bytes for upload.
fn upload<E: Element<N> + bytemuck::Pod, const N: usize>(f: &Family<E, N>) -> (usize, &[std::ops::Range<u32>], &[u8]) {
    (f.len(), &f.colors, bytemuck::cast_slice(&f.elements))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_of_one_element_groups_become_one_dispatch_each() {
        let colors = [0..3, 3..4, 4..5, 5..6, 6..9, 9..10, 10..11];
        let mut ranges = Vec::new();
        let d = sweep_dispatches(&colors, 7, &mut ranges);
        let runs: Vec<Run> = d.iter().map(|d| d.run).collect();
        let at = |i: usize| (i as u64 * RANGE_STRIDE) as u32;
        assert_eq!(
            runs,
            [Run::None, Run::First(at(7)), Run::Inside, Run::Inside, Run::None, Run::First(at(8)), Run::Inside]
        );
        // Every group keeps an entry of its own (stage-by-stage recording), then one per run.
        assert_eq!(ranges.len(), 9);
        assert_eq!(
            d.iter().map(|d| (d.offset, d.size)).collect::<Vec<_>>(),
            (0..7).map(|i| (at(i), colors[i].len() as u32)).collect::<Vec<_>>()
        );
        assert_eq!((ranges[7].start, ranges[7].count, ranges[7].slot_base), (3, 3, 7));
        assert_eq!((ranges[8].start, ranges[8].count), (9, 2));
    }
}
