// Dihedral bending (mirrors src/constraints/bending.rs): E = ½ k_b (θ − θ₀)², θ the signed angle
// between the triangles (x₀, x₁, x₂) and (x₁, x₀, x₃).

struct Bend {
    p0: u32,
    p1: u32,
    p2: u32,
    p3: u32,
    rest_angle: f32,
    k: f32,
}

@group(1) @binding(0) var<storage, read> bends: array<Bend>;

const PI: f32 = 3.141592653589793;

struct Dihedral {
    theta: f32,
    g0: vec3<f32>,
    g1: vec3<f32>,
    g2: vec3<f32>,
    g3: vec3<f32>,
}

fn signed_angle(n1: vec3<f32>, n2: vec3<f32>, e_hat: vec3<f32>) -> f32 {
    return atan2(dot(cross(n1, n2), e_hat), dot(n1, n2));
}

fn dihedral(x0: vec3<f32>, x1: vec3<f32>, x2: vec3<f32>, x3: vec3<f32>) -> Dihedral {
    let e = x1 - x0;
    let n1 = cross(e, x2 - x0);
    let n2 = cross(x3 - x0, e);
    let e2 = dot(e, e);
    let n1s = dot(n1, n1);
    let n2s = dot(n2, n2);
    let el = sqrt(e2);
    var out: Dihedral;
    out.g0 = vec3<f32>(0.0);
    out.g1 = vec3<f32>(0.0);
    out.g2 = vec3<f32>(0.0);
    out.g3 = vec3<f32>(0.0);
    if (e2 <= TINY || n1s <= TINY * e2 || n2s <= TINY * e2) {
        if (e2 <= TINY) {
            out.theta = 0.0;
        } else {
            out.theta = signed_angle(n1, n2, e * (1.0 / el));
        }
        return out;
    }
    out.theta = signed_angle(n1, n2, e * (1.0 / el));
    out.g2 = n1 * (-el / n1s);
    out.g3 = n2 * (-el / n2s);
    let t2 = dot(x2 - x0, e) / e2;
    let t3 = dot(x3 - x0, e) / e2;
    out.g0 = -(out.g2 * (1.0 - t2)) - out.g3 * (1.0 - t3);
    out.g1 = -(out.g2 * t2) - out.g3 * t3;
    return out;
}

fn wrapped(theta: f32, rest: f32) -> f32 {
    let two_pi = PI + PI;
    var d = theta - rest;
    if (d > PI) {
        d -= two_pi;
    } else if (d <= -PI) {
        d += two_pi;
    }
    return d;
}

struct BendProj {
    c: f32,
    alpha: f32,
    // Gradients of C (scaled by k_b(θ − θ₀) in the energy form).
    dh: Dihedral,
}

// The bend's constraint in the current form (mirrors Element::constraint for Bend).
fn bend_constraint(b: Bend, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, p3: vec3<f32>) -> BendProj {
    var out: BendProj;
    out.dh = dihedral(p0, p1, p2, p3);
    let dtheta = wrapped(out.dh.theta, b.rest_angle);
    if (params.form == FORM_ENERGY) {
        out.c = 0.5 * b.k * dtheta * dtheta;
        let s = b.k * dtheta;
        out.dh.g0 = out.dh.g0 * s;
        out.dh.g1 = out.dh.g1 * s;
        out.dh.g2 = out.dh.g2 * s;
        out.dh.g3 = out.dh.g3 * s;
        out.alpha = params.energy_compliance;
    } else {
        out.c = dtheta;
        out.alpha = 1.0 / b.k;
    }
    return out;
}

fn bend_energy(b: Bend, p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, p3: vec3<f32>) -> f32 {
    let d = wrapped(dihedral(p0, p1, p2, p3).theta, b.rest_angle);
    return 0.5 * b.k * d * d;
}

// The local mode's C̃ for bend j (mirrors solver::cpu::local_adjusted).
fn bend_local(j: u32, b: Bend, p0: vec4<f32>, p1: vec4<f32>, p2: vec4<f32>, p3: vec4<f32>, pr: BendProj) -> f32 {
    var kinetic = 0.0;
    kinetic += local_kinetic(b.p0, p0);
    kinetic += local_kinetic(b.p1, p1);
    kinetic += local_kinetic(b.p2, p2);
    kinetic += local_kinetic(b.p3, p3);
    let r = 0.5 * kinetic * params.inv_h2 + (projected_energy(pr.c, pr.alpha) - energy_start[j]);
    return local_constraint(pr.c, pr.alpha, r);
}

// vec2(Δλ, applied) for bend j with projection pr.
fn bend_update(j: u32, b: Bend, p0: vec4<f32>, p1: vec4<f32>, p2: vec4<f32>, p3: vec4<f32>, pr: BendProj) -> vec2<f32> {
    let dd = pr.dh;
    let alpha_tilde = pr.alpha * params.inv_h2;
    let sum = p0.w * dot(dd.g0, dd.g0) + p1.w * dot(dd.g1, dd.g1) + p2.w * dot(dd.g2, dd.g2) + p3.w * dot(dd.g3, dd.g3);
    var gamma = 0.0;
    var gdx = 0.0;
    if (params.beta > 0.0) {
        gamma = pr.alpha * params.beta * params.inv_h;
        gdx = dot(dd.g0, p0.xyz - x_prev[b.p0].xyz) + dot(dd.g1, p1.xyz - x_prev[b.p1].xyz)
            + dot(dd.g2, p2.xyz - x_prev[b.p2].xyz) + dot(dd.g3, p3.xyz - x_prev[b.p3].xyz);
    }
    return delta_lambda(pr.c, sum, alpha_tilde, lambda[j], gamma, gdx);
}

fn bend_gs_apply(j: u32, b: Bend, p0: vec4<f32>, p1: vec4<f32>, p2: vec4<f32>, p3: vec4<f32>, pr: BendProj, r: vec2<f32>) {
    if (r.y > 0.0) {
        let d = r.x;
        lambda[j] = lambda[j] + d;
        x[b.p0] = vec4<f32>(p0.xyz + pr.dh.g0 * (p0.w * d), p0.w);
        x[b.p1] = vec4<f32>(p1.xyz + pr.dh.g1 * (p1.w * d), p1.w);
        x[b.p2] = vec4<f32>(p2.xyz + pr.dh.g2 * (p2.w * d), p2.w);
        x[b.p3] = vec4<f32>(p3.xyz + pr.dh.g3 * (p3.w * d), p3.w);
    }
}

fn bend_jacobi_store(j: u32, p0: vec4<f32>, p1: vec4<f32>, p2: vec4<f32>, p3: vec4<f32>, pr: BendProj, r: vec2<f32>) {
    let d = r.x * jacobi_scale[j] * r.y;
    lambda[j] = lambda[j] + d;
    let slot = range.slot_base + 4u * j;
    corr[slot] = vec4<f32>(pr.dh.g0 * (p0.w * d), 0.0);
    corr[slot + 1u] = vec4<f32>(pr.dh.g1 * (p1.w * d), 0.0);
    corr[slot + 2u] = vec4<f32>(pr.dh.g2 * (p2.w * d), 0.0);
    corr[slot + 3u] = vec4<f32>(pr.dh.g3 * (p3.w * d), 0.0);
}

@compute @workgroup_size(64)
fn bending_gauss_seidel(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let b = bends[j];
        let p0 = x[b.p0];
        let p1 = x[b.p1];
        let p2 = x[b.p2];
        let p3 = x[b.p3];
        let pr = bend_constraint(b, p0.xyz, p1.xyz, p2.xyz, p3.xyz);
        bend_gs_apply(j, b, p0, p1, p2, p3, pr, bend_update(j, b, p0, p1, p2, p3, pr));
    }
}

@compute @workgroup_size(64)
fn bending_gauss_seidel_local(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let b = bends[j];
        let p0 = x[b.p0];
        let p1 = x[b.p1];
        let p2 = x[b.p2];
        let p3 = x[b.p3];
        var pr = bend_constraint(b, p0.xyz, p1.xyz, p2.xyz, p3.xyz);
        pr.c = bend_local(j, b, p0, p1, p2, p3, pr);
        bend_gs_apply(j, b, p0, p1, p2, p3, pr, bend_update(j, b, p0, p1, p2, p3, pr));
    }
}

@compute @workgroup_size(64)
fn bending_jacobi(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let b = bends[j];
        let p0 = x[b.p0];
        let p1 = x[b.p1];
        let p2 = x[b.p2];
        let p3 = x[b.p3];
        let pr = bend_constraint(b, p0.xyz, p1.xyz, p2.xyz, p3.xyz);
        bend_jacobi_store(j, p0, p1, p2, p3, pr, bend_update(j, b, p0, p1, p2, p3, pr));
    }
}

@compute @workgroup_size(64)
fn bending_jacobi_local(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let b = bends[j];
        let p0 = x[b.p0];
        let p1 = x[b.p1];
        let p2 = x[b.p2];
        let p3 = x[b.p3];
        var pr = bend_constraint(b, p0.xyz, p1.xyz, p2.xyz, p3.xyz);
        pr.c = bend_local(j, b, p0, p1, p2, p3, pr);
        bend_jacobi_store(j, p0, p1, p2, p3, pr, bend_update(j, b, p0, p1, p2, p3, pr));
    }
}

@compute @workgroup_size(64)
fn bending_clear(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        lambda[range.start + t] = 0.0;
    }
}

@compute @workgroup_size(64)
fn bending_local_begin(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let b = bends[j];
        let pr = bend_constraint(b, x_prev[b.p0].xyz, x_prev[b.p1].xyz, x_prev[b.p2].xyz, x_prev[b.p3].xyz);
        energy_start[j] = projected_energy(pr.c, pr.alpha);
    }
}

@compute @workgroup_size(64)
fn bending_energy(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) ng: vec3<u32>,
) {
    var acc = 0.0;
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let b = bends[range.start + t];
        acc += bend_energy(b, x[b.p0].xyz, x[b.p1].xyz, x[b.p2].xyz, x[b.p3].xyz);
    }
    let total = reduce_workgroup(lid.x, vec4<f32>(0.0, 0.0, acc, 0.0));
    if (lid.x == 0u) {
        partials[PARTIAL_BENDS + wid.x] = total;
    }
}
