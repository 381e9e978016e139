//! Dragging a particle: while grabbed it is pinned (inverse mass 0) at the target point, so the
//! constraints pull the rest of the body after it; released, it gets its inverse mass back. The
//! same host-side write on both backends: the CPU solver's arrays, or one `vec4` of the GPU
//! solver's position buffer (no kernel change: every kernel already treats `w = 0` as pinned).

use glam::{Vec3, Vec3A, Vec4};

use crate::simulation::Simulation;

/// A grabbed particle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grab {
    /// The particle.
    pub particle: u32,
    /// Where it is held (m).
    pub target: Vec3,
    /// Its inverse mass before it was grabbed (1/kg).
    pub inv_mass: f32,
    /// Normal of the plane it is dragged in (towards the eye).
    pub plane_normal: Vec3,
}

/// Sets particle `i` to position `x` (m) with inverse mass `w` (1/kg) on either backend; the
/// GPU write is ordered before the next submitted frame. Out-of-range indices are ignored.
pub fn set_particle(sim: &mut Simulation, queue: &wgpu::Queue, i: u32, x: Vec3, w: f32) {
    let i = i as usize;
    if i >= sim.scene().num_particles() {
        return;
    }
    match sim {
        Simulation::Cpu(c) => {
            let p = &mut c.particles;
            p.x[i] = x.into();
            p.x_prev[i] = x.into();
            p.v[i] = Vec3A::ZERO;
            p.w[i] = w;
            // A hand that moves a particle does work no energy budget counts: the global
            // balance and the projection take theirs again from the state it leaves.
            c.ledger.carried = None;
            c.ledger.budget = None;
        }
        Simulation::Gpu(g) => {
            queue.write_buffer(&g.x, (i * 16) as u64, bytemuck::bytes_of(&Vec4::from((x, w))));
            g.restart_budgets();
        }
    }
}

impl Grab {
    /// Pins the particle at the target (before each frame while held).
    pub fn hold(&self, sim: &mut Simulation, queue: &wgpu::Queue) {
        set_particle(sim, queue, self.particle, self.target, 0.0);
    }

    /// Gives the particle its inverse mass back where it is held.
    pub fn release(&self, sim: &mut Simulation, queue: &wgpu::Queue) {
        set_particle(sim, queue, self.particle, self.target, self.inv_mass);
    }
}
