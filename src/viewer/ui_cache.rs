//! The panels drawn once and reused between changes. On a software adapter egui's pass over
//! the two side panels costs most of a frame (about 33 of 43 ms at 1280 × 800 on lavapipe),
//! while the panels only change with input and with new statistics. The cache holds the last
//! panels' image; a frame without a change copies the panels' rectangles from it onto the
//! surface instead of running and drawing egui again.

use std::time::{Duration, Instant};

use crate::render::texture;

/// How often the statistics in cached panels are brought up to date without input.
pub const REFRESH: Duration = Duration::from_millis(250);

/// The last panels' image and where they lie.
#[derive(Debug)]
pub struct UiCache {
    texture: wgpu::Texture,
    view: wgpu::TextureView,
    /// The panels' rectangles in physical pixels `[x, y, w, h]`.
    rects: Vec<[u32; 4]>,
    /// When the image was drawn; `None`: it holds nothing usable.
    drawn: Option<Instant>,
}

impl UiCache {
    /// A cache for a surface of `format` and `width × height` pixels.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, width: u32, height: u32) -> Self {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let texture = texture(device, width.max(1), height.max(1), 1, format, usage);
        let view = texture.create_view(&Default::default());
        UiCache { texture, view, rects: Vec::new(), drawn: None }
    }

    /// Whether the panels must be run and drawn again: `changed` (input that egui took, a
    /// resize, a repaint egui asked for), nothing usable cached, or the cached statistics older
    /// than [`REFRESH`].
    pub fn stale(&self, changed: bool, now: Instant) -> bool {
        stale(self.drawn, changed, now)
    }

    /// The view the panels are drawn into for caching.
    pub fn view(&self) -> &wgpu::TextureView {
        &self.view
    }

    /// Records that the panels were drawn into [`UiCache::view`] at `now`, lying in `rects`
    /// (physical pixels `[x, y, w, h]`); `None` where egui drew outside them (a pop-up or a
    /// tooltip over the scene), which is then not cached.
    pub fn drawn(&mut self, rects: Option<Vec<[u32; 4]>>, now: Instant) {
        match rects {
            Some(r) => {
                self.rects = r;
                self.drawn = Some(now);
            }
            None => self.drawn = None,
        }
    }

    /// Whether the image is usable.
    pub fn valid(&self) -> bool {
        self.drawn.is_some()
    }

    /// Copies the cached panels onto `target` (same size and format as the cache).
    pub fn copy_to(&self, encoder: &mut wgpu::CommandEncoder, target: &wgpu::Texture) {
        for &[x, y, w, h] in &self.rects {
            if w == 0 || h == 0 {
                continue;
            }
            let origin = wgpu::Origin3d { x, y, z: 0 };
            encoder.copy_texture_to_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &self.texture,
                    mip_level: 0,
                    origin,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyTextureInfo { texture: target, mip_level: 0, origin, aspect: wgpu::TextureAspect::All },
                wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
            );
        }
    }
}

/// [`UiCache::stale`] for an image drawn at `drawn`.
fn stale(drawn: Option<Instant>, changed: bool, now: Instant) -> bool {
    changed || drawn.is_none_or(|t| now.duration_since(t) >= REFRESH)
}

/// The side panels' rectangles (physical pixels `[x, y, w, h]`) around the scene's `viewport`
/// in a `width × height` window, or `None` where one of egui's clip rectangles `clips` (in
/// physical pixels `[x0, y0, x1, y1]`) reaches into the scene: something drawn over it.
pub fn panel_rects(viewport: [f32; 4], width: u32, height: u32, clips: &[[f32; 4]]) -> Option<Vec<[u32; 4]>> {
    let [vx, vy, vw, vh] = viewport;
    let inside = |c: &[f32; 4]| c[2] <= vx + 0.5 || c[0] >= vx + vw - 0.5 || c[3] <= vy + 0.5 || c[1] >= vy + vh - 0.5;
    if !clips.iter().all(inside) {
        return None;
    }
    let left = vx.round().clamp(0.0, width as f32) as u32;
    let right = ((vx + vw).round().clamp(left as f32, width as f32)) as u32;
    Some(vec![[0, 0, left, height], [right, 0, width - right, height]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_around_the_scene_are_cached_and_a_pop_up_over_it_is_not() {
        let viewport = [300.0, 0.0, 680.0, 800.0];
        let panels = [[0.0, 0.0, 300.0, 800.0], [980.0, 0.0, 1280.0, 800.0]];
        let rects = panel_rects(viewport, 1280, 800, &panels).unwrap();
        assert_eq!(rects, vec![[0, 0, 300, 800], [980, 0, 300, 800]]);
        let popup = [250.0, 100.0, 420.0, 200.0];
        assert_eq!(panel_rects(viewport, 1280, 800, &[panels[0], popup]), None);
    }

    #[test]
    fn the_cache_goes_stale_with_a_change_or_with_time() {
        let t = Instant::now();
        assert!(stale(None, false, t), "nothing cached");
        assert!(!stale(Some(t), false, t + REFRESH / 2));
        assert!(stale(Some(t), true, t + REFRESH / 2), "a change");
        assert!(stale(Some(t), false, t + REFRESH), "old statistics");
    }
}
