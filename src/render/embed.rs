//! The embedded surface on the GPU: a compute pass that places its vertices from the particle
//! positions each frame (no read-back), before the normals pass.

use wgpu::util::DeviceExt;

use crate::gpu::{bind_group_layout, compute_pipeline, shader_module, shaders, storage_entry};
use crate::scene::Embedding;

/// The embed kernel with its buffers for one scene.
#[derive(Debug)]
pub struct Embedder {
    pipeline: wgpu::ComputePipeline,
    group: wgpu::BindGroup,
    /// The surface's vertices (`vec4` each, `STORAGE | VERTEX | COPY_SRC`), written every frame.
    pub positions: wgpu::Buffer,
    count: u32,
}

impl Embedder {
    /// The kernel for `embedding` over the particles in `particles` (`vec4` per particle).
    pub fn new(device: &wgpu::Device, embedding: &Embedding, particles: &wgpu::Buffer) -> Self {
        let count = embedding.bindings.len() as u32;
        let entries = [storage_entry(0, true), storage_entry(1, true), storage_entry(2, false)];
        let layout = bind_group_layout(device, "embed", &entries);
        let module = shader_module(device, "embed", shaders::EMBED);
        let pipeline = compute_pipeline(device, &module, "embed", "embed", &[Some(&layout)]);
        let bindings = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("bindings"),
            contents: bytemuck::cast_slice(&embedding.bindings),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let positions = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("embedded positions"),
            size: (count.max(1) as u64) * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("embed"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: particles.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: bindings.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: positions.as_entire_binding() },
            ],
        });
        Embedder { pipeline, group, positions, count }
    }

    /// Records the pass that writes [`Embedder::positions`].
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("embed"), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.dispatch_workgroups(self.count.div_ceil(64).clamp(1, 65535), 1, 1);
    }
}
