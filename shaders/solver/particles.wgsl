// Per-particle stages (mirrors src/solver/cpu.rs and src/solver/contacts.rs): predict, contact
// projection with Coulomb friction, velocity update, and Jacobi's gather of corrections.

// Jacobi: corrections of every constraint slot, and for each particle the slots that touch it
// (compressed rows, in the CPU's summation order).
@group(1) @binding(0) var<storage, read> corr: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read> incidence_offsets: array<u32>;
@group(1) @binding(2) var<storage, read> incidence_slots: array<u32>;

// Local energy-aware mode: snapshots ([0, n) this iteration's start, [n, 2n) the previous one).
@group(3) @binding(0) var<storage, read_write> snapshots: array<vec4<f32>>;
// Energy reduction: per-workgroup partial sums and the ledger.
@group(3) @binding(2) var<storage, read_write> partials: array<vec4<f32>>;
@group(3) @binding(3) var<storage, read_write> ledger: Ledger;

// The velocities' w component accumulates each particle's dissipated work (J).

@compute @workgroup_size(64)
fn predict(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        let p = x[i];
        x_prev[i] = p;
        if (p.w > 0.0) {
            let old = v[i];
            var vel = old.xyz + params.gravity.xyz * params.h;
            if (i == params.pull_particle && params.pull.w > 0.0) {
                // The soft grab (src/solver/pull.rs), p.w its effective inverse mass w̃:
                // v ← (1 − a)² v + h k w̃ (t − x) with a = h √(k w̃).
                let k = params.pull.w;
                let keep = 1.0 - params.h * sqrt(k * p.w);
                vel = vel * (keep * keep) + (params.pull.xyz - p.xyz) * (params.h * k * p.w);
            }
            v[i] = vec4<f32>(vel, old.w);
            x[i] = vec4<f32>(p.xyz + vel * params.h, p.w);
        } else {
            v[i] = vec4<f32>(0.0, 0.0, 0.0, v[i].w);
        }
    }
}

fn friction(p: vec3<f32>, prev: vec3<f32>, n: vec3<f32>, depth: f32, mu: f32) -> vec3<f32> {
    let disp = p - prev;
    let t = disp - n * dot(disp, n);
    let tl = sqrt(dot(t, t));
    let limit = mu * depth;
    if (tl <= limit) {
        return p - t;
    }
    return p - t * (limit / tl);
}

// Projects particle i out of the colliders; returns the pass's work (J; mirrors Colliders::work:
// ½ m (after − before)/h · (v_start + v_a), v_start = v − g h, v_a = (after − x_prev)/h).
fn project_contacts(i: u32) -> f32 {
    let p = x[i];
    if (p.w <= 0.0) {
        return 0.0;
    }
    var q = p.xyz;
    let prev = x_prev[i].xyz;
    if (params.has_ground != 0u) {
        let floor = params.ground_height + params.contact_offset;
        let y = q.y;
        if (y < floor) {
            let n = vec3<f32>(0.0, 1.0, 0.0);
            q = q + n * (floor - y);
            q = friction(q, prev, n, floor - y, params.ground_friction);
        }
    }
    for (var s = 0u; s < params.num_spheres; s++) {
        let sp = spheres[s];
        let r = sp.center_radius.w + params.contact_offset;
        let d = q - sp.center_radius.xyz;
        let len = sqrt(dot(d, d));
        if (len < r && len > 1.1920929e-7) {
            let n = d * (1.0 / len);
            q = q + n * (r - len);
            q = friction(q, prev, n, r - len, sp.friction.x);
        }
    }
    x[i] = vec4<f32>(q, p.w);
    let m = 1.0 / p.w;
    let v_start = v[i].xyz - params.gravity.xyz * params.h;
    let va = (q - prev) * params.inv_h;
    return 0.5 * m * dot((q - p.xyz) * params.inv_h, v_start + va);
}

@compute @workgroup_size(64)
fn contacts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        let work = project_contacts(i);
        if (work != 0.0) {
            v[i].w += work;
        }
    }
}

// The last iteration's contact pass (with in_loop_contacts), the final contact pass, then
// v = (x − x_prev)/h · keep; the passes' work and the kinetic energy the damping takes are added
// to the particle's dissipated work (mirrors particles::finish on the CPU).
@compute @workgroup_size(64)
fn finish(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        var work = 0.0;
        if (params.in_loop_contacts != 0u) {
            work += project_contacts(i);
        }
        work += project_contacts(i);
        let p = x[i];
        let old = v[i];
        if (p.w > 0.0) {
            let prev = x_prev[i].xyz;
            let m = 1.0 / p.w;
            let va = (p.xyz - prev) * params.inv_h;
            work += 0.5 * m * dot(va, va) * (params.keep * params.keep - 1.0);
            v[i] = vec4<f32>((p.xyz - prev) * (params.inv_h * params.keep), old.w + work);
        } else {
            v[i] = vec4<f32>(0.0, 0.0, 0.0, old.w);
        }
    }
}

// Local mode, start of a substep: the snapshots are the substep's start and the prediction.
@compute @workgroup_size(64)
fn local_begin(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        snapshots[params.num_particles + i] = x_prev[i];
        snapshots[i] = x[i];
    }
}

// Local mode, start of an iteration after the first: shift the snapshots.
@compute @workgroup_size(64)
fn local_snapshot(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        snapshots[params.num_particles + i] = snapshots[i];
        snapshots[i] = x[i];
    }
}

// Partial sums of kinetic and gravitational energy (about the rest centre of mass) and of the
// dissipated work, over free particles.
@compute @workgroup_size(64)
fn energy_particles(r: Reducer) {
    var acc = vec4<f32>(0.0);
    for (var i = r.gid.x; i < params.num_particles; i += stride(r.ng)) {
        let p = x[i];
        let vel = v[i];
        if (p.w > 0.0) {
            let m = 1.0 / p.w;
            acc.x += 0.5 * m * dot(vel.xyz, vel.xyz);
            acc.y += -m * dot(params.gravity.xyz, p.xyz - params.rest_com.xyz);
        }
        acc.w += vel.w;
    }
    store_partial(r, PARTIAL_PARTICLES, acc);
}

fn reduce_count(n: u32) -> u32 {
    return min((n + 63u) / 64u, REDUCE_GROUPS);
}

// The GPU's band of rounding for the balance (f32 sums; the CPU uses 1e-6 with f64 sums).
const GPU_ROUNDING: f32 = 1e-5;

// The global balance's σ (mirrors solver::energy::global_scale).
fn global_scale(h0: f32, work: f32, k1: f32, p1: f32) -> f32 {
    let goal = h0 + work - p1;
    let band = GPU_ROUNDING * (abs(h0) + abs(work) + abs(k1) + abs(p1));
    if (k1 < 1e-6 * abs(h0) || k1 <= 0.0 || abs(goal - k1) <= band) {
        return 1.0;
    }
    return clamp(sqrt(max(goal, 0.0) / k1), 0.9, 1.1);
}

// Sums the partials; range.start selects what to do with the totals: 0 sets the energy at the
// start of the next substep, 1 runs the global balance, 2 only measures.
@compute @workgroup_size(64)
fn energy_final(@builtin(local_invocation_id) lid: vec3<u32>) {
    var particles = vec4<f32>(0.0);
    var families = vec4<f32>(0.0);
    let np = reduce_count(params.num_particles);
    for (var k = lid.x; k < np; k += 64u) {
        particles += partials[PARTIAL_PARTICLES + k];
    }
    for (var f = 0u; f < FAMILY_COUNT; f++) {
        let n = reduce_count(params.counts[f]);
        for (var k = lid.x; k < n; k += 64u) {
            families += partials[PARTIAL_FAMILIES + f * REDUCE_GROUPS + k];
        }
    }
    let tp = reduce_workgroup(lid.x, particles);
    let tf = reduce_workgroup(lid.x, families);
    if (lid.x == 0u) {
        let k1 = tp.x;
        let p1 = tp.y + tf.z;
        ledger.kinetic = k1;
        ledger.gravitational = tp.y;
        ledger.elastic = tf.z;
        ledger.held = tf.w;
        ledger.work = tp.w;
        if (range.start == 0u) {
            ledger.h0 = k1 + p1;
            ledger.valid = 1u;
            ledger.sigma = 1.0;
            ledger.work_mark = tp.w;
        } else if (range.start == 1u) {
            let sigma = global_scale(ledger.h0, tp.w - ledger.work_mark, k1, p1);
            ledger.sigma = sigma;
            ledger.h0 = sigma * sigma * k1 + p1;
            ledger.work_mark = tp.w;
        }
    }
}

// The global balance: v ← σ v on free particles.
@compute @workgroup_size(64)
fn apply_scale(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    let sigma = ledger.sigma;
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        let p = x[i];
        if (p.w > 0.0 && sigma != 1.0) {
            let old = v[i];
            v[i] = vec4<f32>(old.xyz * sigma, old.w);
        }
    }
}

@compute @workgroup_size(64)
fn jacobi_apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        var sum = vec3<f32>(0.0);
        for (var k = incidence_offsets[i]; k < incidence_offsets[i + 1u]; k++) {
            sum += corr[incidence_slots[k]].xyz;
        }
        let p = x[i];
        x[i] = vec4<f32>(p.xyz + sum, p.w);
    }
}
