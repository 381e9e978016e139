// Tetrahedra with the 3D elastic models (mirrors src/constraints/tet.rs): F = D_s D_m⁻¹,
// E = V₀ Ψ(F), [∇x₁ ∇x₂ ∇x₃] = V₀ P D_m⁻ᵀ, ∇x₀ = −Σ. Compliant form: C = √(2E/s), α = 1/s,
// ∇C = ∇E/(s C), skipped for the iteration when C vanishes or is not finite.

struct Tet {
    p: array<u32, ARITY>,
    // D_m⁻¹ by columns.
    dm_inv: array<f32, 9>,
    // Rest volume V₀ (m³).
    volume: f32,
    pad0: u32,
    pad1: u32,
}

alias Element = Tet;

const ARITY: u32 = 4u;


fn rest_inverse(t: Tet) -> mat3x3<f32> {
    let m = t.dm_inv;
    return mat3x3<f32>(vec3<f32>(m[0], m[1], m[2]), vec3<f32>(m[3], m[4], m[5]), vec3<f32>(m[6], m[7], m[8]));
}

fn deformation(t: Tet, p: array<vec3<f32>, ARITY>) -> mat3x3<f32> {
    return mat3x3<f32>(p[1] - p[0], p[2] - p[0], p[3] - p[0]) * rest_inverse(t);
}

fn element_energy(j: u32, p: array<vec3<f32>, ARITY>) -> f32 {
    let t = elements[j];
    return t.volume * material_stress(deformation(t, p)).psi;
}

fn element_project(j: u32, p: array<vec3<f32>, ARITY>) -> Proj {
    let t = elements[j];
    let st = material_stress(deformation(t, p));
    let h = st.p * transpose(rest_inverse(t));
    let v = t.volume;
    let g1 = h[0] * v;
    let g2 = h[1] * v;
    let g3 = h[2] * v;
    return energy_projection(v * st.psi, array<vec3<f32>, ARITY>(-(g1 + g2 + g3), g1, g2, g3), params.tet_scale);
}

// No lean kernel for this family: the general update always runs.
fn element_plain(j: u32, e: Gathered) -> bool {
    return false;
}
