// Per-particle stages (mirrors src/solver/cpu.rs and src/solver/contacts.rs): predict, contact
// projection with Coulomb friction, velocity update, and Jacobi's gather of corrections.

// Jacobi: corrections of every constraint slot, and for each particle the slots that touch it
// (compressed rows, in the CPU's summation order).
@group(1) @binding(0) var<storage, read> corr: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read> incidence_offsets: array<u32>;
@group(1) @binding(2) var<storage, read> incidence_slots: array<u32>;

@compute @workgroup_size(64)
fn predict(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        let p = x[i];
        x_prev[i] = p;
        if (p.w > 0.0) {
            let vel = v[i].xyz + params.gravity.xyz * params.h;
            v[i] = vec4<f32>(vel, 0.0);
            x[i] = vec4<f32>(p.xyz + vel * params.h, p.w);
        } else {
            v[i] = vec4<f32>(0.0);
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

fn project_contacts(i: u32) {
    let p = x[i];
    if (p.w <= 0.0) {
        return;
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
}

@compute @workgroup_size(64)
fn contacts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        project_contacts(i);
    }
}

// The final contact pass, then v = (x − x_prev)/h · keep.
@compute @workgroup_size(64)
fn finish(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) ng: vec3<u32>) {
    for (var i = gid.x; i < params.num_particles; i += stride(ng)) {
        project_contacts(i);
        let p = x[i];
        if (p.w > 0.0) {
            v[i] = vec4<f32>((p.xyz - x_prev[i].xyz) * (params.inv_h * params.keep), 0.0);
        } else {
            v[i] = vec4<f32>(0.0);
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
