// Bindings and helpers shared by the constraint-family kernels; element.wgsl binds the family's
// records at group(1) binding(0). Keep in sync with src/gpu/kernels.rs (layouts).

@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;
@group(1) @binding(2) var<storage, read> jacobi_scale: array<f32>;
@group(1) @binding(3) var<storage, read_write> corr: array<vec4<f32>>;

// Local energy-aware mode: position snapshots at the start of this iteration ([0, n)) and of
// the previous one ([n, 2n)), and each element's energy at the start of the substep.
@group(3) @binding(0) var<storage, read> snapshots: array<vec4<f32>>;
@group(3) @binding(1) var<storage, read_write> energy_start: array<f32>;
// Energy reduction: per-workgroup partial sums.
@group(3) @binding(2) var<storage, read_write> partials: array<vec4<f32>>;

// m (|V^k|² − |V^{k−1}|²) h² of particle i at live position p (0 when pinned); mirrors the sum
// in solver::cpu::local_adjusted.
fn local_kinetic(i: u32, p: vec4<f32>) -> f32 {
    if (p.w <= 0.0) {
        return 0.0;
    }
    let cur = snapshots[i].xyz;
    let prev = snapshots[params.num_particles + i].xyz;
    return (dot(p.xyz - cur, p.xyz - cur) - dot(cur - prev, cur - prev)) / p.w;
}

// The share of an element's material energy that its multiplier λ holds, min(1, ρ²) (mirrors
// metrics::constraint_pass): ρ = |α̃λ/C| in the compliant form (1 where C = 0 or α = 0), |λ|/h²
// in the energy form.
fn held_share(c: f32, alpha: f32, l: f32) -> f32 {
    var rho = 1.0;
    if (params.form == FORM_ENERGY) {
        rho = l * params.inv_h2;
    } else if (c != 0.0 && alpha > 0.0) {
        rho = alpha * params.inv_h2 * l / c;
    }
    return min(1.0, rho * rho);
}
