//! The team against one thread on scenes small enough for Miri, which checks the threads' shared
//! views for data races and for references that alias another thread's writes:
//! `MIRIFLAGS=-Zmiri-num-cpus=2 cargo +nightly miri test --lib team_tests` (README, "Threads").
//! The same tests run in the ordinary test command.

use glam::Vec3A;

use crate::constraints::Form;
use crate::scene::{self, SceneOptions};
use crate::solver::{EnergyAware, Method, Settings};

use super::CpuSolver;

/// Positions, velocities and the dissipated work after `frames` frames of `name` at `settings`,
/// and the number of frames the team ran.
fn run(name: &str, resolution: u32, settings: Settings, frames: u32) -> (Vec<Vec3A>, Vec<Vec3A>, u64, u32) {
    let opts = SceneOptions {
        resolution: Some(resolution),
        stiffness: 1e5,
        bending_stiffness: Some(0.0),
        ..SceneOptions::default()
    };
    let mut s = CpuSolver::<Vec3A>::new(scene::build(name, &opts).expect("a built-in scene"));
    for _ in 0..frames {
        s.step_frame(&settings);
    }
    (s.particles.x.clone(), s.particles.v.clone(), s.ledger.dissipated.to_bits(), s.team_time().frames)
}

/// Two threads give one thread's bits at `settings` on a 17 × 17 cloth (springs only) over a sphere: the
/// structural springs' color groups hold 136 elements, above `PARALLEL_MIN_GROUP`, so the team
/// splits them; the sphere gives contacts in the loop and in the finish pass.
fn two_threads_match_one(settings: Settings) {
    let base = Settings { iterations: 2, substeps: 2, damping: 0.5, threads: 2, ..Settings::default() };
    let settings = Settings { iterations: base.iterations, substeps: base.substeps, damping: base.damping, ..settings };
    let one = run("cloth-sphere", 17, Settings { threads: 1, ..settings }, 1);
    let two = run("cloth-sphere", 17, Settings { threads: 2, ..settings }, 1);
    assert_eq!(two.3, 1, "{settings:?}: the frame ran on the team");
    assert_eq!(one.3, 0, "{settings:?}: one thread runs no team");
    assert_eq!(one.0, two.0, "{settings:?}: positions");
    assert_eq!(one.1, two.1, "{settings:?}: velocities");
    assert_eq!(one.2, two.2, "{settings:?}: dissipated work");
}

/// Chained substeps with the lean kernels: a thread that is ahead sweeps the next substep while
/// the other's finish pass still writes its particles' start positions.
#[test]
fn chained_lean_kernels() {
    two_threads_match_one(Settings::default());
}

/// Chained substeps with constraint damping: the general update reads the substep-start positions
/// that the other thread's finish pass writes.
#[test]
fn chained_damped_update() {
    two_threads_match_one(Settings { constraint_damping: 1e-3, form: Form::Energy, ..Settings::default() });
}

/// The global balance: thread 0 scales every velocity between two barriers.
#[test]
fn global_balance() {
    two_threads_match_one(Settings { energy_aware: EnergyAware::Global, ..Settings::default() });
}

/// The local mode: snapshots and start energies read every particle between barriers.
#[test]
fn local_mode() {
    two_threads_match_one(Settings { energy_aware: EnergyAware::Local, ..Settings::default() });
}

/// Jacobi: every thread reads every position, then adds its particles' corrections.
#[test]
fn jacobi() {
    two_threads_match_one(Settings { method: Method::Jacobi, ..Settings::default() });
}

/// Self-collision: thread 0 finds the candidates between barriers, then each thread gathers its
/// particles' moves. A 17 × 17 `cloth-drape` folded in two, the upper half 0.8 thicknesses above
/// the lower, so the first pass pushes the layers apart.
#[test]
fn self_collision() {
    let opts = SceneOptions {
        resolution: Some(17),
        stiffness: 1e5,
        bending_stiffness: Some(0.0),
        self_collision: Some(true),
        ..SceneOptions::default()
    };
    let mut sc = scene::build("cloth-drape", &opts).expect("a built-in scene");
    let (rest, t) = sc.self_collision.as_ref().map(|c| (c.rest.clone(), c.thickness)).expect("self-collision");
    let mid = rest.iter().map(|p| p.z).sum::<f32>() / rest.len() as f32;
    sc.positions = rest
        .iter()
        .map(|p| {
            let folded = p.z > mid;
            let z = if folded { 2.0 * mid - p.z } else { p.z };
            glam::Vec3::new(p.x, 0.1 + if folded { 0.8 * t } else { 0.0 }, z)
        })
        .collect();
    let base = Settings { iterations: 2, substeps: 2, damping: 0.5, ..Settings::default() };
    let frame = |threads: u32| {
        let mut s = CpuSolver::<Vec3A>::new(sc.clone());
        s.step_frame(&Settings { threads, ..base });
        (s.particles.x.clone(), s.particles.v.clone(), s.team_time().frames, s.self_pairs().len())
    };
    let (one, two) = (frame(1), frame(2));
    assert_eq!((one.2, two.2), (0, 1), "the frame ran on the team");
    assert!(one.3 > 100, "candidates across the fold: {}", one.3);
    assert_eq!(one.0, two.0, "positions");
    assert_eq!(one.1, two.1, "velocities");
    // The layers were pushed apart: no particle of the upper half within 0.9 thicknesses of one
    // of the lower half right below it.
    let n = 17;
    let stacked = (0..n / 2).flat_map(|r| (0..n).map(move |c| (r * n + c, (n - 1 - r) * n + c)));
    let gap = stacked.map(|(a, b)| (one.0[a] - one.0[b]).length()).fold(f32::MAX, f32::min);
    assert!(gap > 0.9 * t, "closest pair across the fold {gap} m, thickness {t} m");
}
