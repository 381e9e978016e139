// Signed SVD of a 3×3 matrix (Irving, Teran, Fedkiw 2004), mirroring src/material/svd.rs:
// F = U diag(σ) Vᵀ with U, V rotations, σ₁ ≥ σ₂ ≥ |σ₃| and σ₃ < 0 exactly when det F < 0.
// Matrices are column-major as in Rust's M3: m[c][r].

struct Svd {
    u: mat3x3<f32>,
    sigma: vec3<f32>,
    v: mat3x3<f32>,
}

// f32 machine epsilon (Rust's f32::EPSILON).
const F32_EPSILON: f32 = 1.1920929e-7;

// Rust's signum: 1 for +0.
fn signum(a: f32) -> f32 {
    return select(1.0, -1.0, a < 0.0);
}

struct Eigen {
    values: vec3<f32>,
    vectors: mat3x3<f32>,
}

// Cyclic Jacobi rotations of a symmetric matrix (mirrors svd::symmetric_eigen).
fn symmetric_eigen(m: mat3x3<f32>) -> Eigen {
    var a = m;
    var v = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    let eps = 1e-30;
    for (var sweep = 0; sweep < 32; sweep++) {
        let off = a[1][0] * a[1][0] + a[2][0] * a[2][0] + a[2][1] * a[2][1];
        let diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if (off <= F32_EPSILON * F32_EPSILON * diag || off <= eps) {
            break;
        }
        for (var pair = 0u; pair < 3u; pair++) {
            let p = select(0u, 1u, pair == 2u);
            let q = select(2u, 1u, pair == 0u);
            let apq = a[q][p];
            if (abs(apq) <= eps) {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (apq + apq);
            let t = signum(theta) / (abs(theta) + sqrt(theta * theta + 1.0));
            let cs = 1.0 / sqrt(t * t + 1.0);
            let sn = t * cs;
            // A ← Jᵀ A J with the rotation J in the (p, q) plane: columns, then rows.
            let ap = a[p];
            let aq = a[q];
            a[p] = ap * cs - aq * sn;
            a[q] = ap * sn + aq * cs;
            for (var k = 0u; k < 3u; k++) {
                let apk = a[k][p];
                let aqk = a[k][q];
                a[k][p] = cs * apk - sn * aqk;
                a[k][q] = sn * apk + cs * aqk;
            }
            let vp = v[p];
            let vq = v[q];
            v[p] = vp * cs - vq * sn;
            v[q] = vp * sn + vq * cs;
        }
    }
    return Eigen(vec3<f32>(a[0][0], a[1][1], a[2][2]), v);
}

// A unit vector orthogonal to the unit vector a.
fn orthogonal(a: vec3<f32>) -> vec3<f32> {
    let axis = select(vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(1.0, 0.0, 0.0), abs(a.x) < 0.6);
    let o = cross(a, axis);
    return o * (1.0 / sqrt(dot(o, o)));
}

fn signed_svd(f: mat3x3<f32>) -> Svd {
    let eig = symmetric_eigen(transpose(f) * f);
    var lambda = eig.values;
    var cols = eig.vectors;
    // Sort by eigenvalue, largest first.
    for (var i = 0u; i < 3u; i++) {
        for (var j = i + 1u; j < 3u; j++) {
            if (lambda[j] > lambda[i]) {
                let l = lambda[i];
                lambda[i] = lambda[j];
                lambda[j] = l;
                let c = cols[i];
                cols[i] = cols[j];
                cols[j] = c;
            }
        }
    }
    if (determinant(cols) < 0.0) {
        cols[2] = -cols[2];
    }
    let b = f * cols;
    let tiny = 1e-20;
    let s1 = sqrt(dot(b[0], b[0]));
    var u1 = vec3<f32>(1.0, 0.0, 0.0);
    if (s1 > tiny) {
        u1 = b[0] * (1.0 / s1);
    }
    let b2 = b[1] - u1 * dot(b[1], u1);
    let n2 = sqrt(dot(b2, b2));
    var u2: vec3<f32>;
    if (n2 > tiny * (1.0 + s1)) {
        u2 = b2 * (1.0 / n2);
    } else {
        u2 = orthogonal(u1);
    }
    let s2 = dot(b[1], u2);
    let u3 = cross(u1, u2);
    let s3 = dot(b[2], u3);
    return Svd(mat3x3<f32>(u1, u2, u3), vec3<f32>(s1, s2, s3), cols);
}

// U diag(d) Vᵀ.
fn svd_compose(s: Svd, d: vec3<f32>) -> mat3x3<f32> {
    return mat3x3<f32>(s.u[0] * d.x, s.u[1] * d.y, s.u[2] * d.z) * transpose(s.v);
}
