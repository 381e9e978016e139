// Lit, two-sided surfaces with a colour per vertex (color-group, strain and energy views).

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
}

@vertex
fn vs_main(
    @location(0) position: vec4<f32>,
    @location(1) normal: vec4<f32>,
    @location(2) color: vec4<f32>,
) -> VertexOut {
    var out: VertexOut;
    out.clip = camera.view_proj * vec4<f32>(position.xyz, 1.0);
    out.world = position.xyz;
    out.normal = normal.xyz;
    out.color = color.rgb;
    return out;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    return vec4<f32>(shade(in.color, n, in.world), 1.0);
}
