// Second-order forward differentiation in three variables (mirrors src/material/hyperdual.rs):
// a value with its gradient and (symmetric) Hessian.

struct Hd {
    v: f32,
    g: vec3<f32>,
    h: mat3x3<f32>,
}

fn outer(a: vec3<f32>, b: vec3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(a * b.x, a * b.y, a * b.z);
}

fn hd_const(v: f32) -> Hd {
    return Hd(v, vec3<f32>(0.0), mat3x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0)));
}

// The i-th variable at value v.
fn hd_var(i: u32, v: f32) -> Hd {
    var out = hd_const(v);
    out.g[i] = 1.0;
    return out;
}

// f(a) from f(v), f'(v), f''(v).
fn hd_chain(a: Hd, f: f32, df: f32, ddf: f32) -> Hd {
    return Hd(f, a.g * df, a.h * df + outer(a.g, a.g) * ddf);
}

fn hd_add(a: Hd, b: Hd) -> Hd {
    return Hd(a.v + b.v, a.g + b.g, a.h + b.h);
}

fn hd_sub(a: Hd, b: Hd) -> Hd {
    return hd_add(a, hd_scale(b, -1.0));
}

fn hd_mul(a: Hd, b: Hd) -> Hd {
    return Hd(a.v * b.v, a.g * b.v + b.g * a.v, a.h * b.v + b.h * a.v + outer(a.g, b.g) + outer(b.g, a.g));
}

// a + s for a constant s.
fn hd_addc(a: Hd, s: f32) -> Hd {
    return Hd(a.v + s, a.g, a.h);
}

// s a for a constant s.
fn hd_scale(a: Hd, s: f32) -> Hd {
    return hd_chain(a, a.v * s, s, 0.0);
}

// ln a (a > 0).
fn hd_ln(a: Hd) -> Hd {
    let inv = 1.0 / a.v;
    return hd_chain(a, log(a.v), inv, -inv * inv);
}

// a^p (a > 0).
fn hd_powf(a: Hd, p: f32) -> Hd {
    let vp = pow(a.v, p);
    return hd_chain(a, vp, p * vp / a.v, p * (p - 1.0) * vp / (a.v * a.v));
}
