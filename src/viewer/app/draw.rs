//! A frame: the scene, the panels (egui, cached on software adapters), and its capture.

use super::*;

impl Running {
    /// Draws one frame; `Ok(false)` when there was nothing to draw into (minimised, surface
    /// being recreated).
    pub(super) fn redraw(&mut self) -> Result<bool> {
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
        let view =
            frame.texture.create_view(&wgpu::TextureViewDescriptor { format: Some(self.format), ..Default::default() });
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
        twin::sync(&mut self.twin, &mut self.session, &self.ctx, self.format, self.targets.samples)?;
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
    pub(super) fn run_ui(&mut self) -> (Vec<egui::ClippedPrimitive>, egui_wgpu::ScreenDescriptor) {
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

    /// Draws the last frame again into a texture, with its panels where `panels` (else its
    /// scene alone over the whole window), and submits the texture's copy into a buffer to map.
    pub(super) fn capture(&mut self, panels: bool) -> Result<TextureCopy> {
        let texture = self.targets.capture_texture(&self.ctx.device);
        let view = texture.create_view(&Default::default());
        let mut encoder = self.ctx.device.create_command_encoder(&Default::default());
        let mut user_buffers = Vec::new();
        if panels {
            let Some((paint, screen)) = self.last_paint.take() else {
                return Err(Error::Gpu("no frame was drawn to capture".into()));
            };
            self.session.encode_scene_only(&mut encoder, self.targets.views(&view));
            if let Some(t) = &self.twin {
                t.encode_scene_only(&mut encoder, self.targets.views(&view));
            }
            user_buffers =
                self.egui_renderer.update_buffers(&self.ctx.device, &self.ctx.queue, &mut encoder, &paint, &screen);
            encode_ui(&self.egui_renderer, &mut encoder, &view, &paint, &screen, wgpu::LoadOp::Load);
        } else {
            let size = [self.config.width, self.config.height];
            self.session.encode_scene_whole(&mut encoder, self.targets.views(&view), size);
        }
        self.ctx.queue.submit(user_buffers.into_iter().chain([encoder.finish()]));
        copy_texture(&self.ctx.device, &self.ctx.queue, &texture)
    }

    /// Posts the last frame as a PNG to `url` of the page's server (panels included where
    /// `panels`), telling the server the solver that ran, the mean frame rate `fps` (1/s), the
    /// split of a frame and how many particles the mouse grabbed.
    #[cfg(target_arch = "wasm32")]
    pub(super) fn post(&mut self, url: &str, panels: bool, fps: f64) -> Result<()> {
        let copy = self.capture(panels)?;
        let (solver, t) = (self.session.state.backend.name(), &self.session.timings);
        let ms = |v: Option<f64>| v.map_or("-".into(), |ms| format!("{ms:.2}"));
        let (s, u, d) = (ms(t.solver_ms), ms(t.ui_ms), ms(t.draw_ms));
        let grabs = self.grabs;
        let query = format!("solver={solver}&fps={fps:.1}&solver_ms={s}&panels_ms={u}&drawing_ms={d}&grabs={grabs}");
        crate::viewer::web::post(copy, format!("{url}?{query}"));
        Ok(())
    }

    /// Draws the last frame again, panels included, and writes it to `path` as PNG.
    #[cfg(not(target_arch = "wasm32"))]
    pub(super) fn screenshot(&mut self, path: &std::path::Path) -> Result<()> {
        let copy = self.capture(true)?;
        let bytes: Vec<u8> = crate::gpu::map_and_copy(&self.ctx.device, &copy.buffer)?;
        save_png(&copy.image(&bytes, true)?, path)
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
