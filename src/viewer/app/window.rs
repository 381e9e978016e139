//! The window's set-up on an opened device, its size, and the mouse over the scene.

use super::*;

impl Running {
    /// egui and the session on an opened window: the surface configured in an sRGB format where
    /// it has one (in a browser, whose canvas has none, drawn through an sRGB view), the frame's
    /// targets.
    pub(super) fn new(opened: Opened, o: &ViewerOptions) -> Result<Running> {
        let Opened { window, surface, ctx } = opened;
        let caps = surface.get_capabilities(&ctx.adapter);
        let surface_format = caps
            .formats
            .iter()
            .copied()
            .find(|f| f.is_srgb())
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| Error::Gpu("the surface offers no format".into()))?;
        // A browser's canvas has no sRGB format but takes an sRGB view of its texture; the
        // desktop draws in the format the surface offers, as it always has.
        let format = if cfg!(target_arch = "wasm32") { surface_format.add_srgb_suffix() } else { surface_format };
        let size = window.inner_size();
        let software = ctx.adapter.get_info().device_type == wgpu::DeviceType::Cpu;
        let cached = software && caps.usages.contains(wgpu::TextureUsages::COPY_DST);
        let copy = if cached { wgpu::TextureUsages::COPY_DST } else { wgpu::TextureUsages::empty() };
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT | copy,
            format: surface_format,
            width: size.width.clamp(1, max_side(&ctx.device)),
            height: size.height.clamp(1, max_side(&ctx.device)),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: caps.alpha_modes.first().copied().unwrap_or(wgpu::CompositeAlphaMode::Auto),
            view_formats: if format == surface_format { vec![] } else { vec![format] },
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
            format,
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
            #[cfg(target_arch = "wasm32")]
            grabs: 0,
        })
    }

    pub(super) fn resize(&mut self, size: PhysicalSize<u32>) {
        // A minimised window has no size: keep the old configuration and skip frames.
        if size.width == 0 || size.height == 0 {
            return;
        }
        let max = max_side(&self.ctx.device);
        (self.config.width, self.config.height) = (size.width.min(max), size.height.min(max));
        self.surface.configure(&self.ctx.device, &self.config);
        let (w, h, samples) = (self.config.width, self.config.height, self.targets.samples);
        self.targets = FrameTargets::new(&self.ctx.device, self.format, w, h, samples);
        if self.ui_cache.is_some() {
            self.ui_cache = Some(UiCache::new(&self.ctx.device, self.format, w, h));
        }
        self.ui_changed = true;
    }

    pub(super) fn in_scene(&self, p: Vec2) -> bool {
        let [x, y, w, h] = self.viewport;
        p.x >= x && p.y >= y && p.x < x + w && p.y < y + h
    }

    /// Cursor position and size of the scene's viewport (px).
    /// Relative to the main session's part of the scene (its left half in compare mode).
    pub(super) fn scene_pixel(&self, p: Vec2) -> (Vec2, Vec2) {
        let [x, y, w, h] = self.main_viewport();
        (p - Vec2::new(x, y), Vec2::new(w, h))
    }

    /// Where the main session draws, and where the twin does in compare mode.
    pub(super) fn main_viewport(&self) -> [f32; 4] {
        if self.twin.is_some() { twin::halves(self.viewport)[0] } else { self.viewport }
    }

    pub(super) fn mouse_moved(&mut self, p: Vec2) {
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

    pub(super) fn mouse_button(&mut self, state: ElementState, button: MouseButton, consumed: bool) {
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
                let grabbed = self.session.grab_at(pixel, size);
                #[cfg(target_arch = "wasm32")]
                {
                    self.grabs += grabbed as u32;
                }
                Some(if grabbed { Drag::Grab } else { Drag::Orbit })
            }
            MouseButton::Right | MouseButton::Middle => Some(Drag::Pan),
            _ => None,
        };
    }
}

/// The largest surface side the device takes (px): a window larger than that is drawn at this
/// size.
fn max_side(device: &wgpu::Device) -> u32 {
    device.limits().max_texture_dimension_2d
}
