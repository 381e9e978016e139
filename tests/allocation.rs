//! Heap allocations per frame, counted by a counting global allocator: the CPU solver's
//! `step_frame` allocates nothing after warm-up (Gauss-Seidel, one thread); on every core it
//! allocates at most a few times a frame (the team's one wake-up) and gives it all back; the GPU solver creates no device memory per frame and its
//! per-frame host allocations do not grow with the scene or with the number of frames.

use std::alloc::System;
use std::sync::{Arc, Mutex, MutexGuard};

use eapbd::constraints::{Bend, Form, Spring};
use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::scene::{self, Scene, SceneOptions};
use eapbd::solver::{CpuSolver, Settings};
use glam::Vec3A;
use stats_alloc::{INSTRUMENTED_SYSTEM, Region, Stats, StatsAlloc};

#[global_allocator]
static GLOBAL: &StatsAlloc<System> = &INSTRUMENTED_SYSTEM;

/// The counters are process-wide: the tests of this file measure one at a time.
static SERIAL: Mutex<()> = Mutex::new(());

fn serial() -> MutexGuard<'static, ()> {
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

fn cloth(n: u32) -> Scene {
    scene::build("cloth", &SceneOptions { resolution: Some(n), ..SceneOptions::default() }).unwrap()
}

/// Allocator activity during `frames` frames of the CPU solver, after `warm` frames.
fn cpu_frames(scene: Scene, s: &Settings, warm: u32, frames: u32) -> Stats {
    let mut sv = CpuSolver::<Vec3A>::new(scene);
    for _ in 0..warm {
        sv.step_frame(s);
    }
    let region = Region::new(GLOBAL);
    for _ in 0..frames {
        sv.step_frame(s);
    }
    region.change()
}

#[test]
fn cpu_gauss_seidel_single_thread_allocates_nothing_per_frame() {
    let _guard = serial();
    let paper = scene::build("cloth-paper", &SceneOptions::default()).unwrap();
    let cases = [
        ("cloth 32 (springs + bending), 30 × 1", cloth(32), 30, 1, Form::Compliant),
        ("cloth 32, 5 × 6", cloth(32), 5, 6, Form::Compliant),
        ("cloth-paper, energy form", paper, 30, 1, Form::Energy),
    ];
    for (what, scene, iterations, substeps, form) in cases {
        let s = Settings { iterations, substeps, form, threads: 1, ..Settings::default() };
        // The counters are process-wide: threads another test left (the team's pool, the GPU
        // driver's) may still allocate or free while this one measures. A solver that allocates
        // per frame does so in every measurement; one clean measurement of three passes.
        let mut st = cpu_frames(scene.clone(), &s, 3, 20);
        for _ in 0..2 {
            if st.allocations + st.reallocations > 0 {
                st = cpu_frames(scene.clone(), &s, 3, 20);
            }
        }
        assert_eq!(
            (st.allocations, st.reallocations, st.bytes_allocated),
            (0, 0, 0),
            "{what}: step_frame allocated after warm-up: {st:?}"
        );
    }
}

#[test]
fn cpu_every_core_allocations_do_not_accumulate() {
    let _guard = serial();
    // Color groups of about 8,000 springs: above the threshold that splits a group over threads.
    let s = Settings { threads: 0, ..Settings::default() };
    let frames = 20;
    let st = cpu_frames(cloth(128), &s, 3, frames);
    // The frame wakes the team once (one broadcast of the pool, which allocates its jobs); what it
    // allocates it gives back.
    println!(
        "threads 0, cloth 128: {:.1} allocations per frame, {} bytes allocated in {frames} frames",
        st.allocations as f64 / frames as f64,
        st.bytes_allocated
    );
    let net = st.bytes_allocated as i64 + st.bytes_reallocated as i64 - st.bytes_deallocated as i64;
    assert!(net <= 64 * 1024, "memory held grew by {net} bytes over {frames} frames: {st:?}");
    assert!(st.allocations <= 4 * frames as usize, "{} allocations in {frames} frames", st.allocations);
}

/// Device memory in use by the adapter's allocator: (allocations, bytes), where it reports them.
fn device_memory(ctx: &GpuContext) -> Option<(usize, u64)> {
    ctx.device.generate_allocator_report().map(|r| (r.allocations.len(), r.total_allocated_bytes))
}

/// The adapter allocator's allocations as `(label, bytes)`, sorted (empty where it reports none).
fn device_allocations(ctx: &GpuContext) -> Vec<(String, u64)> {
    let mut v: Vec<(String, u64)> = ctx
        .device
        .generate_allocator_report()
        .map(|r| r.allocations.iter().map(|a| (a.name.clone(), a.size)).collect())
        .unwrap_or_default();
    v.sort();
    v
}

/// The entries of `after` not in `before` (a multiset difference).
fn added(before: &[(String, u64)], after: &[(String, u64)]) -> Vec<(String, u64)> {
    let mut left = before.to_vec();
    after
        .iter()
        .filter(|a| match left.iter().position(|b| b == *a) {
            Some(i) => {
                left.swap_remove(i);
                false
            }
            None => true,
        })
        .cloned()
        .collect()
}

/// Host allocations per frame of the GPU solver on `scene` (frames recorded, submitted and waited
/// for), over two windows of frames; checks that no device memory is allocated meanwhile and that
/// the solver's buffer accounting is what the device holds for it.
fn gpu_frames(ctx: &GpuContext, kernels: &Arc<Kernels>, scene: Scene) -> (f64, f64) {
    let s = Settings::default();
    let before = device_memory(ctx);
    let listed = device_allocations(ctx);
    let mut g = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, scene).unwrap();
    for _ in 0..3 {
        g.step_frame(&s);
        ctx.wait().unwrap();
    }
    let warm = device_memory(ctx);
    // The accounting: 3 × vec4<f32> per particle; elements and one f32 multiplier per constraint.
    let (sc, m) = (g.scene(), g.memory());
    let springs = sc.springs.as_ref().map_or(0, |f| f.len() * size_of::<Spring>());
    let bends = sc.bends.as_ref().map_or(0, |f| f.len() * size_of::<Bend>());
    assert_eq!(m.particles, 48 * sc.num_particles() as u64);
    assert_eq!(m.constraints, (springs + bends + 4 * sc.num_constraints()) as u64);
    if before.is_some() {
        // What the device allocated for the solver: the allocations made since `before`, less
        // wgpu's own staging buffers, which come and go with uploads (on a discrete GPU one
        // alive at `before` is given back meanwhile, so the difference of the totals falls short).
        let made = added(&listed, &device_allocations(ctx));
        let held: u64 = made.iter().filter(|(name, _)| !name.starts_with("(wgpu internal)")).map(|a| a.1).sum();
        assert!(
            held >= g.memory_bytes() && held <= g.memory_bytes() + 64 * 1024 + g.memory_bytes() / 8,
            "device holds {held} bytes for the solver, which counts {} ({:?}); allocations made: {:?}; \
             given back: {:?}",
            g.memory_bytes(),
            g.memory(),
            made,
            added(&device_allocations(ctx), &listed)
        );
    }
    let mut per_frame = [0.0; 2];
    for window in &mut per_frame {
        let frames = 10;
        let region = Region::new(GLOBAL);
        for _ in 0..frames {
            g.step_frame(&s);
            ctx.wait().unwrap();
        }
        *window = region.change().allocations as f64 / frames as f64;
    }
    assert_eq!(device_memory(ctx), warm, "device memory (allocations, bytes) changed while frames ran");
    (per_frame[0], per_frame[1])
}

#[test]
fn gpu_frames_create_no_device_memory() {
    let _guard = serial();
    let ctx = GpuContext::new().unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    if device_memory(&ctx).is_none() {
        println!("this adapter reports no device allocations: only host allocations are checked");
    }
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let small = gpu_frames(&ctx, &kernels, cloth(24));
    let large = gpu_frames(&ctx, &kernels, cloth(96));
    println!("GPU host allocations per frame: cloth 24 {small:?}, cloth 96 {large:?}");
    for (what, (first, second)) in [("cloth 24", small), ("cloth 96", large)] {
        assert!(second <= first + 1.0, "{what}: host allocations per frame grew from {first} to {second}");
    }
    assert!(
        large.1 <= 1.5 * small.1 + 4.0,
        "host allocations per frame grow with the scene: {} (cloth 24) against {} (cloth 96)",
        small.1,
        large.1
    );
}
