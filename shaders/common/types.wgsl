// Shared solver types. Keep in sync with src/gpu/layout.rs (SimParams, DispatchRange, GpuSphere)
// and with src/constraints (Spring, Bend).

struct SimParams {
    // xyz: gravity (m/s²); w: unused.
    gravity: vec4<f32>,
    // xyz: the rest centre of mass (m), the reference of gravitational energy in the balance.
    rest_com: vec4<f32>,
    // Substep h (s), 1/h, 1/h², constraint damping β (s).
    h: f32,
    inv_h: f32,
    inv_h2: f32,
    beta: f32,
    // Compliance of the energy form; form: 0 compliant, 1 energy; spring material: 0 Hookean,
    // 1 StVK; keep = max(1 − β_v h, 0), the velocity damping factor.
    energy_compliance: f32,
    form: u32,
    material: u32,
    keep: f32,
    // Ground plane y (m), its friction μ, 1 if there is a ground, number of spheres.
    ground_height: f32,
    ground_friction: f32,
    has_ground: u32,
    num_spheres: u32,
    // Distance kept from colliders (m), number of particles, over-relaxation ω applied to every
    // Δλ, 1 when the finish pass makes the last iteration's contact pass first.
    contact_offset: f32,
    num_particles: u32,
    sor: f32,
    in_loop_contacts: u32,
    // The tetrahedra's model (MODEL_* in shaders/material/models.wgsl) and the compliant form's
    // stiffness scales s of the tetrahedra (Pa) and of the membranes (N/m).
    tet_model: u32,
    tet_scale: f32,
    membrane_scale: f32,
    // The soft grab's particle (0xffffffff when none; src/solver/pull.rs).
    pull_particle: u32,
    // Constants of the 3D model (Pa), precomputed in f64 as in src/material/models.rs: μ, 2μ,
    // μ/2, λ, λ/2, Mooney-Rivlin μ₀₁/2, μ₁₀, ν₁, κ/2, Arruda-Boyce αᵢ, the inversion
    // continuation's curvature κ_inv.
    mu: f32,
    two_mu: f32,
    half_mu: f32,
    lambda: f32,
    half_lambda: f32,
    half_mu01: f32,
    mu10: f32,
    nu1: f32,
    half_kappa: f32,
    ab0: f32,
    ab1: f32,
    ab2: f32,
    ab3: f32,
    ab4: f32,
    inversion_stiffness: f32,
    pad1: f32,
    // The membranes' C_orth = [[c_uu, c_uv, 0], [c_uv, c_vv, 0], [0, 0, c_ss]] (N/m).
    c_uu: f32,
    c_uv: f32,
    c_vv: f32,
    c_ss: f32,
    // Elements of each constraint family, by its index FAMILY (0 where the scene lacks it).
    counts: vec4<u32>,
    // The soft grab's target (m) in xyz and its spring stiffness k (N/m) in w.
    pull: vec4<f32>,
}

// The energy ledger (one per scene), written by the reduction's final kernel.
struct Ledger {
    // Energy at the start of the next substep (J), whether it is set, the last velocity scale σ,
    // and the cumulative dissipated work at the last balance (J).
    h0: f32,
    valid: u32,
    sigma: f32,
    work_mark: f32,
    // The last measurement: kinetic, gravitational (about the rest centre of mass), elastic
    // (the iterate's material energy), and cumulative dissipated work (J).
    kinetic: f32,
    gravitational: f32,
    elastic: f32,
    work: f32,
    // The part of the elastic energy the multipliers hold (J; metrics::ElasticAccount::held).
    held: f32,
    pad0: f32,
    pad1: f32,
    pad2: f32,
}

// The energy-momentum projection's state (mirrors solver::projection and solver::cpu::project).
struct Projection {
    // The free particles' rigid motion now: centre of mass c (xyz, m; w: total mass M, kg, 0 when
    // a particle is pinned and no rigid motion is kept), velocity V (xyz, m/s), angular velocity
    // ω (xyz, rad/s).
    centre: vec4<f32>,
    velocity: vec4<f32>,
    omega: vec4<f32>,
    // The rigid motion the projection gives (xyz; target_velocity.w: its kinetic energy, J).
    target_velocity: vec4<f32>,
    target_omega: vec4<f32>,
    // The momenta an isolated body keeps, P (kg·m/s) and L about the origin (kg·m²/s);
    // momenta_p.w: 1 when they are kept.
    momenta_p: vec4<f32>,
    momenta_l: vec4<f32>,
    // The budget H* (J), the cumulative dissipated work when it was last carried (J), the last
    // scale s, and 1 once the budget is set.
    budget: f32,
    work_mark: f32,
    scale: f32,
    has_budget: u32,
}

// Slots of the reduction's per-workgroup partial sums (particles: x kinetic, y gravitational,
// w work; families: z material energy, w held energy): the particles', then each family's
// (PARTIAL_FAMILIES + FAMILY REDUCE_GROUPS + workgroup), at most REDUCE_GROUPS workgroups each;
// then the projection's five moment sums per workgroup (PARTIAL_MOMENTS + q REDUCE_GROUPS +
// workgroup). FAMILY_COUNT (and FAMILY in a family's module) come from src/scene/mod.rs's
// family_list, written ahead of the module by src/gpu/shaders.rs. Keep PARTIAL_SLOTS in sync
// with src/gpu/kernels.rs.
const REDUCE_GROUPS: u32 = 256u;
const PARTIAL_PARTICLES: u32 = 0u;
const PARTIAL_FAMILIES: u32 = REDUCE_GROUPS;
const PARTIAL_MOMENTS: u32 = PARTIAL_FAMILIES + FAMILY_COUNT * REDUCE_GROUPS;
const PARTIAL_SLOTS: u32 = PARTIAL_MOMENTS + 5u * REDUCE_GROUPS;

// One dispatch's slice of a family (a color group, or all of it for Jacobi), bound with a
// dynamic offset. slot_base: first Jacobi correction slot of the family.
struct DispatchRange {
    start: u32,
    count: u32,
    slot_base: u32,
    pad: u32,
}

struct Sphere {
    // xyz: centre (m); w: radius (m).
    center_radius: vec4<f32>,
    // x: friction μ.
    friction: vec4<f32>,
}

const FORM_ENERGY: u32 = 1u;
const MATERIAL_STVK: u32 = 1u;
// Lengths below this are treated as zero (no direction), as on the CPU.
const TINY: f32 = 1e-12;
// Denominators below this skip the update, as on the CPU.
const EPSILON: f32 = 1e-20;

// Particle state: xyz position (m), w inverse mass (1/kg, 0 = pinned).
@group(0) @binding(0) var<storage, read_write> x: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> x_prev: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> v: array<vec4<f32>>;
@group(0) @binding(3) var<uniform> params: SimParams;
@group(0) @binding(4) var<storage, read> spheres: array<Sphere>;

@group(2) @binding(0) var<uniform> range: DispatchRange;

// XPBD update (Macklin et al. 2016, eq. 26); mirrors solver::delta_lambda. Returns
// vec2(Δλ, 1) or vec2(0, 0) when the update is skipped.
fn delta_lambda(c: f32, sum_w_grad2: f32, alpha_tilde: f32, lambda: f32, gamma: f32, grad_dot_dx: f32) -> vec2<f32> {
    let denom = (1.0 + gamma) * sum_w_grad2 + alpha_tilde;
    if (!(denom > EPSILON)) {
        return vec2<f32>(0.0, 0.0);
    }
    return vec2<f32>(((-c - alpha_tilde * lambda - gamma * grad_dot_dx) / denom) * params.sor, 1.0);
}

// The compliant form without constraint damping: where the CPU's plain sweep takes the families'
// lean kernels (mirrors solver::cpu::gauss_seidel).
fn plain_form() -> bool {
    return params.form != FORM_ENERGY && params.beta == 0.0;
}

// The material energy of a constraint from its projection (mirrors solver::cpu): C in the
// energy form, C²/(2α) in the compliant form.
fn projected_energy(c: f32, alpha: f32) -> f32 {
    if (params.form == FORM_ENERGY) {
        return c;
    }
    return c * c / (alpha + alpha);
}

// The local energy-aware mode's C̃ (mirrors solver::energy::local_constraint).
fn local_constraint(c: f32, alpha: f32, r: f32) -> f32 {
    if (params.form == FORM_ENERGY) {
        if (abs(r) <= abs(c)) {
            return c + r;
        }
        return c;
    }
    let two_alpha = alpha + alpha;
    let c2 = c * c;
    if (two_alpha > 0.0 && abs(r) * two_alpha <= c2) {
        let m = sqrt(max(c2 + two_alpha * r, 0.0));
        if (c < 0.0) {
            return -m;
        }
        return m;
    }
    return c;
}

// Workgroup tree reduction of one vec4 per invocation (64 invocations); returns the sum in
// invocation 0.
var<workgroup> scratch: array<vec4<f32>, 64>;

fn reduce_workgroup(lid: u32, value: vec4<f32>) -> vec4<f32> {
    // A reduction before this one may still be reading scratch[0].
    workgroupBarrier();
    scratch[lid] = value;
    workgroupBarrier();
    for (var s = 32u; s > 0u; s = s >> 1u) {
        if (lid < s) {
            scratch[lid] = scratch[lid] + scratch[lid + s];
        }
        workgroupBarrier();
    }
    return scratch[0];
}

// The builtins of a grid-stride kernel that reduces into the partial sums: the invocation's
// global and local index, its workgroup and the number of workgroups.
struct Reducer {
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) ng: vec3<u32>,
}

// Sums `value` over the workgroup and stores it in partials[base + workgroup] (the module binds
// `partials`).
fn store_partial(r: Reducer, base: u32, value: vec4<f32>) {
    let total = reduce_workgroup(r.lid.x, value);
    if (r.lid.x == 0u) {
        partials[base + r.wid.x] = total;
    }
}

// The stride of a grid-stride loop over `range.count` items.
fn stride(num_groups: vec3<u32>) -> u32 {
    return num_groups.x * 64u;
}
