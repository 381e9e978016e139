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

const ARITY: u32 = 4u;
const PARTIAL_FAMILY: u32 = PARTIAL_BENDS;

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

fn element_particles(j: u32) -> array<u32, ARITY> {
    let b = bends[j];
    return array<u32, ARITY>(b.p0, b.p1, b.p2, b.p3);
}

fn element_project(j: u32, p: array<vec3<f32>, ARITY>) -> Proj {
    let pr = bend_constraint(bends[j], p[0], p[1], p[2], p[3]);
    return Proj(pr.c, pr.alpha, array<vec3<f32>, ARITY>(pr.dh.g0, pr.dh.g1, pr.dh.g2, pr.dh.g3));
}

fn element_energy(j: u32, p: array<vec3<f32>, ARITY>) -> f32 {
    let b = bends[j];
    let d = wrapped(dihedral(p[0], p[1], p[2], p[3]).theta, b.rest_angle);
    return 0.5 * b.k * d * d;
}
