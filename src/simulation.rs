//! A scene running on either backend, behind one interface for the command line and the viewer.

use std::sync::Arc;

use glam::{Vec3, Vec3A, Vec4};

use crate::error::{Error, Result};
use crate::gpu::{GpuContext, GpuSolver, Kernels};
use crate::metrics::FrameStats;
use crate::scene::Scene;
use crate::solver::{CpuSolver, Settings};

/// Where the solver runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Backend {
    /// The CPU reference solver.
    #[default]
    Cpu,
    /// The wgpu compute solver.
    Gpu,
}

crate::error::command_names!(Backend, "backend", { Cpu => "cpu", Gpu => "gpu" });

/// A scene being simulated on one backend.
#[derive(Debug)]
pub enum Simulation {
    /// On the CPU (`f32`).
    Cpu(Box<CpuSolver<Vec3A>>),
    /// On the GPU.
    Gpu(Box<GpuSolver>),
}

impl Simulation {
    /// Starts `scene` on `backend`; the GPU backend needs a context and its kernels.
    pub fn new(backend: Backend, scene: Scene, gpu: Option<(&GpuContext, &Arc<Kernels>)>) -> Result<Self> {
        Ok(match (backend, gpu) {
            (Backend::Cpu, _) => Simulation::Cpu(Box::new(CpuSolver::new(scene))),
            (Backend::Gpu, Some((ctx, k))) => {
                Simulation::Gpu(Box::new(GpuSolver::new(k.clone(), &ctx.device, &ctx.queue, scene)?))
            }
            (Backend::Gpu, None) => return Err(Error::Gpu("the GPU backend needs a device".into())),
        })
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        match self {
            Simulation::Cpu(s) => s.scene(),
            Simulation::Gpu(s) => s.scene(),
        }
    }

    /// Takes the positions and velocities of `old`, a simulation of the same particles on
    /// either backend (a rebuilt scene, another backend); from the GPU to the CPU, those of
    /// `latest` where given (a snapshot: a browser cannot wait for a read-back).
    pub fn take_state(
        &mut self,
        old: &Simulation,
        ctx: &GpuContext,
        latest: Option<(Vec<Vec3>, Vec<Vec3>)>,
    ) -> Result<()> {
        match (old, self) {
            (Simulation::Cpu(a), Simulation::Cpu(b)) => {
                b.particles.x.clone_from(&a.particles.x);
                b.particles.v.clone_from(&a.particles.v);
            }
            (Simulation::Gpu(a), Simulation::Gpu(b)) => {
                let mut enc = ctx.device.create_command_encoder(&Default::default());
                enc.copy_buffer_to_buffer(&a.x, 0, &b.x, 0, a.x.size().min(b.x.size()));
                let (va, vb) = (a.velocities(), b.velocities());
                enc.copy_buffer_to_buffer(va, 0, vb, 0, va.size().min(vb.size()));
                ctx.queue.submit([enc.finish()]);
            }
            (Simulation::Cpu(a), Simulation::Gpu(b)) => {
                let w = &b.scene().inv_mass;
                let x: Vec<Vec4> = a.particles.x.iter().zip(w).map(|(p, &w)| p.extend(w)).collect();
                let v: Vec<Vec4> = a.particles.v.iter().map(|p| p.extend(0.0)).collect();
                ctx.queue.write_buffer(&b.x, 0, bytemuck::cast_slice(&x));
                ctx.queue.write_buffer(b.velocities(), 0, bytemuck::cast_slice(&v));
            }
            (Simulation::Gpu(a), Simulation::Cpu(b)) => {
                let (x, v) = match latest {
                    Some(state) => state,
                    None => {
                        let st = a.read_state()?;
                        (st.x, st.v)
                    }
                };
                if x.len() != b.particles.len() || v.len() != x.len() {
                    let (n, m) = (b.particles.len(), x.len().min(v.len()));
                    return Err(Error::Gpu(format!("a state of {m} particles taken into a simulation of {n}")));
                }
                b.particles.x = x.iter().map(|&p| p.into()).collect();
                b.particles.v = v.iter().map(|&v| v.into()).collect();
            }
        }
        Ok(())
    }

    /// `Ok` when frames under `s` fit the backend (on the GPU, the buffers they need within the
    /// device's limits, [`GpuSolver::check_settings`]; the CPU takes any).
    pub fn check_settings(&self, s: &Settings) -> Result<()> {
        match self {
            Simulation::Cpu(_) => Ok(()),
            Simulation::Gpu(g) => g.check_settings(s),
        }
    }

    /// Advances one frame (on the GPU: records and submits it without waiting).
    pub fn step_frame(&mut self, s: &Settings) {
        match self {
            Simulation::Cpu(c) => c.step_frame(s),
            Simulation::Gpu(g) => g.step_frame(s),
        }
    }

    /// Measures the current state (the GPU reads it back).
    pub fn stats(&self, frame: u32, time_ms: f64) -> Result<FrameStats> {
        match self {
            Simulation::Cpu(c) => Ok(FrameStats::measure(c, frame, time_ms)),
            Simulation::Gpu(g) => g.stats(frame, time_ms),
        }
    }

    /// Overwrites the velocities (m/s), one per particle (the GPU checks the count and starts
    /// the projection's budget again).
    pub fn set_velocities(&mut self, v: &[Vec3]) -> Result<()> {
        match self {
            Simulation::Cpu(c) if v.len() == c.particles.len() => {
                c.particles.set_velocities(v);
                Ok(())
            }
            Simulation::Cpu(_) => Err(Error::param("velocities", v.len(), "must be one per particle")),
            Simulation::Gpu(g) => g.set_velocities(v),
        }
    }

    /// Current positions (m).
    pub fn positions(&self) -> Result<Vec<Vec3>> {
        match self {
            Simulation::Cpu(c) => Ok(c.particles.positions()),
            Simulation::Gpu(g) => g.read_positions(),
        }
    }

    /// The self-collision's broad phase so far (the GPU reads it back); `None` without
    /// self-collision.
    pub fn self_collision_counts(&self) -> Result<Option<SelfCollisionCounts>> {
        Ok(match self {
            Simulation::Cpu(c) => c.scene().self_collision.as_ref().map(|_| {
                let p = c.self_pairs();
                SelfCollisionCounts { pairs: p.len(), builds: p.builds(), dropped: p.dropped() }
            }),
            Simulation::Gpu(g) => g.read_self_pairs()?.map(|p| SelfCollisionCounts {
                pairs: p.pairs.len(),
                builds: p.builds,
                dropped: p.dropped,
            }),
        })
    }
}

/// What the self-collision's broad phase has done ([`Simulation::self_collision_counts`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SelfCollisionCounts {
    /// Candidate pairs now.
    pub pairs: usize,
    /// Checks that renewed references and searched candidates anew (the first included).
    pub builds: u64,
    /// Candidates dropped at the last finding beyond
    /// [`crate::solver::self_collision::CAPACITY`] per particle.
    pub dropped: u64,
}

/// The positions the renderer draws, one `vec4` per particle (xyz in m, w the inverse mass):
/// the GPU solver's own buffer, or for the CPU solver a `STORAGE | VERTEX` buffer that
/// [`Simulation::refresh_draw`] uploads its positions into.
#[derive(Clone, Debug)]
pub struct DrawBuffer {
    buffer: wgpu::Buffer,
    /// The buffer takes uploads from the CPU solver.
    uploaded: bool,
}

impl DrawBuffer {
    /// The buffer to bind.
    pub fn buffer(&self) -> &wgpu::Buffer {
        &self.buffer
    }
}

impl Simulation {
    /// The buffer the renderer draws this simulation's positions from, up to date now: the GPU
    /// solver's positions, or a new buffer holding the CPU solver's.
    pub fn draw_buffer(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> DrawBuffer {
        let draw = match self {
            Simulation::Gpu(g) => DrawBuffer { buffer: g.x.clone(), uploaded: false },
            Simulation::Cpu(c) => DrawBuffer { buffer: upload_buffer(device, c.particles.len()), uploaded: true },
        };
        self.refresh_draw(queue, &draw);
        draw
    }

    /// Brings `draw` (from [`Simulation::draw_buffer`]) up to date: uploads the CPU solver's
    /// positions; nothing to do on the GPU, which draws its own buffer.
    pub fn refresh_draw(&self, queue: &wgpu::Queue, draw: &DrawBuffer) {
        if let (Simulation::Cpu(c), true) = (self, draw.uploaded) {
            let x: Vec<Vec4> = c.particles.x.iter().zip(&c.particles.w).map(|(p, &w)| p.extend(w)).collect();
            queue.write_buffer(&draw.buffer, 0, bytemuck::cast_slice(&x));
        }
    }
}

/// A `STORAGE | VERTEX | COPY_DST` position buffer for `n` particles.
fn upload_buffer(device: &wgpu::Device, n: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("uploaded positions"),
        size: (n.max(1) * 16) as u64,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
