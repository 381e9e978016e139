//! WGSL sources, composed from `shaders/common/` and one stage file each, embedded at build time.

/// Springs: Gauss-Seidel, Jacobi and λ reset kernels.
pub const SPRINGS: &str = concat!(
    include_str!("../../shaders/common/types.wgsl"),
    include_str!("../../shaders/common/family.wgsl"),
    include_str!("../../shaders/solver/springs.wgsl")
);
/// Dihedral bending kernels.
pub const BENDING: &str = concat!(
    include_str!("../../shaders/common/types.wgsl"),
    include_str!("../../shaders/common/family.wgsl"),
    include_str!("../../shaders/solver/bending.wgsl")
);
/// Per-particle kernels: predict, contacts, finish, Jacobi apply.
pub const PARTICLES: &str =
    concat!(include_str!("../../shaders/common/types.wgsl"), include_str!("../../shaders/solver/particles.wgsl"));
/// Vertex normals for drawing.
pub const NORMALS: &str = include_str!("../../shaders/render/normals.wgsl");
/// Lit two-sided surfaces.
pub const MESH: &str =
    concat!(include_str!("../../shaders/render/common.wgsl"), include_str!("../../shaders/render/mesh.wgsl"));
/// The ground plane.
pub const GROUND: &str =
    concat!(include_str!("../../shaders/render/common.wgsl"), include_str!("../../shaders/render/ground.wgsl"));

/// Every composed module with its name, for validation.
pub const ALL: [(&str, &str); 6] = [
    ("springs", SPRINGS),
    ("bending", BENDING),
    ("particles", PARTICLES),
    ("normals", NORMALS),
    ("mesh", MESH),
    ("ground", GROUND),
];
