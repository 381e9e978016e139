//! Uniform and storage layouts shared with WGSL. Keep in sync with `shaders/common/types.wgsl`.

use bytemuck::{Pod, Zeroable};

use crate::constraints::{Form, SpringMaterial};
use crate::scene::{Scene, Sphere};
use crate::solver::Settings;

/// Per-frame simulation constants (`SimParams` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct SimParams {
    /// Gravity (m/s²) in xyz.
    pub gravity: [f32; 4],
    /// Rest centre of mass (m) in xyz: the reference of gravitational energy in the balance.
    pub rest_com: [f32; 4],
    /// Substep `h` (s).
    pub h: f32,
    /// `1/h` (1/s).
    pub inv_h: f32,
    /// `1/h²` (1/s²).
    pub inv_h2: f32,
    /// Constraint damping `β` (s).
    pub beta: f32,
    /// Compliance of the energy form.
    pub energy_compliance: f32,
    /// 0 compliant, 1 energy.
    pub form: u32,
    /// 0 Hookean, 1 StVK.
    pub material: u32,
    /// Velocity damping factor `max(1 − β_v h, 0)`.
    pub keep: f32,
    /// Ground height (m).
    pub ground_height: f32,
    /// Ground friction μ.
    pub ground_friction: f32,
    /// 1 when the scene has a ground.
    pub has_ground: u32,
    /// Number of spheres.
    pub num_spheres: u32,
    /// Contact offset (m).
    pub contact_offset: f32,
    /// Number of particles.
    pub num_particles: u32,
    /// Number of springs.
    pub num_springs: u32,
    /// Number of bending elements.
    pub num_bends: u32,
    /// Over-relaxation `ω`.
    pub sor: f32,
    /// Padding.
    pub pad: [u32; 3],
}

const _: () = assert!(std::mem::size_of::<SimParams>() == 112);

/// The energy ledger (`Ledger` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuLedger {
    /// Energy at the start of the next substep (J).
    pub h0: f32,
    /// 1 once `h0` is set.
    pub valid: u32,
    /// The last velocity scale `σ`.
    pub sigma: f32,
    /// Cumulative dissipated work at the last balance (J).
    pub work_mark: f32,
    /// Last measured kinetic energy (J).
    pub kinetic: f32,
    /// Last measured gravitational energy about the rest centre of mass (J).
    pub gravitational: f32,
    /// Last measured elastic energy (J).
    pub elastic: f32,
    /// Cumulative dissipated work (J).
    pub work: f32,
}

const _: () = assert!(std::mem::size_of::<GpuLedger>() == 32);

impl SimParams {
    /// The constants of `scene` under `s`, with the same `f32` arithmetic as the CPU solver.
    pub fn new(scene: &Scene, s: &Settings) -> Self {
        let h = s.h();
        let material = scene.springs.as_ref().map_or(SpringMaterial::Hookean, |f| f.params.material);
        let ground = scene.ground;
        SimParams {
            gravity: scene.gravity.extend(0.0).to_array(),
            rest_com: scene.rest_center_of_mass().extend(0.0).to_array(),
            h,
            inv_h: 1.0 / h,
            inv_h2: 1.0 / (h * h),
            beta: s.constraint_damping,
            energy_compliance: s.energy_compliance,
            form: (s.form == Form::Energy) as u32,
            material: (material == SpringMaterial::StVK) as u32,
            keep: (1.0 - s.damping * h).max(0.0),
            ground_height: ground.map_or(0.0, |g| g.height),
            ground_friction: ground.map_or(0.0, |g| g.friction),
            has_ground: ground.is_some() as u32,
            num_spheres: scene.spheres.len() as u32,
            contact_offset: scene.contact_offset,
            num_particles: scene.num_particles() as u32,
            num_springs: scene.springs.as_ref().map_or(0, |f| f.len() as u32),
            num_bends: scene.bends.as_ref().map_or(0, |f| f.len() as u32),
            sor: s.sor,
            pad: [0; 3],
        }
    }
}

/// One dispatch's slice of a family (`DispatchRange` in WGSL), stored at a 256-byte stride and
/// bound with a dynamic offset.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Pod, Zeroable)]
pub struct DispatchRange {
    /// First element.
    pub start: u32,
    /// Number of elements.
    pub count: u32,
    /// First Jacobi correction slot of the family.
    pub slot_base: u32,
    /// Padding.
    pub pad: u32,
}

/// A sphere collider (`Sphere` in WGSL).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct GpuSphere {
    /// Centre (m) and radius (m).
    pub center_radius: [f32; 4],
    /// Friction μ in x.
    pub friction: [f32; 4],
}

impl From<&Sphere> for GpuSphere {
    fn from(s: &Sphere) -> Self {
        GpuSphere { center_radius: s.center.extend(s.radius).to_array(), friction: [s.friction, 0.0, 0.0, 0.0] }
    }
}
