// Lit, two-sided surfaces (cloth and colliders), read straight from the solver's position buffer.

struct Material {
    front: vec4<f32>,
    back: vec4<f32>,
}

@group(1) @binding(0) var<uniform> material: Material;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
}

@vertex
fn vs_main(@location(0) position: vec4<f32>, @location(1) normal: vec4<f32>) -> VertexOut {
    var out: VertexOut;
    out.clip = camera.view_proj * vec4<f32>(position.xyz, 1.0);
    out.world = position.xyz;
    out.normal = normal.xyz;
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var n = normalize(in.normal);
    var base = material.front.rgb;
    if (!front) {
        n = -n;
        base = material.back.rgb;
    }
    return vec4<f32>(shade(base, n, in.world), 1.0);
}
