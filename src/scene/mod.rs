//! Scenes: particles, constraint families, colliders and gravity, built from a name and options.

mod cloth;
mod family;
mod solid;

pub use family::Family;
pub use solid::DENSITY as SOLID_DENSITY;

use glam::Vec3;

use crate::constraints::{Bend, Spring, SpringMaterial, Tet};
use crate::error::{Error, Result};

/// A horizontal ground plane `y = height` with Coulomb friction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// Height of the plane (m).
    pub height: f32,
    /// Friction coefficient μ (dimensionless).
    pub friction: f32,
}

/// A fixed analytic sphere collider with Coulomb friction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre (m).
    pub center: Vec3,
    /// Radius (m).
    pub radius: f32,
    /// Friction coefficient μ (dimensionless).
    pub friction: f32,
}

/// Everything a solver needs to simulate: the initial state, the constraint families it uses
/// (only those), the colliders and gravity. Backends never change a scene; they copy its initial
/// state into their own buffers.
#[derive(Clone, Debug)]
pub struct Scene {
    /// Scene name (as on the command line).
    pub name: String,
    /// Initial positions (m).
    pub positions: Vec<Vec3>,
    /// Inverse masses (1/kg); 0 pins a particle.
    pub inv_mass: Vec<f32>,
    /// Surface triangles, for drawing and export.
    pub triangles: Vec<[u32; 3]>,
    /// Edges whose relative stretch is reported (SPEC §7).
    pub edges: Vec<[u32; 2]>,
    /// Rest length of each of `edges` (m).
    pub edge_rest: Vec<f32>,
    /// Spring family, if the scene has springs.
    pub springs: Option<Family<Spring, 2>>,
    /// Bending family, if the scene has bending.
    pub bends: Option<Family<Bend, 4>>,
    /// Tetrahedra, if the scene has a volumetric body.
    pub tets: Option<Family<Tet, 4>>,
    /// Ground plane, if any.
    pub ground: Option<Ground>,
    /// Sphere colliders.
    pub spheres: Vec<Sphere>,
    /// Gravity (m/s²).
    pub gravity: Vec3,
    /// Distance kept between particles and colliders (m).
    pub contact_offset: f32,
}

/// What a user may choose about a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneOptions {
    /// Particles per side of a cloth; `None` takes the scene's own (41).
    pub resolution: Option<u32>,
    /// Small-strain spring stiffness `k_s` (N/m, SPEC §3).
    pub stiffness: f32,
    /// Spring energy model.
    pub material: SpringMaterial,
    /// Dihedral bending stiffness `k_b` (N·m/rad); `None` takes the scene's own, 0 disables.
    pub bending_stiffness: Option<f32>,
    /// Gravity on (9.81 m/s² downwards) or off.
    pub gravity: bool,
    /// The 3D model of a volumetric scene (`None`: Neo-Hookean); cloth scenes refuse one.
    pub solid: Option<crate::material::Model>,
    /// Young's modulus of a volumetric scene (Pa).
    pub young: f64,
    /// Poisson's ratio of a volumetric scene.
    pub poisson: f64,
}

impl Default for SceneOptions {
    fn default() -> Self {
        SceneOptions {
            resolution: None,
            stiffness: 1.0e4,
            material: SpringMaterial::Hookean,
            bending_stiffness: None,
            gravity: true,
            solid: None,
            young: 2.0e6,
            poisson: 0.3,
        }
    }
}

/// Names of the scenes [`build`] knows.
pub const SCENES: [&str; 6] = ["cloth", "cloth-paper", "cloth-sphere", "cloth-free", "beam", "cube"];

/// Builds the scene called `name`.
pub fn build(name: &str, opts: &SceneOptions) -> Result<Scene> {
    validate(opts)?;
    #[derive(Clone, Copy)]
    enum K {
        Cloth(cloth::Kind),
        Solid(solid::Kind),
    }
    let kind = Error::lookup(
        "scene",
        name,
        &[
            ("cloth", K::Cloth(cloth::Kind::Hanging)),
            ("cloth-paper", K::Cloth(cloth::Kind::Paper)),
            ("cloth-sphere", K::Cloth(cloth::Kind::Sphere)),
            ("cloth-free", K::Cloth(cloth::Kind::Free)),
            ("beam", K::Solid(solid::Kind::Beam)),
            ("cube", K::Solid(solid::Kind::Cube)),
        ],
    )?;
    match kind {
        K::Cloth(k) => {
            if let Some(m) = opts.solid {
                return Err(Error::param(
                    "--material",
                    m.name(),
                    "is a volumetric model for beam and cube; cloth scenes take hookean or stvk-spring",
                ));
            }
            cloth::build(k, opts)
        }
        K::Solid(k) => solid::build(k, opts),
    }
}

fn validate(o: &SceneOptions) -> Result<()> {
    if let Some(n) = o.resolution
        && !(2..=2048).contains(&n)
    {
        return Err(Error::param("--resolution", n, "particles per side must be in 2..=2048"));
    }
    if !(o.stiffness.is_finite() && o.stiffness > 0.0) {
        return Err(Error::param("--stiffness", o.stiffness, "must be a positive finite N/m"));
    }
    if let Some(kb) = o.bending_stiffness
        && !(kb.is_finite() && kb >= 0.0)
    {
        return Err(Error::param("--bending-stiffness", kb, "must be a finite N·m/rad ≥ 0"));
    }
    Ok(())
}

impl Scene {
    /// Number of particles.
    pub fn num_particles(&self) -> usize {
        self.positions.len()
    }

    /// Number of constraints over all families.
    pub fn num_constraints(&self) -> usize {
        self.springs.as_ref().map_or(0, Family::len)
            + self.bends.as_ref().map_or(0, Family::len)
            + self.tets.as_ref().map_or(0, Family::len)
    }

    /// Centre of mass of the free particles at the start (m): heights for gravitational energy
    /// are measured from it.
    pub fn rest_center_of_mass(&self) -> Vec3 {
        let (mut sum, mut mass) = (glam::DVec3::ZERO, 0.0f64);
        for (p, &w) in self.positions.iter().zip(&self.inv_mass) {
            if w > 0.0 {
                sum += p.as_dvec3() / w as f64;
                mass += 1.0 / w as f64;
            }
        }
        if mass > 0.0 { (sum / mass).as_vec3() } else { Vec3::ZERO }
    }
}
