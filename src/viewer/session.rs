//! The viewer without its window: one simulation on the shared device, its draw data, the
//! statistics and the grabbed particle. Each frame it applies what the panels changed (a new
//! scene or material rebuilds the simulation, settings apply as they are), steps the solver and
//! records the drawing into the caller's encoder. Windows and tests drive it the same way.

use std::sync::Arc;
use web_time::Instant;

use glam::{Vec2, Vec3};

use super::grab::Grab;
use super::orbit::Orbit;
use super::overlay::{self, GroupView, WIRE_COLOR};
use super::picking::{Ray, pick};
use super::plots::{History, Sample};
use super::readback::StatsReadback;
use super::state::{ColorMode, SceneChoice, ViewerState};
use super::strain::{StrainPass, ramp_colors, vertex_energy};
use crate::compare::Compare;
use crate::error::Result;
use crate::gpu::{GpuContext, Kernels};
use crate::metrics::FrameStats;
use crate::render::{Camera, FrameViews, LineSet, Renderer, SceneView};
use crate::scene::{self, Scene};
use crate::simulation::{Backend, DrawBuffer, Simulation};
use crate::solver::{EnergyAware, Settings};

/// What the statistics panel shows of the scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneInfo {
    /// Scene name.
    pub name: String,
    /// Number of particles.
    pub particles: usize,
    /// Number of constraints.
    pub constraints: usize,
    /// `(family, elements, color groups)` in solve order.
    pub families: Vec<(&'static str, usize, usize)>,
    /// Adapter description.
    pub adapter: String,
}

/// Timings, smoothed over recent frames.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timings {
    /// Frames per second of the window (set by the caller).
    pub fps: f64,
    /// Solver time per frame (ms): wall time on the CPU backend, GPU timestamps on the GPU one
    /// (`None` where the device has none).
    pub solver_ms: Option<f64>,
    /// Laying out and tessellating the panels on the CPU (ms per frame, set by the caller).
    pub ui_ms: Option<f64>,
    /// Recording the scene and the panels, submitting and presenting (ms per frame, set by the
    /// caller, the solver's share on the CPU backend excluded): on a software adapter this
    /// includes rasterising whenever the swap chain waits for a free image.
    pub draw_ms: Option<f64>,
    /// Wall time of the last frame's CPU solve (ms; 0 on the GPU backend or when paused): what
    /// the caller leaves out of `draw_ms`.
    pub cpu_solve_ms: f64,
}

/// An exponential moving average (weight 0.1 on the new value); the first value as is.
pub fn smooth(old: Option<f64>, new: f64) -> f64 {
    match old {
        Some(o) if o.is_finite() => o + 0.1 * (new - o),
        _ => new,
    }
}

/// The family lengths of a scene, to tell whether a rebuilt scene has the same mesh.
fn shape(s: &Scene) -> (usize, [usize; 4]) {
    let mut f = [0usize; 4];
    crate::for_each_family!(s, |i, fam| f[i] = fam.len());
    (s.num_particles(), f)
}

/// Device timestamps around the solver's commands.
#[derive(Debug)]
struct Timestamps {
    set: wgpu::QuerySet,
    resolved: wgpu::Buffer,
}

/// A scene simulated and drawn on the viewer's device.
#[derive(Debug)]
pub struct Session {
    device: wgpu::Device,
    queue: wgpu::Queue,
    kernels: Arc<Kernels>,
    renderer: Renderer,
    /// What the panels edit.
    pub state: ViewerState,
    built: (SceneChoice, Backend),
    sim: Simulation,
    view: SceneView,
    positions: DrawBuffer,
    strain: StrainPass,
    groups: Vec<GroupView>,
    wire: LineSet,
    group_lines: Option<(usize, LineSet)>,
    readback: Option<StatsReadback>,
    timestamps: Option<Timestamps>,
    /// The camera.
    pub orbit: Orbit,
    /// In compare mode, the comparison and which of its sides this session runs (0 left, 1
    /// right): its settings are the panels' with that side's setting.
    pub side: Option<(Compare, usize)>,
    /// Draw over the target rather than clearing it (the right half in compare mode).
    pub draw_over: bool,
    grab: Option<Grab>,
    /// Frames simulated since the last reset.
    pub frame: u32,
    /// The settings the last frame was stepped with.
    pub last_settings: Option<Settings>,
    /// The latest statistics.
    pub stats: Option<FrameStats>,
    /// The GPU backend's latest snapshot: positions (m) and velocities (m/s), a frame or two
    /// old; what a browser picks and carries from, where nothing may wait for the device.
    latest: Option<(Vec<Vec3>, Vec<Vec3>)>,
    /// Recent statistics for the plots.
    pub history: History,
    /// Timings.
    pub timings: Timings,
    /// Range of the energy view's colour scale (J per particle).
    pub energy_scale: f32,
    info: SceneInfo,
    adapter: String,
}

impl Session {
    /// Builds the scene `state` chooses on `ctx`'s device, drawn into targets of `format` with
    /// `samples` samples per pixel.
    pub fn new(ctx: &GpuContext, format: wgpu::TextureFormat, samples: u32, state: ViewerState) -> Result<Self> {
        // In a browser wgpu's handles are neither Send nor Sync, and everything runs on one
        // thread, where an Arc costs nothing more than an Rc.
        #[cfg_attr(target_arch = "wasm32", allow(clippy::arc_with_non_send_sync))]
        let kernels = Arc::new(Kernels::new(&ctx.device));
        let renderer = Renderer::new(&ctx.device, format, samples);
        let scene = scene::build(state.choice.name(), &state.choice.options()?)?;
        let sim = Simulation::new(state.backend, scene, Some((ctx, &kernels)))?;
        let timestamps = ctx
            .device
            .features()
            .contains(wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS)
            .then(|| Timestamps {
                set: ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("solver time"),
                    ty: wgpu::QueryType::Timestamp,
                    count: 2,
                }),
                resolved: ctx.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("solver time"),
                    size: 16,
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                }),
            });
        let parts = Self::draw_data(&ctx.device, &ctx.queue, &renderer, &sim, timestamps.is_some());
        let orbit = Orbit::from_camera(&Camera::framing(sim.scene()));
        let built = (state.choice, state.backend);
        let mut s = Session {
            device: ctx.device.clone(),
            queue: ctx.queue.clone(),
            kernels,
            renderer,
            state,
            built,
            view: parts.view,
            positions: parts.positions,
            strain: parts.strain,
            groups: parts.groups,
            wire: parts.wire,
            group_lines: None,
            readback: parts.readback,
            timestamps,
            sim,
            orbit,
            side: None,
            draw_over: false,
            grab: None,
            frame: 0,
            last_settings: None,
            stats: None,
            latest: None,
            history: History::default(),
            timings: Timings::default(),
            energy_scale: 0.0,
            info: SceneInfo::default(),
            adapter: ctx.describe(),
        };
        s.refresh_info();
        Ok(s)
    }

    /// The simulation.
    pub fn simulation(&self) -> &Simulation {
        &self.sim
    }

    /// What the statistics panel shows of the scene.
    pub fn info(&self) -> &SceneInfo {
        &self.info
    }

    /// The color-group views of the scene's families.
    pub fn group_views(&self) -> &[GroupView] {
        &self.groups
    }

    /// Whether a particle is held.
    pub fn is_grabbing(&self) -> bool {
        self.grab.is_some()
    }

    fn refresh_info(&mut self) {
        let s = self.sim.scene();
        self.info = SceneInfo {
            name: s.name.clone(),
            particles: s.num_particles(),
            constraints: s.num_constraints(),
            families: self.groups.iter().map(|g| (g.name, g.elements, g.colors)).collect(),
            adapter: self.adapter.clone(),
        };
    }

    fn draw_data(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        r: &Renderer,
        sim: &Simulation,
        timestamps: bool,
    ) -> DrawData {
        let scene = sim.scene();
        let readback = match sim {
            Simulation::Gpu(g) => Some(StatsReadback::new(device, queue, g, timestamps)),
            Simulation::Cpu(_) => None,
        };
        let draw = sim.draw_buffer(device, queue);
        let positions = draw.buffer();
        let view = SceneView::new(device, r, scene, positions);
        let strain = StrainPass::new(device, scene, positions);
        let wire_edges = overlay::wireframe(scene);
        let wire = LineSet::new(device, r, positions, &wire_edges, &vec![WIRE_COLOR; wire_edges.len()]);
        DrawData { view, positions: draw, strain, groups: overlay::group_views(scene), wire, readback }
    }

    /// Rebuilds the simulation for the chosen scene and backend. With the same mesh (a material
    /// or backend change) the positions and velocities carry over; otherwise it starts afresh.
    fn rebuild(&mut self, ctx: &GpuContext, keep_state: bool) -> Result<()> {
        let (choice, backend) = (self.state.choice, self.state.backend);
        let scene = scene::build(choice.name(), &choice.options()?)?;
        let same_mesh = keep_state && shape(&scene) == shape(self.sim.scene());
        if let Some(g) = self.grab.take() {
            g.release(&mut self.sim, &self.queue);
        }
        let mut sim = Simulation::new(backend, scene, Some((ctx, &self.kernels)))?;
        // The old scene's snapshot; a browser carries its state from it.
        let latest = self.latest.take().filter(|_| cfg!(target_arch = "wasm32"));
        if same_mesh {
            sim.take_state(&self.sim, ctx, latest)?;
        } else {
            self.frame = 0;
            self.history.clear();
            self.stats = None;
        }
        let new_scene = self.built.0.scene != choice.scene;
        let parts = Self::draw_data(&ctx.device, &ctx.queue, &self.renderer, &sim, self.timestamps.is_some());
        self.sim = sim;
        self.view = parts.view;
        self.positions = parts.positions;
        self.strain = parts.strain;
        self.groups = parts.groups;
        self.wire = parts.wire;
        self.group_lines = None;
        self.readback = parts.readback;
        self.built = (choice, backend);
        if new_scene {
            self.orbit = Orbit::from_camera(&Camera::framing(self.sim.scene()));
        }
        if self.state.group_family >= self.groups.len() {
            self.state.group_family = 0;
        }
        self.refresh_info();
        Ok(())
    }

    /// Back to the scene's initial state.
    fn reset(&mut self, ctx: &GpuContext) -> Result<()> {
        self.grab = None;
        self.rebuild(ctx, false)
    }

    /// Applies what the panels changed: rebuilds, resets, the camera reset.
    pub fn apply_changes(&mut self, ctx: &GpuContext) {
        let req = std::mem::take(&mut self.state.requests);
        let changed = (self.state.choice, self.state.backend) != self.built;
        let result = if req.reset {
            self.reset(ctx)
        } else if changed {
            let keep = self.state.choice.scene == self.built.0.scene;
            self.rebuild(ctx, keep)
        } else {
            Ok(())
        };
        match result {
            Ok(()) if changed || req.reset => self.state.error = None,
            Ok(()) => {}
            Err(e) => {
                // Go back to what runs, and say why.
                self.state.error = Some(e.to_string());
                (self.state.choice, self.state.backend) = self.built;
            }
        }
        if req.reset_camera || req.reset {
            self.orbit = Orbit::from_camera(&Camera::framing(self.sim.scene()));
        }
        self.state.requests.step = req.step;
    }

    /// Steps the simulation (unless paused) and records the frame's drawing into `views`, the
    /// scene drawn in `viewport` (`[x, y, width, height]`, px). Call [`Session::apply_changes`]
    /// first and [`Session::after_submit`] after submitting `encoder`.
    pub fn encode_frame(
        &mut self,
        encoder: &mut wgpu::CommandEncoder,
        views: FrameViews<'_>,
        viewport: [f32; 4],
    ) -> Result<()> {
        let step = !self.state.paused || std::mem::take(&mut self.state.requests.step);
        let mut settings = match self.state.frame_settings().and_then(|s| self.sim.check_settings(&s).map(|()| s)) {
            Ok(s) => s,
            Err(e) => {
                self.state.error = Some(e.to_string());
                self.last_settings.unwrap_or_default()
            }
        };
        if let Some((c, i)) = self.side {
            settings = c.sides(&settings)[i].1;
        }
        if let Some(g) = &self.grab {
            settings.pull = g.hold(&mut self.sim, &self.queue);
            // The hand's work is in no energy budget: the global balance and the projection
            // would take it back each frame, so they pause while it pulls (the local mode runs).
            if settings.pull.is_some() && matches!(settings.energy_aware, EnergyAware::Global | EnergyAware::Project) {
                settings.energy_aware = EnergyAware::Off;
            }
        }
        if step {
            self.frame += 1;
            self.last_settings = Some(settings);
        }
        self.timings.cpu_solve_ms = 0.0;
        match &mut self.sim {
            Simulation::Cpu(c) => {
                if step {
                    let t = Instant::now();
                    c.step_frame(&settings);
                    let ms = t.elapsed().as_secs_f64() * 1e3;
                    self.timings.solver_ms = Some(smooth(self.timings.solver_ms, ms));
                    self.timings.cpu_solve_ms = ms;
                }
                let stats = FrameStats::measure(c, self.frame, 0.0);
                self.history.push(Sample::from(&stats));
                self.stats = Some(stats);
            }
            Simulation::Gpu(g) => {
                let ts = self.timestamps.as_ref().filter(|_| step);
                if let Some(t) = ts {
                    encoder.write_timestamp(&t.set, 0);
                }
                if step {
                    g.encode_frame(encoder, &settings);
                }
                if let Some(t) = ts {
                    encoder.write_timestamp(&t.set, 1);
                    encoder.resolve_query_set(&t.set, 0..2, &t.resolved, 0);
                }
                if let Some(r) = &mut self.readback
                    && r.is_idle()
                {
                    let stepped = self.last_settings.is_some();
                    r.record(encoder, g, ts.map(|t| &t.resolved), self.frame, &settings, stepped);
                }
            }
        }
        self.sim.refresh_draw(&self.queue, &self.positions);
        self.prepare_draw(encoder);
        self.view.camera = self.orbit.camera();
        self.view.viewport = Some(viewport);
        self.view.clear = !self.draw_over;
        self.view.update_camera(&self.queue, viewport[2].max(1.0) as u32, viewport[3].max(1.0) as u32);
        self.view.encode(&self.renderer, encoder, views);
        Ok(())
    }

    /// Records the drawing of the current state again (no step), as the last frame drew it.
    pub fn encode_scene_only(&self, encoder: &mut wgpu::CommandEncoder, views: FrameViews<'_>) {
        self.view.encode(&self.renderer, encoder, views);
    }

    /// Records the drawing of the current state again (no step) over the whole of targets of
    /// `size` pixels, as the frame alone would be drawn without the panels.
    pub fn encode_scene_whole(&mut self, encoder: &mut wgpu::CommandEncoder, views: FrameViews<'_>, size: [u32; 2]) {
        let [w, h] = size.map(|v| v.max(1));
        self.view.viewport = Some([0.0, 0.0, w as f32, h as f32]);
        self.view.clear = true;
        self.view.update_camera(&self.queue, w, h);
        self.view.encode(&self.renderer, encoder, views);
    }

    /// The state the panels edit and what the statistics panel shows, borrowed together.
    pub fn ui_parts(&mut self) -> (&mut ViewerState, super::ui::StatsView<'_>) {
        let stats = super::ui::StatsView {
            info: &self.info,
            stats: self.stats.as_ref(),
            history: &self.history,
            timings: self.timings,
            frame: self.frame,
            energy_scale: self.energy_scale,
            twin: None,
        };
        (&mut self.state, stats)
    }

    /// Colours and overlays of the current view mode.
    fn prepare_draw(&mut self, encoder: &mut wgpu::CommandEncoder) {
        let mode = self.state.color_mode;
        self.view.show_surface = mode != ColorMode::ColorGroups;
        self.view.vertex_colors = match mode {
            ColorMode::Strain | ColorMode::Energy => Some(self.strain.colors.clone()),
            _ => None,
        };
        match mode {
            ColorMode::Strain => self.strain.encode(&self.queue, encoder, self.state.strain_scale),
            ColorMode::Energy => {
                let e = match &self.sim {
                    Simulation::Cpu(c) => Some(vertex_energy(c.scene(), &c.particles.x)),
                    Simulation::Gpu(_) => None,
                };
                if let Some(e) = e {
                    self.write_energy_colors(&e);
                }
            }
            _ => {}
        }
        let family = self.state.group_family.min(self.groups.len().saturating_sub(1));
        if mode == ColorMode::ColorGroups && self.group_lines.as_ref().is_none_or(|(f, _)| *f != family) {
            self.group_lines = self.groups.get(family).map(|g| {
                (
                    family,
                    LineSet::new(&self.device, &self.renderer, self.view.positions(), &g.segments, &g.segment_colors),
                )
            });
        }
        let mut lines = Vec::new();
        if mode == ColorMode::ColorGroups
            && let Some((_, l)) = &self.group_lines
        {
            lines.push(l.clone());
        }
        if self.state.wireframe {
            lines.push(self.wire.clone());
        }
        self.view.lines = lines;
    }

    fn write_energy_colors(&mut self, e: &[f32]) {
        let max = e.iter().copied().fold(0.0f32, f32::max);
        // A scale that follows the maximum, rising at once and falling slowly.
        self.energy_scale = if max > self.energy_scale { max } else { self.energy_scale * 0.98 + max * 0.02 };
        let colors = ramp_colors(e, self.energy_scale);
        self.queue.write_buffer(&self.strain.colors, 0, bytemuck::cast_slice(&colors));
    }

    /// Starts the statistics copy's mapping (after the frame's encoder was submitted).
    pub fn after_submit(&mut self) {
        if let Some(r) = &mut self.readback {
            r.after_submit();
        }
    }

    /// Collects finished statistics without waiting (polls the device once).
    pub fn poll(&mut self) {
        let _ = self.device.poll(wgpu::PollType::Poll);
        let (snap, energy) = {
            let (Some(r), Simulation::Gpu(g)) = (&mut self.readback, &self.sim) else { return };
            let Some(snap) = r.take(g) else { return };
            let energy =
                (self.state.color_mode == ColorMode::Energy).then(|| vertex_energy(g.scene(), &snap.positions));
            (snap, energy)
        };
        if let Some(ms) = snap.gpu_ms {
            self.timings.solver_ms = Some(smooth(self.timings.solver_ms, ms));
        }
        self.history.push(Sample::from(&snap.stats));
        self.stats = Some(snap.stats);
        self.latest = Some((snap.positions, snap.velocities));
        if let Some(e) = energy {
            self.write_energy_colors(&e);
        }
    }

    /// The current positions (m): read back from the GPU at once, except in a browser, where
    /// nothing may wait for the device: there the latest snapshot's.
    fn current_positions(&self) -> Option<Vec<Vec3>> {
        if cfg!(target_arch = "wasm32") && matches!(self.sim, Simulation::Gpu(_)) {
            return self.latest.as_ref().map(|(x, _)| x.clone());
        }
        self.sim.positions().ok()
    }

    /// Tries to grab the particle under `pixel` of a view of `size` pixels; `true` on a hit.
    /// The positions are read back once for the pick (a user action, not a per-frame cost).
    pub fn grab_at(&mut self, pixel: Vec2, size: Vec2) -> bool {
        let aspect = size.x / size.y.max(1.0);
        let Some(ray) = Ray::through_pixel(self.orbit.view_proj(aspect), pixel, size) else { return false };
        let Some(x) = self.current_positions() else { return false };
        let Some((i, _)) = pick(&ray, &x, &self.sim.scene().triangles) else { return false };
        let inv_mass = match &self.sim {
            Simulation::Cpu(c) => c.particles.w[i as usize],
            Simulation::Gpu(g) => g.scene().inv_mass[i as usize],
        };
        let eye = self.orbit.eye();
        let target = x[i as usize];
        let plane_normal = (eye - target).normalize_or(Vec3::Z);
        self.grab = Some(Grab { particle: i, target, inv_mass, plane_normal, stiffness: self.state.grab_stiffness });
        true
    }

    /// Moves the held particle under `pixel` (in the plane through it facing the eye).
    pub fn drag_to(&mut self, pixel: Vec2, size: Vec2) {
        let Some(g) = &mut self.grab else { return };
        let aspect = size.x / size.y.max(1.0);
        let Some(ray) = Ray::through_pixel(self.orbit.view_proj(aspect), pixel, size) else { return };
        if let Some(t) = ray.plane(g.target, g.plane_normal) {
            let p = ray.at(t);
            if p.is_finite() {
                g.target = p;
            }
        }
    }

    /// The grabbed particle, if one is held.
    pub fn grab(&self) -> Option<Grab> {
        self.grab
    }

    /// Holds `g` as this session's grab (compare mode's twin pulls what the main session pulls),
    /// letting go of a different one held before.
    pub fn share_grab(&mut self, g: Option<Grab>) {
        if let Some(old) = self.grab.take().filter(|old| g.is_none_or(|g| g.particle != old.particle)) {
            old.release(&mut self.sim, &self.queue);
        }
        self.grab = g;
    }

    /// Lets the held particle go.
    pub fn release(&mut self) {
        if let Some(g) = self.grab.take() {
            g.release(&mut self.sim, &self.queue);
        }
    }
}

/// The per-scene draw data.
struct DrawData {
    view: SceneView,
    positions: DrawBuffer,
    strain: StrainPass,
    groups: Vec<GroupView>,
    wire: LineSet,
    readback: Option<StatsReadback>,
}
