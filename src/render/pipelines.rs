//! Render and normals pipelines, built once per device, colour format and sample count.

use crate::gpu::shaders;

use super::target::DEPTH_FORMAT;

/// The renderer's pipelines and layouts.
#[derive(Debug)]
pub struct Renderer {
    /// Group 0 of both draw pipelines: the camera.
    pub camera_layout: wgpu::BindGroupLayout,
    /// Group 1 of the mesh pipeline (material) and of the ground pipeline (ground).
    pub uniform_layout: wgpu::BindGroupLayout,
    /// The vertex-normals kernel's group.
    pub normals_layout: wgpu::BindGroupLayout,
    /// Lit two-sided surfaces.
    pub mesh: wgpu::RenderPipeline,
    /// The ground plane.
    pub ground: wgpu::RenderPipeline,
    /// Lit surfaces with a colour per vertex.
    pub mesh_colored: wgpu::RenderPipeline,
    /// Group 1 of the lines pipeline: positions, segments, colours.
    pub lines_layout: wgpu::BindGroupLayout,
    /// Line segments between particles.
    pub lines: wgpu::RenderPipeline,
    /// Vertex normals from positions.
    pub normals: wgpu::ComputePipeline,
    /// Colour format drawn into.
    pub format: wgpu::TextureFormat,
    /// Samples per pixel.
    pub samples: u32,
}

fn uniform_layout(device: &wgpu::Device, label: &str) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    })
}

impl Renderer {
    /// Builds the pipelines for targets of `format` with `samples` samples per pixel.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, samples: u32) -> Self {
        let camera_layout = uniform_layout(device, "camera");
        let uniform_layout = uniform_layout(device, "material");
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("draw"),
            bind_group_layouts: &[Some(&camera_layout), Some(&uniform_layout)],
            immediate_size: 0,
        });
        let vec4 = |location| wgpu::VertexAttribute {
            format: wgpu::VertexFormat::Float32x4,
            offset: 0,
            shader_location: location,
        };
        let (pos_attr, nrm_attr) = ([vec4(0)], [vec4(1)]);
        let buffers = [
            Some(wgpu::VertexBufferLayout {
                array_stride: 16,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &pos_attr,
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: 16,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &nrm_attr,
            }),
        ];
        let color_attr = [vec4(2)];
        let colored_buffers = [
            buffers[0].clone(),
            buffers[1].clone(),
            Some(wgpu::VertexBufferLayout {
                array_stride: 16,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &color_attr,
            }),
        ];
        let storage = crate::gpu::storage_entry;
        let vertex_storage =
            |binding| wgpu::BindGroupLayoutEntry { visibility: wgpu::ShaderStages::VERTEX, ..storage(binding, true) };
        let lines_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("lines"),
            entries: &[vertex_storage(0), vertex_storage(1), vertex_storage(2)],
        });
        let lines_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("lines"),
            bind_group_layouts: &[Some(&camera_layout), Some(&lines_layout)],
            immediate_size: 0,
        });
        let draw = |label: &str,
                    source: &str,
                    buffers: &[Option<wgpu::VertexBufferLayout>],
                    layout: &wgpu::PipelineLayout,
                    topology: wgpu::PrimitiveTopology| {
            let module = crate::gpu::shader_module(device, label, source);
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: Default::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState { topology, cull_mode: None, ..Default::default() },
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Less),
                    stencil: Default::default(),
                    bias: Default::default(),
                }),
                multisample: wgpu::MultisampleState { count: samples, ..Default::default() },
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some("fs_main"),
                    compilation_options: Default::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format,
                        blend: None,
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let triangles = wgpu::PrimitiveTopology::TriangleList;
        let mesh = draw("mesh", shaders::MESH, &buffers, &layout, triangles);
        let ground = draw("ground", shaders::GROUND, &[], &layout, triangles);
        let mesh_colored = draw("mesh_colored", shaders::MESH_COLORED, &colored_buffers, &layout, triangles);
        let lines = draw("lines", shaders::LINES, &[], &lines_pipeline_layout, wgpu::PrimitiveTopology::LineList);
        let normals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("normals"),
            entries: &[storage(0, true), storage(1, true), storage(2, true), storage(3, true), storage(4, false)],
        });
        let normals_module = crate::gpu::shader_module(device, "normals", shaders::NORMALS);
        let normals = crate::gpu::compute_pipeline(
            device,
            &normals_module,
            "vertex_normals",
            "vertex_normals",
            &[Some(&normals_layout)],
        );
        Renderer {
            camera_layout,
            uniform_layout,
            normals_layout,
            mesh,
            ground,
            mesh_colored,
            lines_layout,
            lines,
            normals,
            format,
            samples,
        }
    }
}
