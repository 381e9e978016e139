// Cloth self-collision (mirrors src/solver/self_collision.rs and its broad_phase): the check of
// the references, the spatial hash of the references (clear, count, prefix sum, scatter), each
// particle's candidates (all of them again where one thread finds only the renewed particles',
// the same lists), and the Jacobi projection with its apply. The head defines CAPACITY, the
// candidates kept per particle, KEEP, the share of the margin beyond which a check renews a
// reference, and OVER_RELAXATION, the projection's ω. Keep the bindings in sync with
// src/gpu/kernels.rs (self_layout) and SelfParams with src/gpu/solver/self_collision.rs.

struct SelfParams {
    // Distance kept between particles (m).
    thickness: f32,
    // Friction coefficient μ.
    friction: f32,
    // 1 / reach (1/m): the hash's cells are a reach wide.
    inv_reach: f32,
    // reach² (m²): candidates are closer than the reach.
    reach2: f32,
    // margin² (m²): a particle may stray this far (squared) from its reference beyond the mean
    // displacement.
    margin2: f32,
    // Rest distances up to this make mesh neighbours (m).
    neighbour: f32,
    // Buckets of the hash: a power of two, at least 64.
    table_size: u32,
    // 1 / the number of particles: the mean displacement is the sum times this.
    inv_n: f32,
}

@group(1) @binding(0) var<uniform> sp: SelfParams;
// Rest positions [0, n), the references the candidates were found from [n, 2n), each
// particle's move in the pass [2n, 3n).
@group(1) @binding(1) var<storage, read_write> points: array<vec4<f32>>;
// The hash's bucket starts [0, S] (counts at b + 1 while counting), its fill cursors
// [S + 1, 2S + 1), then the state: stale, built, dropped, builds.
@group(1) @binding(2) var<storage, read_write> words: array<atomic<u32>>;
// Particles ordered by bucket [0, n), candidate counts [n, 2n), candidate lists
// [2n, 2n + n CAPACITY).
@group(1) @binding(3) var<storage, read_write> lists: array<u32>;

// store_partial in types.wgsl names it; no kernel here reduces into it.
@group(3) @binding(2) var<storage, read_write> partials: array<vec4<f32>>;

fn state_at() -> u32 {
    return 2u * sp.table_size + 1u;
}

fn is_stale() -> bool {
    return atomicLoad(&words[state_at()]) != 0u;
}

fn cell_of(p: vec3<f32>) -> vec3<i32> {
    return vec3<i32>(floor(p * sp.inv_reach));
}

// The bucket of cell c (src/solver/self_collision.rs bucket: i32 products wrap, as u32 ones do).
fn bucket_of(c: vec3<i32>) -> u32 {
    let h = (bitcast<u32>(c.x) * 92837111u) ^ (bitcast<u32>(c.y) * 689287499u) ^ (bitcast<u32>(c.z) * 283923481u);
    return h & (sp.table_size - 1u);
}

var<workgroup> stale_flag: u32;
var<workgroup> run_sums: array<u32, 64>;

// How far particle i is from its reference beyond the mean displacement `shift`, squared (m²).
fn strayed2(i: u32, n: u32, shift: vec3<f32>) -> f32 {
    let d = x[i].xyz - points[n + i].xyz - shift;
    return dot(d, d);
}

// One workgroup: the particles' mean displacement from their references, T (summed as
// broad_phase::mean_shift does). When some particle strayed more than the margin beyond it,
// every particle beyond KEEP times the margin takes x − T as its reference, and the candidates
// are found anew from the references (at the first check, every reference is the position).
@compute @workgroup_size(64)
fn self_check(@builtin(local_invocation_id) lid3: vec3<u32>) {
    let lid = lid3.x;
    let n = params.num_particles;
    let first = atomicLoad(&words[state_at() + 1u]) == 0u;
    var sum = vec3<f32>(0.0);
    for (var i = lid; i < n; i += 64u) {
        sum += x[i].xyz - points[n + i].xyz;
    }
    let shift = reduce_workgroup(lid, vec4<f32>(sum, 0.0)).xyz * sp.inv_n;
    var far = 0.0;
    for (var i = lid; i < n; i += 64u) {
        if (strayed2(i, n, shift) > sp.margin2) {
            far = 1.0;
        }
    }
    let strayed = reduce_workgroup(lid, vec4<f32>(far, 0.0, 0.0, 0.0)).x > 0.0;
    let stale = strayed || first;
    workgroupBarrier();
    if (first) {
        for (var i = lid; i < n; i += 64u) {
            points[n + i] = x[i];
        }
    } else if (strayed) {
        let renew2 = sp.margin2 * (KEEP * KEEP);
        for (var i = lid; i < n; i += 64u) {
            if (strayed2(i, n, shift) > renew2) {
                points[n + i] = vec4<f32>(x[i].xyz - shift, 0.0);
            }
        }
    }
    if (lid == 0u) {
        atomicStore(&words[state_at()], select(0u, 1u, stale));
        atomicStore(&words[state_at() + 1u], 1u);
        if (stale) {
            atomicStore(&words[state_at() + 2u], 0u);
            atomicAdd(&words[state_at() + 3u], 1u);
        }
    }
}

@compute @workgroup_size(64)
fn self_clear(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    if (!is_stale()) {
        return;
    }
    for (var b = gid.x; b <= sp.table_size; b += stride(ng)) {
        atomicStore(&words[b], 0u);
    }
}

@compute @workgroup_size(64)
fn self_count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    if (!is_stale()) {
        return;
    }
    let n = params.num_particles;
    for (var i = gid.x; i < n; i += stride(ng)) {
        atomicAdd(&words[bucket_of(cell_of(points[n + i].xyz)) + 1u], 1u);
    }
}

// One workgroup: the bucket counts at b + 1 become the ends of the buckets (the starts shifted
// by one), each invocation over its 1/64 of the table; the fill cursors start at the starts.
@compute @workgroup_size(64)
fn self_prefix(@builtin(local_invocation_id) lid3: vec3<u32>) {
    let lid = lid3.x;
    if (lid == 0u) {
        stale_flag = atomicLoad(&words[state_at()]);
    }
    if (workgroupUniformLoad(&stale_flag) == 0u) {
        return;
    }
    let size = sp.table_size;
    let chunk = size / 64u;
    let base = lid * chunk;
    var total = 0u;
    for (var k = 0u; k < chunk; k++) {
        total += atomicLoad(&words[base + k + 1u]);
    }
    run_sums[lid] = total;
    workgroupBarrier();
    var run = 0u;
    for (var t = 0u; t < lid; t++) {
        run += run_sums[t];
    }
    for (var k = 0u; k < chunk; k++) {
        let b = base + k;
        let c = atomicLoad(&words[b + 1u]);
        atomicStore(&words[size + 1u + b], run);
        run += c;
        atomicStore(&words[b + 1u], run);
    }
}

@compute @workgroup_size(64)
fn self_scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    if (!is_stale()) {
        return;
    }
    let n = params.num_particles;
    for (var i = gid.x; i < n; i += stride(ng)) {
        let slot = atomicAdd(&words[sp.table_size + 1u + bucket_of(cell_of(points[n + i].xyz))], 1u);
        lists[slot] = i;
    }
}

// Particle i's candidates: every other particle whose reference is closer than the reach to its
// own, in the 27 cells around its own, no mesh neighbour, not both pinned, in increasing order,
// the lowest CAPACITY kept.
@compute @workgroup_size(64)
fn self_find(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    if (!is_stale()) {
        return;
    }
    let n = params.num_particles;
    for (var i = gid.x; i < n; i += stride(ng)) {
        let p = points[n + i].xyz;
        let pinned = x[i].w == 0.0;
        let c = cell_of(p);
        let rest = points[i].xyz;
        let base = 2u * n + i * CAPACITY;
        var count = 0u;
        var dropped = 0u;
        for (var dz = -1; dz <= 1; dz++) {
            for (var dy = -1; dy <= 1; dy++) {
                for (var dx = -1; dx <= 1; dx++) {
                    let cell = c + vec3<i32>(dx, dy, dz);
                    let b = bucket_of(cell);
                    let end = atomicLoad(&words[b + 1u]);
                    for (var k = atomicLoad(&words[b]); k < end; k++) {
                        let j = lists[k];
                        let q = points[n + j].xyz;
                        let d = p - q;
                        if (j == i || any(cell_of(q) != cell) || (pinned && x[j].w == 0.0)
                            || dot(d, d) >= sp.reach2 || length(rest - points[j].xyz) <= sp.neighbour) {
                            continue;
                        }
                        // Sorted insertion, keeping the lowest indices (self_collision::insert).
                        let full = count == CAPACITY;
                        if (full && j >= lists[base + CAPACITY - 1u]) {
                            dropped += 1u;
                            continue;
                        }
                        var at = select(count, CAPACITY - 1u, full);
                        while (at > 0u && lists[base + at - 1u] > j) {
                            lists[base + at] = lists[base + at - 1u];
                            at -= 1u;
                        }
                        lists[base + at] = j;
                        if (full) {
                            dropped += 1u;
                        } else {
                            count += 1u;
                        }
                    }
                }
            }
        }
        lists[n + i] = count;
        if (dropped > 0u) {
            atomicAdd(&words[state_at() + 2u], dropped);
        }
    }
}

// Particle i's move in the pass: its pairs' shares averaged with over-relaxation
// (SelfPairs::correction).
@compute @workgroup_size(64)
fn self_project(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    let n = params.num_particles;
    for (var i = gid.x; i < n; i += stride(ng)) {
        let p = x[i];
        var sum = vec3<f32>(0.0);
        var touching = 0.0;
        if (p.w != 0.0) {
            let prev = x_prev[i].xyz;
            let moved = p.xyz - prev;
            let base = 2u * n + i * CAPACITY;
            for (var k = 0u; k < lists[n + i]; k++) {
                let j = lists[base + k];
                let q = x[j];
                let d = p.xyz - q.xyz;
                let qprev = x_prev[j].xyz;
                let d0 = prev - qprev;
                var nrm: vec3<f32>;
                var depth: f32;
                if (dot(d, d0) < 0.0) {
                    // Passed through each other along their axis: back along the start axis.
                    nrm = d0 * (1.0 / length(d0));
                    depth = sp.thickness - dot(d, nrm);
                } else {
                    let dd = dot(d, d);
                    if (dd >= sp.thickness * sp.thickness || dd <= 0.0) {
                        continue;
                    }
                    let dist = sqrt(dd);
                    nrm = d * (1.0 / dist);
                    depth = sp.thickness - dist;
                }
                let share = p.w / (p.w + q.w);
                var c = nrm * (depth * share);
                // Coulomb friction on the relative motion since the substep's start.
                let rel = moved - (q.xyz - qprev);
                let t = rel - nrm * dot(rel, nrm);
                let tl = length(t);
                if (tl > 0.0) {
                    c -= t * (min(sp.friction * depth, tl) / tl * share);
                }
                sum += c;
                touching += 1.0;
            }
        }
        if (touching > 0.0) {
            sum = sum * (1.0 / max(touching * (1.0 / OVER_RELAXATION), 1.0));
        }
        points[2u * n + i] = vec4<f32>(sum, 0.0);
    }
}

@compute @workgroup_size(64)
fn self_apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    let n = params.num_particles;
    for (var i = gid.x; i < n; i += stride(ng)) {
        let p = x[i];
        x[i] = vec4<f32>(p.xyz + points[2u * n + i].xyz, p.w);
    }
}
