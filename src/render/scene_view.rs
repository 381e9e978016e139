//! Per-scene draw data: index and normal buffers for the simulated surface (positions come from
//! the solver's buffer), collider meshes, camera and material uniforms.

use wgpu::util::DeviceExt;

use super::camera::Camera;
use super::embed::Embedder;
use super::lines::LineSet;
use super::pipelines::Renderer;
use super::sphere::uv_sphere;
use super::target::FrameViews;
use crate::coloring::Incidence;
use crate::scene::Scene;

/// A surface to draw: positions and normals (`vec4` per vertex), triangles, material.
#[derive(Debug)]
struct DrawMesh {
    positions: wgpu::Buffer,
    normals: wgpu::Buffer,
    index: wgpu::Buffer,
    count: u32,
    material: wgpu::BindGroup,
}

/// Two colours: front and back faces (linear RGB).
fn material(device: &wgpu::Device, r: &Renderer, front: [f32; 3], back: [f32; 3]) -> wgpu::BindGroup {
    let data = [front[0], front[1], front[2], 1.0, back[0], back[1], back[2], 1.0];
    uniform_group(device, &r.uniform_layout, bytemuck::cast_slice(&data))
}

fn uniform_group(device: &wgpu::Device, layout: &wgpu::BindGroupLayout, bytes: &[u8]) -> wgpu::BindGroup {
    let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("uniform"),
        contents: bytes,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
    });
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("uniform"),
        layout,
        entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
    })
}

fn buffer(device: &wgpu::Device, label: &str, bytes: &[u8], usage: wgpu::BufferUsages) -> wgpu::Buffer {
    let bytes = if bytes.is_empty() { &[0u8; 16][..] } else { bytes };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytes, usage })
}

fn entry(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }
}

/// What the renderer draws of one scene.
#[derive(Debug)]
pub struct SceneView {
    camera_buffer: wgpu::Buffer,
    camera_group: wgpu::BindGroup,
    surface: DrawMesh,
    colliders: Vec<DrawMesh>,
    ground: Option<wgpu::BindGroup>,
    normals_group: wgpu::BindGroup,
    n_vertices: u32,
    /// Places an embedded surface's vertices each frame (scenes with an embedding).
    pub embedder: Option<Embedder>,
    /// The camera in use.
    pub camera: Camera,
    /// Whether the simulated surface is drawn (tests draw the background alone to measure it).
    pub show_surface: bool,
    /// A colour per vertex (`vec4`, `VERTEX`) replacing the surface's material, if set.
    pub vertex_colors: Option<wgpu::Buffer>,
    /// Line segments drawn after the surfaces (wireframe, color groups).
    pub lines: Vec<LineSet>,
    /// Where in the target the scene is drawn: `[x, y, width, height]` in pixels (the whole
    /// target when `None`; the background is cleared everywhere).
    pub viewport: Option<[f32; 4]>,
    /// Clear the target to the sky first (`false`: draw over what another view drew beside it).
    pub clear: bool,
}

impl SceneView {
    /// Draw data for `scene`, whose particle positions live in `particles` (`vec4` per particle,
    /// `STORAGE | VERTEX`: the GPU solver's buffer, or one the CPU backend uploads into). A scene
    /// with an embedding draws its embedded surface, placed from the particles on the GPU.
    pub fn new(device: &wgpu::Device, r: &Renderer, scene: &Scene, particles: &wgpu::Buffer) -> Self {
        use wgpu::BufferUsages as U;
        let embedder = scene.embedding.as_ref().map(|e| Embedder::new(device, e, particles));
        let (positions, triangles, n) = match (&embedder, &scene.embedding) {
            (Some(em), Some(e)) => (&em.positions, &e.triangles, e.bindings.len()),
            _ => (particles, &scene.triangles, scene.num_particles()),
        };
        let normals = buffer(device, "normals", &vec![0u8; n * 16], U::STORAGE | U::VERTEX);
        let flat: Vec<u32> = triangles.iter().flatten().copied().collect();
        let index = buffer(device, "triangles", bytemuck::cast_slice(&flat), U::INDEX | U::STORAGE);
        let inc = Incidence::new(n, triangles);
        let offsets = buffer(device, "vertex offsets", bytemuck::cast_slice(&inc.offsets), U::STORAGE);
        let tris = buffer(device, "vertex triangles", bytemuck::cast_slice(&inc.elements), U::STORAGE);
        let normals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("normals"),
            layout: &r.normals_layout,
            entries: &[entry(0, positions), entry(1, &index), entry(2, &offsets), entry(3, &tris), entry(4, &normals)],
        });
        let surface = DrawMesh {
            positions: positions.clone(),
            normals,
            index,
            count: flat.len() as u32,
            material: material(device, r, [0.62, 0.13, 0.07], [0.07, 0.20, 0.55]),
        };
        let colliders = scene
            .spheres
            .iter()
            .map(|s| {
                let (p, nrm, idx) = uv_sphere(s.center, s.radius, 24);
                DrawMesh {
                    positions: buffer(device, "sphere", bytemuck::cast_slice(&p), U::VERTEX),
                    normals: buffer(device, "sphere normals", bytemuck::cast_slice(&nrm), U::VERTEX),
                    index: buffer(device, "sphere triangles", bytemuck::cast_slice(&idx), U::INDEX),
                    count: idx.len() as u32,
                    material: material(device, r, [0.40, 0.42, 0.45], [0.40, 0.42, 0.45]),
                }
            })
            .collect();
        let camera = Camera::framing(scene);
        let ground = scene.ground.map(|g| {
            let extent = (camera.eye - camera.target).length() * 3.0;
            uniform_group(device, &r.uniform_layout, bytemuck::cast_slice(&[g.height, extent, 0.25, 0.0]))
        });
        let camera_buffer =
            buffer(device, "camera", bytemuck::bytes_of(&camera.uniform(1.0)), U::UNIFORM | U::COPY_DST);
        let camera_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("camera"),
            layout: &r.camera_layout,
            entries: &[entry(0, &camera_buffer)],
        });
        SceneView {
            camera_buffer,
            camera_group,
            surface,
            colliders,
            ground,
            normals_group,
            n_vertices: n as u32,
            embedder,
            camera,
            show_surface: true,
            vertex_colors: None,
            lines: Vec::new(),
            viewport: None,
            clear: true,
        }
    }

    /// The position buffer the surface is drawn from.
    pub fn positions(&self) -> &wgpu::Buffer {
        &self.surface.positions
    }

    /// Uploads the camera for a target of `width × height` pixels.
    pub fn update_camera(&self, queue: &wgpu::Queue, width: u32, height: u32) {
        let aspect = width as f32 / height.max(1) as f32;
        queue.write_buffer(&self.camera_buffer, 0, bytemuck::bytes_of(&self.camera.uniform(aspect)));
    }

    /// Records the normals pass and the draw of the scene into `views`.
    pub fn encode(&self, r: &Renderer, encoder: &mut wgpu::CommandEncoder, views: FrameViews<'_>) {
        if let Some(e) = &self.embedder {
            e.encode(encoder);
        }
        if self.show_surface && self.surface.count > 0 {
            let mut pass = encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("normals"), timestamp_writes: None });
            pass.set_pipeline(&r.normals);
            pass.set_bind_group(0, &self.normals_group, &[]);
            pass.dispatch_workgroups(self.n_vertices.div_ceil(64).clamp(1, 65535), 1, 1);
        }
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: views.color,
                depth_slice: None,
                resolve_target: views.resolve,
                ops: wgpu::Operations {
                    load: if self.clear { wgpu::LoadOp::Clear(super::SKY) } else { wgpu::LoadOp::Load },
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: views.depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        if let Some([x, y, w, h]) = self.viewport
            && w >= 1.0
            && h >= 1.0
        {
            pass.set_viewport(x, y, w, h, 0.0, 1.0);
        }
        pass.set_bind_group(0, &self.camera_group, &[]);
        if let Some(g) = &self.ground {
            pass.set_pipeline(&r.ground);
            pass.set_bind_group(1, g, &[]);
            pass.draw(0..6, 0..1);
        }
        pass.set_pipeline(&r.mesh);
        let surface = self.show_surface.then_some(&self.surface);
        for m in self.colliders.iter().chain(surface) {
            if m.count == 0 {
                continue;
            }
            pass.set_bind_group(1, &m.material, &[]);
            pass.set_vertex_buffer(0, m.positions.slice(..));
            pass.set_vertex_buffer(1, m.normals.slice(..));
            if let (true, Some(colors)) = (std::ptr::eq(m, &self.surface), &self.vertex_colors) {
                pass.set_pipeline(&r.mesh_colored);
                pass.set_vertex_buffer(2, colors.slice(..));
            }
            pass.set_index_buffer(m.index.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..m.count, 0, 0..1);
        }
        for l in &self.lines {
            l.draw(r, &mut pass);
        }
    }
}
