//! Dragging a particle. The soft grab (a stiffness above zero) pulls it towards the target
//! through a spring that both backends integrate in their prediction ([`Pull`]), so a hard pull
//! stretches the body. The rigid grab (stiffness 0) pins it (inverse mass 0) at the target, so
//! the constraints pull the rest of the body after it, and gives it its inverse mass back when
//! released: the same host-side write on both backends, the CPU solver's arrays or one `vec4` of
//! the GPU solver's position buffer (every kernel treats `w = 0` as pinned).

use glam::{Vec3, Vec3A, Vec4};

use crate::simulation::Simulation;
use crate::solver::Pull;

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
    /// The soft grab's spring stiffness (N/m); 0 pins the particle (the rigid grab).
    pub stiffness: f32,
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
    /// Before each frame while held: the soft grab's pull for the frame's settings, or (rigid)
    /// the particle pinned at the target and `None`. Either way the hand does work that no
    /// energy budget counts, so the global balance and the projection start theirs again from
    /// the state it leaves.
    pub fn hold(&self, sim: &mut Simulation, queue: &wgpu::Queue) -> Option<Pull> {
        if self.stiffness <= 0.0 {
            set_particle(sim, queue, self.particle, self.target, 0.0);
            return None;
        }
        match sim {
            Simulation::Cpu(c) => {
                c.ledger.carried = None;
                c.ledger.budget = None;
            }
            Simulation::Gpu(g) => g.restart_budgets(),
        }
        Some(Pull { particle: self.particle, target: self.target.to_array(), stiffness: self.stiffness })
    }

    /// Lets go: the rigid grab gives the particle its inverse mass back where it is held; the
    /// soft grab's spring simply stops.
    pub fn release(&self, sim: &mut Simulation, queue: &wgpu::Queue) {
        if self.stiffness <= 0.0 {
            set_particle(sim, queue, self.particle, self.target, self.inv_mass);
        }
    }
}
