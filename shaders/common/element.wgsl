// Kernels shared by every constraint family, of ARITY particles (springs, bending, tetrahedra,
// triangles).
// Keep in sync with src/solver/cpu.rs and src/solver/xpbd.rs. The family's index FAMILY (its
// line in src/scene/mod.rs's family_list) is written ahead of the module; its own file defines:
//   const ARITY: u32;             particles per element
//   alias Element = ...;          its element record, whose first field p: array<u32, ARITY>
//                                 holds the element's particles
//   fn element_project(j: u32, p: array<vec3<f32>, ARITY>) -> Proj   (C, ∇C, α in the current form)
//   fn element_energy(j: u32, p: array<vec3<f32>, ARITY>) -> f32     (material energy, J)
//   fn element_plain(j: u32, e: Gathered) -> bool   (the lean compliant update in place, or false)

struct Proj {
    c: f32,
    alpha: f32,
    g: array<vec3<f32>, ARITY>,
}

// Bit test for NaN and infinity (WGSL has no isFinite).
fn is_finite(a: f32) -> bool {
    return (bitcast<u32>(a) & 0x7f800000u) != 0x7f800000u;
}

// The constraint of an energy-based element with energy e (J) and energy gradient g, in the
// current form (mirrors constraints::energy_root): the energy form projects C = E with the fixed
// compliance; the compliant form uses C = √(2E/s), α = 1/s, ∇C = ∇E/(s C) for the stiffness scale
// s, and skips the element (C = 0, ∇C = 0) where C vanishes or is not finite.
fn energy_projection(e: f32, g: array<vec3<f32>, ARITY>, s: f32) -> Proj {
    var out: Proj;
    out.g = g;
    if (params.form == FORM_ENERGY) {
        out.c = e;
        out.alpha = params.energy_compliance;
        return out;
    }
    let c = sqrt(2.0 * max(e, 0.0) / s);
    out.alpha = 1.0 / s;
    let live = c > 1e-12 && is_finite(c);
    out.c = select(0.0, c, live);
    let k = 1.0 / (s * c);
    for (var i = 0u; i < ARITY; i++) {
        out.g[i] = select(vec3<f32>(0.0), out.g[i] * k, live);
    }
    return out;
}

@group(1) @binding(0) var<storage, read> elements: array<Element>;

fn element_particles(j: u32) -> array<u32, ARITY> {
    return elements[j].p;
}

// An element's particles and their live state (xyz position, w inverse mass).
struct Gathered {
    idx: array<u32, ARITY>,
    p: array<vec4<f32>, ARITY>,
}

fn gather_live(j: u32) -> Gathered {
    var e: Gathered;
    e.idx = element_particles(j);
    for (var k = 0u; k < ARITY; k++) {
        e.p[k] = x[e.idx[k]];
    }
    return e;
}

fn positions_of(e: Gathered) -> array<vec3<f32>, ARITY> {
    var out: array<vec3<f32>, ARITY>;
    for (var k = 0u; k < ARITY; k++) {
        out[k] = e.p[k].xyz;
    }
    return out;
}

fn previous_positions(idx: array<u32, ARITY>) -> array<vec3<f32>, ARITY> {
    var out: array<vec3<f32>, ARITY>;
    for (var k = 0u; k < ARITY; k++) {
        out[k] = x_prev[idx[k]].xyz;
    }
    return out;
}

// The local mode's C̃ for element j (mirrors solver::cpu::local_adjusted).
fn element_local(j: u32, e: Gathered, pr: Proj) -> f32 {
    var kinetic = 0.0;
    for (var k = 0u; k < ARITY; k++) {
        kinetic += local_kinetic(e.idx[k], e.p[k]);
    }
    let r = 0.5 * kinetic * params.inv_h2 + (projected_energy(pr.c, pr.alpha) - energy_start[j]);
    return local_constraint(pr.c, pr.alpha, r);
}

// vec2(Δλ, applied) for element j with projection pr (mirrors solver::xpbd::solve_element).
fn element_update(j: u32, e: Gathered, pr: Proj) -> vec2<f32> {
    let alpha_tilde = pr.alpha * params.inv_h2;
    var sum = 0.0;
    for (var k = 0u; k < ARITY; k++) {
        sum += e.p[k].w * dot(pr.g[k], pr.g[k]);
    }
    var gamma = 0.0;
    var gdx = 0.0;
    if (params.beta > 0.0) {
        gamma = pr.alpha * params.beta * params.inv_h;
        for (var k = 0u; k < ARITY; k++) {
            gdx += dot(pr.g[k], e.p[k].xyz - x_prev[e.idx[k]].xyz);
        }
    }
    return delta_lambda(pr.c, sum, alpha_tilde, lambda[j], gamma, gdx);
}

fn element_gs_apply(j: u32, e: Gathered, pr: Proj, r: vec2<f32>) {
    if (r.y > 0.0) {
        let d = r.x;
        lambda[j] = lambda[j] + d;
        for (var k = 0u; k < ARITY; k++) {
            let p = e.p[k];
            x[e.idx[k]] = vec4<f32>(p.xyz + pr.g[k] * (p.w * d), p.w);
        }
    }
}

fn element_jacobi_store(j: u32, e: Gathered, pr: Proj, r: vec2<f32>) {
    let d = r.x * jacobi_scale[j] * r.y;
    lambda[j] = lambda[j] + d;
    let slot = range.slot_base + ARITY * j;
    for (var k = 0u; k < ARITY; k++) {
        corr[slot + k] = vec4<f32>(pr.g[k] * (e.p[k].w * d), 0.0);
    }
}

// Gauss-Seidel over the dispatch range's elements first, first + step, ...: a thread's share
// of a color group (independent elements), or with (0, 1) a run of one-element color groups in
// their order (each element sees the one before it, as separate dispatches would).
fn sweep_gauss_seidel(first: u32, step: u32) {
    let plain = plain_form();
    for (var t = first; t < range.count; t += step) {
        let j = range.start + t;
        let e = gather_live(j);
        if (plain && element_plain(j, e)) {
            continue;
        }
        let pr = element_project(j, positions_of(e));
        element_gs_apply(j, e, pr, element_update(j, e, pr));
    }
}

// sweep_gauss_seidel in the local energy-aware mode.
fn sweep_gauss_seidel_local(first: u32, step: u32) {
    for (var t = first; t < range.count; t += step) {
        let j = range.start + t;
        let e = gather_live(j);
        var pr = element_project(j, positions_of(e));
        pr.c = element_local(j, e, pr);
        element_gs_apply(j, e, pr, element_update(j, e, pr));
    }
}

@compute @workgroup_size(64)
fn gauss_seidel(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    sweep_gauss_seidel(gid.x, stride(ng));
}

@compute @workgroup_size(64)
fn gauss_seidel_local(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    sweep_gauss_seidel_local(gid.x, stride(ng));
}

// A run of one-element color groups in one dispatch of one invocation (centroid meshes, where
// every tetrahedron shares the centre, have one group per element).
@compute @workgroup_size(1)
fn gauss_seidel_run() {
    sweep_gauss_seidel(0u, 1u);
}

@compute @workgroup_size(1)
fn gauss_seidel_local_run() {
    sweep_gauss_seidel_local(0u, 1u);
}

@compute @workgroup_size(64)
fn jacobi(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let e = gather_live(j);
        let pr = element_project(j, positions_of(e));
        element_jacobi_store(j, e, pr, element_update(j, e, pr));
    }
}

@compute @workgroup_size(64)
fn jacobi_local(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let e = gather_live(j);
        var pr = element_project(j, positions_of(e));
        pr.c = element_local(j, e, pr);
        element_jacobi_store(j, e, pr, element_update(j, e, pr));
    }
}

@compute @workgroup_size(64)
fn clear(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        lambda[range.start + t] = 0.0;
    }
}

// Local mode: each element's projected energy at the start of the substep.
@compute @workgroup_size(64)
fn local_begin(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let pr = element_project(j, previous_positions(element_particles(j)));
        energy_start[j] = projected_energy(pr.c, pr.alpha);
    }
}

// Partial sums of the family's material energy (z) and of the part its multipliers hold (w).
@compute @workgroup_size(64)
fn energy(r: Reducer) {
    var acc = vec2<f32>(0.0);
    for (var t = r.gid.x; t < range.count; t += stride(r.ng)) {
        let j = range.start + t;
        let p = positions_of(gather_live(j));
        let e = element_energy(j, p);
        let pr = element_project(j, p);
        acc += vec2<f32>(e, e * held_share(pr.c, pr.alpha, lambda[j]));
    }
    store_partial(r, PARTIAL_FAMILIES + FAMILY * REDUCE_GROUPS, vec4<f32>(0.0, 0.0, acc.x, acc.y));
}
