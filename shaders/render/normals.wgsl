// Vertex normals for drawing: for each vertex, the sum of the (area-weighted) normals of the
// triangles around it, gathered through a vertex → triangle incidence (no atomics).

@group(0) @binding(0) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read> triangles: array<u32>;
@group(0) @binding(2) var<storage, read> vertex_offsets: array<u32>;
@group(0) @binding(3) var<storage, read> vertex_triangles: array<u32>;
@group(0) @binding(4) var<storage, read_write> normals: array<vec4<f32>>;

@compute @workgroup_size(64)
fn vertex_normals(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    let n_vertices = arrayLength(&vertex_offsets) - 1u;
    for (var i = gid.x; i < n_vertices; i += ng.x * 64u) {
        var n = vec3<f32>(0.0);
        for (var k = vertex_offsets[i]; k < vertex_offsets[i + 1u]; k++) {
            let t = vertex_triangles[k] * 3u;
            let a = positions[triangles[t]].xyz;
            let b = positions[triangles[t + 1u]].xyz;
            let c = positions[triangles[t + 2u]].xyz;
            n += cross(b - a, c - a);
        }
        let len = length(n);
        if (len > 0.0) {
            n = n / len;
        } else {
            n = vec3<f32>(0.0, 1.0, 0.0);
        }
        normals[i] = vec4<f32>(n, 0.0);
    }
}
