//! The panels drawn once and reused between changes. On a software adapter egui's pass over
//! the two side panels costs most of a frame (about 33 of 43 ms at 1280 × 800 on lavapipe),
//! while the panels only change with input and with new statistics. The cache holds the last
//! panels' image; a frame without a change copies the panels' rectangles from it onto the
//! surface instead of running and drawing egui again.

use web_time::{Duration, Instant};

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

/// The rectangles to copy from the cache (physical pixels `[x, y, w, h]`): the side panels
/// around the scene's `viewport` in a `width × height` window, and the opaque `labels` drawn
/// over the scene (`[x0, y0, x1, y1]`, each copied less its anti-aliased rim); `None` where one
/// of the places egui drew, `painted` (`[x0, y0, x1, y1]`), reaches into the scene elsewhere: a
/// pop-up or a tooltip, which the cache does not hold.
pub fn panel_rects(
    viewport: [f32; 4],
    width: u32,
    height: u32,
    painted: &[[f32; 4]],
    labels: &[[f32; 4]],
) -> Option<Vec<[u32; 4]>> {
    let [vx, vy, vw, vh] = viewport;
    let outside = |c: &[f32; 4]| c[2] <= vx + 0.5 || c[0] >= vx + vw - 0.5 || c[3] <= vy + 0.5 || c[1] >= vy + vh - 0.5;
    let in_label = |c: &[f32; 4]| {
        labels.iter().any(|l| c[0] >= l[0] - 2.0 && c[1] >= l[1] - 2.0 && c[2] <= l[2] + 2.0 && c[3] <= l[3] + 2.0)
    };
    if !painted.iter().all(|c| outside(c) || in_label(c)) {
        return None;
    }
    let left = vx.round().clamp(0.0, width as f32) as u32;
    let right = ((vx + vw).round().clamp(left as f32, width as f32)) as u32;
    let mut rects = vec![[0, 0, left, height], [right, 0, width - right, height]];
    for l in labels {
        let x0 = (l[0] + 1.0).ceil().clamp(0.0, width as f32) as u32;
        let y0 = (l[1] + 1.0).ceil().clamp(0.0, height as f32) as u32;
        let x1 = (l[2] - 1.0).floor().clamp(x0 as f32, width as f32) as u32;
        let y1 = (l[3] - 1.0).floor().clamp(y0 as f32, height as f32) as u32;
        rects.push([x0, y0, x1 - x0, y1 - y0]);
    }
    Some(rects)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_around_the_scene_are_cached_and_a_pop_up_over_it_is_not() {
        let viewport = [300.0, 0.0, 680.0, 800.0];
        let panels = [[0.0, 0.0, 300.0, 800.0], [980.0, 0.0, 1280.0, 800.0]];
        let rects = panel_rects(viewport, 1280, 800, &panels, &[]).unwrap();
        assert_eq!(rects, vec![[0, 0, 300, 800], [980, 0, 300, 800]]);
        let popup = [250.0, 100.0, 420.0, 200.0];
        assert_eq!(panel_rects(viewport, 1280, 800, &[panels[0], popup], &[]), None);
        // A label over the scene is copied too, less its rim.
        let label = [308.0, 8.0, 420.0, 30.0];
        let painted = [panels[0], panels[1], [307.5, 7.5, 420.5, 30.5]];
        let rects = panel_rects(viewport, 1280, 800, &painted, &[label]).unwrap();
        assert_eq!(rects[2], [309, 9, 110, 20]);
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
