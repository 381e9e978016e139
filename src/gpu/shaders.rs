//! WGSL sources, composed from `shaders/common/` and one stage file each, embedded at build time.

/// A constraint family's module: the shared types and family bindings, the family's own files
/// (paths under `shaders/`), then the shared element kernels.
macro_rules! family_module {
    ($($file:literal),+) => {
        concat!(
            include_str!("../../shaders/common/types.wgsl"),
            include_str!("../../shaders/common/family.wgsl"),
            $(include_str!(concat!("../../shaders/", $file)),)+
            include_str!("../../shaders/common/element.wgsl")
        )
    };
}

/// Springs: the shared element kernels with two particles.
pub const SPRINGS: &str = family_module!("solver/springs.wgsl");
/// Dihedral bending kernels.
pub const BENDING: &str = family_module!("solver/bending.wgsl");
/// Tetrahedra with the 3D elastic models: the shared element kernels over the models' energy
/// and stress (closed forms where the element is regular, the signed SVD elsewhere).
pub const TETS: &str = family_module!(
    "material/svd.wgsl",
    "material/hyperdual.wgsl",
    "material/models.wgsl",
    "material/invariants.wgsl",
    "solver/tets.wgsl"
);
/// Anisotropic membrane triangles (orthotropic StVK).
pub const MEMBRANES: &str = family_module!("solver/membranes.wgsl");
/// Per-particle kernels: predict, contacts, finish, Jacobi apply, the energy reduction and the
/// energy-momentum projection.
pub const PARTICLES: &str = concat!(
    include_str!("../../shaders/common/types.wgsl"),
    include_str!("../../shaders/solver/particles.wgsl"),
    include_str!("../../shaders/solver/projection.wgsl")
);
/// Cloth self-collision: the candidates' check, the spatial hash, the candidates and their
/// Jacobi projection.
pub const SELF_COLLISION: &str =
    concat!(include_str!("../../shaders/common/types.wgsl"), include_str!("../../shaders/solver/self_collision.wgsl"));
/// Vertex normals for drawing.
pub const NORMALS: &str = include_str!("../../shaders/render/normals.wgsl");
/// An embedded surface's vertices from the particles.
pub const EMBED: &str = include_str!("../../shaders/render/embed.wgsl");
/// Lit two-sided surfaces.
pub const MESH: &str =
    concat!(include_str!("../../shaders/render/common.wgsl"), include_str!("../../shaders/render/mesh.wgsl"));
/// The ground plane.
pub const GROUND: &str =
    concat!(include_str!("../../shaders/render/common.wgsl"), include_str!("../../shaders/render/ground.wgsl"));

/// Lit surfaces with a colour per vertex.
pub const MESH_COLORED: &str =
    concat!(include_str!("../../shaders/render/common.wgsl"), include_str!("../../shaders/render/mesh_colored.wgsl"));
/// Line segments between particles (wireframe, color groups).
pub const LINES: &str =
    concat!(include_str!("../../shaders/render/common.wgsl"), include_str!("../../shaders/render/lines.wgsl"));
/// Strain colours per vertex.
pub const STRAIN: &str = include_str!("../../shaders/render/strain.wgsl");

/// What every solver module is compiled with ahead of its source, from
/// [`crate::family_list`]: `FAMILY_COUNT`, the number of constraint families, and in a family's
/// module `FAMILY`, the family's index there.
pub fn solver_head(family: Option<usize>) -> String {
    let count = format!("const FAMILY_COUNT: u32 = {}u;\n", crate::scene::FAMILY_COUNT);
    match family {
        Some(f) => format!("{count}const FAMILY: u32 = {f}u;\n"),
        None => count,
    }
}

/// The per-particle module as compiled ([`PARTICLES`] with its [`solver_head`]).
pub fn particles() -> String {
    solver_head(None) + PARTICLES
}

/// The self-collision module as compiled: [`SELF_COLLISION`] with its [`solver_head`],
/// `CAPACITY`, `KEEP` and `OVER_RELAXATION` ([`crate::solver::self_collision`]'s constants).
pub fn self_collision() -> String {
    use crate::solver::self_collision::{CAPACITY, KEEP, OVER_RELAXATION};
    let constants = format!(
        "const CAPACITY: u32 = {CAPACITY}u;\nconst KEEP: f32 = {KEEP:?};\nconst OVER_RELAXATION: f32 = {OVER_RELAXATION:?};\n"
    );
    solver_head(None) + &constants + SELF_COLLISION
}

/// The drawing modules, which need no head.
pub const RENDER: [(&str, &str); 7] = [
    ("normals", NORMALS),
    ("embed", EMBED),
    ("mesh", MESH),
    ("ground", GROUND),
    ("mesh_colored", MESH_COLORED),
    ("lines", LINES),
    ("strain", STRAIN),
];

/// Every module as compiled, with its name, for validation: each constraint family's, the
/// per-particle one, the self-collision one and the drawing ones.
pub fn all() -> Vec<(&'static str, String)> {
    let mut v: Vec<(&str, String)> = super::FamilyKind::ALL.iter().map(|k| (k.name(), k.source())).collect();
    v.push(("particles", particles()));
    v.push(("self_collision", self_collision()));
    v.extend(RENDER.iter().map(|&(name, src)| (name, src.to_string())));
    v
}
