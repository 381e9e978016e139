// An embedded surface's vertices from the particles (mirrors mesh::embedded_positions):
// x_i = Σ_k w_k x[p_k] over the four particles of the vertex's tetrahedron.

struct Binding {
    p: vec4<u32>,
    w: vec4<f32>,
}

@group(0) @binding(0) var<storage, read> particles: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read> bindings: array<Binding>;
@group(0) @binding(2) var<storage, read_write> embedded: array<vec4<f32>>;

@compute @workgroup_size(64)
fn embed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < arrayLength(&bindings); i += ng.x * 64u) {
        let b = bindings[i];
        var acc = vec3<f32>(0.0);
        acc = acc + particles[b.p.x].xyz * b.w.x;
        acc = acc + particles[b.p.y].xyz * b.w.y;
        acc = acc + particles[b.p.z].xyz * b.w.z;
        acc = acc + particles[b.p.w].xyz * b.w.w;
        embedded[i] = vec4<f32>(acc, 1.0);
    }
}
