// Strain colours for drawing: for each vertex, the mean relative stretch ||d| − l₀| / l₀ of the
// edges around it (gathered through a vertex → edge incidence), mapped through the colour ramp
// with `scale` at the red end. Mirrors src/viewer/strain.rs (vertex_strain, ramp).

struct StrainParams {
    // x: relative stretch drawn red.
    scale: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read> edges: array<vec2<u32>>;
@group(0) @binding(2) var<storage, read> rest: array<f32>;
@group(0) @binding(3) var<storage, read> vertex_offsets: array<u32>;
@group(0) @binding(4) var<storage, read> vertex_edges: array<u32>;
@group(0) @binding(5) var<storage, read_write> colors: array<vec4<f32>>;
@group(0) @binding(6) var<uniform> params: StrainParams;

// Blue (0) → green → yellow → red (1), linear RGB.
fn ramp(t: f32) -> vec3<f32> {
    let s = clamp(t, 0.0, 1.0) * 3.0;
    let c0 = vec3<f32>(0.10, 0.25, 0.85);
    let c1 = vec3<f32>(0.10, 0.65, 0.25);
    let c2 = vec3<f32>(0.95, 0.80, 0.10);
    let c3 = vec3<f32>(0.85, 0.08, 0.05);
    if (s < 1.0) {
        return mix(c0, c1, s);
    }
    if (s < 2.0) {
        return mix(c1, c2, s - 1.0);
    }
    return mix(c2, c3, s - 2.0);
}

@compute @workgroup_size(64)
fn vertex_strain(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    let n_vertices = arrayLength(&vertex_offsets) - 1u;
    for (var i = gid.x; i < n_vertices; i += ng.x * 64u) {
        let first = vertex_offsets[i];
        let last = vertex_offsets[i + 1u];
        var sum = 0.0;
        for (var k = first; k < last; k++) {
            let e = vertex_edges[k];
            let ends = edges[e];
            let l0 = rest[e];
            let l = length(positions[ends.y].xyz - positions[ends.x].xyz);
            if (l0 > 0.0) {
                sum += abs(l - l0) / l0;
            }
        }
        var strain = 0.0;
        if (last > first) {
            strain = sum / f32(last - first);
        }
        colors[i] = vec4<f32>(ramp(strain / params.scale.x), strain);
    }
}
