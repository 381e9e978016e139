// The ground plane: a large quad at the ground height with a checker pattern fading with distance.

struct Ground {
    // x: height (m); y: half extent (m); z: checker size (m).
    params: vec4<f32>,
}

@group(1) @binding(0) var<uniform> ground: Ground;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> VertexOut {
    let corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0),
    );
    let c = corners[i] * ground.params.y;
    let world = vec3<f32>(c.x, ground.params.x, c.y);
    var out: VertexOut;
    out.clip = camera.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    return out;
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let cell = floor(in.world.xz / ground.params.z);
    let checker = (i32(cell.x) + i32(cell.y)) & 1;
    var base = vec3<f32>(0.42, 0.43, 0.45);
    if (checker == 1) {
        base = vec3<f32>(0.30, 0.31, 0.33);
    }
    let lit = shade(base, vec3<f32>(0.0, 1.0, 0.0), in.world);
    let fade = clamp(length(in.world.xz) / ground.params.y, 0.0, 1.0);
    let sky = vec3<f32>(0.80, 0.84, 0.90);
    return vec4<f32>(mix(lit, sky, fade * fade), 1.0);
}
