//! The window's render targets (multisampled colour and depth, resolved into the surface) and
//! the copy of a captured frame (`--screenshot`; in a web page, the frame it posts).

use crate::error::{Error, Result};
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

/// A texture copied into a mappable buffer, its rows padded to wgpu's alignment.
#[derive(Debug)]
pub struct TextureCopy {
    /// The buffer to map (`padded × height` bytes).
    pub buffer: wgpu::Buffer,
    width: u32,
    height: u32,
    padded: u32,
    bgra: bool,
}

/// Records and submits the copy of a 4-byte-per-pixel texture into a buffer to map.
pub fn copy_texture(device: &wgpu::Device, queue: &wgpu::Queue, texture: &wgpu::Texture) -> Result<TextureCopy> {
    let (width, height) = (texture.width(), texture.height());
    let format = texture.format();
    if format.block_copy_size(None) != Some(4) {
        return Err(Error::Unsupported(format!("capturing a {format:?} surface")));
    }
    let padded = (width * 4).div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT) * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("capture readback"),
        size: padded as u64 * height as u64,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    let mut enc = device.create_command_encoder(&Default::default());
    enc.copy_texture_to_buffer(
        texture.as_image_copy(),
        wgpu::TexelCopyBufferInfo {
            buffer: &buffer,
            layout: wgpu::TexelCopyBufferLayout { offset: 0, bytes_per_row: Some(padded), rows_per_image: None },
        },
        wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
    );
    queue.submit([enc.finish()]);
    let bgra = matches!(format, wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Bgra8UnormSrgb);
    Ok(TextureCopy { buffer, width, height, padded, bgra })
}

impl TextureCopy {
    /// The image in the mapped `bytes` as RGBA (BGRA formats swizzled), opaque.
    pub fn image(&self, bytes: &[u8]) -> Result<image::RgbaImage> {
        let (row, padded) = (self.width as usize * 4, self.padded as usize);
        let mut pixels = Vec::with_capacity(row * self.height as usize);
        for line in bytes.chunks_exact(padded).take(self.height as usize) {
            for px in line[..row].chunks_exact(4) {
                let [a, b, c] = [px[0], px[1], px[2]];
                pixels.extend_from_slice(&if self.bgra { [c, b, a, 255] } else { [a, b, c, 255] });
            }
        }
        image::RgbaImage::from_raw(self.width, self.height, pixels)
            .ok_or_else(|| Error::Gpu("image size mismatch".into()))
    }
}
