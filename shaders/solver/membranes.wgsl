// Anisotropic continuum cloth (mirrors src/constraints/membrane.rs): the orthotropic StVK
// triangle. F = [x₁ − x₀, x₂ − x₀] D_m⁻¹ (3×2, columns f_u, f_v), ε = (E_uu, E_vv, 2E_uv) of
// E = ½(FᵀF − I), Ψ = ½ εᵀ C_orth ε, E = A₀ Ψ; s = C_orth ε, P = F [[s₀, s₂], [s₂, s₁]],
// [∇x₁ ∇x₂] = A₀ P D_m⁻ᵀ, ∇x₀ = −Σ. Compliant form: C = √(2E/s), α = 1/s, ∇C = ∇E/(s C).

struct Membrane {
    p: array<u32, ARITY>,
    // Rest area A₀ (m²).
    area: f32,
    // D_m⁻¹ by columns (1/m).
    dm_inv: vec4<f32>,
}

alias Element = Membrane;

const ARITY: u32 = 3u;

struct MembraneState {
    // Columns of F.
    fu: vec3<f32>,
    fv: vec3<f32>,
    // Voigt strain and C_orth ε.
    strain: vec3<f32>,
    stress: vec3<f32>,
}

fn membrane_state(m: Membrane, p: array<vec3<f32>, ARITY>) -> MembraneState {
    let d1 = p[1] - p[0];
    let d2 = p[2] - p[0];
    let k = m.dm_inv;
    var out: MembraneState;
    out.fu = d1 * k.x + d2 * k.y;
    out.fv = d1 * k.z + d2 * k.w;
    out.strain = vec3<f32>((dot(out.fu, out.fu) - 1.0) * 0.5, (dot(out.fv, out.fv) - 1.0) * 0.5, dot(out.fu, out.fv));
    let e = out.strain;
    out.stress = vec3<f32>(
        params.c_uu * e.x + params.c_uv * e.y,
        params.c_uv * e.x + params.c_vv * e.y,
        params.c_ss * e.z,
    );
    return out;
}

fn membrane_energy(m: Membrane, st: MembraneState) -> f32 {
    let e = st.strain;
    let s = st.stress;
    return m.area * ((e.x * s.x + e.y * s.y + e.z * s.z) * 0.5);
}

fn element_energy(j: u32, p: array<vec3<f32>, ARITY>) -> f32 {
    let m = elements[j];
    return membrane_energy(m, membrane_state(m, p));
}

fn element_project(j: u32, p: array<vec3<f32>, ARITY>) -> Proj {
    let m = elements[j];
    let st = membrane_state(m, p);
    let s = st.stress;
    let pu = st.fu * s.x + st.fv * s.z;
    let pv = st.fu * s.z + st.fv * s.y;
    let k = m.dm_inv;
    let g1 = (pu * k.x + pv * k.z) * m.area;
    let g2 = (pu * k.y + pv * k.w) * m.area;
    let g = array<vec3<f32>, ARITY>(-(g1 + g2), g1, g2);
    return energy_projection(membrane_energy(m, st), g, params.membrane_scale);
}

// No lean kernel for this family: the general update always runs.
fn element_plain(j: u32, e: Gathered) -> bool {
    return false;
}
