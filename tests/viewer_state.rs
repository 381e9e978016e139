//! The viewer without a window: the widgets edit the state, and the next frame runs with it;
//! dragging a particle, the strain kernel and the view modes on the GPU (lavapipe in CI).
#![cfg(feature = "viewer")]

use std::sync::Arc;

use eapbd::compare::Compare;
use eapbd::constraints::Form;
use eapbd::gpu::{GpuContext, Kernels, read_buffer};
use eapbd::render::{OFFSCREEN_FORMAT, OffscreenTarget};
use eapbd::scene::{self, Scene, SceneOptions};
use eapbd::simulation::{Backend, Simulation};
use eapbd::solver::{EnergyAware, Settings};
use eapbd::viewer::grab::Grab;
use eapbd::viewer::session::SceneInfo;
use eapbd::viewer::strain::{StrainPass, ramp, vertex_strain};
use eapbd::viewer::{ColorMode, SceneChoice, Session, ViewerState, twin, ui};
use egui::accesskit::Role;
use egui_kittest::Harness;
use egui_kittest::kittest::{By, Queryable};
use glam::{Vec3, Vec4};

fn gpu() -> GpuContext {
    GpuContext::new().unwrap_or_else(|e| panic!("the viewer tests need a GPU adapter: {e}"))
}

fn start_state(backend: Backend) -> ViewerState {
    let choice = SceneChoice::new("cloth-paper", &SceneOptions::default()).unwrap();
    ViewerState::new(choice, Settings::default(), backend)
}

const W: u32 = 320;
const H: u32 = 240;

/// Applies the state and draws one frame offscreen.
fn frame(ctx: &GpuContext, s: &mut Session, target: &OffscreenTarget) -> image::RgbaImage {
    s.apply_changes(ctx);
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    s.encode_frame(&mut enc, target.views(), [0.0, 0.0, W as f32, H as f32]).unwrap();
    ctx.queue.submit([enc.finish()]);
    s.after_submit();
    let img = target.read_rgba(&ctx.device, &ctx.queue).unwrap();
    s.poll();
    img
}

/// The control panel under test, editing the start state on `backend`.
fn controls(backend: Backend) -> Harness<'static, ViewerState> {
    let info = SceneInfo::default();
    Harness::builder()
        .with_size([330.0, 1500.0])
        .build_ui_state(move |ui, s: &mut ViewerState| ui::controls(ui, s, &info), start_state(backend))
}

#[test]
fn keyboard_shortcuts_pause_step_and_reset() {
    let mut s = start_state(Backend::Cpu);
    assert!(!s.paused);
    assert!(s.shortcut(' '));
    assert!(s.paused && !s.requests.step);
    assert!(s.shortcut(' '));
    assert!(!s.paused);
    // S pauses a running simulation and steps one frame.
    assert!(s.shortcut('S'));
    assert!(s.paused && s.requests.step);
    assert!(s.shortcut('r'));
    assert!(s.requests.reset);
    assert!(s.shortcut('c'));
    assert_eq!(s.compare, Some(Compare::EnergyAware));
    assert!(s.shortcut('C'));
    assert_eq!(s.compare, None);
    let before = s.clone();
    assert!(!s.shortcut('x'), "x is no shortcut");
    assert_eq!(s, before);
}

#[test]
fn the_compare_control_runs_both_sides_with_their_settings() {
    // Choose "energy-aware" in the Compare box as a user would; then both sessions run a frame:
    // the left with energy-aware off, the right with project, the rest as the panels say.
    let mut harness = controls(Backend::Cpu);
    harness.get_by_label("Compare").click();
    harness.run();
    harness.get_by_label("energy-aware").click();
    harness.run();
    let mut edited = harness.state().clone();
    assert_eq!(edited.compare, Some(Compare::EnergyAware));
    edited.settings.iterations = 12;

    let ctx = gpu();
    let target = OffscreenTarget::new(&ctx.device, 2 * W, H, 4).unwrap();
    let mut main = Session::new(&ctx, OFFSCREEN_FORMAT, 4, edited).unwrap();
    let mut twin_session = None;
    for _ in 0..2 {
        twin::sync(&mut twin_session, &mut main, &ctx, OFFSCREEN_FORMAT, 4).unwrap();
        let t = twin_session.as_mut().expect("compare mode makes the twin");
        main.apply_changes(&ctx);
        t.apply_changes(&ctx);
        let [left, right] = twin::halves([0.0, 0.0, 2.0 * W as f32, H as f32]);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        main.encode_frame(&mut enc, target.views(), left).unwrap();
        t.encode_frame(&mut enc, target.views(), right).unwrap();
        ctx.queue.submit([enc.finish()]);
    }
    let t = twin_session.as_ref().unwrap();
    let (l, r) = (main.last_settings.unwrap(), t.last_settings.unwrap());
    assert_eq!((l.energy_aware, r.energy_aware), (EnergyAware::Off, EnergyAware::Project));
    assert_eq!((l.iterations, r.iterations), (12, 12), "the rest is the panels' on both sides");
    assert_eq!((main.frame, t.frame), (2, 2), "both started together");

    // Turning compare mode off drops the twin.
    main.state.compare = None;
    twin::sync(&mut twin_session, &mut main, &ctx, OFFSCREEN_FORMAT, 4).unwrap();
    assert!(twin_session.is_none() && main.side.is_none());
}

#[test]
fn compare_mode_pulls_the_same_particle_on_both_sides() {
    // Grab the cloth in the left half: the twin holds the same grab, both runs pull that particle
    // towards the target, and letting go lets go in both.
    let ctx = gpu();
    let target = OffscreenTarget::new(&ctx.device, 2 * W, H, 4).unwrap();
    let mut state = start_state(Backend::Cpu);
    state.compare = Some(Compare::EnergyAware);
    state.settings.substeps = 10;
    state.settings.iterations = 3;
    let mut main = Session::new(&ctx, OFFSCREEN_FORMAT, 4, state).unwrap();
    let mut twin_session = None;
    let [left, right] = twin::halves([0.0, 0.0, 2.0 * W as f32, H as f32]);
    let size = glam::Vec2::new(left[2], left[3]);
    let step = |main: &mut Session, twin_session: &mut Option<Session>| {
        twin::sync(twin_session, main, &ctx, OFFSCREEN_FORMAT, 4).unwrap();
        let t = twin_session.as_mut().expect("compare mode makes the twin");
        main.apply_changes(&ctx);
        t.apply_changes(&ctx);
        let mut enc = ctx.device.create_command_encoder(&Default::default());
        main.encode_frame(&mut enc, target.views(), left).unwrap();
        t.encode_frame(&mut enc, target.views(), right).unwrap();
        ctx.queue.submit([enc.finish()]);
    };
    step(&mut main, &mut twin_session);
    // The first pixel of a coarse grid over the left half that hits the cloth.
    let grid = (1..8).flat_map(|i| (1..8).map(move |j| glam::Vec2::new(i as f32, j as f32) / 8.0));
    let pixel = grid.map(|f| f * size).find(|&p| main.grab_at(p, size)).expect("the cloth is in the left half");
    let g = main.grab().unwrap();
    main.drag_to(pixel - glam::Vec2::new(0.0, 30.0), size);
    for _ in 0..20 {
        step(&mut main, &mut twin_session);
    }
    let t = twin_session.as_ref().unwrap();
    assert_eq!(t.grab().map(|t| t.particle), Some(g.particle), "the twin holds the same particle");
    let aim = main.grab().unwrap().target;
    for s in [&main, t] {
        let x = s.simulation().positions().unwrap()[g.particle as usize];
        assert!(x.distance(aim) < 0.05, "{:?}: the pulled particle at {x}, the target at {aim}", s.side);
    }
    main.release();
    step(&mut main, &mut twin_session);
    assert!(twin_session.as_ref().unwrap().grab().is_none(), "letting go lets go in both");
}

#[test]
fn widgets_change_the_solver_settings_on_the_next_frame() {
    // Drive the control panel as a user would: the iterations and stiffness sliders, the
    // energy-aware radio button.
    let mut harness = controls(Backend::Gpu);
    // A slider and its number field share the label: set the slider.
    harness.get(By::new().role(Role::Slider).label("Iterations")).set_value_accesskit(55.0);
    harness.run();
    harness.get(By::new().role(Role::Slider).label("Stiffness")).set_value_accesskit(2.0e5);
    harness.run();
    harness.get_by_label("global").click();
    harness.run();
    harness.get_by_label("energy").click();
    harness.run();
    let edited = harness.state().clone();
    assert_eq!(edited.settings.iterations, 55);
    assert_eq!(edited.settings.energy_aware, EnergyAware::Global);
    assert_eq!(edited.settings.form, Form::Energy);
    assert!((edited.choice.stiffness - 2.0e5).abs() < 1.0, "stiffness {}", edited.choice.stiffness);

    let ctx = gpu();
    let target = OffscreenTarget::new(&ctx.device, W, H, 4).unwrap();
    let mut session = Session::new(&ctx, OFFSCREEN_FORMAT, 4, start_state(Backend::Gpu)).unwrap();
    for _ in 0..3 {
        frame(&ctx, &mut session, &target);
    }
    let Simulation::Gpu(g) = session.simulation() else { panic!("expected the GPU backend") };
    assert_eq!(g.last_settings(), Some(&Settings::default()));
    let x_before = g.read_positions().unwrap();

    // The next frame runs with the edited state: the settings as they are, the stiffness by a
    // rebuild that keeps the cloth's motion.
    session.state = edited.clone();
    frame(&ctx, &mut session, &target);
    let Simulation::Gpu(g) = session.simulation() else { panic!("expected the GPU backend") };
    assert_eq!(g.last_settings(), Some(&edited.settings));
    assert_eq!(session.last_settings, Some(edited.settings));
    assert_eq!(session.frame, 4, "a material change keeps the frame count (no reset)");
    let springs = g.scene().springs.as_ref().unwrap();
    assert!(springs.elements.iter().all(|s| (s.k - 2.0e5).abs() < 1.0));
    let x_after = g.read_positions().unwrap();
    let moved = x_before.iter().zip(&x_after).map(|(a, b)| a.distance(*b)).fold(0.0f32, f32::max);
    assert!(moved < 0.05, "the cloth jumped by {moved} m: its state was not carried over");
    let free = x_before.len() - 1;
    let start = scene::build("cloth-paper", &SceneOptions::default()).unwrap().positions[free];
    assert!(x_before[free].distance(start) > 1e-3, "the cloth was moving before the change");

    // A backend switch carries the state to the CPU solver.
    session.state.backend = Backend::Cpu;
    frame(&ctx, &mut session, &target);
    let Simulation::Cpu(c) = session.simulation() else { panic!("expected the CPU backend") };
    assert!(c.particles.positions().iter().zip(&x_after).all(|(a, b)| a.distance(*b) < 0.05));
    assert!(session.stats.is_some());
}

/// `cloth-paper` on the CPU and on the GPU (in that order), its free corner and where it starts.
fn cloth_on_both_backends(ctx: &GpuContext) -> (Scene, u32, Vec3, Vec<Simulation>) {
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let sc = scene::build("cloth-paper", &SceneOptions::default()).unwrap();
    let corner = (sc.num_particles() - 1) as u32;
    let start = sc.positions[corner as usize];
    let sims = [Backend::Cpu, Backend::Gpu]
        .into_iter()
        .map(|b| Simulation::new(b, sc.clone(), Some((ctx, &kernels))).unwrap())
        .collect();
    (sc, corner, start, sims)
}

#[test]
fn dragging_a_particle_is_the_same_on_both_backends() {
    let ctx = gpu();
    let (sc, corner, start, mut sims) = cloth_on_both_backends(&ctx);
    let s = Settings::default();
    let inv_mass = sc.inv_mass[corner as usize];
    let mut grab = Grab { particle: corner, target: start, inv_mass, plane_normal: Vec3::Z, stiffness: 0.0 };
    for f in 0..40 {
        grab.target = start + Vec3::new(0.0, 0.01 * f as f32, 0.01 * f as f32);
        for sim in &mut sims {
            grab.hold(sim, &ctx.queue);
            sim.step_frame(&s);
        }
    }
    let cpu = sims[0].positions().unwrap();
    let gpu_x = sims[1].positions().unwrap();
    assert!(cpu[corner as usize].distance(grab.target) < 1e-6, "the held particle is at the target");
    assert!(gpu_x[corner as usize].distance(grab.target) < 1e-6);
    let diff = cpu.iter().zip(&gpu_x).map(|(a, b)| a.distance(*b)).fold(0.0f32, f32::max);
    assert!(diff < 1e-3, "CPU and GPU differ by {diff} m while dragging");
    // The free corner was lifted: its neighbour follows it up.
    assert!(cpu[corner as usize - 1].y > 1.0, "neighbour at {}", cpu[corner as usize - 1].y);
    for sim in &mut sims {
        grab.release(sim, &ctx.queue);
    }
    let Simulation::Gpu(g) = &sims[1] else { unreachable!() };
    let w = g.read_state().unwrap().w[corner as usize];
    let Simulation::Cpu(c) = &sims[0] else { unreachable!() };
    assert_eq!(w, sc.inv_mass[corner as usize]);
    assert_eq!(c.particles.w[corner as usize], sc.inv_mass[corner as usize]);
}

#[test]
fn the_soft_grab_pulls_on_both_backends_without_pinning() {
    let ctx = gpu();
    let (sc, corner, start, mut sims) = cloth_on_both_backends(&ctx);
    let inv_mass = sc.inv_mass[corner as usize];
    let mut grab = Grab { particle: corner, target: start, inv_mass, plane_normal: Vec3::Z, stiffness: 1000.0 };
    // Held up, a third of the way towards the pins (where the cloth reaches without stretching).
    let pins: Vec<Vec3> = sc.positions.iter().zip(&sc.inv_mass).filter(|(_, w)| **w == 0.0).map(|(x, _)| *x).collect();
    let mid = pins.iter().sum::<Vec3>() / pins.len() as f32;
    for f in 0..40 {
        grab.target = start + (mid - start) * (f as f32 / 120.0);
        for sim in &mut sims {
            let pull = grab.hold(sim, &ctx.queue);
            assert!(pull.is_some(), "a soft grab pulls through the settings");
            sim.step_frame(&Settings { pull, substeps: 10, iterations: 3, ..Settings::default() });
        }
    }
    let (cpu, gpu_x) = (sims[0].positions().unwrap(), sims[1].positions().unwrap());
    for x in [&cpu, &gpu_x] {
        // Held near the target, where the unheld corner would have fallen away.
        let p = x[corner as usize];
        assert!(p.distance(grab.target) < 0.05, "the pulled corner at {p}, the target at {}", grab.target);
    }
    // Without bending this cloth folds chaotically (tests/gpu_parity.rs), so the backends are
    // compared where the grab holds the cloth: at the pulled corner.
    let diff = cpu[corner as usize].distance(gpu_x[corner as usize]);
    assert!(diff < 1e-2, "CPU and GPU differ by {diff} m at the pulled corner");
    for sim in &mut sims {
        grab.release(sim, &ctx.queue);
    }
    // Never pinned: the inverse mass stays the particle's on both backends.
    let Simulation::Gpu(g) = &sims[1] else { unreachable!() };
    assert_eq!(g.read_state().unwrap().w[corner as usize], inv_mass);
    let Simulation::Cpu(c) = &sims[0] else { unreachable!() };
    assert_eq!(c.particles.w[corner as usize], inv_mass);
}

#[test]
fn strain_kernel_matches_its_cpu_twin() {
    let ctx = gpu();
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let sc = scene::build("cloth-free", &SceneOptions { resolution: Some(12), ..SceneOptions::default() }).unwrap();
    let mut sim = Simulation::new(Backend::Gpu, sc.clone(), Some((&ctx, &kernels))).unwrap();
    for _ in 0..5 {
        sim.step_frame(&Settings { iterations: 3, ..Settings::default() });
    }
    let Simulation::Gpu(g) = &sim else { unreachable!() };
    let pass = StrainPass::new(&ctx.device, &sc, &g.x);
    let mut enc = ctx.device.create_command_encoder(&Default::default());
    pass.encode(&ctx.queue, &mut enc, 0.2);
    ctx.queue.submit([enc.finish()]);
    let colors: Vec<Vec4> = read_buffer(&ctx.device, &ctx.queue, &pass.colors).unwrap();
    let x = g.read_positions().unwrap();
    let strain = vertex_strain(sc.num_particles(), &sc.edges, &sc.edge_rest, &x);
    assert!(strain.iter().any(|&s| s > 0.01), "the stretched cloth shows strain");
    for (i, (c, s)) in colors.iter().zip(&strain).enumerate() {
        assert!((c.w - s).abs() < 1e-5, "vertex {i}: GPU {} CPU {s}", c.w);
        let rgb = ramp(s / 0.2);
        assert!((0..3).all(|k| (c[k] - rgb[k]).abs() < 1e-5), "vertex {i}: {c} vs {rgb:?}");
    }
}

#[test]
fn view_modes_draw_different_pictures() {
    let ctx = gpu();
    let target = OffscreenTarget::new(&ctx.device, W, H, 4).unwrap();
    let mut session = Session::new(&ctx, OFFSCREEN_FORMAT, 4, start_state(Backend::Gpu)).unwrap();
    session.state.paused = true;
    let mut images = Vec::new();
    for (mode, wire) in [
        (ColorMode::Shaded, false),
        (ColorMode::Shaded, true),
        (ColorMode::ColorGroups, false),
        (ColorMode::Strain, false),
    ] {
        session.state.color_mode = mode;
        session.state.wireframe = wire;
        images.push(frame(&ctx, &mut session, &target));
    }
    let diff = |a: &image::RgbaImage, b: &image::RgbaImage| {
        a.pixels().zip(b.pixels()).filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 30)).count()
    };
    for i in 0..images.len() {
        for j in i + 1..images.len() {
            let d = diff(&images[i], &images[j]);
            assert!(d > 200, "modes {i} and {j} differ in only {d} pixels");
        }
    }
    assert_eq!(session.frame, 0, "paused: nothing was stepped");
    session.state.requests.step = true;
    frame(&ctx, &mut session, &target);
    assert_eq!(session.frame, 1, "Step advances one frame while paused");
}
