//! The window's render targets (multisampled colour and depth, resolved into the surface), and
//! the texture a frame is captured into (`--screenshot`; in a web page, the frame it posts).

use crate::render::{DEPTH_FORMAT, FrameViews, texture};

/// Multisampled colour and depth of the window's size; frames resolve into the surface texture.
#[derive(Debug)]
pub struct FrameTargets {
    /// Width (px).
    pub width: u32,
    /// Height (px).
    pub height: u32,
    /// Samples per pixel (1: no multisampling).
    pub samples: u32,
    format: wgpu::TextureFormat,
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
}

impl FrameTargets {
    /// Targets of `width × height` pixels for a surface of `format`.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, width: u32, height: u32, samples: u32) -> Self {
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let size = (width.max(1), height.max(1));
        let msaa = (samples > 1)
            .then(|| texture(device, size.0, size.1, samples, format, attach).create_view(&Default::default()));
        let depth = texture(device, size.0, size.1, samples, DEPTH_FORMAT, attach).create_view(&Default::default());
        FrameTargets { width, height, samples, format, msaa, depth }
    }

    /// The views of a frame resolving into `target`.
    pub fn views<'a>(&'a self, target: &'a wgpu::TextureView) -> FrameViews<'a> {
        match &self.msaa {
            Some(m) => FrameViews { color: m, resolve: Some(target), depth: &self.depth },
            None => FrameViews { color: target, resolve: None, depth: &self.depth },
        }
    }

    /// A texture like the surface's that can be copied out.
    pub fn capture_texture(&self, device: &wgpu::Device) -> wgpu::Texture {
        let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        texture(device, self.width.max(1), self.height.max(1), 1, self.format, usage)
    }
}
