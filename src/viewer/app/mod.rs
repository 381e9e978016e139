//! The window: a winit event loop, a surface on the solver's device, egui through egui-winit
//! and egui-wgpu, the mouse (orbit, pan, zoom, grab) and the `--screenshot` capture.
//!
//! - this module: the options, the event loop and what lives as long as the window;
//! - [`window`]: the window's set-up, its size and the mouse;
//! - [`draw`]: a frame (the scene, the panels) and its capture.

mod draw;
mod window;

use std::path::PathBuf;
use std::sync::Arc;
use web_time::Instant;

use glam::Vec2;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use super::capture::FrameTargets;
use super::session::{Session, smooth};
use super::state::ViewerState;
use super::twin;
use super::ui;
use super::ui_cache::{UiCache, panel_rects};
use crate::error::{Error, Result};
use crate::gpu::GpuContext;
#[cfg(not(target_arch = "wasm32"))]
use crate::render::save_png;
use crate::render::{TextureCopy, copy_texture};

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
    /// In a web page: after the last frame, POST it as a PNG to this path of the page's server.
    #[cfg(target_arch = "wasm32")]
    pub post_to: Option<String>,
    /// In a web page: the frame posted has its panels (else its scene alone, over the whole
    /// window).
    #[cfg(target_arch = "wasm32")]
    pub post_panels: bool,
}

/// The largest window side asked for (px): the largest texture side of desktop GPUs (the surface
/// is also held to the device's own limit).
pub const MAX_WINDOW: u32 = 16384;

/// Opens the window and runs until it is closed (or `exit_after_frames` have been drawn).
pub fn run(options: ViewerOptions) -> Result<()> {
    if options.exit_after_frames == Some(0) {
        return Err(Error::param("--exit-after-frames", 0, "must be at least 1"));
    }
    if let Some(n) = options.msaa.filter(|n| ![1, 2, 4].contains(n)) {
        return Err(Error::param("--msaa", n, "must be 1, 2 or 4"));
    }
    let sides = 1..=MAX_WINDOW;
    if !(sides.contains(&options.width) && sides.contains(&options.height)) {
        return Err(Error::param(
            "--width/--height",
            format!("{}x{}", options.width, options.height),
            "must be between 1 and 16384 pixels",
        ));
    }
    let event_loop =
        EventLoop::<Result<Opened>>::with_user_event().build().map_err(|e| Error::NoDisplay(e.to_string()))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    #[cfg(target_arch = "wasm32")]
    let proxy = event_loop.create_proxy();
    #[cfg_attr(target_arch = "wasm32", allow(unused_mut))]
    let mut app = App {
        options,
        window: None,
        error: None,
        frames: 0,
        started: None,
        #[cfg(target_arch = "wasm32")]
        proxy,
        #[cfg(target_arch = "wasm32")]
        opening: false,
    };
    #[cfg(target_arch = "wasm32")]
    {
        // The browser runs the loop; errors are shown on the page.
        use winit::platform::web::EventLoopExtWebSys;
        event_loop.spawn_app(app);
        Ok(())
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        event_loop.run_app(&mut app).map_err(|e| Error::NoDisplay(e.to_string()))?;
        if let (Some(t), Some(r)) = (app.started, &app.window) {
            let (secs, fps) = run_time(app.frames, Some(t));
            let t = &r.session.timings;
            let ms = |v: Option<f64>| v.map_or("–".into(), |ms| format!("{ms:.2}"));
            eprintln!(
                "viewer: {} frames in {secs:.2} s ({:.1} FPS); ms/frame: solver {}, panels {}, drawing {}; on {}",
                app.frames,
                fps,
                ms(t.solver_ms),
                ms(t.ui_ms),
                ms(t.draw_ms),
                r.session.info().adapter
            );
        }
        app.error.map_or(Ok(()), Err)
    }
}

/// Seconds since `started` (the first frame's window) and the mean frames per second over
/// `frames` frames, from one reading of the clock.
fn run_time(frames: u32, started: Option<Instant>) -> (f64, f64) {
    let secs = started.map_or(0.0, |t| t.elapsed().as_secs_f64());
    (secs, frames as f64 / secs.max(1e-9))
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
    /// The format everything is drawn in: the surface's, or an sRGB view of it.
    format: wgpu::TextureFormat,
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
    /// Particles grabbed with the mouse so far (the web page reports it).
    #[cfg(target_arch = "wasm32")]
    grabs: u32,
}

/// A window, its surface and a device that can draw into it: what the session is built on.
pub(super) struct Opened {
    pub window: Arc<Window>,
    pub surface: wgpu::Surface<'static>,
    pub ctx: GpuContext,
}

struct App {
    options: ViewerOptions,
    window: Option<Running>,
    error: Option<Error>,
    frames: u32,
    started: Option<Instant>,
    /// Where the page's device arrives once the browser has answered (see `web::open`).
    #[cfg(target_arch = "wasm32")]
    proxy: winit::event_loop::EventLoopProxy<Result<Opened>>,
    /// The page's device is being opened (a second `resumed` must not open another).
    #[cfg(target_arch = "wasm32")]
    opening: bool,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        #[cfg(target_arch = "wasm32")]
        super::web::show_error(&e);
        self.error = Some(e);
        event_loop.exit();
    }

    /// Builds the session on an opened window and device, and starts drawing.
    fn ready(&mut self, event_loop: &ActiveEventLoop, opened: Result<Opened>) {
        match opened.and_then(|o| Running::new(o, &self.options)) {
            Ok(r) => {
                r.window.request_redraw();
                self.window = Some(r);
                self.started = Some(Instant::now());
                #[cfg(target_arch = "wasm32")]
                super::web::show_status("", false);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    /// Draws a frame; after the last one (`exit_after_frames`) writes the screenshot and exits.
    fn redrawn(&mut self, event_loop: &ActiveEventLoop) {
        let Some(r) = &mut self.window else { return };
        match r.redraw() {
            Ok(true) => {
                self.frames += 1;
                #[cfg(target_arch = "wasm32")]
                super::web::count_frames(&r.window, self.frames);
                if self.options.exit_after_frames.is_some_and(|n| self.frames >= n) {
                    #[cfg(not(target_arch = "wasm32"))]
                    let result = match &self.options.screenshot {
                        Some(path) => r.screenshot(path),
                        None => Ok(()),
                    };
                    // A browser maps the capture later; `web::post` sends it when it has.
                    #[cfg(target_arch = "wasm32")]
                    let result = match &self.options.post_to {
                        Some(url) => r.post(url, self.options.post_panels, run_time(self.frames, self.started).1),
                        None => Ok(()),
                    };
                    match result {
                        Ok(()) => event_loop.exit(),
                        Err(e) => self.fail(event_loop, e),
                    }
                }
            }
            Ok(false) => {}
            Err(e) => self.fail(event_loop, e),
        }
    }
}

impl ApplicationHandler<Result<Opened>> for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() || self.error.is_some() {
            return;
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            let opened = open(event_loop, &self.options);
            self.ready(event_loop, opened);
        }
        #[cfg(target_arch = "wasm32")]
        if !std::mem::replace(&mut self.opening, true)
            && let Err(e) = super::web::open(event_loop, &self.options, self.proxy.clone())
        {
            self.fail(event_loop, e);
        }
    }

    fn user_event(&mut self, event_loop: &ActiveEventLoop, opened: Result<Opened>) {
        self.ready(event_loop, opened);
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

/// Opens the window, its surface and a device compatible with it.
#[cfg(not(target_arch = "wasm32"))]
fn open(event_loop: &ActiveEventLoop, o: &ViewerOptions) -> Result<Opened> {
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
    Ok(Opened { window, surface, ctx })
}
