// Springs (mirrors src/constraints/spring.rs): Hookean E = ½k(|d| − l₀)², StVK E = ½k(|d|² − l₀²)².

struct Spring {
    a: u32,
    b: u32,
    rest: f32,
    k: f32,
}

@group(1) @binding(0) var<storage, read> springs: array<Spring>;
@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;
@group(1) @binding(2) var<storage, read> jacobi_scale: array<f32>;
@group(1) @binding(3) var<storage, read_write> corr: array<vec4<f32>>;

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

// Returns vec2(Δλ, applied) for spring j against the current positions.
fn spring_solve(j: u32, xa: vec4<f32>, xb: vec4<f32>) -> vec4<f32> {
    let s = springs[j];
    let p = spring_constraint(s, xa.xyz, xb.xyz);
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

@compute @workgroup_size(64)
fn springs_gauss_seidel(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let s = springs[j];
        let xa = x[s.a];
        let xb = x[s.b];
        let r = spring_solve(j, xa, xb);
        let d = r.w;
        lambda[j] = lambda[j] + d;
        x[s.a] = vec4<f32>(xa.xyz + (-r.xyz) * (xa.w * d), xa.w);
        x[s.b] = vec4<f32>(xb.xyz + r.xyz * (xb.w * d), xb.w);
    }
}

@compute @workgroup_size(64)
fn springs_jacobi(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        let j = range.start + t;
        let s = springs[j];
        let xa = x[s.a];
        let xb = x[s.b];
        let r = spring_solve(j, xa, xb);
        let d = r.w * jacobi_scale[j];
        lambda[j] = lambda[j] + d;
        let slot = range.slot_base + 2u * j;
        corr[slot] = vec4<f32>((-r.xyz) * (xa.w * d), 0.0);
        corr[slot + 1u] = vec4<f32>(r.xyz * (xb.w * d), 0.0);
    }
}

@compute @workgroup_size(64)
fn springs_clear(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var t = gid.x; t < range.count; t += stride(ng)) {
        lambda[range.start + t] = 0.0;
    }
}
