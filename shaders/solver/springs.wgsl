// Springs (mirrors src/constraints/spring.rs): Hookean E = ½k(|d| − l₀)², StVK E = ½k(|d|² − l₀²)².

struct Spring {
    a: u32,
    b: u32,
    rest: f32,
    k: f32,
}

@group(1) @binding(0) var<storage, read> springs: array<Spring>;

struct SpringProj {
    c: f32,
    // Gradient with respect to x_b (x_a gets its negative).
    g: vec3<f32>,
    alpha: f32,
}

fn spring_constraint(s: Spring, xa: vec3<f32>, xb: vec3<f32>) -> SpringProj {
    let d = xb - xa;
    let len = sqrt(dot(d, d));
    let l0 = s.rest;
    var out: SpringProj;
    if (params.form == FORM_ENERGY) {
        out.alpha = params.energy_compliance;
        if (params.material == MATERIAL_STVK) {
            let q = len * len - l0 * l0;
            out.c = 0.5 * s.k * (q * q);
            out.g = d * (2.0 * s.k * q);
        } else {
            let q = len - l0;
            out.c = 0.5 * s.k * (q * q);
            if (len <= TINY) {
                out.g = vec3<f32>(0.0);
            } else {
                out.g = d * (s.k * q / len);
            }
        }
    } else {
        out.alpha = 1.0 / s.k;
        if (params.material == MATERIAL_STVK) {
            out.c = len * len - l0 * l0;
            out.g = d * 2.0;
        } else {
            out.c = len - l0;
            if (len <= TINY) {
                out.g = vec3<f32>(0.0);
            } else {
                out.g = d * (1.0 / len);
            }
        }
    }
    return out;
}

// Material energy of a spring (mirrors Spring::energy).
fn spring_energy(s: Spring, xa: vec3<f32>, xb: vec3<f32>) -> f32 {
    let d = xb - xa;
    let len = sqrt(dot(d, d));
    var q = len - s.rest;
    if (params.material == MATERIAL_STVK) {
        q = len * len - s.rest * s.rest;
    }
    return 0.5 * s.k * (q * q);
}

// The local mode's C̃ for spring j (mirrors solver::cpu::local_adjusted).
fn spring_local(j: u32, s: Spring, xa: vec4<f32>, xb: vec4<f32>, p: SpringProj) -> f32 {
    var kinetic = 0.0;
    kinetic += local_kinetic(s.a, xa);
    kinetic += local_kinetic(s.b, xb);
    let r = 0.5 * kinetic * params.inv_h2 + (projected_energy(p.c, p.alpha) - energy_start[j]);
    return local_constraint(p.c, p.alpha, r);
}

// vec4(gradient w.r.t. x_b, Δλ), zero when skipped, for spring j with projection p.
fn spring_update(j: u32, s: Spring, xa: vec4<f32>, xb: vec4<f32>, p: SpringProj) -> vec4<f32> {
    let alpha_tilde = p.alpha * params.inv_h2;
    let g2 = dot(p.g, p.g);
    let sum = xa.w * g2 + xb.w * g2;
    var gamma = 0.0;
    var gdx = 0.0;
    if (params.beta > 0.0) {
        gamma = p.alpha * params.beta * params.inv_h;
        gdx = dot(-p.g, xa.xyz - x_prev[s.a].xyz) + dot(p.g, xb.xyz - x_prev[s.b].xyz);
    }
    let r = delta_lambda(p.c, sum, alpha_tilde, lambda[j], gamma, gdx);
    return vec4<f32>(p.g, r.x) * r.y;
}

// The lean compliant Hookean update (mirrors Spring::project_plain): Σw|∇C|² = w_a + w_b and
// one division on the dependency chain. Returns false, changing nothing, for a zero-length spring
// or a vanishing denominator; the general update then runs.
fn spring_plain(j: u32, s: Spring, xa: vec4<f32>, xb: vec4<f32>) -> bool {
    let d = xb.xyz - xa.xyz;
    let len = sqrt(dot(d, d));
    let alpha_tilde = params.inv_h2 / s.k;
    let denom = xa.w + xb.w + alpha_tilde;
    if (!(len > TINY && denom > EPSILON)) {
        return false;
    }
    let q = (s.rest - len - alpha_tilde * lambda[j]) * params.sor / (denom * len);
    lambda[j] = lambda[j] + q * len;
    x[s.a] = vec4<f32>(xa.xyz - d * (xa.w * q), xa.w);
    x[s.b] = vec4<f32>(xb.xyz + d * (xb.w * q), xb.w);
    return true;
}

fn gs_apply(j: u32, s: Spring, xa: vec4<f32>, xb: vec4<f32>, r: vec4<f32>) {
    let d = r.w;
    lambda[j] = lambda[j] + d;
    x[s.a] = vec4<f32>(xa.xyz + (-r.xyz) * (xa.w * d), xa.w);
    x[s.b] = vec4<f32>(xb.xyz + r.xyz * (xb.w * d), xb.w);
}

fn jacobi_store(j: u32, xa: vec4<f32>, xb: vec4<f32>, r: vec4<f32>) {
    let d = r.w * jacobi_scale[j];
    lambda[j] = lambda[j] + d;
    let slot = range.slot_base + 2u * j;
    corr[slot] = vec4<f32>((-r.xyz) * (xa.w * d), 0.0);
    corr[slot + 1u] = vec4<f32>(r.xyz * (xb.w * d), 0.0);
}

@compute @workgroup_size(64)
fn gauss_seidel(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    let plain = plain_form() && params.material != MATERIAL_STVK;
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let s = springs[j];
        let xa = x[s.a];
        let xb = x[s.b];
        if (plain && spring_plain(j, s, xa, xb)) {
            continue;
        }
        gs_apply(j, s, xa, xb, spring_update(j, s, xa, xb, spring_constraint(s, xa.xyz, xb.xyz)));
    }
}

@compute @workgroup_size(64)
fn gauss_seidel_local(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let s = springs[j];
        let xa = x[s.a];
        let xb = x[s.b];
        var p = spring_constraint(s, xa.xyz, xb.xyz);
        p.c = spring_local(j, s, xa, xb, p);
        gs_apply(j, s, xa, xb, spring_update(j, s, xa, xb, p));
    }
}

@compute @workgroup_size(64)
fn jacobi(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let s = springs[j];
        let xa = x[s.a];
        let xb = x[s.b];
        jacobi_store(j, xa, xb, spring_update(j, s, xa, xb, spring_constraint(s, xa.xyz, xb.xyz)));
    }
}

@compute @workgroup_size(64)
fn jacobi_local(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let s = springs[j];
        let xa = x[s.a];
        let xb = x[s.b];
        var p = spring_constraint(s, xa.xyz, xb.xyz);
        p.c = spring_local(j, s, xa, xb, p);
        jacobi_store(j, xa, xb, spring_update(j, s, xa, xb, p));
    }
}

// λ = 0.
@compute @workgroup_size(64)
fn clear(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        lambda[range.start + t] = 0.0;
    }
}

// Local mode: each spring's energy at the start of the substep.
@compute @workgroup_size(64)
fn local_begin(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let s = springs[j];
        let p = spring_constraint(s, x_prev[s.a].xyz, x_prev[s.b].xyz);
        energy_start[j] = projected_energy(p.c, p.alpha);
    }
}

// Partial sums of the springs' material energy (z) and of the part their multipliers hold (w).
@compute @workgroup_size(64)
fn energy(
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) ng: vec3<u32>,
) {
    var acc = vec2<f32>(0.0);
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let s = springs[j];
        let xa = x[s.a].xyz;
        let xb = x[s.b].xyz;
        let e = spring_energy(s, xa, xb);
        let p = spring_constraint(s, xa, xb);
        acc += vec2<f32>(e, e * held_share(p.c, p.alpha, lambda[j]));
    }
    let total = reduce_workgroup(lid.x, vec4<f32>(0.0, 0.0, acc.x, acc.y));
    if (lid.x == 0u) {
        partials[PARTIAL_SPRINGS + wid.x] = total;
    }
}
