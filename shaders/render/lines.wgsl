// Line segments between particles, read straight from the solver's position buffer (no vertex
// buffers: vertex 2k and 2k + 1 are the ends of segment k), one colour per segment. Drawn a
// little towards the eye so edges lying on the surface are not hidden by it.

@group(1) @binding(0) var<storage, read> positions: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read> segments: array<vec2<u32>>;
@group(1) @binding(2) var<storage, read> colors: array<vec4<f32>>;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec3<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> VertexOut {
    let s = segments[i / 2u];
    var p = positions[s.x].xyz;
    if ((i & 1u) == 1u) {
        p = positions[s.y].xyz;
    }
    var out: VertexOut;
    let clip = camera.view_proj * vec4<f32>(p, 1.0);
    out.clip = vec4<f32>(clip.xy, clip.z - 2e-4 * clip.w, clip.w);
    out.color = colors[i / 2u].rgb;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.color, 1.0);
}
