//! Line segments between particles drawn from the solver's position buffer: the wireframe and
//! the color-group view.

use wgpu::util::DeviceExt;

use super::pipelines::Renderer;

/// A set of segments `[a, b]` between particles, each with a colour (linear RGB). Cloning
/// shares the GPU buffers.
#[derive(Clone, Debug)]
pub struct LineSet {
    bind_group: wgpu::BindGroup,
    count: u32,
}

impl LineSet {
    /// Segments between particles of `positions` (`vec4` per particle, `STORAGE`), one colour
    /// per segment.
    pub fn new(
        device: &wgpu::Device,
        r: &Renderer,
        positions: &wgpu::Buffer,
        segments: &[[u32; 2]],
        colors: &[[f32; 3]],
    ) -> Self {
        let storage = |label, bytes: &[u8]| {
            let bytes = if bytes.is_empty() { &[0u8; 16][..] } else { bytes };
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let rgba: Vec<[f32; 4]> = colors.iter().map(|c| [c[0], c[1], c[2], 1.0]).collect();
        let seg = storage("segments", bytemuck::cast_slice(segments));
        let col = storage("segment colors", bytemuck::cast_slice(&rgba));
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("lines"),
            layout: &r.lines_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: positions.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: seg.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: col.as_entire_binding() },
            ],
        });
        LineSet { bind_group, count: segments.len().min(colors.len()) as u32 }
    }

    /// Number of segments.
    pub fn len(&self) -> usize {
        self.count as usize
    }

    /// `true` when there is no segment.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Records the draw (the camera is bound at group 0).
    pub(super) fn draw(&self, r: &Renderer, pass: &mut wgpu::RenderPass<'_>) {
        if self.count == 0 {
            return;
        }
        pass.set_pipeline(&r.lines);
        pass.set_bind_group(1, &self.bind_group, &[]);
        pass.draw(0..2 * self.count, 0..1);
    }
}
