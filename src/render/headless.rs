//! Headless frames: a simulation drawn offscreen and read back as an image.

use crate::error::Result;
use crate::gpu::GpuContext;
use crate::simulation::{DrawBuffer, Simulation};

use super::{OFFSCREEN_FORMAT, OffscreenTarget, Renderer, SceneView};

/// Samples per pixel of headless frames.
pub const HEADLESS_SAMPLES: u32 = 4;

/// Draws one simulation into an offscreen target, from the buffer the simulation gives
/// ([`Simulation::draw_buffer`], brought up to date before each capture).
#[derive(Debug)]
pub struct Snapshotter {
    renderer: Renderer,
    target: OffscreenTarget,
    /// The scene's draw data (camera, what is shown).
    pub view: SceneView,
    positions: DrawBuffer,
}

impl Snapshotter {
    /// Prepares `width × height` frames of `sim`.
    pub fn new(ctx: &GpuContext, sim: &Simulation, width: u32, height: u32) -> Result<Self> {
        let renderer = Renderer::new(&ctx.device, OFFSCREEN_FORMAT, HEADLESS_SAMPLES);
        let target = OffscreenTarget::new(&ctx.device, width, height, HEADLESS_SAMPLES)?;
        let positions = sim.draw_buffer(&ctx.device, &ctx.queue);
        let view = SceneView::new(&ctx.device, &renderer, sim.scene(), positions.buffer());
        view.update_camera(&ctx.queue, width, height);
        Ok(Snapshotter { renderer, target, view, positions })
    }

    /// Draws the simulation's current state and reads the image back.
    pub fn capture(&self, ctx: &GpuContext, sim: &Simulation) -> Result<image::RgbaImage> {
        sim.refresh_draw(&ctx.queue, &self.positions);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        self.view.encode(&self.renderer, &mut enc, self.target.views());
        ctx.queue.submit([enc.finish()]);
        self.target.read_rgba(&ctx.device, &ctx.queue)
    }
}
