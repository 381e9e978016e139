//! The window: a winit event loop, a surface on the solver's device, egui through egui-winit
//! and egui-wgpu, the mouse (orbit, pan, zoom, grab) and the `--screenshot` capture.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec2;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use super::capture::{FrameTargets, read_texture};
use super::session::{Session, smooth};
use super::state::ViewerState;
use super::twin;
use super::ui;
use super::ui_cache::{UiCache, panel_rects};
use crate::error::{Error, Result};
use crate::gpu::GpuContext;
use crate::render::save_png;

/// How the viewer starts.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    /// Scene, material, settings and backend at the start.
    pub state: ViewerState,
    /// Window width (px).
    pub width: u32,
    /// Window height (px).
    pub height: u32,
    /// Close after this many frames.
    pub exit_after_frames: Option<u32>,
    /// Write the last frame (UI included) to this PNG file.
    pub screenshot: Option<PathBuf>,
    /// Samples per pixel of the scene (1, 2 or 4); `None`: 4 on a GPU, 1 on a software adapter,
    /// which rasterises every sample on the CPU.
    pub msaa: Option<u32>,
    /// Whether `state.backend` was asked for; if not, a software adapter runs the CPU solver.
    pub backend_given: bool,
}

/// Opens the window and runs until it is closed (or `exit_after_frames` have been drawn).
pub fn run(options: ViewerOptions) -> Result<()> {
    if options.exit_after_frames == Some(0) {
        return Err(Error::param("--exit-after-frames", 0, "must be at least 1"));
    }
    if let Some(n) = options.msaa.filter(|n| ![1, 2, 4].contains(n)) {
        return Err(Error::param("--msaa", n, "must be 1, 2 or 4"));
    }
    if options.width == 0 || options.height == 0 {
        return Err(Error::param(
            "--width/--height",
            format!("{}x{}", options.width, options.height),
            "must be positive",
        ));
    }
    let event_loop = EventLoop::new().map_err(|e| Error::NoDisplay(e.to_string()))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App { options, window: None, error: None, frames: 0, started: None };
    event_loop.run_app(&mut app).map_err(|e| Error::NoDisplay(e.to_string()))?;
    if let (Some(t), Some(r)) = (app.started, &app.window) {
        let secs = t.elapsed().as_secs_f64();
        let t = &r.session.timings;
        let ms = |v: Option<f64>| v.map_or("–".into(), |ms| format!("{ms:.2}"));
        eprintln!(
            "viewer: {} frames in {secs:.2} s ({:.1} FPS); ms/frame: solver {}, panels {}, drawing {}; on {}",
            app.frames,
            app.frames as f64 / secs.max(1e-9),
            ms(t.solver_ms),
            ms(t.ui_ms),
            ms(t.draw_ms),
            r.session.info().adapter
        );
    }
    match app.error {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// What a mouse drag in the scene does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Drag {
    Orbit,
    Pan,
    Grab,
}

/// Everything that lives as long as the window.
struct Running {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    ctx: GpuContext,
    session: Session,
    egui_ctx: egui::Context,
    egui_state: egui_winit::State,
    egui_renderer: egui_wgpu::Renderer,
    targets: FrameTargets,
    /// The scene's rectangle in physical pixels `[x, y, w, h]`.
    viewport: [f32; 4],
    cursor: Vec2,
    drag: Option<Drag>,
    last_frame: Option<Instant>,
    /// Configure the surface again after the next present.
    reconfigure: bool,
    /// The last frame's UI, drawn again by the screenshot.
    last_paint: Option<(Vec<egui::ClippedPrimitive>, egui_wgpu::ScreenDescriptor)>,
    /// The panels' image between changes (software adapters, where egui's pass is costly).
    ui_cache: Option<UiCache>,
    /// Input egui took, a resize or a repaint egui asked for since the panels were last drawn.
    ui_changed: bool,
    /// Compare mode's second run, drawn in the right half of the scene.
    twin: Option<Session>,
    /// Compare mode's labels over the scene (physical pixels `[x0, y0, x1, y1]`).
    labels: Vec<[f32; 4]>,
}

struct App {
    options: ViewerOptions,
    window: Option<Running>,
    error: Option<Error>,
    frames: u32,
    started: Option<Instant>,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        self.error = Some(e);
        event_loop.exit();
    }

    /// Draws a frame; after the last one (`exit_after_frames`) writes the screenshot and exits.
    fn redrawn(&mut self, event_loop: &ActiveEventLoop) {
        let Some(r) = &mut self.window else { return };
        match r.redraw() {
            Ok(true) => {
                self.frames += 1;
                if self.options.exit_after_frames.is_some_and(|n| self.frames >= n) {
                    let result = match &self.options.screenshot {
                        Some(path) => r.screenshot(path),
                        None => Ok(()),
                    };
                    if let Err(e) = result {
                        self.error = Some(e);
                    }
                    event_loop.exit();
                }
            }
            Ok(false) => {}
            Err(e) => self.fail(event_loop, e),
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        match open(event_loop, &self.options) {
            Ok(r) => {
                r.window.request_redraw();
                self.window = Some(r);
                self.started = Some(Instant::now());
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(r) = &mut self.window else { return };
        let egui_response = r.egui_state.on_window_event(&r.window, &event);
        // Pointer events over the scene change nothing in the panels (their hover state catches
        // up at the next refresh); anything else egui asks a repaint for does.
        let pointer = matches!(
            event,
            WindowEvent::CursorMoved { .. } | WindowEvent::MouseInput { .. } | WindowEvent::MouseWheel { .. }
        );
        let over_scene = pointer && r.in_scene(r.cursor) && !r.egui_ctx.egui_is_using_pointer();
        let redraw = matches!(event, WindowEvent::RedrawRequested);
        if egui_response.repaint && !over_scene && !redraw {
            r.ui_changed = true;
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => r.resize(size),
            WindowEvent::RedrawRequested => {
                // The last frame's panels are drawn fresh: the screenshot shows its figures.
                let last = self.options.exit_after_frames.is_some_and(|n| self.frames + 1 >= n);
                r.ui_changed |= last;
                self.redrawn(event_loop);
            }
            WindowEvent::CursorMoved { position, .. } => {
                let p = Vec2::new(position.x as f32, position.y as f32);
                r.mouse_moved(p);
            }
            WindowEvent::MouseInput { state, button, .. } => r.mouse_button(state, button, egui_response.consumed),
            WindowEvent::KeyboardInput { event, .. }
                if event.state == ElementState::Pressed
                    && !egui_response.consumed
                    && !r.egui_ctx.egui_wants_keyboard_input() =>
            {
                let key = match &event.logical_key {
                    Key::Named(NamedKey::Space) => Some(' '),
                    Key::Character(c) => c.chars().next(),
                    _ => None,
                };
                if let Some(k) = key {
                    r.session.state.shortcut(k);
                }
            }
            WindowEvent::MouseWheel { delta, .. } if !egui_response.consumed && r.in_scene(r.cursor) => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                r.session.orbit.zoom(steps);
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(r) = &self.window {
            r.window.request_redraw();
        }
    }
}

/// Opens the window, the surface, a device compatible with it, egui and the session.
fn open(event_loop: &ActiveEventLoop, o: &ViewerOptions) -> Result<Running> {
    let attributes = Window::default_attributes()
        .with_title("eapbd: energy-aware XPBD")
        .with_inner_size(PhysicalSize::new(o.width, o.height));
    let window = Arc::new(event_loop.create_window(attributes).map_err(|e| Error::NoDisplay(e.to_string()))?);
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(
        event_loop.owned_display_handle(),
    )));
    let surface =
        instance.create_surface(window.clone()).map_err(|e| Error::Gpu(format!("cannot create a surface: {e}")))?;
    let adapter = pollster::block_on(wgpu::util::initialize_adapter_from_env_or_default(&instance, Some(&surface)))
        .map_err(|e| Error::NoAdapter(e.to_string()))?;
    let ctx = GpuContext::with_adapter(instance, adapter)?;
    let caps = surface.get_capabilities(&ctx.adapter);
    let format = caps
        .formats
        .iter()
        .copied()
        .find(|f| f.is_srgb())
        .or_else(|| caps.formats.first().copied())
        .ok_or_else(|| Error::Gpu("the surface offers no format".into()))?;
    let size = window.inner_size();
    let software = ctx.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
    let cached = software && caps.usages.contains(wgpu::TextureUsages::COPY_DST);
    let copy = if cached { wgpu::TextureUsages::COPY_DST } else { wgpu::TextureUsages::empty() };
    let config = wgpu::SurfaceConfiguration {
        usage: wgpu::TextureUsages::RENDER_ATTACHMENT | copy,
        format,
        width: size.width.max(1),
        height: size.height.max(1),
        present_mode: wgpu::PresentMode::AutoVsync,
        desired_maximum_frame_latency: 2,
        alpha_mode: caps.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto),
        view_formats: vec![],
        color_space: wgpu::SurfaceColorSpace::Auto,
    };
    surface.configure(&ctx.device, &config);
    let samples = o.msaa.unwrap_or(if software { 1 } else { 4 });
    let mut state = o.state.clone();
    if software && !o.backend_given {
        // The CPU solver outruns a software rasteriser's compute (cloth-paper: 0.3 against 13 ms).
        state.backend = crate::simulation::Backend::Cpu;
    }
    let session = Session::new(&ctx, format, samples, state)?;
    let egui_ctx = egui::Context::default();
    egui_ctx.set_theme(egui::Theme::Dark);
    let egui_state = egui_winit::State::new(
        egui_ctx.clone(),
        egui::ViewportId::ROOT,
        &window,
        Some(window.scale_factor() as f32),
        None,
        Some(ctx.device.limits().max_texture_dimension_2d as usize),
    );
    let egui_renderer = egui_wgpu::Renderer::new(&ctx.device, format, egui_wgpu::RendererOptions::default());
    let targets = FrameTargets::new(&ctx.device, format, config.width, config.height, samples);
    let ui_cache = cached.then(|| UiCache::new(&ctx.device, format, config.width, config.height));
    Ok(Running {
        viewport: [0.0, 0.0, config.width as f32, config.height as f32],
        window,
        surface,
        config,
        ctx,
        session,
        egui_ctx,
        egui_state,
        egui_renderer,
        targets,
        cursor: Vec2::ZERO,
        drag: None,
        last_frame: None,
        last_paint: None,
        reconfigure: false,
        ui_cache,
        ui_changed: true,
        twin: None,
        labels: Vec::new(),
    })
}

impl Running {
    fn resize(&mut self, size: PhysicalSize<u32>) {
        // A minimised window has no size: keep the old configuration and skip frames.
        if size.width == 0 || size.height == 0 {
            return;
        }
        self.config.width = size.width;
        self.config.height = size.height;
        self.surface.configure(&self.ctx.device, &self.config);
        let samples = self.targets.samples;
        self.targets = FrameTargets::new(&self.ctx.device, self.config.format, size.width, size.height, samples);
        if self.ui_cache.is_some() {
            self.ui_cache = Some(UiCache::new(&self.ctx.device, self.config.format, size.width, size.height));
        }
        self.ui_changed = true;
    }

    fn in_scene(&self, p: Vec2) -> bool {
        let [x, y, w, h] = self.viewport;
        p.x >= x && p.y >= y && p.x < x + w && p.y < y + h
    }

    /// Cursor position and size of the scene's viewport (px).
    /// Relative to the main session's part of the scene (its left half in compare mode).
    fn scene_pixel(&self, p: Vec2) -> (Vec2, Vec2) {
        let [x, y, w, h] = self.main_viewport();
        (p - Vec2::new(x, y), Vec2::new(w, h))
    }

    /// Where the main session draws, and where the twin does in compare mode.
    fn main_viewport(&self) -> [f32; 4] {
        if self.twin.is_some() { twin::halves(self.viewport)[0] } else { self.viewport }
    }

    fn mouse_moved(&mut self, p: Vec2) {
        let delta = p - self.cursor;
        self.cursor = p;
        match self.drag {
            Some(Drag::Orbit) => self.session.orbit.rotate(delta),
            Some(Drag::Pan) => self.session.orbit.pan(delta, self.viewport[3]),
            Some(Drag::Grab) => {
                let (pixel, size) = self.scene_pixel(p);
                self.session.drag_to(pixel, size);
            }
            None => {}
        }
    }

    fn mouse_button(&mut self, state: ElementState, button: MouseButton, consumed: bool) {
        if state == ElementState::Released {
            if self.drag == Some(Drag::Grab) {
                self.session.release();
            }
            self.drag = None;
            return;
        }
        if consumed || !self.in_scene(self.cursor) || self.egui_ctx.is_pointer_over_egui() {
            return;
        }
        self.drag = match button {
            MouseButton::Left => {
                let (pixel, size) = self.scene_pixel(self.cursor);
                Some(if self.session.grab_at(pixel, size) { Drag::Grab } else { Drag::Orbit })
            }
            MouseButton::Right | MouseButton::Middle => Some(Drag::Pan),
            _ => None,
        };
    }

    /// Draws one frame; `Ok(false)` when there was nothing to draw into (minimised, surface
    /// being recreated).
    fn redraw(&mut self) -> Result<bool> {
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(false);
        }
        let now = Instant::now();
        if let Some(last) = self.last_frame {
            let fps = 1.0 / now.duration_since(last).as_secs_f64().max(1e-6);
            let t = &mut self.session.timings;
            t.fps = if t.fps > 0.0 { t.fps + 0.1 * (fps - t.fps) } else { fps };
        }
        self.last_frame = Some(now);

        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(f) => f,
            wgpu::CurrentSurfaceTexture::Suboptimal(f) => {
                // Draw this one; configure again once it is presented.
                self.reconfigure = true;
                f
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => return Ok(false),
            wgpu::CurrentSurfaceTexture::Outdated => {
                self.surface.configure(&self.ctx.device, &self.config);
                return Ok(false);
            }
            wgpu::CurrentSurfaceTexture::Lost => {
                self.surface = self
                    .ctx
                    .instance
                    .create_surface(self.window.clone())
                    .map_err(|e| Error::Gpu(format!("cannot recreate the surface: {e}")))?;
                self.surface.configure(&self.ctx.device, &self.config);
                return Ok(false);
            }
            other => {
                eprintln!("skipping a frame: {other:?}");
                return Ok(false);
            }
        };
        if frame.texture.width() != self.targets.width || frame.texture.height() != self.targets.height {
            // The surface and the targets disagree: drop this frame and configure both again.
            drop(frame);
            self.resize(self.window.inner_size());
            return Ok(false);
        }
        let view = frame.texture.create_view(&Default::default());
        let now = Instant::now();
        let changed = std::mem::take(&mut self.ui_changed);
        let ui = if self.ui_cache.as_ref().is_none_or(|c| c.stale(changed, now)) {
            let (paint, screen) = self.run_ui();
            let t = &mut self.session.timings;
            t.ui_ms = Some(smooth(t.ui_ms, now.elapsed().as_secs_f64() * 1e3));
            Some((paint, screen))
        } else {
            None
        };
        let draw_start = Instant::now();
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        twin::sync(&mut self.twin, &mut self.session, &self.ctx, self.config.format, self.targets.samples)?;
        self.session.apply_changes(&self.ctx);
        let [left, right] = twin::halves(self.viewport);
        let mine = if self.twin.is_some() { left } else { self.viewport };
        self.session.encode_frame(&mut encoder, self.targets.views(&view), mine)?;
        let mut solver_wall = self.session.timings.cpu_solve_ms;
        if let Some(t) = &mut self.twin {
            t.apply_changes(&self.ctx);
            t.encode_frame(&mut encoder, self.targets.views(&view), right)?;
            solver_wall += t.timings.cpu_solve_ms;
        }
        let mut user_buffers = Vec::new();
        if let Some((paint, screen)) = &ui {
            user_buffers =
                self.egui_renderer.update_buffers(&self.ctx.device, &self.ctx.queue, &mut encoder, paint, screen);
        }
        match (&ui, &mut self.ui_cache) {
            (Some((paint, screen)), Some(cache)) => {
                let ppp = screen.pixels_per_point;
                let clips: Vec<[f32; 4]> = paint.iter().map(|p| painted_rect(p).map(|v| v * ppp)).collect();
                match panel_rects(self.viewport, self.config.width, self.config.height, &clips, &self.labels) {
                    Some(rects) => {
                        let clear = wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT);
                        encode_ui(&self.egui_renderer, &mut encoder, cache.view(), paint, screen, clear);
                        cache.drawn(Some(rects), now);
                        cache.copy_to(&mut encoder, &frame.texture);
                    }
                    None => {
                        encode_ui(&self.egui_renderer, &mut encoder, &view, paint, screen, wgpu::LoadOp::Load);
                        cache.drawn(None, now);
                    }
                }
            }
            (Some((paint, screen)), None) => {
                encode_ui(&self.egui_renderer, &mut encoder, &view, paint, screen, wgpu::LoadOp::Load);
            }
            (None, Some(cache)) => cache.copy_to(&mut encoder, &frame.texture),
            (None, None) => {}
        }
        self.ctx.queue.submit(user_buffers.into_iter().chain([encoder.finish()]));
        self.session.after_submit();
        if let Some(t) = &mut self.twin {
            t.after_submit();
        }
        self.window.pre_present_notify();
        self.ctx.queue.present(frame);
        if std::mem::take(&mut self.reconfigure) {
            self.resize(self.window.inner_size());
        }
        self.session.poll();
        if let Some(t) = &mut self.twin {
            t.poll();
        }
        let draw_ms = draw_start.elapsed().as_secs_f64() * 1e3 - solver_wall;
        let t = &mut self.session.timings;
        t.draw_ms = Some(smooth(t.draw_ms, draw_ms));
        if ui.is_some() {
            self.last_paint = ui;
        }
        Ok(true)
    }

    /// Runs the panels; returns egui's paint jobs and the screen descriptor.
    fn run_ui(&mut self) -> (Vec<egui::ClippedPrimitive>, egui_wgpu::ScreenDescriptor) {
        let input = self.egui_state.take_egui_input(&self.window);
        let mut rect = egui::Rect::NOTHING;
        let (state, mut stats) = self.session.ui_parts();
        stats.twin =
            self.twin.as_ref().zip(state.compare).map(|(t, c)| (&t.history, c.sides(&state.settings).map(|s| s.0)));
        let mut labels = Vec::new();
        let mut output = self.egui_ctx.run_ui(input, |ui| {
            rect = ui::panels(ui, state, &stats);
            let halves = twin::halves([rect.min.x, rect.min.y, rect.width(), rect.height()])
                .map(|[x, y, w, h]| egui::Rect::from_min_size(egui::pos2(x, y), egui::vec2(w, h)));
            labels = ui::compare_labels(ui, state, halves);
        });
        let ppp_labels = output.pixels_per_point;
        self.labels = labels.iter().map(|r| [r.min.x, r.min.y, r.max.x, r.max.y].map(|v| v * ppp_labels)).collect();
        self.egui_state.handle_platform_output(&self.window, std::mem::take(&mut output.platform_output));
        // An animation (a panel opening, a widget fading) wants the next frame drawn too.
        if output.viewport_output.get(&egui::ViewportId::ROOT).is_some_and(|v| v.repaint_delay.is_zero()) {
            self.ui_changed = true;
        }
        let ppp = output.pixels_per_point;
        let paint = self.egui_ctx.tessellate(std::mem::take(&mut output.shapes), ppp);
        let mut delta = std::mem::take(&mut output.textures_delta);
        for (id, deltas) in delta.set.drain() {
            for d in &deltas {
                self.egui_renderer.update_texture(&self.ctx.device, &self.ctx.queue, id, d);
            }
        }
        // Textures egui no longer uses; the frames already recorded do not draw them.
        for id in delta.free.drain() {
            self.egui_renderer.free_texture(&id);
        }
        let (w, h) = (self.config.width as f32, self.config.height as f32);
        self.viewport = if rect.is_positive() {
            let x0 = (rect.min.x * ppp).clamp(0.0, w - 1.0);
            let y0 = (rect.min.y * ppp).clamp(0.0, h - 1.0);
            let x1 = (rect.max.x * ppp).clamp(x0 + 1.0, w);
            let y1 = (rect.max.y * ppp).clamp(y0 + 1.0, h);
            [x0, y0, x1 - x0, y1 - y0]
        } else {
            [0.0, 0.0, w, h]
        };
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point: ppp,
        };
        (paint, screen)
    }

    /// Draws the last frame again into a texture and writes it to `path` as PNG.
    fn screenshot(&mut self, path: &std::path::Path) -> Result<()> {
        let Some((paint, screen)) = self.last_paint.take() else {
            return Err(Error::Gpu("no frame was drawn to capture".into()));
        };
        let texture = self.targets.capture_texture(&self.ctx.device);
        let view = texture.create_view(&Default::default());
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        self.session.encode_scene_only(&mut encoder, self.targets.views(&view));
        if let Some(t) = &self.twin {
            t.encode_scene_only(&mut encoder, self.targets.views(&view));
        }
        let user_buffers =
            self.egui_renderer.update_buffers(&self.ctx.device, &self.ctx.queue, &mut encoder, &paint, &screen);
        encode_ui(&self.egui_renderer, &mut encoder, &view, &paint, &screen, wgpu::LoadOp::Load);
        self.ctx.queue.submit(user_buffers.into_iter().chain([encoder.finish()]));
        let img = read_texture(&self.ctx.device, &self.ctx.queue, &texture)?;
        save_png(&img, path)?;
        Ok(())
    }
}

/// Where a paint job draws (points `[x0, y0, x1, y1]`): its mesh's bounds within its clip
/// rectangle (the clip rectangle for a callback).
fn painted_rect(p: &egui::ClippedPrimitive) -> [f32; 4] {
    let clip = p.clip_rect;
    let bounds = match &p.primitive {
        egui::epaint::Primitive::Mesh(m) => m.calc_bounds(),
        egui::epaint::Primitive::Callback(_) => clip,
    };
    let r = bounds.intersect(clip);
    if r.is_positive() { [r.min.x, r.min.y, r.max.x, r.max.y] } else { [0.0; 4] }
}

/// Records egui's paint jobs into `view`, over what is there (`LoadOp::Load`) or cleared.
fn encode_ui(
    r: &egui_wgpu::Renderer,
    encoder: &mut wgpu::CommandEncoder,
    view: &wgpu::TextureView,
    paint: &[egui::ClippedPrimitive],
    screen: &egui_wgpu::ScreenDescriptor,
    load: wgpu::LoadOp<wgpu::Color>,
) {
    let pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some("egui"),
        color_attachments: &[Some(wgpu::RenderPassColorAttachment {
            view,
            depth_slice: None,
            resolve_target: None,
            ops: wgpu::Operations { load, store: wgpu::StoreOp::Store },
        })],
        depth_stencil_attachment: None,
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    });
    let mut pass = pass.forget_lifetime();
    r.render(&mut pass, paint, screen);
}
