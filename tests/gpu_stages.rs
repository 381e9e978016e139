//! Every stage of the stage list (`eapbd::solver::stages`) on the GPU against its CPU twin: before
//! each stage of a frame the GPU takes the CPU's state (positions, start positions, velocities,
//! multipliers), both run that one stage, and they must agree: positions and velocities to a fixed
//! fraction of their scale, the multipliers to 1e-3 of their family's largest plus ten times the
//! CPU's own change when the positions move by one unit in the last place (a stiff tetrahedron's
//! multiplier responds to rounding more than lavapipe and the CPU differ by, but a GPU that fuses
//! multiply-adds or rounds its division differently meets it). The scenes and settings together
//! list every stage: predict, clear, the sweeps of all four families, Jacobi, the contacts, the
//! finish pass, the local mode's two stages, the global balance with its start, the
//! energy-momentum projection with its start, and the self-collision's candidates and projection. These tests need a GPU adapter (Mesa lavapipe in
//! CI) and fail without one.

mod common;

use std::collections::BTreeSet;
use std::sync::Arc;

use eapbd::constraints::{Form, Orthotropic};
use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::stages::{self, FrameStart, Stage};
use eapbd::solver::{CpuSolver, EnergyAware, Method, Settings};
use glam::{Vec3, Vec3A};

fn vec3(x: &[Vec3A]) -> Vec<Vec3> {
    x.iter().map(|&p| p.into()).collect()
}

/// `a` within `tol` of `b` element by element, relative to the largest `|b|` (at least `floor`).
fn close(what: &str, a: &[Vec3], b: &[Vec3], tol: f32, floor: f32) {
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    let scale = b.iter().map(|p| p.length()).fold(floor, f32::max);
    let (i, worst) = a
        .iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).length())
        .enumerate()
        .fold((0, 0.0f32), |m, (i, d)| if d > m.1 { (i, d) } else { m });
    assert!(
        worst <= tol * scale,
        "{what}: particle {i} differs by {worst:e} (scale {scale:e}): {:?} vs {:?}",
        a[i],
        b[i]
    );
}

/// Moves every coordinate by one unit in the last place, up or down in a fixed pattern: the size
/// of the rounding by which two compilers of the same arithmetic may differ. A stage's response
/// to it is the CPU's own sensitivity, which bounds what a GPU that rounds differently (fused
/// multiply-adds, its own division and square root) may differ by.
fn nudge(x: &mut [Vec3A]) {
    for (i, p) in x.iter_mut().enumerate() {
        let s = if i % 2 == 0 { f32::EPSILON } else { -f32::EPSILON };
        *p *= Vec3A::new(1.0 + s, 1.0 - s, 1.0 + s);
    }
}

/// One frame of `name` under `s`, stage by stage after `warm` frames on the CPU; returns the
/// stages it checked.
fn check_frame(
    ctx: &GpuContext,
    kernels: &Arc<Kernels>,
    name: &str,
    opts: SceneOptions,
    s: Settings,
    warm: u32,
) -> Vec<Stage> {
    let scene = scene::build(name, &opts).unwrap();
    let mut cpu = CpuSolver::<Vec3A>::new(scene.clone());
    let mut gpu = GpuSolver::new(kernels.clone(), &ctx.device, &ctx.queue, scene).unwrap();
    for _ in 0..warm {
        cpu.step_frame(&s);
    }
    let start = FrameStart {
        balance_start: s.energy_aware == EnergyAware::Global,
        projection_start: s.energy_aware == EnergyAware::Project,
        self_collision: cpu.scene().self_collision.is_some(),
    };
    let list = stages::frame(&stages::color_counts(cpu.scene()), &s, start);
    for (i, &stage) in list.iter().enumerate() {
        let p = &cpu.particles;
        gpu.set_state(&vec3(&p.x), &vec3(&p.x_prev), &vec3(&p.v), cpu.lambdas()).unwrap();
        let mut twin = cpu.clone();
        nudge(&mut twin.particles.x);
        cpu.step_stages(&[stage], &s);
        twin.step_stages(&[stage], &s);
        gpu.step_stages(&[stage], &s);
        let what = format!("{name}, {:?} {:?} {:?}, stage {i} {stage:?}", s.method, s.form, s.energy_aware);
        let state = gpu.read_state().unwrap();
        let p = &cpu.particles;
        close(&format!("{what}: positions"), &state.x, &vec3(&p.x), 1e-5, 1.0);
        close(&format!("{what}: start positions"), &gpu.read_start_positions().unwrap(), &vec3(&p.x_prev), 1e-5, 1.0);
        close(&format!("{what}: velocities"), &state.v, &vec3(&p.v), 1e-4, 1.0);
        let apart = |a: &[f32], b: &[f32]| a.iter().zip(b).map(|(a, b)| (a - b).abs()).fold(0.0f32, f32::max);
        for (f, ((g, c), t)) in state.lambdas.iter().zip(cpu.lambdas()).zip(twin.lambdas()).enumerate() {
            let scale = c.iter().fold(1e-6f32, |m, l| m.max(l.abs()));
            let (worst, own) = (apart(g, c), apart(t, c));
            assert!(
                worst <= 1e-3 * scale + 10.0 * own,
                "{what}: family {f} multipliers differ by {worst:e} (scale {scale:e}; the CPU's own change under \
                 a one-ulp nudge of the positions {own:e})"
            );
        }
    }
    list
}

#[test]
fn every_stage_matches_its_cpu_twin() {
    let (ctx, kernels) = common::gpu();
    let cloth = SceneOptions { resolution: Some(12), stiffness: 1e4, ..SceneOptions::default() };
    let base = Settings { substeps: 2, iterations: 2, damping: 0.5, threads: 1, ..Settings::default() };
    let membrane = SceneOptions { membrane: Some(Orthotropic::new(200.0, 100.0, None, 0.2).unwrap()), ..cloth };
    let cases = [
        ("cloth-sphere", cloth, base),
        ("cloth-sphere", cloth, Settings { constraint_damping: 1e-3, form: Form::Energy, ..base }),
        ("cloth-sphere", cloth, Settings { method: Method::Jacobi, ..base }),
        ("cloth-sphere", cloth, Settings { energy_aware: EnergyAware::Local, ..base }),
        ("cloth-sphere", cloth, Settings { energy_aware: EnergyAware::Global, ..base }),
        ("cloth", cloth, Settings { energy_aware: EnergyAware::Project, ..base }),
        ("cloth", membrane, base),
        ("beam", SceneOptions::default(), base),
        ("cloth-drape", cloth, base),
    ];
    let mut seen = BTreeSet::new();
    for (name, opts, s) in cases {
        for stage in check_frame(&ctx, &kernels, name, opts, s, 8) {
            seen.insert(match stage {
                Stage::Sweep { family, .. } => format!("Sweep {family}"),
                other => format!("{other:?}"),
            });
        }
    }
    let every = [
        "ProjectionStart",
        "BalanceStart",
        "Predict",
        "Clear",
        "LocalBegin",
        "LocalSnapshot",
        "Sweep 0",
        "Sweep 1",
        "Sweep 2",
        "Sweep 3",
        "Jacobi",
        "SelfPairs",
        "SelfCollision",
        "Contacts",
        "Finish",
        "Balance",
        "Projection",
    ];
    let missing: Vec<_> = every.iter().filter(|s| !seen.contains(**s)).collect();
    assert!(missing.is_empty(), "stages not checked: {missing:?} (checked {seen:?})");
}
