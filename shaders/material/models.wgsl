// The five 3D elastic models (mirrors src/material/models.rs): energy density Ψ(F) (J/m³) and
// first Piola–Kirchhoff stress P(F) (Pa). Constants come precomputed in SimParams. All but the
// linear model are evaluated in closed form (invariants.wgsl) where F is regular, else on the
// signed singular values with the inversion continuation below SIGMA_MIN (after Stomakhin et al.
// 2012; the module docs of src/material/models.rs).

const MODEL_LINEAR: u32 = 0u;
const MODEL_STVK: u32 = 1u;
const MODEL_NEO_HOOKEAN: u32 = 2u;
const MODEL_MOONEY_RIVLIN: u32 = 3u;
const MODEL_ARRUDA_BOYCE: u32 = 4u;
const SIGMA_MIN: f32 = 0.15;

// Ψ̂(σ) with derivatives, for the isotropic models (positive σ).
fn psi_hat(s0: Hd, s1: Hd, s2: Hd) -> Hd {
    let sq0 = hd_mul(s0, s0);
    let sq1 = hd_mul(s1, s1);
    let sq2 = hd_mul(s2, s2);
    let i1 = hd_add(hd_add(sq0, sq1), sq2);
    switch params.tet_model {
        case MODEL_NEO_HOOKEAN: {
            let l = hd_add(hd_add(hd_ln(s0), hd_ln(s1)), hd_ln(s2));
            return hd_add(
                hd_sub(hd_scale(hd_addc(i1, -3.0), params.half_mu), hd_scale(l, params.mu)),
                hd_scale(hd_mul(l, l), params.half_lambda),
            );
        }
        case MODEL_MOONEY_RIVLIN: {
            let j = hd_mul(hd_mul(s0, s1), s2);
            let i2 = hd_add(hd_add(hd_mul(sq0, sq0), hd_mul(sq1, sq1)), hd_mul(sq2, sq2));
            let a = hd_sub(hd_mul(i1, i1), i2);
            let jm = hd_sub(j, hd_const(1.0));
            let t01 = hd_scale(hd_addc(hd_mul(a, hd_powf(j, -4.0 / 3.0)), -6.0), params.half_mu01);
            let t10 = hd_scale(hd_addc(hd_mul(i1, hd_powf(j, -2.0 / 3.0)), -3.0), params.mu10);
            return hd_add(hd_add(t01, t10), hd_scale(hd_mul(jm, jm), params.nu1));
        }
        case MODEL_ARRUDA_BOYCE: {
            let j = hd_mul(hd_mul(s0, s1), s2);
            let ib = hd_mul(i1, hd_powf(j, -2.0 / 3.0));
            let alphas = array<f32, 5>(params.ab0, params.ab1, params.ab2, params.ab3, params.ab4);
            var psi = hd_const(0.0);
            var power = ib;
            var three = 3.0;
            for (var i = 0u; i < 5u; i++) {
                if (i > 0u) {
                    power = hd_mul(power, ib);
                    three = three * 3.0;
                }
                psi = hd_add(psi, hd_scale(hd_addc(power, -three), alphas[i]));
            }
            let jm = hd_sub(j, hd_const(1.0));
            return hd_add(psi, hd_scale(hd_mul(jm, jm), params.half_kappa));
        }
        default: {
            // StVK (and the linear model, which never comes here).
            let e0 = hd_scale(hd_addc(sq0, -1.0), 0.5);
            let e1 = hd_scale(hd_addc(sq1, -1.0), 0.5);
            let e2 = hd_scale(hd_addc(sq2, -1.0), 0.5);
            let tr = hd_add(hd_add(e0, e1), e2);
            let ee = hd_add(hd_add(hd_mul(e0, e0), hd_mul(e1, e1)), hd_mul(e2, e2));
            return hd_add(hd_scale(ee, params.mu), hd_scale(hd_mul(tr, tr), params.half_lambda));
        }
    }
}

// Ψ and ∂Ψ/∂σ with the inversion continuation below SIGMA_MIN: vec4(∂Ψ/∂σ, Ψ).
// Ψ = Ψ̂(σ̂) + Σ_k [min(ĝ_k, 0) δ_k + ½ κ_inv δ_k²] over the clamped axes.
fn extended(sigma: vec3<f32>) -> vec4<f32> {
    let kappa = params.inversion_stiffness;
    let clamped = max(sigma, vec3<f32>(SIGMA_MIN));
    let h = psi_hat(hd_var(0u, clamped.x), hd_var(1u, clamped.y), hd_var(2u, clamped.z));
    let delta = sigma - clamped;
    // Clamped axes whose slope counts (ĝ_k < 0).
    let pulls = (delta != vec3<f32>(0.0)) & (h.g < vec3<f32>(0.0));
    var psi = h.v;
    var grad = h.g;
    for (var k = 0u; k < 3u; k++) {
        if (delta[k] != 0.0) {
            let slope = select(0.0, h.g[k], pulls[k]);
            psi += (slope + 0.5 * kappa * delta[k]) * delta[k];
            grad[k] = slope + kappa * delta[k];
        } else {
            for (var i = 0u; i < 3u; i++) {
                if (pulls[i]) {
                    grad[k] += h.h[k][i] * delta[i];
                }
            }
        }
    }
    return vec4<f32>(grad, psi);
}

// Energy density and stress of the configured model at F.
struct Stress {
    psi: f32,
    p: mat3x3<f32>,
}

fn material_stress(f: mat3x3<f32>) -> Stress {
    if (params.tet_model == MODEL_LINEAR) {
        let identity = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
        let sym = f + transpose(f);
        let eps = mat3x3<f32>(sym[0] * 0.5, sym[1] * 0.5, sym[2] * 0.5) - identity;
        let tr = eps[0][0] + eps[1][1] + eps[2][2];
        let ddot = dot(eps[0], eps[0]) + dot(eps[1], eps[1]) + dot(eps[2], eps[2]);
        let p = mat3x3<f32>(eps[0] * params.two_mu, eps[1] * params.two_mu, eps[2] * params.two_mu);
        let diag = params.lambda * tr;
        return Stress(params.mu * ddot + params.half_lambda * tr * tr, p + mat3x3<f32>(
            vec3<f32>(diag, 0.0, 0.0), vec3<f32>(0.0, diag, 0.0), vec3<f32>(0.0, 0.0, diag)));
    }
    let fast = closed_form(f);
    if (fast.ok) {
        return Stress(fast.psi, fast.p);
    }
    let d = signed_svd(f);
    let e = extended(d.sigma);
    return Stress(e.w, svd_compose(d, e.xyz));
}
