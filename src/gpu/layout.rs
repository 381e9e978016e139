//! Uniform and storage layouts shared with WGSL. Keep in sync with `shaders/common/types.wgsl`.

use bytemuck::{Pod, Zeroable};

use crate::constraints::{Form, SpringMaterial};
use crate::material::{Elastic, Model};
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
    /// Over-relaxation `ω`.
    pub sor: f32,
    /// 1 when the finish pass makes the last iteration's contact pass first (`iterations > 0`;
    /// the frame then has no dispatch of its own for it).
    pub in_loop_contacts: u32,
    /// The tetrahedra's model, its index in [`Model::ALL`].
    pub tet_model: u32,
    /// The compliant form's stiffness scale `s` of the tetrahedra (Pa).
    pub tet_scale: f32,
    /// The compliant form's stiffness scale `s` of the membranes (N/m).
    pub membrane_scale: f32,
    /// The soft grab's particle ([`crate::solver::Pull`]; `u32::MAX` when none).
    pub pull_particle: u32,
    /// Constants of the 3D model (Pa): `[μ, 2μ, μ/2, λ, λ/2, μ₀₁/2, μ₁₀, ν₁, κ/2, α₁..α₅, κ_inv, 0]`
    /// (Mooney-Rivlin and Arruda-Boyce as in [`crate::material::Elastic`]), each rounded once
    /// from `f64` as on the CPU.
    pub elastic: [f32; 16],
    /// The membranes' `C_orth` entries `[c_uu, c_uv, c_vv, c_ss]` (N/m).
    pub membrane: [f32; 4],
    /// Elements of each constraint family, by its index in [`crate::family_list`] (`FAMILY` in
    /// the family's WGSL); 0 for a family the scene lacks.
    pub counts: [u32; 4],
    /// The soft grab's target (m) in xyz and its stiffness (N/m) in w (0 when none).
    pub pull: [f32; 4],
}

const _: () = assert!(crate::scene::FAMILY_COUNT <= 4, "SimParams::counts holds four families");
const _: () = assert!(std::mem::size_of::<SimParams>() == 224);

/// The 3D model's constants as [`SimParams::elastic`] holds them.
fn elastic_constants(e: &Elastic) -> [f32; 16] {
    let ab = e.arruda_boyce_alphas();
    let c = [
        e.mu,
        2.0 * e.mu,
        0.5 * e.mu,
        e.lambda,
        0.5 * e.lambda,
        0.5 * e.mu01,
        e.mu10,
        e.nu1,
        0.5 * e.kappa,
        ab[0],
        ab[1],
        ab[2],
        ab[3],
        ab[4],
        e.inversion_stiffness,
        0.0,
    ];
    c.map(|v| v as f32)
}

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
    /// Last measured elastic energy that the multipliers hold (J).
    pub held: f32,
    /// Padding to 16 bytes.
    pub pad: [f32; 3],
}

const _: () = assert!(std::mem::size_of::<GpuLedger>() == 48);

/// The energy-momentum projection's state (`Projection` in WGSL; `shaders/solver/projection.wgsl`).
/// Positions are relative to the rest centre of mass `r₀`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuProjection {
    /// Centre of mass less `r₀` (xyz, m); w: total mass (kg), 0 when no rigid motion is kept.
    pub centre: [f32; 4],
    /// Velocity of the centre of mass (xyz, m/s).
    pub velocity: [f32; 4],
    /// Angular velocity (xyz, rad/s).
    pub omega: [f32; 4],
    /// The rigid motion's velocity the projection gives (xyz, m/s); w: its kinetic energy (J).
    pub target_velocity: [f32; 4],
    /// The rigid motion's angular velocity the projection gives (xyz, rad/s).
    pub target_omega: [f32; 4],
    /// Linear momentum an isolated body keeps (xyz, kg·m/s); w: 1 when kept.
    pub momenta_p: [f32; 4],
    /// Angular momentum about `r₀` an isolated body keeps (xyz, kg·m²/s).
    pub momenta_l: [f32; 4],
    /// The budget `H*` (J).
    pub budget: f32,
    /// Cumulative dissipated work when the budget was last carried (J).
    pub work_mark: f32,
    /// The last scale `s`.
    pub scale: f32,
    /// 1 once the budget is set.
    pub has_budget: u32,
}

const _: () = assert!(std::mem::size_of::<GpuProjection>() == 128);

impl SimParams {
    /// The constants of `scene` under `s`, with the same `f32` arithmetic as the CPU solver.
    pub fn new(scene: &Scene, s: &Settings) -> Self {
        let h = s.h();
        let material = scene.springs.as_ref().map_or(SpringMaterial::Hookean, |f| f.params.material);
        let ground = scene.ground;
        let tets = scene.tets.as_ref().map(|f| &f.params);
        let membranes = scene.membranes.as_ref().map(|f| &f.params);
        let mut counts = [0u32; 4];
        crate::for_each_family!(scene, |i, f| counts[i] = f.len() as u32);
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
            sor: s.sor,
            in_loop_contacts: s.contacts_in_finish() as u32,
            tet_model: tets.map_or(0, |p| Model::ALL.iter().position(|&m| m == p.elastic.model).unwrap_or(0) as u32),
            tet_scale: tets.map_or(1.0, |p| p.scale as f32),
            membrane_scale: membranes.map_or(1.0, |p| p.scale as f32),
            pull_particle: s.pull.map_or(u32::MAX, |p| p.particle),
            elastic: tets.map_or([0.0; 16], |p| elastic_constants(&p.elastic)),
            membrane: membranes.map_or([0.0; 4], |p| p.c.map(|v| v as f32)),
            counts,
            pull: s.pull.map_or([0.0; 4], |p| [p.target[0], p.target[1], p.target[2], p.stiffness]),
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
