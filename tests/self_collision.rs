//! Cloth self-collision on the CPU: the folding cloth (`cloth-drape`) ends no frame with two
//! triangles passing through each other, where without self-collision it has thousands; two
//! sheets pressed together keep their layers apart; the GPU refuses it by name.

use eapbd::constraints::Spring;
use eapbd::mesh::crossing_pairs;
use eapbd::scene::{self, Family, Scene, SceneOptions, SelfCollision};
use eapbd::simulation::{Backend, Simulation};
use eapbd::solver::{CpuSolver, Settings};
use glam::{Vec3, Vec3A};

/// Crossing triangle pairs of `sv`'s surface, every `every` frames of `frames`.
fn crossings_over(mut sv: CpuSolver<Vec3A>, s: &Settings, frames: u32, every: u32) -> Vec<usize> {
    let mut out = Vec::new();
    for f in 1..=frames {
        sv.step_frame(s);
        if f % every == 0 {
            let x = sv.particles.positions();
            let (surface, triangles) = sv.scene().surface(&x);
            out.push(crossing_pairs(&surface, triangles).len());
        }
    }
    out
}

#[test]
fn the_draped_cloth_never_passes_through_itself() {
    let s = Settings { substeps: 10, iterations: 3, ..Settings::default() };
    let on = scene::build("cloth-drape", &SceneOptions::default()).unwrap();
    assert!(on.self_collision.is_some(), "on by default for cloth-drape");
    let with = crossings_over(CpuSolver::new(on), &s, 300, 30);
    let off = SceneOptions { self_collision: Some(false), ..SceneOptions::default() };
    let without = crossings_over(CpuSolver::new(scene::build("cloth-drape", &off).unwrap()), &s, 300, 30);
    println!("crossing pairs every 30 frames: with {with:?}, without {without:?}");
    assert!(without.iter().skip(2).all(|&c| c > 100), "without self-collision the folds pass through each other");
    assert!(with.iter().all(|&c| c == 0), "crossing pairs with self-collision: {with:?}");
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
fn a_two_layer_sheet_pressed_together_keeps_its_layers_apart() {
    let s = Settings { substeps: 10, iterations: 3, ..Settings::default() };
    let thickness = 1.0 / 20.0;
    let run = |self_collision: bool| {
        let (sc, v) = two_layers(21, 0.2, 1.0, self_collision);
        let np = sc.num_particles() / 2;
        let mut sv = CpuSolver::<Vec3A>::new(sc);
        sv.particles.set_velocities(&v);
        let mut closest = f32::MAX;
        for _ in 0..60 {
            sv.step_frame(&s);
            let x = sv.particles.positions();
            let gap = (0..np).map(|i| x[np + i].y - x[i].y).fold(f32::MAX, f32::min);
            closest = closest.min(gap);
        }
        let x = sv.particles.positions();
        let (surface, triangles) = sv.scene().surface(&x);
        (closest, crossing_pairs(&surface, triangles).len())
    };
    let (closest, crossing) = run(true);
    let (closest_off, crossing_off) = run(false);
    println!("with: closest {closest:.4} m, {crossing} crossing pairs; without: {closest_off:.4} m, {crossing_off}");
    assert!(closest_off < 0.0, "without self-collision the upper layer passes through the lower");
    assert_eq!(crossing, 0);
    assert!(closest > 0.9 * thickness, "the layers came within {closest} m (thickness {thickness} m)");
}

#[test]
fn self_collision_is_refused_by_the_gpu_backend_and_by_solids() {
    let sc = scene::build("cloth-drape", &SceneOptions::default()).unwrap();
    if let Ok(ctx) = eapbd::gpu::GpuContext::new() {
        let kernels = std::sync::Arc::new(eapbd::gpu::Kernels::new(&ctx.device));
        let err = Simulation::new(Backend::Gpu, sc, Some((&ctx, &kernels))).unwrap_err().to_string();
        assert!(err.contains("self-collision") && err.contains("--backend cpu"), "{err}");
    }
    let err = scene::build("cube", &SceneOptions { self_collision: Some(true), ..SceneOptions::default() })
        .unwrap_err()
        .to_string();
    assert!(err.contains("--self-collision") && err.contains("cloth"), "{err}");
    let err = scene::build("cloth", &SceneOptions { thickness: Some(-1.0), ..SceneOptions::default() })
        .unwrap_err()
        .to_string();
    assert!(err.contains("--thickness"), "{err}");
}
