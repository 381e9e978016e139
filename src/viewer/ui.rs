//! The egui panels: controls on the left (they only edit [`ViewerState`]), statistics and live
//! plots on the right.

use egui::{ComboBox, RichText, Slider, Ui};
use egui_plot::{Legend, Line, LineStyle, Plot};

use super::plots::History;
use super::session::{SceneInfo, Timings};
use super::state::{ColorMode, DEFAULT_GRAB_STIFFNESS, MaterialChoice, ViewerState};
use crate::compare::Compare;
use crate::constraints::Form;
use crate::mesh::Diagonals;
use crate::metrics::FrameStats;
use crate::scene::{SCENES, TetMode};
use crate::simulation::Backend;
use crate::solver::{EnergyAware, Method};

/// Width of the side panels (points).
pub const PANEL_WIDTH: f32 = 290.0;

/// What the statistics panel shows.
#[derive(Clone, Copy, Debug)]
pub struct StatsView<'a> {
    /// The scene.
    pub info: &'a SceneInfo,
    /// The latest statistics.
    pub stats: Option<&'a FrameStats>,
    /// Recent statistics.
    pub history: &'a History,
    /// Timings.
    pub timings: Timings,
    /// Frames simulated since the last reset.
    pub frame: u32,
    /// Range of the energy view's colour scale (J).
    pub energy_scale: f32,
    /// In compare mode, the other run's statistics and both sides' labels (this run's first):
    /// the plots then overlay the two runs, one colour each.
    pub twin: Option<(&'a History, [&'static str; 2])>,
}

/// Draws both panels; returns the rectangle left for the scene (points).
pub fn panels(ui: &mut Ui, state: &mut ViewerState, stats: &StatsView<'_>) -> egui::Rect {
    egui::Panel::left("controls")
        .exact_size(PANEL_WIDTH)
        .show(ui, |ui| egui::ScrollArea::vertical().show(ui, |ui| controls(ui, state, stats.info)));
    egui::Panel::right("statistics")
        .exact_size(PANEL_WIDTH)
        .show(ui, |ui| egui::ScrollArea::vertical().show(ui, |ui| statistics(ui, state, stats)));
    ui.available_rect_before_wrap()
}

/// A logarithmic slider over `range` showing the value with `unit`.
fn log_slider<'a, N: egui::emath::Numeric>(
    value: &'a mut N,
    range: std::ops::RangeInclusive<N>,
    label: &str,
    unit: &str,
) -> Slider<'a> {
    Slider::new(value, range)
        .logarithmic(true)
        .text(label.to_string())
        .suffix(format!(" {unit}"))
        .custom_formatter(|v, _| format!("{v:.3e}"))
}

/// The splits of 30 projections a frame offered as one click each: (name, substeps, iterations).
pub const SPLITS: [(&str, u32, u32); 3] = [("paper", 1, 30), ("balanced", 10, 3), ("small steps", 30, 1)];

/// A labelled row of radio buttons choosing `value` among `options` (value, text); `hint`, when
/// not empty, shows over the label.
fn radio_row<T: PartialEq + Copy>(ui: &mut Ui, (label, hint): (&str, &str), value: &mut T, options: &[(T, &str)]) {
    ui.horizontal(|ui| {
        let label = ui.label(label);
        if !hint.is_empty() {
            label.on_hover_text(hint);
        }
        for &(v, text) in options {
            ui.radio_value(value, v, text);
        }
    });
}

/// The control panel: scene, material, solver, simulation buttons and view options.
pub fn controls(ui: &mut Ui, state: &mut ViewerState, info: &SceneInfo) {
    ui.heading("eapbd");
    ui.label(RichText::new("Energy-aware XPBD").small());
    ui.separator();
    scene_controls(ui, state);
    ui.separator();
    material_controls(ui, state);
    ui.separator();
    solver_controls(ui, state);
    ui.separator();
    simulation_buttons(ui, state);
    ui.separator();
    view_controls(ui, state, info);
    if let Some(e) = &state.error {
        ui.separator();
        ui.colored_label(egui::Color32::from_rgb(200, 40, 30), e);
    }
}

fn scene_controls(ui: &mut Ui, state: &mut ViewerState) {
    ui.label(RichText::new("Scene").strong());
    let c = &mut state.choice;
    let mut index = c.scene;
    ComboBox::from_label("Scene").selected_text(c.name()).show_ui(ui, |ui| {
        for (i, name) in SCENES.iter().enumerate() {
            ui.selectable_value(&mut index, i, *name);
        }
    });
    c.set_scene(index);
    let mut own = c.resolution.is_none();
    ui.horizontal(|ui| {
        ui.checkbox(&mut own, "scene's resolution")
            .on_hover_text("Particles per side of a cloth, cells along a beam or cube side; unticked: your own.");
        if !own {
            let mut n = c.resolution.unwrap_or(if c.solid { 10 } else { 41 });
            let range = if c.solid { 2..=40 } else { 3..=128 };
            ui.add(Slider::new(&mut n, range).text("Resolution"));
            c.resolution = Some(n);
        }
    });
    if own {
        c.resolution = None;
    }
    ui.checkbox(&mut c.gravity, "Gravity").on_hover_text("g = 9.81 m/s² downwards.");
    if c.solid {
        let hint =
            "volume: a tetrahedral mesh of the body; centroid: the paper's surface triangles joined to the centre.";
        radio_row(
            ui,
            ("Tetrahedra", hint),
            &mut c.tets,
            &[(TetMode::Volume, "volume"), (TetMode::Centroid, "centroid")],
        );
    }
    if c.is_cloth() {
        let hint = "How each grid quad is split into triangles: all alike, or in a checkerboard.";
        let options = [(Diagonals::Uniform, "uniform"), (Diagonals::Alternating, "alternating")];
        radio_row(ui, ("Diagonals", hint), &mut c.diagonals, &options);
        let mut on = c.self_collides();
        let hint = "Particles kept a thickness (1.2 × the grid's spacing) apart inside the iteration loop, so \
                    the cloth cannot pass through itself.";
        if ui.checkbox(&mut on, "Self-collision").on_hover_text(hint).changed() {
            c.self_collision = Some(on);
        }
    }
}

fn material_controls(ui: &mut Ui, state: &mut ViewerState) {
    ui.label(RichText::new("Material").strong());
    let c = &mut state.choice;
    ComboBox::from_label("Material").selected_text(c.material.name()).show_ui(ui, |ui| {
        for m in c.materials() {
            ui.selectable_value(&mut c.material, *m, m.name());
        }
    });
    match c.material {
        MaterialChoice::Spring(_) => {
            ui.add(log_slider(&mut c.stiffness, 10.0..=1.0e7, "Stiffness", "N/m"))
                .on_hover_text("Small-strain spring stiffness k_s (N/m); the compliance is 1/k_s.");
        }
        MaterialChoice::AnisoCloth => {
            ui.add(log_slider(&mut c.warp, 10.0..=1.0e7, "Warp E_u", "N/m"))
                .on_hover_text("Membrane modulus along x (N/m: a 2D modulus, Pa × thickness).");
            ui.add(log_slider(&mut c.weft, 10.0..=1.0e7, "Weft E_v", "N/m"))
                .on_hover_text("Membrane modulus along z (N/m).");
            let mut auto = c.shear.is_none();
            ui.checkbox(&mut auto, "Shear from Huber's estimate");
            if auto {
                c.shear = None;
            } else {
                let mut g = c.shear.unwrap_or((c.warp * c.weft).sqrt() / (2.0 * (1.0 + c.poisson)));
                ui.add(log_slider(&mut g, 1.0..=1.0e7, "Shear G", "N/m"));
                c.shear = Some(g);
            }
            ui.add(Slider::new(&mut c.poisson, 0.0..=0.49).text("Poisson ν_uv"))
                .on_hover_text("Contraction along z under stretch along x (dimensionless).");
        }
        MaterialChoice::Solid(_) => {
            ui.add(log_slider(&mut c.young, 1.0e4..=1.0e9, "Young E", "Pa"))
                .on_hover_text("Young's modulus E (Pa) of the 3D model.");
            ui.add(Slider::new(&mut c.poisson, 0.0..=0.49).text("Poisson ratio"))
                .on_hover_text("Poisson's ratio ν (dimensionless; 0.5 would be incompressible).");
        }
    }
    if !c.solid {
        let mut on = c.bending.is_some_and(|k| k > 0.0);
        ui.checkbox(&mut on, "Bending");
        if on {
            let mut kb = c.bending.filter(|k| *k > 0.0).unwrap_or(1.0e-3);
            ui.add(log_slider(&mut kb, 1.0e-6..=1.0, "Bending k_b", "N·m/rad"))
                .on_hover_text("Dihedral bending stiffness k_b (N·m/rad): E = ½ k_b (θ − θ₀)².");
            c.bending = Some(kb);
        } else {
            c.bending = Some(0.0);
        }
    }
}

fn solver_controls(ui: &mut Ui, state: &mut ViewerState) {
    ui.label(RichText::new("Solver").strong());
    let s = &mut state.settings;
    ui.add(Slider::new(&mut s.iterations, 1..=200).logarithmic(true).text("Iterations"))
        .on_hover_text("Constraint projections per substep: the solve's work per substep.");
    ui.add(Slider::new(&mut s.substeps, 1..=64).logarithmic(true).text("Substeps"))
        .on_hover_text("Substeps per frame: each advances dt / substeps (s). More substeps converge better than more iterations at the same work.");
    ui.horizontal_wrapped(|ui| {
        ui.label("Split")
            .on_hover_text("Substeps × iterations per frame: the same 30 projections divided differently.");
        for (name, substeps, iterations) in SPLITS {
            let on = s.substeps == substeps && s.iterations == iterations;
            let text = format!("{name} ({substeps} × {iterations})");
            if ui.selectable_label(on, text).clicked() {
                (s.substeps, s.iterations) = (substeps, iterations);
            }
        }
    });
    ui.add(log_slider(&mut s.dt, 1.0 / 480.0..=1.0 / 15.0, "Time step", "s"))
        .on_hover_text("The frame's time step dt (s).");
    ui.add(Slider::new(&mut s.damping, 0.0..=5.0).text("Damping").suffix(" 1/s"))
        .on_hover_text("Velocity damping β_v (1/s): v ← v max(1 − β_v h, 0) every substep.");
    radio_row(ui, ("Form", ""), &mut s.form, &[(Form::Compliant, "compliant"), (Form::Energy, "energy")]);
    if s.form == Form::Energy {
        ui.add(log_slider(&mut s.energy_compliance, 1.0e-9..=1.0e-1, "Energy compliance", ""))
            .on_hover_text("Compliance α of the energy form C = E (1/J): 0 would enforce E = 0 exactly.");
    }
    radio_row(
        ui,
        ("Iteration", ""),
        &mut s.method,
        &[(Method::GaussSeidel, "Gauss-Seidel"), (Method::Jacobi, "Jacobi")],
    );
    if s.method == Method::Jacobi {
        ui.add(Slider::new(&mut s.jacobi_omega, 0.1..=1.9).text("Jacobi ω"))
            .on_hover_text("Relaxation ω of the averaged Jacobi corrections (dimensionless).");
    }
    ui.horizontal_wrapped(|ui| {
        ui.label("Energy-aware");
        ui.radio_value(&mut s.energy_aware, EnergyAware::Off, "off").on_hover_text("Plain XPBD.");
        ui.radio_value(&mut s.energy_aware, EnergyAware::Local, "local")
            .on_hover_text("The paper's per-constraint energy-aware Gauss-Seidel.");
        ui.radio_value(&mut s.energy_aware, EnergyAware::Global, "global")
            .on_hover_text("A velocity scale per substep that balances the iterate's whole energy.");
        ui.radio_value(&mut s.energy_aware, EnergyAware::Project, "project (on)").on_hover_text(
            "After each frame, positions and velocities are projected back to the energy (and momenta) the frame \
             started with, less what gravity, damping and contacts took.",
        );
    });
    ui.add(Slider::new(&mut s.sor, 0.1..=1.9).text("SOR ω")).on_hover_text("Over-relaxation ω of every Δλ (1: none).");
    radio_row(ui, ("Backend", ""), &mut state.backend, &[(Backend::Gpu, "GPU"), (Backend::Cpu, "CPU")]);
}

fn simulation_buttons(ui: &mut Ui, state: &mut ViewerState) {
    ui.horizontal(|ui| {
        let label = if state.paused { "Run" } else { "Pause" };
        if ui.button(label).on_hover_text("Pause or run the simulation (space)").clicked() {
            state.paused = !state.paused;
        }
        let step = ui.add_enabled(state.paused, egui::Button::new("Step"));
        if step.on_hover_text("One frame while paused (S)").clicked() {
            state.requests.step = true;
        }
        if ui.button("Reset").on_hover_text("Back to the scene's start (R)").clicked() {
            state.requests.reset = true;
        }
        if ui.button("Camera").clicked() {
            state.requests.reset_camera = true;
        }
    });
    let name = state.compare.map_or("none", Compare::name);
    egui::ComboBox::from_label("Compare")
        .selected_text(name)
        .show_ui(ui, |ui| {
            ui.selectable_value(&mut state.compare, None, "none");
            for (name, c) in Compare::ALL {
                ui.selectable_value(&mut state.compare, Some(c), name);
            }
        })
        .response
        .on_hover_text("A second run beside this one, differing in one setting, from the same start (C: energy-aware)");
    let mut rigid = state.grab_stiffness <= 0.0;
    if ui.checkbox(&mut rigid, "Rigid grab").on_hover_text("Pin the grabbed particle to the cursor").changed() {
        state.grab_stiffness = if rigid { 0.0 } else { DEFAULT_GRAB_STIFFNESS };
    }
    if !rigid {
        ui.add(log_slider(&mut state.grab_stiffness, 1.0..=1.0e5, "Grab stiffness", "N/m")).on_hover_text(
            "The spring k (N/m) that pulls the grabbed particle to the cursor, critically damped: \
             the particle trails by the body's pull divided by k, so a hard pull stretches the body.",
        );
    }
    ui.label(
        RichText::new("Drag the body to pull it; drag elsewhere to orbit, right-drag to pan, wheel to zoom.").small(),
    );
}

fn view_controls(ui: &mut Ui, state: &mut ViewerState, info: &SceneInfo) {
    ui.label(RichText::new("View").strong());
    ui.checkbox(&mut state.wireframe, "Wireframe").on_hover_text("The surface's edges over it.");
    ui.horizontal_wrapped(|ui| {
        ui.label("Colour");
        for m in ColorMode::ALL {
            ui.radio_value(&mut state.color_mode, m, m.label());
        }
    });
    match state.color_mode {
        ColorMode::ColorGroups if !info.families.is_empty() => {
            let f = state.group_family.min(info.families.len() - 1);
            ComboBox::from_label("Family").selected_text(info.families[f].0).show_ui(ui, |ui| {
                for (i, (name, _, _)) in info.families.iter().enumerate() {
                    ui.selectable_value(&mut state.group_family, i, *name);
                }
            });
            let (_, n, colors) = info.families[f];
            ui.label(format!("{n} elements in {colors} color groups: one dispatch per group, no two elements of a group share a particle."));
        }
        ColorMode::Strain => {
            ui.add(log_slider(&mut state.strain_scale, 1.0e-4..=1.0, "Red at stretch", ""))
                .on_hover_text("Mean relative stretch (|d| − l₀)/l₀ of a vertex's edges drawn red.");
            ramp_legend(ui, "unstretched", &format!("{:.1e} stretch", state.strain_scale));
        }
        ColorMode::Energy => ramp_legend(ui, "0 J", "'Red at' in Statistics"),
        _ => {}
    }
}

/// The statistics panel: figures and live plots.
pub fn statistics(ui: &mut Ui, state: &ViewerState, v: &StatsView<'_>) {
    ui.heading("Statistics");
    egui::CollapsingHeader::new("What is on screen").show(ui, explanation);
    let info = v.info;
    egui::Grid::new("figures").num_columns(2).striped(true).show(ui, |ui| {
        let mut row = |name: &str, value: String| {
            ui.label(name);
            ui.label(value);
            ui.end_row();
        };
        row("FPS", format!("{:.1}", v.timings.fps));
        row(
            "Solver",
            v.timings.solver_ms.map_or("–".into(), |ms| format!("{ms:.2} ms/frame ({})", state.backend.name())),
        );
        let ms = |t: Option<f64>| t.map_or("–".into(), |ms| format!("{ms:.2} ms/frame"));
        row("Panels", ms(v.timings.ui_ms));
        row("Drawing", ms(v.timings.draw_ms));
        row("Frame", v.frame.to_string());
        row("Particles", info.particles.to_string());
        row("Constraints", info.constraints.to_string());
        for (name, n, colors) in &info.families {
            row(name, format!("{n} in {colors} colors"));
        }
        if let Some(s) = v.stats {
            row("Residual", format!("{:.3e} rms, {:.3e} max", s.residual_rms, s.residual_max));
            row("Stretch", format!("{:.2}% mean, {:.2}% max", 100.0 * s.stretch_mean, 100.0 * s.stretch_max));
            row("Kinetic", format!("{:.4e} J", s.kinetic));
            row("Elastic", format!("{:.4e} J", s.elastic));
            row("Unresolved", format!("{:.4e} J (not in total)", s.unresolved));
            row("Gravity", format!("{:+.4e} J", s.gravitational));
            row("Total", format!("{:+.4e} J", s.total()));
        }
        if state.color_mode == ColorMode::Energy {
            row("Red at", format!("{:.3e} J", v.energy_scale));
        }
    });
    ui.label(RichText::new(&info.adapter).small());
    ui.separator();
    ui.label(RichText::new("Energy (J)").strong());
    let h = v.history;
    if let Some((t, names)) = v.twin {
        return compared_plots(ui, [h, t], names);
    }
    Plot::new("energy").height(130.0).legend(Legend::default()).allow_scroll(false).show(ui, |p| {
        p.line(Line::new("kinetic", h.series(|s| s.kinetic)));
        p.line(Line::new("elastic (held)", h.series(|s| s.elastic)));
        p.line(Line::new("gravity", h.series(|s| s.gravitational)));
        p.line(Line::new("total", h.series(|s| s.total)));
    });
    // Often far larger than the energies: a plot of its own, so theirs keeps its scale.
    ui.label(RichText::new("Unresolved stretch (J; not energy, not in the total)").strong());
    Plot::new("unresolved").height(70.0).allow_scroll(false).show(ui, |p| {
        p.line(Line::new("unresolved", h.series(|s| s.unresolved)).style(LineStyle::dashed_dense()));
    });
    ui.label(RichText::new("log₁₀ residual (rms)").strong());
    Plot::new("residual").height(90.0).allow_scroll(false).show(ui, |p| {
        p.line(Line::new("residual", h.series(|s| s.residual.max(1e-30).log10())));
    });
}

/// The plots in compare mode: each run in its colour (the left half's blue, the right half's
/// orange), total solid and kinetic dashed, unresolved stretch and residual one line a run.
fn compared_plots(ui: &mut Ui, runs: [&History; 2], names: [&'static str; 2]) {
    let colours = [egui::Color32::from_rgb(70, 130, 230), egui::Color32::from_rgb(235, 130, 40)];
    let each = |f: &mut dyn FnMut(&History, &'static str, egui::Color32)| {
        for ((h, name), colour) in runs.iter().zip(names).zip(colours) {
            f(h, name, colour);
        }
    };
    Plot::new("energy").height(130.0).legend(Legend::default()).allow_scroll(false).show(ui, |p| {
        each(&mut |h, name, colour| {
            p.line(Line::new(format!("total, {name}"), h.series(|s| s.total)).color(colour));
            p.line(
                Line::new(format!("kinetic, {name}"), h.series(|s| s.kinetic))
                    .color(colour)
                    .style(LineStyle::dashed_loose()),
            );
        });
    });
    ui.label(RichText::new("Unresolved stretch (J; not energy, not in the total)").strong());
    Plot::new("unresolved").height(70.0).allow_scroll(false).show(ui, |p| {
        each(&mut |h, name, colour| {
            let line = Line::new(name, h.series(|s| s.unresolved)).color(colour);
            p.line(line.style(LineStyle::dashed_dense()));
        });
    });
    ui.label(RichText::new("log₁₀ residual (rms)").strong());
    Plot::new("residual").height(90.0).allow_scroll(false).show(ui, |p| {
        each(&mut |h, name, colour| {
            p.line(Line::new(name, h.series(|s| s.residual.max(1e-30).log10())).color(colour));
        });
    });
}

/// A few sentences on what the energy-aware settings do and what the figures are.
fn explanation(ui: &mut Ui) {
    ui.label(
        "XPBD projects each constraint a fixed number of times a frame. When it stops short of \
         convergence the body is left stretched beyond what its forces hold: that unresolved stretch \
         (the dashed plot) is the solve's shortfall, not energy, so it is kept out of the total.",
    );
    ui.label(
        "Total = kinetic + gravitational + elastic (the part the multipliers hold): \
         H = ½ Σ m|v|² − Σ m g·x + E_held. Plain XPBD (off) loses kinetic energy to its numerical damping; \
         'project' restores what the frame started with, less the work of gravity, damping and contacts, \
         by an energy-momentum projection after each frame.",
    );
    ui.label("More: docs/energy-aware.md in the repository.");
}

/// Labels each half of the scene with its side's setting in compare mode, at the top left of
/// `halves` (points); returns the labels' rectangles (opaque, so that a cached copy of them
/// stands for them).
pub fn compare_labels(ui: &mut Ui, state: &ViewerState, halves: [egui::Rect; 2]) -> Vec<egui::Rect> {
    let Some(c) = state.compare else { return Vec::new() };
    let sides = c.sides(&state.settings);
    let pad = egui::vec2(6.0, 3.0);
    halves
        .iter()
        .zip(sides)
        .map(|(half, (text, _))| {
            let galley = ui.painter().layout_no_wrap(
                text.to_string(),
                egui::FontId::proportional(14.0),
                egui::Color32::from_gray(20),
            );
            let rect = egui::Rect::from_min_size(half.min + egui::vec2(8.0, 8.0), galley.size() + 2.0 * pad);
            // A clip rectangle of its own: a paint job apart from the rest, bounded by the label.
            let painter = ui.painter().with_clip_rect(rect.expand(1.0));
            painter.rect_filled(rect, 0.0, egui::Color32::from_gray(235));
            painter.galley(rect.min + pad, galley, egui::Color32::from_gray(20));
            rect
        })
        .collect()
}

/// The colour ramp of the strain and energy views as a bar, labelled at both ends.
fn ramp_legend(ui: &mut Ui, low: &str, high: &str) {
    ui.horizontal(|ui| {
        ui.label(RichText::new(low).small());
        let (rect, _) = ui.allocate_exact_size(egui::vec2(120.0, 12.0), egui::Sense::hover());
        let steps = 24;
        for k in 0..steps {
            // The ramp is in linear RGB; egui's colours are sRGB.
            let [r, g, b] =
                super::strain::ramp((k as f32 + 0.5) / steps as f32).map(|c| (c.powf(1.0 / 2.2) * 255.0) as u8);
            let x0 = rect.min.x + rect.width() * k as f32 / steps as f32;
            let x1 = rect.min.x + rect.width() * (k + 1) as f32 / steps as f32;
            let cell = egui::Rect::from_min_max(egui::pos2(x0, rect.min.y), egui::pos2(x1, rect.max.y));
            ui.painter().rect_filled(cell, 0.0, egui::Color32::from_rgb(r, g, b));
        }
        ui.label(RichText::new(high).small());
    });
}
