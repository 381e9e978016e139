//! An offscreen render target (multisampled colour, resolve, depth), the copy of a texture
//! back to the CPU and PNG output.

use std::path::Path;

use crate::error::{Error, Result};

/// The views a frame is drawn into: the window and the offscreen target both provide them.
#[derive(Clone, Copy, Debug)]
pub struct FrameViews<'a> {
    /// Colour attachment (multisampled when `resolve` is set).
    pub color: &'a wgpu::TextureView,
    /// Single-sample view the colour is resolved into.
    pub resolve: Option<&'a wgpu::TextureView>,
    /// Depth attachment (`Depth32Float`, same sample count as `color`).
    pub depth: &'a wgpu::TextureView,
}

/// An offscreen target of a fixed size.
#[derive(Debug)]
pub struct OffscreenTarget {
    /// Width (px).
    pub width: u32,
    /// Height (px).
    pub height: u32,
    msaa: Option<wgpu::TextureView>,
    resolved: wgpu::Texture,
    resolved_view: wgpu::TextureView,
    depth: wgpu::TextureView,
}

/// Colour format of offscreen targets.
pub const OFFSCREEN_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;
/// Depth format of every target.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// A 2D render texture of `w × h` pixels (one mip level).
pub fn texture(
    device: &wgpu::Device,
    w: u32,
    h: u32,
    samples: u32,
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some("render target"),
        size: wgpu::Extent3d { width: w, height: h, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

impl OffscreenTarget {
    /// A `width × height` target with `samples` samples per pixel (1 or 4).
    pub fn new(device: &wgpu::Device, width: u32, height: u32, samples: u32) -> Result<Self> {
        let max = device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > max || height > max {
            return Err(Error::param(
                "--width/--height",
                format!("{width}x{height}"),
                "must be between 1 and the device's texture limit",
            ));
        }
        let attach = wgpu::TextureUsages::RENDER_ATTACHMENT;
        let msaa = (samples > 1).then(|| {
            texture(device, width, height, samples, OFFSCREEN_FORMAT, attach).create_view(&Default::default())
        });
        let resolved = texture(device, width, height, 1, OFFSCREEN_FORMAT, attach | wgpu::TextureUsages::COPY_SRC);
        let resolved_view = resolved.create_view(&Default::default());
        let depth = texture(device, width, height, samples, DEPTH_FORMAT, attach).create_view(&Default::default());
        Ok(OffscreenTarget { width, height, msaa, resolved, resolved_view, depth })
    }

    /// The views to draw into.
    pub fn views(&self) -> FrameViews<'_> {
        match &self.msaa {
            Some(m) => FrameViews { color: m, resolve: Some(&self.resolved_view), depth: &self.depth },
            None => FrameViews { color: &self.resolved_view, resolve: None, depth: &self.depth },
        }
    }

    /// Copies the resolved image back (rows padded to 256 bytes on the GPU, stripped here).
    pub fn read_rgba(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<image::RgbaImage> {
        let copy = copy_texture(device, queue, &self.resolved)?;
        let bytes: Vec<u8> = crate::gpu::map_and_copy(device, &copy.buffer)?;
        copy.image(&bytes, false)
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
    /// The image in the mapped `bytes` as RGBA (BGRA formats swizzled), its alpha made 255
    /// where `opaque` (a window's surface: what is on screen).
    pub fn image(&self, bytes: &[u8], opaque: bool) -> Result<image::RgbaImage> {
        let (row, padded) = (self.width as usize * 4, self.padded as usize);
        let mut pixels = Vec::with_capacity(row * self.height as usize);
        for line in bytes.chunks_exact(padded).take(self.height as usize) {
            for px in line[..row].chunks_exact(4) {
                let [a, b, c, d] = [px[0], px[1], px[2], if opaque { 255 } else { px[3] }];
                pixels.extend_from_slice(&if self.bgra { [c, b, a, d] } else { [a, b, c, d] });
            }
        }
        image::RgbaImage::from_raw(self.width, self.height, pixels)
            .ok_or_else(|| Error::Gpu("image size mismatch".into()))
    }
}

/// Writes an image as PNG.
pub fn save_png(img: &image::RgbaImage, path: &Path) -> Result<()> {
    img.save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| Error::Io { path: path.to_path_buf(), source: std::io::Error::other(e.to_string()) })
}
