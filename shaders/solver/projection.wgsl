// The energy-momentum projection after a frame (`--energy-aware project`; mirrors
// src/solver/projection.rs and src/solver/cpu/project.rs). After the energy reduction has put
// K, G, the held elastic energy and the dissipated work in the ledger:
//   projection_moments  per-workgroup sums of the free particles' mass moments;
//   projection_rigid    (one workgroup) the rigid motion with their momenta, and the target one;
//   projection_deform   per-workgroup sums of the kinetic energy the scale acts on;
//   projection_scale    (one workgroup) the budget and the scale s;
//   projection_apply    v ← target(x) + s (v − now(x)), or v ← s v with a pinned particle.
// range.start selects the mode of projection_rigid and projection_scale: 0 starts the budget
// (and the momenta an isolated body keeps), 1 projects. Positions are taken relative to the
// rest centre of mass r₀, which keeps the f32 moments near the body.

@group(3) @binding(4) var<storage, read_write> projection: Projection;

// ε of solver::projection::PROJECTION_EPSILON: s within [1 − ε, 1 + ε] per frame.
const PROJECTION_EPSILON: f32 = 1.0;
// The rounding band of the f32 reduction (the CPU's PROJECTION_ROUNDING is 1e-5 with f64 sums).
const GPU_PROJECTION_ROUNDING: f32 = 1e-4;

@compute @workgroup_size(64)
fn projection_moments(r: Reducer) {
    // M, Σ m q; Σ m v, pinned particles; Σ m q × v, Σ m qx²; Σ m (qy², qz², qx qy, qx qz); Σ m qy qz.
    var a = array<vec4<f32>, 5>();
    for (var i = r.gid.x; i < params.num_particles; i += stride(r.ng)) {
        let p = x[i];
        if (p.w > 0.0) {
            let m = 1.0 / p.w;
            let q = p.xyz - params.rest_com.xyz;
            let vel = v[i].xyz;
            a[0] += vec4<f32>(m, m * q);
            a[1] += vec4<f32>(m * vel, 0.0);
            a[2] += vec4<f32>(m * cross(q, vel), m * q.x * q.x);
            a[3] += m * vec4<f32>(q.y * q.y, q.z * q.z, q.x * q.y, q.x * q.z);
            a[4].x += m * q.y * q.z;
        } else {
            a[1].w += 1.0;
        }
    }
    for (var k = 0u; k < 5u; k++) {
        store_partial(r, PARTIAL_MOMENTS + k * REDUCE_GROUPS, a[k]);
    }
}

// I⁻¹ l by Cramer's rule, or zero where I is singular against its scale (mirrors solve_inertia).
fn solve_inertia(i: mat3x3<f32>, l: vec3<f32>) -> vec3<f32> {
    let scale = i[0].x + i[1].y + i[2].z;
    let det = determinant(i);
    if (!(scale > 0.0 && det > 1e-12 * scale * scale * scale)) {
        return vec3<f32>(0.0);
    }
    let x = dot(l, cross(i[1], i[2]));
    let y = dot(i[0], cross(l, i[2]));
    let z = dot(i[0], cross(i[1], l));
    return vec3<f32>(x, y, z) / det;
}

// The sum of moment region k over the reduction's workgroups.
fn moment_sum(lid: u32, k: u32) -> vec4<f32> {
    var acc = vec4<f32>(0.0);
    for (var j = lid; j < reduce_count(params.num_particles); j += 64u) {
        acc += partials[PARTIAL_MOMENTS + k * REDUCE_GROUPS + j];
    }
    return reduce_workgroup(lid, acc);
}

@compute @workgroup_size(64)
fn projection_rigid(@builtin(local_invocation_id) lid: vec3<u32>) {
    let s0 = moment_sum(lid.x, 0u);
    let s1 = moment_sum(lid.x, 1u);
    let s2 = moment_sum(lid.x, 2u);
    let s3 = moment_sum(lid.x, 3u);
    let s4 = moment_sum(lid.x, 4u);
    if (lid.x != 0u) {
        return;
    }
    let mass = s0.x;
    let pinned = s1.w > 0.5;
    let p = s1.xyz;
    let l = s2.xyz;
    let isolated = !pinned && all(params.gravity.xyz == vec3<f32>(0.0)) && params.has_ground == 0u
        && params.num_spheres == 0u;
    if (range.start == 0u) {
        projection.momenta_p = vec4<f32>(p, select(0.0, 1.0, isolated));
        projection.momenta_l = vec4<f32>(l, 0.0);
    }
    if (pinned || !(mass > 0.0)) {
        projection.centre = vec4<f32>(0.0);
        return;
    }
    let c = s0.yzw / mass;
    // Σ m (|q|² 1 − q qᵀ) about r₀, then about c: I_c = I₀ − M (|c|² 1 − c cᵀ).
    let tr = s2.w + s3.x + s3.y;
    let i0 = mat3x3<f32>(
        vec3<f32>(tr - s2.w, -s3.z, -s3.w),
        vec3<f32>(-s3.z, tr - s3.x, -s4.x),
        vec3<f32>(-s3.w, -s4.x, tr - s3.y),
    );
    let cc = dot(c, c);
    let shift = mat3x3<f32>(
        vec3<f32>(cc - c.x * c.x, -c.x * c.y, -c.x * c.z),
        vec3<f32>(-c.y * c.x, cc - c.y * c.y, -c.y * c.z),
        vec3<f32>(-c.z * c.x, -c.z * c.y, cc - c.z * c.z),
    );
    let ic = i0 - shift * mass;
    let velocity = p / mass;
    let omega = solve_inertia(ic, l - cross(c, p));
    var target_velocity = velocity;
    var target_omega = omega;
    if (isolated && projection.momenta_p.w == 1.0) {
        let pt = projection.momenta_p.xyz;
        target_velocity = pt / mass;
        target_omega = solve_inertia(ic, projection.momenta_l.xyz - cross(c, pt));
    }
    let target_kinetic = 0.5 * mass * dot(target_velocity, target_velocity)
        + 0.5 * dot(target_omega, ic * target_omega);
    projection.centre = vec4<f32>(c, mass);
    projection.velocity = vec4<f32>(velocity, 0.0);
    projection.omega = vec4<f32>(omega, 0.0);
    projection.target_velocity = vec4<f32>(target_velocity, target_kinetic);
    projection.target_omega = vec4<f32>(target_omega, 0.0);
}

// The rigid velocity now at relative position q (zero without a rigid motion).
fn rigid_now(q: vec3<f32>) -> vec3<f32> {
    if (projection.centre.w <= 0.0) {
        return vec3<f32>(0.0);
    }
    return projection.velocity.xyz + cross(projection.omega.xyz, q - projection.centre.xyz);
}

@compute @workgroup_size(64)
fn projection_deform(r: Reducer) {
    var acc = 0.0;
    for (var i = r.gid.x; i < params.num_particles; i += stride(r.ng)) {
        let p = x[i];
        if (p.w > 0.0) {
            let d = v[i].xyz - rigid_now(p.xyz - params.rest_com.xyz);
            acc += 0.5 * dot(d, d) / p.w;
        }
    }
    store_partial(r, PARTIAL_MOMENTS, vec4<f32>(acc, 0.0, 0.0, 0.0));
}

// The scale s for a gap (J) in the scaled kinetic energy k_scaled, with k the whole kinetic
// energy (mirrors projection::projection_scale, with the f32 reduction's band).
fn projection_scale_of(gap: f32, k: f32, k_scaled: f32, budget: f32) -> f32 {
    let band = GPU_PROJECTION_ROUNDING * (abs(budget) + abs(k));
    if (k_scaled <= band || abs(gap) <= band || !(abs(gap) < 3.0e38)) {
        return 1.0;
    }
    let s = sqrt(max(k_scaled + gap, 0.0) / k_scaled);
    return clamp(s, 1.0 - PROJECTION_EPSILON, 1.0 + PROJECTION_EPSILON);
}

@compute @workgroup_size(64)
fn projection_scale(@builtin(local_invocation_id) lid: vec3<u32>) {
    let scaled = moment_sum(lid.x, 0u).x;
    if (lid.x != 0u) {
        return;
    }
    let k = ledger.kinetic;
    let held = k + ledger.gravitational + ledger.held;
    if (range.start == 0u) {
        projection.budget = held;
        projection.work_mark = ledger.work;
        projection.has_budget = 1u;
        projection.scale = 1.0;
        return;
    }
    let budget = projection.budget + (ledger.work - projection.work_mark);
    var gap = budget - held;
    if (projection.centre.w > 0.0) {
        // The gap in the scaled part: the energy's gap less what the new rigid motion changes.
        gap -= projection.target_velocity.w - (k - scaled);
    }
    projection.budget = budget;
    projection.work_mark = ledger.work;
    projection.scale = projection_scale_of(gap, k, scaled, budget);
}

@compute @workgroup_size(64)
fn projection_apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    let s = projection.scale;
    let rigid = projection.centre.w > 0.0;
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        let p = x[i];
        if (p.w > 0.0) {
            let old = v[i];
            var out = old.xyz * s;
            if (rigid) {
                let q = p.xyz - params.rest_com.xyz - projection.centre.xyz;
                let now = projection.velocity.xyz + cross(projection.omega.xyz, q);
                let to = projection.target_velocity.xyz + cross(projection.target_omega.xyz, q);
                out = to + s * (old.xyz - now);
            }
            v[i] = vec4<f32>(out, old.w);
        }
    }
}
