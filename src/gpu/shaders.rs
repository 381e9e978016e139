//! WGSL sources, composed from `shaders/common/` and one stage file each, embedded at build time.

/// Springs: the shared element kernels with two particles.
pub const SPRINGS: &str = concat!(
    include_str!("../../shaders/common/types.wgsl"),
    include_str!("../../shaders/common/family.wgsl"),
    include_str!("../../shaders/solver/springs.wgsl"),
    include_str!("../../shaders/common/element.wgsl")
);
/// Dihedral bending kernels.
pub const BENDING: &str = concat!(
    include_str!("../../shaders/common/types.wgsl"),
    include_str!("../../shaders/common/family.wgsl"),
    include_str!("../../shaders/solver/bending.wgsl"),
    include_str!("../../shaders/common/element.wgsl")
);
/// Tetrahedra with the 3D elastic models: the shared element kernels over signed SVD and the
/// models' energy and stress.
pub const TETS: &str = concat!(
    include_str!("../../shaders/common/types.wgsl"),
    include_str!("../../shaders/common/family.wgsl"),
    include_str!("../../shaders/material/svd.wgsl"),
    include_str!("../../shaders/material/hyperdual.wgsl"),
    include_str!("../../shaders/material/models.wgsl"),
    include_str!("../../shaders/solver/tets.wgsl"),
    include_str!("../../shaders/common/element.wgsl")
);
/// Anisotropic membrane triangles (orthotropic StVK).
pub const MEMBRANES: &str = concat!(
    include_str!("../../shaders/common/types.wgsl"),
    include_str!("../../shaders/common/family.wgsl"),
    include_str!("../../shaders/solver/membranes.wgsl"),
    include_str!("../../shaders/common/element.wgsl")
);
/// Per-particle kernels: predict, contacts, finish, Jacobi apply, the energy reduction and the
/// energy-momentum projection.
pub const PARTICLES: &str = concat!(
    include_str!("../../shaders/common/types.wgsl"),
    include_str!("../../shaders/solver/particles.wgsl"),
    include_str!("../../shaders/solver/projection.wgsl")
);
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

/// Every composed module with its name, for validation.
pub const ALL: [(&str, &str); 12] = [
    ("springs", SPRINGS),
    ("bending", BENDING),
    ("tets", TETS),
    ("membranes", MEMBRANES),
    ("particles", PARTICLES),
    ("normals", NORMALS),
    ("embed", EMBED),
    ("mesh", MESH),
    ("ground", GROUND),
    ("mesh_colored", MESH_COLORED),
    ("lines", LINES),
    ("strain", STRAIN),
];
