//! Scenes: particles, constraint families, colliders and gravity, built from a name and options.

mod bunny;
mod cloth;
mod family;
mod solid;

pub use bunny::{Body, DEFAULT_LATTICE, HEIGHT as BUNNY_HEIGHT, PAPER_FACES, bunny_surface};
pub use family::Family;
pub use solid::DENSITY as SOLID_DENSITY;

/// The constraint families, declared once, in solve order: each family's index, its field of
/// [`Scene`] (an `Option<Family<Element, N>>`), its name in the GPU solver
/// ([`crate::gpu::FamilyKind`]) with that variant's documentation, its name (the WGSL file
/// `shaders/solver/NAME.wgsl` and its buffers' labels), its label for people (what the command
/// line and the viewer print), its particles per element and its
/// composed WGSL module ([`crate::gpu::shaders`]). [`for_each_family`], [`FAMILY_COUNT`] and
/// [`crate::gpu::FamilyKind`] are made from this list; README, "Adding a constraint family".
#[macro_export]
#[doc(hidden)]
macro_rules! family_list {
    ([$($callback:tt)*] $args:tt) => {
        $($callback)*! { $args;
            (0, springs, Springs, "Springs.", "springs", "springs", 2, SPRINGS),
            (1, bends, Bending, "Dihedral bending.", "bending", "bending", 4, BENDING),
            (2, tets, Tets, "Tetrahedra.", "tets", "tetrahedra", 4, TETS),
            (3, membranes, Membranes, "Anisotropic membrane triangles.", "membranes", "membrane triangles", 3, MEMBRANES),
        }
    };
}

/// [`family_list`]'s length.
#[macro_export]
#[doc(hidden)]
macro_rules! family_count {
    ((); $(($i:literal, $($rest:tt)*)),* $(,)?) => {
        [$($i),*].len()
    };
}

/// Number of constraint families a scene may have.
pub const FAMILY_COUNT: usize = family_list!([family_count]());

/// [`family_list`]'s labels.
#[macro_export]
#[doc(hidden)]
macro_rules! family_labels {
    ((); $(($i:literal, $field:ident, $kind:ident, $doc:literal, $name:literal, $label:literal, $($rest:tt)*)),* $(,)?) => {
        [$($label),*]
    };
}

/// Each family's label for people, by index ([`family_list`]): what the command line and the
/// viewer print.
pub const FAMILY_LABELS: [&str; FAMILY_COUNT] = family_list!([family_labels]());

/// Evaluates `$body` once for each constraint family `$scene` has, in solve order (springs,
/// bending, tetrahedra, membranes: [`family_list`]), with `$f` bound to the `&Family` and `$i` to
/// the family's index (`0..FAMILY_COUNT`) in that order.
#[macro_export]
#[doc(hidden)]
macro_rules! for_each_family {
    ($scene:expr, |$i:ident, $f:ident| $body:expr) => {
        $crate::family_list!([$crate::for_each_family_in]($scene, $i, $f, $body))
    };
}

/// [`for_each_family`] over the list.
#[macro_export]
#[doc(hidden)]
macro_rules! for_each_family_in {
    (($scene:expr, $i:ident, $f:ident, $body:expr); $(($index:literal, $field:ident, $($rest:tt)*)),* $(,)?) => {{
        $(
            if let Some($f) = &$scene.$field {
                let $i: usize = $index;
                $body;
            }
        )*
    }};
}

/// Evaluates `$body` for family `$index` of `$scene` (its index in [`for_each_family`]'s order)
/// with `$f` bound to the `&Family`; nothing when the scene has no such family.
#[macro_export]
#[doc(hidden)]
macro_rules! with_family {
    ($scene:expr, $index:expr, |$f:ident| $body:expr) => {{
        let index: usize = $index;
        $crate::for_each_family!($scene, |i, $f| if i == index {
            $body;
        });
    }};
}

use glam::Vec3;

use crate::constraints::{Bend, Membrane, Orthotropic, Spring, SpringMaterial, Tet};
use crate::error::{Error, Result};
use crate::mesh::{Binding, Diagonals, embedded_positions};

/// A horizontal ground plane `y = height` with Coulomb friction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ground {
    /// Height of the plane (m).
    pub height: f32,
    /// Friction coefficient μ (dimensionless).
    pub friction: f32,
}

/// Particle-particle self-collision of a cloth (docs/algorithm.md §3.1): every pair of particles
/// (not both pinned) closer than the thickness is pushed apart to it inside the iteration loop,
/// with Coulomb friction on their relative motion. Pairs whose rest distance is at most the
/// thickness (neighbours in the mesh) are left to the cloth's own constraints.
#[derive(Clone, Debug, PartialEq)]
pub struct SelfCollision {
    /// Distance kept between particles (m).
    pub thickness: f32,
    /// Friction coefficient μ (dimensionless).
    pub friction: f32,
    /// The rest shape the pairs' rest distances come from (m).
    pub rest: Vec<Vec3>,
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
    /// Edges whose relative stretch is reported (docs/algorithm.md §7).
    pub edges: Vec<[u32; 2]>,
    /// Rest length of each of `edges` (m).
    pub edge_rest: Vec<f32>,
    /// Spring family, if the scene has springs.
    pub springs: Option<Family<Spring, 2>>,
    /// Bending family, if the scene has bending.
    pub bends: Option<Family<Bend, 4>>,
    /// Tetrahedra, if the scene has a volumetric body.
    pub tets: Option<Family<Tet, 4>>,
    /// Anisotropic membrane triangles, if the cloth uses the continuum model.
    pub membranes: Option<Family<Membrane, 3>>,
    /// A surface drawn (and exported) instead of `triangles`, moving with the particles.
    pub embedding: Option<Embedding>,
    /// Ground plane, if any.
    pub ground: Option<Ground>,
    /// Sphere colliders.
    pub spheres: Vec<Sphere>,
    /// Gravity (m/s²).
    pub gravity: Vec3,
    /// Distance kept between particles and colliders (m).
    pub contact_offset: f32,
    /// The cloth's self-collision, if on.
    pub self_collision: Option<SelfCollision>,
}

/// A surface embedded in a tetrahedral mesh: each vertex follows a tetrahedron by barycentric
/// weights, so the smooth original surface is drawn while the coarser tetrahedra are simulated.
#[derive(Clone, Debug, PartialEq)]
pub struct Embedding {
    /// One binding per surface vertex.
    pub bindings: Vec<Binding>,
    /// The surface's triangles, indexing its vertices.
    pub triangles: Vec<[u32; 3]>,
}

impl Embedding {
    /// The surface's vertex positions for particle positions `x` (m).
    pub fn positions(&self, x: &[Vec3]) -> Vec<Vec3> {
        embedded_positions(&self.bindings, x)
    }
}

/// What a user may choose about a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneOptions {
    /// Particles per side of a cloth, cells along the beam or along each side of the cube;
    /// `None` takes the scene's own (41, 10, 4).
    pub resolution: Option<u32>,
    /// Small-strain spring stiffness `k_s` (N/m, docs/algorithm.md §3).
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
    /// Poisson's ratio of a volumetric scene, and `ν_uv` of the anisotropic cloth.
    pub poisson: f64,
    /// Cloth scenes: the anisotropic continuum cloth with these moduli instead of springs.
    pub membrane: Option<Orthotropic>,
    /// Volumetric scenes: how the body is split into tetrahedra.
    pub tets: TetMode,
    /// Bunny scenes: how the surface becomes a body (`None`: the scene's own).
    pub body: Option<Body>,
    /// `volume` bodies: lattice cells along the longest side (`None`: [`DEFAULT_LATTICE`]).
    pub lattice: Option<u32>,
    /// Cloth scenes: how the grid's quads are split into triangles.
    pub diagonals: Diagonals,
    /// Cloth scenes: self-collision on or off (`None`: the scene's own, on for
    /// `cloth-drape` and `cloth-sphere`).
    pub self_collision: Option<bool>,
    /// Cloth scenes: the self-collision's thickness (m; `None`: 1.2 × the grid's
    /// spacing).
    pub thickness: Option<f32>,
}

/// How a volumetric scene's body is split into tetrahedra.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TetMode {
    /// A volumetric mesh filling the body.
    #[default]
    Volume,
    /// The paper's "3D meshes": each triangle of the closed surface paired with the centroid.
    Centroid,
}

crate::error::command_names!(TetMode, "tetrahedra", { Volume => "volume", Centroid => "centroid" });

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
            membrane: None,
            tets: TetMode::Volume,
            body: None,
            lattice: None,
            diagonals: Diagonals::Uniform,
            self_collision: None,
            thickness: None,
        }
    }
}

/// Names of the scenes [`build`] knows.
pub const SCENES: [&str; 9] =
    ["cloth", "cloth-paper", "cloth-sphere", "cloth-free", "cloth-drape", "beam", "cube", "bunny", "bunny-paper"];

/// The main demo, `(scene, substeps, iterations)`: what `eapbd` alone and the web page without
/// a scene open. The hanging cloth at 10 substeps × 3 iterations, where the stretch stays near
/// a percent and plain XPBD visibly loses the swing that the energy-aware projection keeps
/// within ten seconds (docs/energy-aware.md).
pub const MAIN_DEMO: (&str, u32, u32) = ("cloth", 10, 3);

/// Constraint iterations a scene is meant to run with: the paper's 15 for `bunny-paper`, 30
/// otherwise.
pub fn default_iterations(name: &str) -> u32 {
    if name == "bunny-paper" { 15 } else { 30 }
}

/// Whether scene `name` with `body` simulates tetrahedra (and so takes a 3D material).
pub fn uses_tets(name: &str, body: Option<Body>) -> bool {
    match name {
        "beam" | "cube" => true,
        "bunny" => body != Some(Body::Springs),
        "bunny-paper" => matches!(body, Some(Body::CentroidTets | Body::Volume)),
        _ => false,
    }
}

/// Whether scene `name`'s cloth collides with itself unless told otherwise (`cloth-drape`, and
/// `cloth-sphere`, whose cloth folds where it meets the ground).
pub fn self_collides_by_default(name: &str) -> bool {
    matches!(name, "cloth-drape" | "cloth-sphere")
}

/// Whether scene `name` is a cloth grid (and so takes [`Diagonals`]).
pub fn is_cloth(name: &str) -> bool {
    matches!(name, "cloth" | "cloth-paper" | "cloth-sphere" | "cloth-free" | "cloth-drape")
}

/// Builds the scene called `name`.
pub fn build(name: &str, opts: &SceneOptions) -> Result<Scene> {
    build_from(name, opts, None)
}

/// Builds a bunny scene (`bunny` or `bunny-paper`) on another closed surface, such as one read
/// with [`crate::mesh::load_obj`] (scaled to the bunny's height; `springs` bodies accept open
/// surfaces).
pub fn build_with_surface(name: &str, opts: &SceneOptions, surface: crate::mesh::TriMesh) -> Result<Scene> {
    if !matches!(name, "bunny" | "bunny-paper") {
        return Err(Error::param("--mesh", name, "replaces the surface of the scenes bunny and bunny-paper only"));
    }
    build_from(name, opts, Some(surface))
}

/// Builds `bunny` or `bunny-paper` from a tetrahedral mesh (such as one read with
/// [`crate::mesh::load_tetgen`]): scaled like a surface, simulated as it is and drawn by its
/// boundary.
pub fn build_with_tets(name: &str, opts: &SceneOptions, tets: crate::mesh::TetMesh) -> Result<Scene> {
    if !matches!(name, "bunny" | "bunny-paper") {
        return Err(Error::param("--mesh", name, "replaces the body of the scenes bunny and bunny-paper only"));
    }
    validate(opts)?;
    let kind = if name == "bunny" { bunny::Kind::Drop } else { bunny::Kind::Paper };
    bunny::build_tets(kind, opts, tets)
}

fn build_from(name: &str, opts: &SceneOptions, surface: Option<crate::mesh::TriMesh>) -> Result<Scene> {
    validate(opts)?;
    #[derive(Clone, Copy)]
    enum K {
        Cloth(cloth::Kind),
        Solid(solid::Kind),
        Bunny(bunny::Kind),
    }
    let kind = Error::lookup(
        "scene",
        name,
        &[
            ("cloth", K::Cloth(cloth::Kind::Hanging)),
            ("cloth-paper", K::Cloth(cloth::Kind::Paper)),
            ("cloth-sphere", K::Cloth(cloth::Kind::Sphere)),
            ("cloth-free", K::Cloth(cloth::Kind::Free)),
            ("cloth-drape", K::Cloth(cloth::Kind::Drape)),
            ("beam", K::Solid(solid::Kind::Beam)),
            ("cube", K::Solid(solid::Kind::Cube)),
            ("bunny", K::Bunny(bunny::Kind::Drop)),
            ("bunny-paper", K::Bunny(bunny::Kind::Paper)),
        ],
    )?;
    if !matches!(kind, K::Bunny(_)) && opts.body.is_some() {
        return Err(Error::param("--body", name, "applies to the scenes bunny and bunny-paper"));
    }
    if !matches!(kind, K::Cloth(_)) && opts.diagonals != Diagonals::Uniform {
        return Err(Error::param(
            "--diagonals",
            "alternating",
            "applies to the cloth scenes (cloth, cloth-paper, cloth-sphere, cloth-free, cloth-drape)",
        ));
    }
    if !matches!(kind, K::Cloth(_)) && (opts.self_collision == Some(true) || opts.thickness.is_some()) {
        return Err(Error::param(
            if opts.thickness.is_some() { "--thickness" } else { "--self-collision" },
            name,
            "self-collision applies to the cloth scenes",
        ));
    }
    if matches!(kind, K::Bunny(_)) && opts.membrane.is_some() {
        return Err(Error::param("--material", "aniso-cloth", "is a cloth model; the bunny takes springs or tets"));
    }
    if matches!(kind, K::Bunny(_)) && !uses_tets(name, opts.body) && opts.solid.is_some() {
        return Err(Error::param(
            "--material",
            opts.solid.map_or("", |m| m.name()),
            "is a 3D model for tetrahedra; the springs body takes hookean or stvk-spring",
        ));
    }
    match kind {
        K::Cloth(_) | K::Bunny(_) if opts.tets != TetMode::Volume => Err(Error::param(
            "--tets",
            "centroid",
            "applies to the volumetric scenes beam and cube (the bunny takes --body centroid-tets)",
        )),
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
        K::Solid(_) if opts.membrane.is_some() => Err(Error::param(
            "--material",
            "aniso-cloth",
            "is a cloth model; beam and cube take linear, stvk, neo-hookean, mooney-rivlin or arruda-boyce",
        )),
        K::Solid(k) => solid::build(k, opts),
        K::Bunny(k) => bunny::build(k, opts, surface),
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
    if let Some(t) = o.thickness
        && !(t.is_finite() && t > 0.0 && t < 1.0)
    {
        return Err(Error::param("--thickness", t, "must be a positive distance below 1 m"));
    }
    Ok(())
}

impl Scene {
    /// Number of particles.
    pub fn num_particles(&self) -> usize {
        self.positions.len()
    }

    /// The surface as drawn and exported at particle positions `x`: the embedded surface where
    /// there is one, else the particles with [`Scene::triangles`].
    pub fn surface(&self, x: &[Vec3]) -> (Vec<Vec3>, &[[u32; 3]]) {
        match &self.embedding {
            Some(e) => (e.positions(x), &e.triangles),
            None => (x.to_vec(), &self.triangles),
        }
    }

    /// Number of constraints over all families.
    pub fn num_constraints(&self) -> usize {
        let mut n = 0;
        crate::for_each_family!(self, |_i, f| n += f.len());
        n
    }

    /// Color groups over all families: the groups one Gauss-Seidel sweep visits in turn.
    pub fn num_color_groups(&self) -> usize {
        let mut n = 0;
        crate::for_each_family!(self, |_i, f| n += f.colors.len());
        n
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
