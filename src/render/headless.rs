//! Headless frames: a simulation drawn offscreen and read back as an image.

use crate::error::Result;
use crate::gpu::GpuContext;
use crate::simulation::{Simulation, upload_buffer, upload_positions};

use super::{OFFSCREEN_FORMAT, OffscreenTarget, Renderer, SceneView};

/// Samples per pixel of headless frames.
pub const HEADLESS_SAMPLES: u32 = 4;

/// Draws one simulation into an offscreen target. The GPU backend's position buffer is drawn
/// directly; the CPU backend's positions are uploaded before each capture.
#[derive(Debug)]
pub struct Snapshotter {
    renderer: Renderer,
    target: OffscreenTarget,
    /// The scene's draw data (camera, what is shown).
    pub view: SceneView,
    upload: Option<wgpu::Buffer>,
}

impl Snapshotter {
    /// Prepares `width × height` frames of `sim`.
    pub fn new(ctx: &GpuContext, sim: &Simulation, width: u32, height: u32) -> Result<Self> {
        let renderer = Renderer::new(&ctx.device, OFFSCREEN_FORMAT, HEADLESS_SAMPLES);
        let target = OffscreenTarget::new(&ctx.device, width, height, HEADLESS_SAMPLES)?;
        let (positions, upload) = match sim {
            Simulation::Gpu(g) => (g.x.clone(), None),
            Simulation::Cpu(_) => {
                let b = upload_buffer(&ctx.device, sim.scene().num_particles());
                (b.clone(), Some(b))
            }
        };
        let view = SceneView::new(&ctx.device, &renderer, sim.scene(), &positions);
        view.update_camera(&ctx.queue, width, height);
        Ok(Snapshotter { renderer, target, view, upload })
    }

    /// Draws the simulation's current state and reads the image back.
    pub fn capture(&self, ctx: &GpuContext, sim: &Simulation) -> Result<image::RgbaImage> {
        if let (Simulation::Cpu(c), Some(b)) = (sim, &self.upload) {
            upload_positions(&ctx.queue, b, c);
        }
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        self.view.encode(&self.renderer, &mut enc, self.target.views());
        ctx.queue.submit([enc.finish()]);
        self.target.read_rgba(&ctx.device, &ctx.queue)
    }
}
