// Springs (mirrors src/constraints/spring.rs): Hookean E = ½k(|d| − l₀)², StVK E = ½k(|d|² − l₀²)²,
// d = x_b − x_a. The family's part of the shared element kernels (shaders/common/element.wgsl),
// with two particles: ∇_b C = g, ∇_a C = −g.

// Particles a and b, rest length l₀ (m), stiffness k.
struct Spring {
    p: array<u32, ARITY>,
    rest: f32,
    k: f32,
}

alias Element = Spring;

const ARITY: u32 = 2u;

// C, ∇C and α of spring j in the current form and material (mirrors Spring::constraint).
fn element_project(j: u32, p: array<vec3<f32>, ARITY>) -> Proj {
    let s = elements[j];
    let d = p[1] - p[0];
    let len = sqrt(dot(d, d));
    let l0 = s.rest;
    var c: f32;
    var g: vec3<f32>;
    var out: Proj;
    if (params.form == FORM_ENERGY) {
        out.alpha = params.energy_compliance;
        if (params.material == MATERIAL_STVK) {
            let q = len * len - l0 * l0;
            c = 0.5 * s.k * (q * q);
            g = d * (2.0 * s.k * q);
        } else {
            let q = len - l0;
            c = 0.5 * s.k * (q * q);
            g = select(d * (s.k * q / len), vec3<f32>(0.0), len <= TINY);
        }
    } else {
        out.alpha = 1.0 / s.k;
        if (params.material == MATERIAL_STVK) {
            c = len * len - l0 * l0;
            g = d * 2.0;
        } else {
            c = len - l0;
            g = select(d * (1.0 / len), vec3<f32>(0.0), len <= TINY);
        }
    }
    out.c = c;
    out.g = array<vec3<f32>, ARITY>(-g, g);
    return out;
}

// Material energy of spring j (mirrors Spring::energy).
fn element_energy(j: u32, p: array<vec3<f32>, ARITY>) -> f32 {
    let s = elements[j];
    let d = p[1] - p[0];
    let len = sqrt(dot(d, d));
    var q = len - s.rest;
    if (params.material == MATERIAL_STVK) {
        q = len * len - s.rest * s.rest;
    }
    return 0.5 * s.k * (q * q);
}

// The lean compliant Hookean update (mirrors Spring::project_plain): Σw|∇C|² = w_a + w_b and
// one division on the dependency chain. Returns false, changing nothing, for the StVK spring, a
// zero-length spring or a vanishing denominator; the general update then runs.
fn element_plain(j: u32, e: Gathered) -> bool {
    if (params.material == MATERIAL_STVK) {
        return false;
    }
    let s = elements[j];
    let xa = e.p[0];
    let xb = e.p[1];
    let d = xb.xyz - xa.xyz;
    let len = sqrt(dot(d, d));
    let alpha_tilde = params.inv_h2 / s.k;
    let denom = xa.w + xb.w + alpha_tilde;
    if (!(len > TINY && denom > EPSILON)) {
        return false;
    }
    let q = (s.rest - len - alpha_tilde * lambda[j]) * params.sor / (denom * len);
    lambda[j] = lambda[j] + q * len;
    x[e.idx[0]] = vec4<f32>(xa.xyz - d * (xa.w * q), xa.w);
    x[e.idx[1]] = vec4<f32>(xb.xyz + d * (xb.w * q), xb.w);
    return true;
}
