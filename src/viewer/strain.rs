//! Per-vertex colours of the strain and energy views. Strain is computed on the GPU from the
//! position buffer every frame (`shaders/render/strain.wgsl`); [`vertex_strain`] and [`ramp`]
//! are its CPU twins. The energy view is computed on the CPU from the statistics snapshot.

use glam::Vec3;
use wgpu::util::DeviceExt;

use crate::coloring::Incidence;
use crate::constraints::{Element, gather};
use crate::gpu::{compute_pipeline, shader_module, shaders, storage_entry};
use crate::math::Vector;
use crate::scene::{Family, Scene};

/// The colour ramp, blue (0) → green → yellow → red (1), linear RGB. Mirrors `ramp` in
/// `shaders/render/strain.wgsl`.
pub fn ramp(t: f32) -> [f32; 3] {
    const C: [[f32; 3]; 4] = [[0.10, 0.25, 0.85], [0.10, 0.65, 0.25], [0.95, 0.80, 0.10], [0.85, 0.08, 0.05]];
    let s = t.clamp(0.0, 1.0) * 3.0;
    let (k, f) = if s < 1.0 {
        (0, s)
    } else if s < 2.0 {
        (1, s - 1.0)
    } else {
        (2, s - 2.0)
    };
    std::array::from_fn(|c| C[k][c] + (C[k + 1][c] - C[k][c]) * f)
}

/// Mean relative stretch `||d| − l₀| / l₀` of the edges around each of `n` vertices (0 for a
/// vertex without edges). Mirrors `vertex_strain` in `shaders/render/strain.wgsl`.
pub fn vertex_strain(n: usize, edges: &[[u32; 2]], rest: &[f32], x: &[Vec3]) -> Vec<f32> {
    let inc = Incidence::new(n, edges);
    (0..n)
        .map(|i| {
            let around = inc.of(i);
            let sum: f32 = around
                .iter()
                .map(|&e| {
                    let ([a, b], l0) = (edges[e as usize], rest[e as usize]);
                    let l = (x[b as usize] - x[a as usize]).length();
                    if l0 > 0.0 { (l - l0).abs() / l0 } else { 0.0 }
                })
                .sum();
            if around.is_empty() { 0.0 } else { sum / around.len() as f32 }
        })
        .collect()
}

/// Each particle's share of the elastic energy (J): every element's energy split evenly among
/// its particles.
pub fn vertex_energy<V: Vector<S = f32>>(scene: &Scene, x: &[V]) -> Vec<f32> {
    fn family<E: Element<N>, V: Vector<S = f32>, const N: usize>(f: &Family<E, N>, x: &[V], out: &mut [f32]) {
        for e in &f.elements {
            let idx = e.particles();
            let share = e.energy(&f.params, &gather(x, idx)) / N as f32;
            if share.is_finite() {
                for i in idx {
                    out[i as usize] += share;
                }
            }
        }
    }
    let mut out = vec![0.0f32; scene.num_particles()];
    crate::for_each_family!(scene, |_i, f| family(f, x, &mut out));
    out
}

/// Colours of `values` on the ramp with `scale` at the red end (`vec4`, w = the value).
pub fn ramp_colors(values: &[f32], scale: f32) -> Vec<[f32; 4]> {
    let inv = if scale > 0.0 { 1.0 / scale } else { 0.0 };
    values
        .iter()
        .map(|&v| {
            let [r, g, b] = ramp(v * inv);
            [r, g, b, v]
        })
        .collect()
}

/// The strain kernel and its buffers for one scene, writing into a per-vertex colour buffer.
#[derive(Debug)]
pub struct StrainPass {
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    params: wgpu::Buffer,
    /// The colours (`vec4` per vertex, `STORAGE | VERTEX | COPY_DST | COPY_SRC`).
    pub colors: wgpu::Buffer,
    n: u32,
}

impl StrainPass {
    /// Builds the kernel for `scene`, whose positions live in `positions`.
    pub fn new(device: &wgpu::Device, scene: &Scene, positions: &wgpu::Buffer) -> Self {
        use wgpu::BufferUsages as U;
        let n = scene.num_particles();
        let init = |label, bytes: &[u8], usage| {
            let bytes = if bytes.is_empty() { &[0u8; 16][..] } else { bytes };
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor { label: Some(label), contents: bytes, usage })
        };
        let inc = Incidence::new(n, &scene.edges);
        let edges = init("strain edges", bytemuck::cast_slice(&scene.edges), U::STORAGE);
        let rest = init("strain rest", bytemuck::cast_slice(&scene.edge_rest), U::STORAGE);
        let offsets = init("strain offsets", bytemuck::cast_slice(&inc.offsets), U::STORAGE);
        let list = init("strain incidence", bytemuck::cast_slice(&inc.elements), U::STORAGE);
        let colors = init("vertex colors", &vec![0u8; n * 16], U::STORAGE | U::VERTEX | U::COPY_DST | U::COPY_SRC);
        let params = init("strain params", &[0u8; 16], U::UNIFORM | U::COPY_DST);
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("strain"),
            entries: &[
                storage_entry(0, true),
                storage_entry(1, true),
                storage_entry(2, true),
                storage_entry(3, true),
                storage_entry(4, true),
                storage_entry(5, false),
                wgpu::BindGroupLayoutEntry {
                    binding: 6,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                },
            ],
        });
        fn entry(binding: u32, b: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: b.as_entire_binding() }
        }
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("strain"),
            layout: &layout,
            entries: &[
                entry(0, positions),
                entry(1, &edges),
                entry(2, &rest),
                entry(3, &offsets),
                entry(4, &list),
                entry(5, &colors),
                entry(6, &params),
            ],
        });
        let module = shader_module(device, "strain", shaders::STRAIN);
        let pipeline = compute_pipeline(device, &module, "vertex_strain", "vertex_strain", &[Some(&layout)]);
        StrainPass { pipeline, bind_group, params, colors, n: n as u32 }
    }

    /// Records the kernel with `scale` (relative stretch drawn red).
    pub fn encode(&self, queue: &wgpu::Queue, encoder: &mut wgpu::CommandEncoder, scale: f32) {
        queue.write_buffer(&self.params, 0, bytemuck::cast_slice(&[scale.max(1e-9), 0.0, 0.0, 0.0]));
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("strain"), timestamp_writes: None });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.dispatch_workgroups(self.n.div_ceil(64).clamp(1, 65535), 1, 1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_runs_from_blue_to_red_and_clamps() {
        assert_eq!(ramp(-1.0), ramp(0.0));
        assert_eq!(ramp(2.0), ramp(1.0));
        let (lo, hi) = (ramp(0.0), ramp(1.0));
        assert!(lo[2] > lo[0] && hi[0] > hi[2]);
    }

    #[test]
    fn strain_of_a_stretched_pair() {
        let x = [Vec3::ZERO, Vec3::new(1.5, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
        let s = vertex_strain(4, &[[0, 1], [0, 2]], &[1.0, 1.0], &x);
        assert!((s[0] - 0.25).abs() < 1e-6 && (s[1] - 0.5).abs() < 1e-6 && s[2] == 0.0 && s[3] == 0.0, "{s:?}");
    }
}
