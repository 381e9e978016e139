//! Cloth self-collision on both backends: the folding cloth (`cloth-drape`) ends no frame with
//! two triangles passing through each other, where without self-collision it has thousands; two
//! sheets pressed together keep their layers apart; the GPU finds the same candidates as the CPU
//! and projects them alike. The GPU cases need an adapter (Mesa lavapipe in CI) and fail without
//! one.

mod common;

use std::sync::Arc;

use eapbd::constraints::Spring;
use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::mesh::crossing_pairs;
use eapbd::scene::{self, Family, Scene, SceneOptions, SelfCollision};
use eapbd::simulation::{Backend, Simulation};
use eapbd::solver::stages::Stage;
use eapbd::solver::{CpuSolver, Settings, self_collision};
use glam::{Vec3, Vec3A};

/// `scene` on `backend`.
fn simulation(backend: Backend, scene: Scene, gpu: &(GpuContext, Arc<Kernels>)) -> Simulation {
    Simulation::new(backend, scene, Some((&gpu.0, &gpu.1))).unwrap()
}

/// Crossing triangle pairs of `sim`'s surface, every `every` frames of `frames`.
fn crossings_over(sim: &mut Simulation, s: &Settings, frames: u32, every: u32) -> Vec<usize> {
    let mut out = Vec::new();
    for f in 1..=frames {
        sim.step_frame(s);
        if f % every == 0 {
            let x = sim.positions().unwrap();
            let (surface, triangles) = sim.scene().surface(&x);
            out.push(crossing_pairs(&surface, triangles).len());
        }
    }
    out
}

#[test]
fn the_draped_cloth_never_passes_through_itself_on_either_backend() {
    let gpu = common::gpu();
    let on = scene::build("cloth-drape", &SceneOptions::default()).unwrap();
    assert!(on.self_collision.is_some(), "on by default for cloth-drape");
    let off = SceneOptions { self_collision: Some(false), ..SceneOptions::default() };
    let paper = Settings::default();
    assert_eq!((paper.substeps, paper.iterations), (1, 30), "the command line's default");
    let fine = Settings { substeps: 10, iterations: 3, ..paper };
    let without =
        crossings_over(&mut simulation(Backend::Cpu, scene::build("cloth-drape", &off).unwrap(), &gpu), &fine, 300, 30);
    println!("without self-collision, 10 x 3, every 30 frames: {without:?}");
    assert!(without.iter().skip(2).all(|&c| c > 100), "without self-collision the folds pass through each other");
    for backend in [Backend::Cpu, Backend::Gpu] {
        for s in [paper, fine] {
            let with = crossings_over(&mut simulation(backend, on.clone(), &gpu), &s, 300, 30);
            let what = format!("{} {} x {}", backend.name(), s.substeps, s.iterations);
            println!("{what}, every 30 frames: {with:?}");
            assert!(with.iter().all(|&c| c == 0), "{what}: crossing pairs with self-collision: {with:?}");
        }
    }
}

/// Two `n × n` sheets of `cloth-free` (no gravity, no ground, springs only), the upper `gap` m
/// above the lower and moving down onto it at `speed` m/s, with self-collision when asked (its
/// rest shape puts the layers 1 m apart, so every pair across them collides).
fn two_layers(n: u32, gap: f32, speed: f32, self_collision: bool) -> (Scene, Vec<Vec3>) {
    let opts = SceneOptions {
        resolution: Some(n),
        bending_stiffness: Some(0.0),
        self_collision: Some(true),
        ..SceneOptions::default()
    };
    let one = scene::build("cloth-free", &opts).unwrap();
    let flat = one.self_collision.clone().unwrap();
    let np = one.num_particles() as u32;
    let mut sc = one.clone();
    let lift = |p: &Vec3, dy: f32| Vec3::new(p.x, p.y + dy, p.z);
    sc.positions = flat.rest.iter().copied().chain(flat.rest.iter().map(|p| lift(p, gap))).collect();
    sc.inv_mass = [one.inv_mass.clone(), one.inv_mass.clone()].concat();
    sc.triangles = one.triangles.iter().copied().chain(one.triangles.iter().map(|t| t.map(|v| v + np))).collect();
    sc.edges = one.edges.iter().copied().chain(one.edges.iter().map(|e| e.map(|v| v + np))).collect();
    sc.edge_rest = [one.edge_rest.clone(), one.edge_rest.clone()].concat();
    let springs = one.springs.as_ref().unwrap();
    let elements: Vec<Spring> = springs
        .elements
        .iter()
        .copied()
        .chain(springs.elements.iter().map(|e| Spring { a: e.a + np, b: e.b + np, ..*e }))
        .collect();
    sc.springs = Some(Family::new(springs.params, elements, 2 * np as usize));
    sc.self_collision = self_collision.then(|| SelfCollision {
        rest: flat.rest.iter().copied().chain(flat.rest.iter().map(|p| lift(p, 1.0))).collect(),
        ..flat
    });
    let v = (0..2 * np).map(|i| if i < np { Vec3::ZERO } else { Vec3::new(0.0, -speed, 0.0) }).collect();
    (sc, v)
}

#[test]
fn a_two_layer_sheet_pressed_together_keeps_its_layers_apart_on_either_backend() {
    let gpu = common::gpu();
    let s = Settings { substeps: 10, iterations: 3, ..Settings::default() };
    let thickness = 1.0 / 20.0;
    let run = |backend: Backend, self_collision: bool| {
        let (sc, v) = two_layers(21, 0.2, 1.0, self_collision);
        let np = sc.num_particles() / 2;
        let mut sim = simulation(backend, sc, &gpu);
        sim.set_velocities(&v).unwrap();
        let mut closest = f32::MAX;
        for _ in 0..60 {
            sim.step_frame(&s);
            let x = sim.positions().unwrap();
            let gap = (0..np).map(|i| x[np + i].y - x[i].y).fold(f32::MAX, f32::min);
            closest = closest.min(gap);
        }
        let x = sim.positions().unwrap();
        let (surface, triangles) = sim.scene().surface(&x);
        (closest, crossing_pairs(&surface, triangles).len())
    };
    let (closest_off, crossing_off) = run(Backend::Cpu, false);
    assert!(closest_off < 0.0, "without self-collision the upper layer passes through the lower");
    for backend in [Backend::Cpu, Backend::Gpu] {
        let (closest, crossing) = run(backend, true);
        println!(
            "{}: closest {closest:.4} m, {crossing} crossing pairs; without: {closest_off:.4} m, {crossing_off}",
            backend.name()
        );
        assert_eq!(crossing, 0, "{}", backend.name());
        assert!(
            closest > 0.9 * thickness,
            "{}: the layers came within {closest} m (thickness {thickness} m)",
            backend.name()
        );
    }
}

/// `cpu`'s positions, start positions and velocities.
fn state(cpu: &CpuSolver<Vec3A>) -> [Vec<Vec3>; 3] {
    let p = &cpu.particles;
    [&p.x, &p.x_prev, &p.v].map(|v| v.iter().map(|&q| q.into()).collect())
}

/// A 21 × 21 `cloth-drape` landing in folds (45 frames at 10 × 3 on the CPU): its scene,
/// self-collision, settings and solver.
fn landing_drape() -> (Scene, SelfCollision, Settings, CpuSolver<Vec3A>) {
    let opts = SceneOptions { resolution: Some(21), ..SceneOptions::default() };
    let scene = scene::build("cloth-drape", &opts).unwrap();
    let sc = scene.self_collision.clone().unwrap();
    let s = Settings { substeps: 10, iterations: 3, threads: 1, ..Settings::default() };
    let mut cpu = CpuSolver::<Vec3A>::new(scene.clone());
    for _ in 0..45 {
        cpu.step_frame(&s);
    }
    (scene, sc, s, cpu)
}

#[test]
fn the_gpu_finds_the_cpus_candidates_and_projects_them_alike() {
    let (ctx, kernels) = common::gpu();
    let (scene, sc, s, cpu) = landing_drape();
    // The cloth is landing in folds; a fresh solver finds its candidates anew after the next
    // prediction, as the GPU does once its state is overwritten.
    let mut fresh = CpuSolver::<Vec3A>::new(scene.clone());
    fresh.particles = cpu.particles.clone();
    fresh.step_stages(&[Stage::Predict, Stage::Clear], &s);
    let [x, x_prev, v] = state(&fresh);
    let mut gpu = GpuSolver::new(kernels, &ctx.device, &ctx.queue, scene).unwrap();
    gpu.set_state(&x, &x_prev, &v, fresh.lambdas()).unwrap();
    fresh.step_stages(&[Stage::SelfPairs], &s);
    gpu.step_stages(&[Stage::SelfPairs], &s);
    let found = gpu.read_self_pairs().unwrap().expect("self-collision on the GPU");
    let (pairs, mine) = (found.pairs, fresh.self_pairs().pairs());
    assert_eq!((found.dropped, fresh.self_pairs().dropped()), (0, 0));
    assert_eq!(found.builds, 1);
    let far = mine.iter().filter(|&&(i, j)| sc.rest[i as usize].distance(sc.rest[j as usize]) > 0.25).count();
    println!("{} candidate pairs, {far} of them between parts of the cloth over 0.25 m apart at rest", mine.len());
    assert!(far > 100, "the cloth lies on itself");
    assert!(pairs == mine, "the GPU's {} candidate pairs differ from the CPU's {}", pairs.len(), mine.len());

    // One pass from the same state: the same moves, to rounding.
    let before = fresh.particles.x.clone();
    fresh.step_stages(&[Stage::SelfCollision], &s);
    gpu.step_stages(&[Stage::SelfCollision], &s);
    let after = gpu.read_positions().unwrap();
    let moves: Vec<f32> = before.iter().zip(&fresh.particles.x).map(|(a, b)| a.distance(*b)).collect();
    let moved = moves.iter().filter(|&&d| d > 1e-5).count();
    let largest = moves.iter().fold(0.0f32, |m, &d| m.max(d));
    let worst = after.iter().zip(&fresh.particles.x).map(|(g, c)| g.distance(Vec3::from(*c))).fold(0.0f32, f32::max);
    println!(
        "{moved} particles moved over 10 µm (at most {largest:e} m); the GPU's positions within {worst:e} m of the CPU's"
    );
    assert!(moved > 50, "the pass pushes particles apart ({moved} moved over 10 µm)");
    // Positions near 1 m round at 1e-7 m: a GPU that fuses multiply-adds differs by that much.
    assert!(worst <= 1e-3 * largest, "the GPU's pass differs from the CPU's by {worst:e} m");
}

#[test]
fn references_renewed_on_either_backend_give_the_same_candidates() {
    // After a first finding, a common translation, a few particles moved beyond the margin and
    // the others within it: the CPU finds only the renewed particles' candidates, the GPU all of
    // them again, from references that agree to the bit.
    let (ctx, kernels) = common::gpu();
    let (scene, sc, s, cpu) = landing_drape();
    let [x, x_prev, v] = state(&cpu);
    let mut gpu = GpuSolver::new(kernels, &ctx.device, &ctx.queue, scene).unwrap();
    gpu.set_state(&x, &x_prev, &v, cpu.lambdas()).unwrap();
    let mut fresh = CpuSolver::<Vec3A>::new(cpu.scene().clone());
    fresh.particles = cpu.particles.clone();
    fresh.step_stages(&[Stage::SelfPairs], &s);
    gpu.step_stages(&[Stage::SelfPairs], &s);
    let before = fresh.self_pairs().pairs();
    assert_eq!(gpu.read_self_pairs().unwrap().unwrap().pairs, before);

    let m = self_collision::margin(&sc);
    let moved: Vec<Vec3> = x
        .iter()
        .enumerate()
        .map(|(i, &p)| {
            let wobble = Vec3::new((i % 7) as f32 - 3.0, (i % 5) as f32 - 2.0, (i % 3) as f32 - 1.0) * (0.1 * m);
            let far = if i % 37 == 5 { Vec3::new(3.0 * m, -2.0 * m, 4.0 * m) } else { Vec3::ZERO };
            p + Vec3::new(0.01, -0.02, 0.005) + wobble + far
        })
        .collect();
    fresh.particles.x = moved.iter().map(|&p| p.into()).collect();
    gpu.overwrite_positions(&moved).unwrap();
    fresh.step_stages(&[Stage::SelfPairs], &s);
    gpu.step_stages(&[Stage::SelfPairs], &s);
    let found = gpu.read_self_pairs().unwrap().unwrap();
    let mine = fresh.self_pairs().pairs();
    assert_eq!((found.builds, fresh.self_pairs().builds()), (2, 2));
    assert_ne!(mine, before, "the moved particles have new candidates");
    assert!(
        found.pairs == mine,
        "the GPU's {} candidate pairs differ from the CPU's {}",
        found.pairs.len(),
        mine.len()
    );
    // Every pair within the query distance now is a candidate.
    let r = self_collision::QUERY * sc.thickness;
    let neighbour = self_collision::neighbour_distance(&sc);
    for i in 0..moved.len() {
        for j in i + 1..moved.len() {
            if moved[i].distance(moved[j]) < r && sc.rest[i].distance(sc.rest[j]) > neighbour {
                assert!(mine.binary_search(&(i as u32, j as u32)).is_ok(), "({i}, {j}) is not a candidate");
            }
        }
    }
}

#[test]
fn self_collision_is_refused_by_solids_and_a_bad_thickness() {
    let err = scene::build("cube", &SceneOptions { self_collision: Some(true), ..SceneOptions::default() })
        .unwrap_err()
        .to_string();
    assert!(err.contains("--self-collision") && err.contains("cloth"), "{err}");
    for t in [-1.0, 0.05] {
        // The default 41 × 41 cloth's spacing is 0.025 m: 0.05 m is two of them.
        let err = scene::build("cloth", &SceneOptions { thickness: Some(t), ..SceneOptions::default() })
            .unwrap_err()
            .to_string();
        assert!(err.contains("--thickness"), "{err}");
    }
    let fine = SceneOptions { thickness: Some(0.035), ..SceneOptions::default() };
    assert_eq!(scene::build("cloth-drape", &fine).unwrap().self_collision.unwrap().thickness, 0.035);
}
