//! The per-scene state of the GPU solver and the recording of a frame.

use std::sync::Arc;

use glam::{Vec3, Vec4};
use wgpu::util::DeviceExt;

use super::kernels::{FamilyKernels, Kernels, groups};
use super::layout::{DispatchRange, GpuSphere, SimParams};
use super::readback::read_buffer;
use crate::constraints::Element;
use crate::error::Result;
use crate::metrics::{FrameStats, StateView};
use crate::scene::Scene;
use crate::solver::{Method, Settings, StepConstants, jacobi};

/// Stride of the dispatch-range table (the uniform offset alignment).
const RANGE_STRIDE: u64 = 256;

/// Buffers of one constraint family on the GPU.
#[derive(Debug)]
struct GpuFamily {
    elements: wgpu::Buffer,
    lambda: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    /// Dynamic offsets of each color group's range entry.
    color_offsets: Vec<u32>,
    /// Dynamic offset of the whole-family range entry.
    all_offset: u32,
    len: u32,
    /// First Jacobi correction slot and slots per element.
    slot_base: u32,
    arity: u32,
    jacobi: Option<(wgpu::Buffer, wgpu::BindGroup)>,
}

/// Jacobi's buffers, allocated on the first Jacobi frame.
#[derive(Debug)]
struct JacobiBuffers {
    apply_bind_group: wgpu::BindGroup,
    omega: f32,
}

/// State read back from the GPU.
#[derive(Clone, Debug, Default)]
pub struct GpuState {
    /// Positions (m).
    pub x: Vec<Vec3>,
    /// Velocities (m/s).
    pub v: Vec<Vec3>,
    /// Inverse masses (1/kg).
    pub w: Vec<f32>,
    /// Spring multipliers of the last substep.
    pub springs_lambda: Vec<f32>,
    /// Bending multipliers of the last substep.
    pub bends_lambda: Vec<f32>,
}

/// One scene on the GPU: particle buffers (`x` is `STORAGE | VERTEX`, read by the renderer), the
/// buffers of the families the scene has and nothing else, and the recorded stage list.
#[derive(Debug)]
pub struct GpuSolver {
    kernels: Arc<Kernels>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    scene: Scene,
    /// Positions (xyz, m) and inverse masses (w, 1/kg), one `vec4<f32>` per particle.
    pub x: wgpu::Buffer,
    v: wgpu::Buffer,
    params: wgpu::Buffer,
    particles_bind_group: wgpu::BindGroup,
    range_bind_group: wgpu::BindGroup,
    springs: Option<GpuFamily>,
    bends: Option<GpuFamily>,
    jacobi: Option<JacobiBuffers>,
    last: Option<Settings>,
    n: u32,
}

fn storage_buffer(device: &wgpu::Device, label: &str, data: &[u8], extra: wgpu::BufferUsages) -> wgpu::Buffer {
    // wgpu rejects zero-sized bindings: keep at least one element.
    let data = if data.is_empty() { &[0u8; 64][..] } else { data };
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: data,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST | extra,
    })
}

fn entry(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
}

impl GpuSolver {
    /// Uploads `scene` to the device of `kernels`.
    pub fn new(kernels: Arc<Kernels>, device: &wgpu::Device, queue: &wgpu::Queue, scene: Scene) -> Self {
        let n = scene.num_particles() as u32;
        let x4: Vec<Vec4> = scene.positions.iter().zip(&scene.inv_mass).map(|(p, &w)| p.extend(w)).collect();
        let bytes = bytemuck::cast_slice(&x4);
        let x = storage_buffer(device, "x", bytes, wgpu::BufferUsages::VERTEX);
        let x_prev = storage_buffer(device, "x_prev", bytes, wgpu::BufferUsages::empty());
        let v = storage_buffer(device, "v", &vec![0u8; bytes.len()], wgpu::BufferUsages::empty());
        let spheres: Vec<GpuSphere> = scene.spheres.iter().map(GpuSphere::from).collect();
        let spheres = storage_buffer(device, "spheres", bytemuck::cast_slice(&spheres), wgpu::BufferUsages::empty());
        let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::bytes_of(&SimParams::new(&scene, &Settings::default())),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let particles_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("particles"),
            layout: &kernels.particles_layout,
            entries: &[entry(0, &x), entry(1, &x_prev), entry(2, &v), entry(3, &params), entry(4, &spheres)],
        });

        // The dispatch-range table: each family's color groups, then the whole family.
        let mut ranges: Vec<DispatchRange> = Vec::new();
        let mut slot_base = 0u32;
        let mut family = |label: &str, len: usize, colors: &[std::ops::Range<u32>], arity: u32, bytes: &[u8]| {
            let elements = storage_buffer(device, label, bytes, wgpu::BufferUsages::empty());
            let lambda = storage_buffer(device, "lambda", &vec![0u8; len * 4], wgpu::BufferUsages::empty());
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &kernels.family_layout,
                entries: &[entry(0, &elements), entry(1, &lambda)],
            });
            let mut color_offsets = Vec::with_capacity(colors.len());
            for r in colors {
                color_offsets.push((ranges.len() as u64 * RANGE_STRIDE) as u32);
                ranges.push(DispatchRange { start: r.start, count: r.end - r.start, slot_base, pad: 0 });
            }
            let all_offset = (ranges.len() as u64 * RANGE_STRIDE) as u32;
            ranges.push(DispatchRange { start: 0, count: len as u32, slot_base, pad: 0 });
            let f = GpuFamily {
                elements,
                lambda,
                bind_group,
                color_offsets,
                all_offset,
                len: len as u32,
                slot_base,
                arity,
                jacobi: None,
            };
            slot_base += arity * len as u32;
            f
        };
        let springs =
            scene.springs.as_ref().map(|f| family("springs", f.len(), &f.colors, 2, bytemuck::cast_slice(&f.elements)));
        let bends =
            scene.bends.as_ref().map(|f| family("bending", f.len(), &f.colors, 4, bytemuck::cast_slice(&f.elements)));
        let mut table = vec![0u8; (ranges.len().max(1) as u64 * RANGE_STRIDE) as usize];
        for (i, r) in ranges.iter().enumerate() {
            let at = i * RANGE_STRIDE as usize;
            table[at..at + 16].copy_from_slice(bytemuck::bytes_of(r));
        }
        let range_table = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("dispatch ranges"),
            contents: &table,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let range_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("range"),
            layout: &kernels.range_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &range_table,
                    offset: 0,
                    size: wgpu::BufferSize::new(16),
                }),
            }],
        });
        GpuSolver {
            kernels,
            device: device.clone(),
            queue: queue.clone(),
            scene,
            x,
            v,
            params,
            particles_bind_group,
            range_bind_group,
            springs,
            bends,
            jacobi: None,
            last: None,
            n,
        }
    }

    /// The scene being simulated.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// Records one frame of `settings.dt` into `encoder` (one compute pass, no read-back).
    /// Call [`Settings::validate`] first.
    pub fn encode_frame(&mut self, encoder: &mut wgpu::CommandEncoder, s: &Settings) {
        if self.last.as_ref() != Some(s) {
            self.queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&SimParams::new(&self.scene, s)));
            self.last = Some(*s);
        }
        if s.method == Method::Jacobi {
            self.prepare_jacobi(s.jacobi_omega);
        }
        let k = &*self.kernels;
        let springs = self.springs.as_ref().map(|f| (f, k.springs()));
        let bends = self.bends.as_ref().map(|f| (f, k.bending()));
        let families: Vec<(&GpuFamily, &FamilyKernels)> = springs.into_iter().chain(bends).collect();
        let particle_groups = groups(self.n);
        let mut pass =
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("frame"), timestamp_writes: None });
        pass.set_bind_group(0, &self.particles_bind_group, &[]);
        for _ in 0..s.substeps {
            pass.set_pipeline(&k.predict);
            pass.dispatch_workgroups(particle_groups, 1, 1);
            for (f, fk) in &families {
                pass.set_pipeline(&fk.clear);
                pass.set_bind_group(1, &f.bind_group, &[]);
                pass.set_bind_group(2, &self.range_bind_group, &[f.all_offset]);
                pass.dispatch_workgroups(groups(f.len), 1, 1);
            }
            for _ in 0..s.iterations {
                match s.method {
                    Method::GaussSeidel => {
                        for (f, fk) in &families {
                            pass.set_pipeline(&fk.gauss_seidel);
                            pass.set_bind_group(1, &f.bind_group, &[]);
                            for (&offset, r) in f.color_offsets.iter().zip(self.color_sizes(f)) {
                                pass.set_bind_group(2, &self.range_bind_group, &[offset]);
                                pass.dispatch_workgroups(groups(r), 1, 1);
                            }
                        }
                    }
                    Method::Jacobi => {
                        for (f, fk) in &families {
                            if let Some((_, bg)) = &f.jacobi {
                                pass.set_pipeline(&fk.jacobi);
                                pass.set_bind_group(1, bg, &[]);
                                pass.set_bind_group(2, &self.range_bind_group, &[f.all_offset]);
                                pass.dispatch_workgroups(groups(f.len), 1, 1);
                            }
                        }
                        if let Some(j) = &self.jacobi {
                            pass.set_pipeline(k.jacobi_apply());
                            pass.set_bind_group(1, &j.apply_bind_group, &[]);
                            pass.dispatch_workgroups(particle_groups, 1, 1);
                        }
                    }
                }
                pass.set_pipeline(&k.contacts);
                pass.dispatch_workgroups(particle_groups, 1, 1);
            }
            pass.set_pipeline(&k.finish);
            pass.dispatch_workgroups(particle_groups, 1, 1);
        }
    }

    /// Sizes of a family's color groups, in order.
    fn color_sizes<'a>(&'a self, f: &GpuFamily) -> impl Iterator<Item = u32> + 'a {
        let colors = if f.arity == 2 {
            self.scene.springs.as_ref().map(|s| &s.colors)
        } else {
            self.scene.bends.as_ref().map(|s| &s.colors)
        };
        colors.into_iter().flatten().map(|r| r.end - r.start)
    }

    /// Dispatches one frame needs under `s` (for reports).
    pub fn dispatches_per_frame(&self, s: &Settings) -> u64 {
        let fams = [&self.springs, &self.bends];
        let present = fams.iter().filter(|f| f.is_some()).count() as u64;
        let per_iteration = match s.method {
            Method::GaussSeidel => {
                fams.iter().flat_map(|f| f.iter()).map(|f| f.color_offsets.len() as u64).sum::<u64>()
            }
            Method::Jacobi => present + 1,
        } + 1;
        s.substeps as u64 * (2 + present + s.iterations as u64 * per_iteration)
    }

    /// Records and submits one frame, without waiting.
    pub fn step_frame(&mut self, s: &Settings) {
        let mut encoder = self.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("frame") });
        self.encode_frame(&mut encoder, s);
        self.queue.submit([encoder.finish()]);
    }

    /// Allocates Jacobi's scales, corrections and incidence (once per ω).
    fn prepare_jacobi(&mut self, omega: f32) {
        if self.jacobi.as_ref().is_some_and(|j| j.omega == omega) {
            return;
        }
        let count = jacobi::constraint_counts(&self.scene);
        // For each particle, the correction slots touching it in the CPU's summation order
        // (springs, then bending; elements in order).
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); self.n as usize];
        let mut spring_scales = Vec::new();
        let mut bend_scales = Vec::new();
        if let (Some(f), Some(g)) = (&self.scene.springs, &self.springs) {
            incidence(&f.elements, g.slot_base, &mut lists);
            spring_scales = jacobi::scales(&f.elements, &count, omega);
        }
        if let (Some(f), Some(g)) = (&self.scene.bends, &self.bends) {
            incidence(&f.elements, g.slot_base, &mut lists);
            bend_scales = jacobi::scales(&f.elements, &count, omega);
        }
        let total_slots: u32 =
            [&self.springs, &self.bends].iter().flat_map(|f| f.iter()).map(|f| f.arity * f.len).sum();
        let corr = storage_buffer(
            &self.device,
            "jacobi corrections",
            &vec![0u8; total_slots as usize * 16],
            wgpu::BufferUsages::empty(),
        );
        let mut offsets = Vec::with_capacity(lists.len() + 1);
        let mut slots = Vec::new();
        offsets.push(0u32);
        for l in &lists {
            slots.extend_from_slice(l);
            offsets.push(slots.len() as u32);
        }
        let offsets = storage_buffer(
            &self.device,
            "incidence offsets",
            bytemuck::cast_slice(&offsets),
            wgpu::BufferUsages::empty(),
        );
        let slots =
            storage_buffer(&self.device, "incidence slots", bytemuck::cast_slice(&slots), wgpu::BufferUsages::empty());
        let apply_bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("jacobi apply"),
            layout: &self.kernels.apply_layout,
            entries: &[entry(0, &corr), entry(1, &offsets), entry(2, &slots)],
        });
        for (fam, sc) in [(&mut self.springs, spring_scales), (&mut self.bends, bend_scales)] {
            if let Some(f) = fam {
                let scale = storage_buffer(
                    &self.device,
                    "jacobi scale",
                    bytemuck::cast_slice(&sc),
                    wgpu::BufferUsages::empty(),
                );
                let bg = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("family jacobi"),
                    layout: &self.kernels.family_jacobi_layout,
                    entries: &[entry(0, &f.elements), entry(1, &f.lambda), entry(2, &scale), entry(3, &corr)],
                });
                f.jacobi = Some((scale, bg));
            }
        }
        self.jacobi = Some(JacobiBuffers { apply_bind_group, omega });
    }

    /// Reads positions, velocities and multipliers back (waits for the GPU).
    pub fn read_state(&self) -> Result<GpuState> {
        let x: Vec<Vec4> = read_buffer(&self.device, &self.queue, &self.x)?;
        let v: Vec<Vec4> = read_buffer(&self.device, &self.queue, &self.v)?;
        let lambda = |f: &Option<GpuFamily>| -> Result<Vec<f32>> {
            match f {
                Some(f) => {
                    let mut l: Vec<f32> = read_buffer(&self.device, &self.queue, &f.lambda)?;
                    l.truncate(f.len as usize);
                    Ok(l)
                }
                None => Ok(Vec::new()),
            }
        };
        Ok(GpuState {
            w: x.iter().map(|p| p.w).collect(),
            x: x.iter().map(|p| p.truncate()).collect(),
            v: v.iter().map(|p| p.truncate()).collect(),
            springs_lambda: lambda(&self.springs)?,
            bends_lambda: lambda(&self.bends)?,
        })
    }

    /// Reads the positions back (waits for the GPU).
    pub fn read_positions(&self) -> Result<Vec<Vec3>> {
        let x: Vec<Vec4> = read_buffer(&self.device, &self.queue, &self.x)?;
        Ok(x.iter().map(|p| p.truncate()).collect())
    }

    /// Measures the current state (reads it back).
    pub fn stats(&self, frame: u32, time_ms: f64) -> Result<FrameStats> {
        let st = self.read_state()?;
        let k = self.last.as_ref().map(StepConstants::<f32>::new);
        let view = StateView {
            x: &st.x,
            v: &st.v,
            w: &st.w,
            springs_lambda: &st.springs_lambda,
            bends_lambda: &st.bends_lambda,
            constants: k.as_ref(),
            dissipated: 0.0,
        };
        Ok(FrameStats::of_state(&self.scene, &view, frame, time_ms))
    }
}

/// Appends, for each particle, the correction slots of `elements` that touch it.
fn incidence<E: Element<N>, const N: usize>(elements: &[E], slot_base: u32, lists: &mut [Vec<u32>]) {
    for (j, e) in elements.iter().enumerate() {
        for (k, &p) in e.particles().iter().enumerate() {
            lists[p as usize].push(slot_base + (N * j + k) as u32);
        }
    }
}
