//! The viewer in a web page (wasm32, built by `web/build.sh`): the page's canvas as the window,
//! WebGPU as the device, URL parameters for what the command line sets, and the capture of the
//! last frame's scene sent back to the page's server (the browser test's check).
//!
//! A browser answers a request for an adapter or a device, and maps a buffer, only after the
//! page's script has returned to it: the device is opened in a task that hands it to the event
//! loop when it is ready ([`open`]), and the capture is sent from the mapping's callback
//! ([`post`]).
//!
//! URL parameters (all optional): `scene` (default: the hanging `cloth` at 10 substeps × 3
//! iterations, the desktop's main demo), `substeps`, `iterations`, `energy-aware` (as the
//! command line's options), `backend` (`cpu` or `gpu`; default: the GPU solver, the CPU solver
//! on a software adapter), `compare` (as `view --compare`), `width` and `height` (the canvas in
//! CSS pixels; default: the browser's window), `frames` (stop after that many), `post` (with
//! `frames`: POST the last frame as a PNG to that path of the page's server) and `panels`
//! (`1`: the frame posted has the panels; else it is the main run's scene alone, drawn over the
//! whole canvas: in compare mode, without the second run).

use std::str::FromStr;
use std::sync::Arc;

use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;
use winit::dpi::LogicalSize;
use winit::event_loop::{ActiveEventLoop, EventLoopProxy};
use winit::platform::web::WindowAttributesExtWebSys;
use winit::window::Window;

use super::app::{Opened, ViewerOptions};
use super::state::{SceneChoice, ViewerState};
use crate::error::{Error, Result};
use crate::gpu::GpuContext;
use crate::render::TextureCopy;
use crate::scene::{MAIN_DEMO, SceneOptions, default_iterations};
use crate::simulation::Backend;
use crate::solver::Settings;

/// The page's entry point (wasm-bindgen calls it when the module has loaded).
#[wasm_bindgen(start)]
pub fn start() {
    std::panic::set_hook(Box::new(|info| show_status(&format!("eapbd stopped: {info}"), true)));
    if let Err(e) = options().and_then(super::run) {
        show_error(&e);
    }
}

/// The page's URL parameter `name`.
fn param(name: &str) -> Option<String> {
    let search = web_sys::window()?.location().search().ok()?;
    web_sys::UrlSearchParams::new_with_str(&search).ok()?.get(name)
}

/// The URL parameter `name` parsed, `None` where it is absent.
fn parsed<T: FromStr>(name: &'static str) -> Result<Option<T>>
where
    T::Err: std::fmt::Display,
{
    param(name).map(|v| v.parse().map_err(|e| Error::param(name, format!("{v} ({e})"), "not understood"))).transpose()
}

/// What the URL asks for, as the command line's `view` would; without a scene, the main demo
/// ([`MAIN_DEMO`]).
fn options() -> Result<ViewerOptions> {
    let (name, split) = match param("scene") {
        Some(name) => (name, None),
        None => (MAIN_DEMO.0.to_string(), Some((MAIN_DEMO.1, MAIN_DEMO.2))),
    };
    let scene_options = SceneOptions::default();
    let mut settings = Settings { iterations: default_iterations(&name), ..Settings::default() };
    if let Some((substeps, iterations)) = split {
        (settings.substeps, settings.iterations) = (substeps, iterations);
    }
    settings.substeps = parsed("substeps")?.unwrap_or(settings.substeps);
    settings.iterations = parsed("iterations")?.unwrap_or(settings.iterations);
    settings.energy_aware = parsed("energy-aware")?.unwrap_or(settings.energy_aware);
    settings.validate()?;
    let backend: Option<Backend> = parsed("backend")?;
    let mut state =
        ViewerState::new(SceneChoice::new(&name, &scene_options)?, settings, backend.unwrap_or(Backend::Gpu));
    state.compare = parsed("compare")?;
    let window = web_sys::window().ok_or_else(|| Error::Web("no browser window".into()))?;
    let inner = |v: std::result::Result<JsValue, JsValue>| v.ok().and_then(|v| v.as_f64()).unwrap_or(800.0) as u32;
    let width = parsed("width")?.unwrap_or_else(|| inner(window.inner_width()));
    let height = parsed("height")?.unwrap_or_else(|| inner(window.inner_height()));
    let exit_after_frames = parsed("frames")?;
    let post_to = param("post");
    if post_to.is_some() && exit_after_frames.is_none() {
        return Err(Error::param("post", post_to.unwrap_or_default(), "needs frames"));
    }
    Ok(ViewerOptions {
        state,
        width,
        height,
        exit_after_frames,
        screenshot: None,
        msaa: None,
        backend_given: backend.is_some(),
        post_to,
        post_panels: param("panels").is_some_and(|v| v == "1"),
    })
}

/// The window on the page's canvas (`<canvas id="eapbd">`, else a new one), its surface, and a
/// task that opens a WebGPU device for it and hands it to the event loop through `proxy`.
pub(super) fn open(
    event_loop: &ActiveEventLoop,
    o: &ViewerOptions,
    proxy: EventLoopProxy<Result<Opened>>,
) -> Result<()> {
    let canvas = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("eapbd"))
        .and_then(|e| e.dyn_into::<web_sys::HtmlCanvasElement>().ok());
    let append = canvas.is_none();
    let attributes = Window::default_attributes()
        .with_title("eapbd: energy-aware XPBD")
        .with_inner_size(LogicalSize::new(o.width, o.height))
        .with_canvas(canvas)
        .with_append(append);
    #[allow(clippy::arc_with_non_send_sync)]
    let window = Arc::new(
        event_loop.create_window(attributes).map_err(|e| Error::Web(format!("cannot use the page's canvas: {e}")))?,
    );
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
    desc.backends = wgpu::Backends::BROWSER_WEBGPU;
    let instance = wgpu::Instance::new(desc);
    let surface =
        instance.create_surface(window.clone()).map_err(|e| Error::Gpu(format!("cannot create a surface: {e}")))?;
    wasm_bindgen_futures::spawn_local(async move {
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            compatible_surface: Some(&surface),
            ..Default::default()
        };
        let opened = match instance.request_adapter(&options).await {
            Ok(adapter) => GpuContext::open_device(instance, adapter).await.map(|ctx| Opened { window, surface, ctx }),
            Err(e) => Err(Error::Gpu(format!(
                "this browser gives no WebGPU adapter ({e}); the desktop viewer (see the README) runs without one"
            ))),
        };
        // The loop has ended only if the page is going away.
        let _ = proxy.send_event(opened);
    });
    Ok(())
}

/// Maps the capture and POSTs it as a PNG to `url` of the page's server; says on the page when
/// it is sent (`posted`) or what went wrong.
pub(super) fn post(copy: TextureCopy, url: String) {
    let buffer = copy.buffer.clone();
    buffer.slice(..).map_async(wgpu::MapMode::Read, move |mapped| {
        let png = mapped
            .map_err(|e| Error::Gpu(format!("capture map: {e}")))
            .and_then(|()| {
                let view =
                    copy.buffer.slice(..).get_mapped_range().map_err(|e| Error::Gpu(format!("capture range: {e}")))?;
                copy.image(&view, true)
            })
            .and_then(|img| {
                let mut png = std::io::Cursor::new(Vec::new());
                img.write_to(&mut png, image::ImageFormat::Png)
                    .map_err(|e| Error::Unsupported(format!("encoding the capture: {e}")))?;
                Ok(png.into_inner())
            });
        match png {
            Ok(png) => wasm_bindgen_futures::spawn_local(async move {
                match send(&url, &png).await {
                    Ok(()) => show_status("posted", false),
                    Err(e) => show_error(&e),
                }
            }),
            Err(e) => show_error(&e),
        }
    });
}

/// POSTs `body` to `url`.
async fn send(url: &str, body: &[u8]) -> Result<()> {
    let failed = |e: JsValue| Error::Web(format!("sending the capture to {url}: {e:?}"));
    let init = web_sys::RequestInit::new();
    init.set_method("POST");
    init.set_body(&js_sys::Uint8Array::from(body).into());
    let request = web_sys::Request::new_with_str_and_init(url, &init).map_err(failed)?;
    let window = web_sys::window().ok_or_else(|| Error::Web("no browser window".into()))?;
    wasm_bindgen_futures::JsFuture::from(window.fetch_with_request(&request)).await.map_err(failed)?;
    Ok(())
}

/// Marks the canvas with the number of frames drawn (`data-frames`), for a script or a test
/// that waits for the page.
pub(super) fn count_frames(window: &Window, frames: u32) {
    use winit::platform::web::WindowExtWebSys;
    if let Some(canvas) = window.canvas() {
        let _ = canvas.set_attribute("data-frames", &frames.to_string());
    }
}

/// Shows `e` on the page.
pub(super) fn show_error(e: &Error) {
    show_status(&format!("eapbd: {e}"), true);
}

/// Writes `text` into the page's `<p id="status">` (shown when `error`), and to the console.
pub(super) fn show_status(text: &str, error: bool) {
    if error {
        web_sys::console::error_1(&text.into());
    }
    let element = web_sys::window().and_then(|w| w.document()).and_then(|d| d.get_element_by_id("status"));
    if let Some(e) = element {
        e.set_text_content(Some(text));
        e.set_class_name(if error { "error" } else { "done" });
    }
}
