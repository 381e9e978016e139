// The isotropic models in closed form from the invariants of F (mirrors
// src/material/invariants.rs): for J = det F > 0 and J² ≥ σ_min² I₂(C), where every singular
// value is at least SIGMA_MIN and the inversion extension is inactive. cof F = ∂J/∂F,
// Ĵ = J^{−2/3}, C = FᵀF, I₁ = tr C.

struct ClosedForm {
    // false: F is near or past inversion; take the SVD path.
    ok: bool,
    psi: f32,
    p: mat3x3<f32>,
}

fn closed_form(f: mat3x3<f32>) -> ClosedForm {
    let cof = mat3x3<f32>(cross(f[1], f[2]), cross(f[2], f[0]), cross(f[0], f[1]));
    let j = dot(f[0], cof[0]);
    let cm = transpose(f) * f;
    let i1 = cm[0][0] + cm[1][1] + cm[2][2];
    let cc = dot(cm[0], cm[0]) + dot(cm[1], cm[1]) + dot(cm[2], cm[2]);
    let i2 = (i1 * i1 - cc) * 0.5;
    if (!(j > 0.0 && j * j >= SIGMA_MIN * SIGMA_MIN * i2)) {
        return ClosedForm(false, 0.0, cm);
    }
    let identity = mat3x3<f32>(vec3<f32>(1.0, 0.0, 0.0), vec3<f32>(0.0, 1.0, 0.0), vec3<f32>(0.0, 0.0, 1.0));
    let jm = j - 1.0;
    switch params.tet_model {
        case MODEL_NEO_HOOKEAN: {
            let l = log(j);
            let psi = params.half_mu * (i1 - 3.0) - params.mu * l + params.half_lambda * l * l;
            return ClosedForm(true, psi, f * params.mu + cof * ((params.lambda * l - params.mu) / j));
        }
        case MODEL_MOONEY_RIVLIN: {
            let jh = pow(j, -2.0 / 3.0);
            let jh2 = jh * jh;
            let a = i1 * i1 - cc;
            let psi = params.half_mu01 * (a * jh2 - 6.0) + params.mu10 * (i1 * jh - 3.0) + params.nu1 * jm * jm;
            let da = (f * i1 - f * cm) * 4.0;
            let p = (da - cof * (4.0 / 3.0 * a / j)) * (params.half_mu01 * jh2)
                + (f * 2.0 - cof * (2.0 / 3.0 * i1 / j)) * (params.mu10 * jh) + cof * (2.0 * params.nu1 * jm);
            return ClosedForm(true, psi, p);
        }
        case MODEL_ARRUDA_BOYCE: {
            let jh = pow(j, -2.0 / 3.0);
            let ib = jh * i1;
            let alphas = array<f32, 5>(params.ab0, params.ab1, params.ab2, params.ab3, params.ab4);
            var psi = params.half_kappa * jm * jm;
            var dpsi = 0.0;
            var power = 1.0;
            var three = 1.0;
            for (var i = 0u; i < 5u; i++) {
                dpsi += f32(i + 1u) * alphas[i] * power;
                power = power * ib;
                three = three * 3.0;
                psi += alphas[i] * (power - three);
            }
            let dib = f * (2.0 * jh) - cof * (2.0 / 3.0 * ib / j);
            return ClosedForm(true, psi, dib * dpsi + cof * (2.0 * params.half_kappa * jm));
        }
        default: {
            // StVK (the linear model never comes here).
            let strain = (cm - identity) * 0.5;
            let tr = (i1 - 3.0) * 0.5;
            let ee = dot(strain[0], strain[0]) + dot(strain[1], strain[1]) + dot(strain[2], strain[2]);
            let psi = params.mu * ee + params.half_lambda * tr * tr;
            return ClosedForm(true, psi, f * (strain * params.two_mu + identity * (params.lambda * tr)));
        }
    }
}
