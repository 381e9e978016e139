// Dihedral bending (mirrors src/constraints/bending.rs): E = ½ k_b (θ − θ₀)², θ the signed angle
// between the triangles (x₀, x₁, x₂) and (x₁, x₀, x₃).

struct Bend {
    p: array<u32, ARITY>,
    rest_angle: f32,
    k: f32,
}

alias Element = Bend;

const ARITY: u32 = 4u;

const PI: f32 = 3.141592653589793;

struct Dihedral {
    theta: f32,
    g0: vec3<f32>,
    g1: vec3<f32>,
    g2: vec3<f32>,
    g3: vec3<f32>,
}

// atan2(y, x) with the operations of the CPU's f32 fast_atan2 (src/math.rs; the CPU fuses its
// multiply-adds where its build targets FMA, so the last bits may differ): one division, the
// Cephes polynomial, the quadrant restored; zero, infinite and NaN inputs take the builtin.
fn fast_atan2(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    let swap = ay > ax;
    let lo = select(ay, ax, swap);
    let hi = select(ax, ay, swap);
    if (!(hi > 0.0 && (bitcast<u32>(hi) & 0x7f800000u) != 0x7f800000u && lo <= hi)) {
        return atan2(y, x);
    }
    let big = lo > 0.41421357 * hi;
    let t = select(lo, lo - hi, big) / select(hi, lo + hi, big);
    let base = select(0.0, 0.7853981633974483, big);
    let z = t * t;
    let poly = (((8.0537445e-2 * z - 1.3877686e-1) * z + 1.9977711e-1) * z - 3.333295e-1) * z;
    var r = base + (t + t * poly);
    r = select(r, 1.5707963267948966 - r, swap);
    r = select(r, PI - r, x < 0.0);
    return bitcast<f32>(bitcast<u32>(r) | (bitcast<u32>(y) & 0x80000000u));
}

fn signed_angle(n1: vec3<f32>, n2: vec3<f32>, e_hat: vec3<f32>) -> f32 {
    return fast_atan2(dot(cross(n1, n2), e_hat), dot(n1, n2));
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

fn element_project(j: u32, p: array<vec3<f32>, ARITY>) -> Proj {
    let pr = bend_constraint(elements[j], p[0], p[1], p[2], p[3]);
    return Proj(pr.c, pr.alpha, array<vec3<f32>, ARITY>(pr.dh.g0, pr.dh.g1, pr.dh.g2, pr.dh.g3));
}

fn element_energy(j: u32, p: array<vec3<f32>, ARITY>) -> f32 {
    let b = elements[j];
    let d = wrapped(dihedral(p[0], p[1], p[2], p[3]).theta, b.rest_angle);
    return 0.5 * b.k * d * d;
}

// The lean compliant Gauss-Seidel update (mirrors Bend::project_plain): θ from atan2 with both
// arguments scaled by |e|, |∇x₂θ|² = |e|²/|n₁|². Returns false, changing nothing, where the element
// is degenerate; the general update then runs.
fn element_plain(j: u32, e: Gathered) -> bool {
    let b = elements[j];
    let x0 = e.p[0].xyz;
    let x1 = e.p[1].xyz;
    let x2 = e.p[2].xyz;
    let x3 = e.p[3].xyz;
    let ed = x1 - x0;
    let a = x2 - x0;
    let c = x3 - x0;
    let n1 = cross(ed, a);
    let n2 = cross(c, ed);
    let e2 = dot(ed, ed);
    let n1s = dot(n1, n1);
    let n2s = dot(n2, n2);
    if (!(e2 > TINY && n1s > TINY * e2 && n2s > TINY * e2)) {
        return false;
    }
    let el = sqrt(e2);
    let theta = fast_atan2(dot(cross(n1, n2), ed), dot(n1, n2) * el);
    let inv_e2 = 1.0 / e2;
    let q1 = el / n1s;
    let q2 = el / n2s;
    let t2 = dot(a, ed) * inv_e2;
    let t3 = dot(c, ed) * inv_e2;
    let g2 = n1 * -q1;
    let g3 = n2 * -q2;
    let g0 = -(g2 * (1.0 - t2)) - g3 * (1.0 - t3);
    let g1 = -(g2 * t2) - g3 * t3;
    let w0 = e.p[0].w;
    let w1 = e.p[1].w;
    let w2 = e.p[2].w;
    let w3 = e.p[3].w;
    let sum = w0 * dot(g0, g0) + w1 * dot(g1, g1) + (w2 * q1 + w3 * q2) * el;
    let alpha_tilde = params.inv_h2 / b.k;
    let denom = sum + alpha_tilde;
    if (!(denom > EPSILON)) {
        return false;
    }
    let dl = (-wrapped(theta, b.rest_angle) - alpha_tilde * lambda[j]) / denom * params.sor;
    lambda[j] = lambda[j] + dl;
    x[e.idx[0]] = vec4<f32>(x0 + g0 * (w0 * dl), w0);
    x[e.idx[1]] = vec4<f32>(x1 + g1 * (w1 * dl), w1);
    x[e.idx[2]] = vec4<f32>(x2 + g2 * (w2 * dl), w2);
    x[e.idx[3]] = vec4<f32>(x3 + g3 * (w3 * dl), w3);
    return true;
}
