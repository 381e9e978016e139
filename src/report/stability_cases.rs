//! The stability study's case matrix ([`super::stability`]): which scenes, settings and starting
//! states it runs, and on which backends.

use super::stability::{Case, DAMPING, Modify, RIGID_MEASURE_K};
use crate::constraints::{Orthotropic, SpringMaterial};
use crate::material::Model;
use crate::scene::SceneOptions;
use crate::simulation::Backend;
use crate::solver::Settings;

const BOTH: &[Backend] = &[Backend::Cpu, Backend::Gpu];
const CPU: &[Backend] = &[Backend::Cpu];
const NONE: &[Backend] = &[];

/// The case matrix.
pub fn cases() -> Vec<Case> {
    let base = Settings { damping: DAMPING, ..Settings::default() };
    let cloth = SceneOptions { resolution: Some(11), stiffness: 1.0e4, ..SceneOptions::default() };
    let cube = |model: Model, young: f64, poisson: f64, gravity: bool| SceneOptions {
        resolution: Some(3),
        solid: Some(model),
        young,
        poisson,
        gravity,
        ..SceneOptions::default()
    };
    let mut out = Vec::new();
    let mut add = |name: &'static str,
                   group: &'static str,
                   description: String,
                   scene: &'static str,
                   options: SceneOptions,
                   settings: Settings,
                   modify: Modify,
                   duration: f32,
                   backends: &'static [Backend],
                   quick: &'static [Backend]| {
        out.push(Case { name, group, description, scene, options, settings, modify, duration, backends, quick });
    };
    // Stiffness: springs on the hanging cloth.
    for (name, k, quick) in [("cloth-k1e3", 1.0e3f32, BOTH), ("cloth-k1e6", 1.0e6, NONE), ("cloth-k1e9", 1.0e9, CPU)] {
        let d = format!("hanging cloth 11×11, Hookean springs k_s = {k:.0e} N/m, 30 it, dt 1/60");
        add(
            name,
            "stiffness",
            d,
            "cloth",
            SceneOptions { stiffness: k, ..cloth },
            base,
            Modify::None,
            3.0,
            BOTH,
            quick,
        );
    }
    add(
        "cloth-rigid",
        "stiffness",
        format!("hanging cloth 11×11, springs k = ∞ (compliance 0; energy measured at k = {RIGID_MEASURE_K:.0e})"),
        "cloth",
        cloth,
        base,
        Modify::Rigid,
        3.0,
        BOTH,
        CPU,
    );
    add(
        "cloth-stvk-k1e9",
        "stiffness",
        "hanging cloth 11×11, StVK springs k_s = 1e9 N/m".into(),
        "cloth",
        SceneOptions { stiffness: 1.0e9, material: SpringMaterial::StVK, ..cloth },
        base,
        Modify::None,
        3.0,
        CPU,
        NONE,
    );
    // Stiffness: the cube released from a 20 % stretch, no gravity.
    for (name, e, quick) in [("cube-E1e3", 1.0e3, CPU), ("cube-E1e6", 1.0e6, NONE), ("cube-E1e9", 1.0e9, CPU)] {
        add(
            name,
            "stiffness",
            format!("Neo-Hookean cube 3³ cells, E = {e:.0e} Pa, ν 0.3, released from 20 % stretch, no gravity"),
            "cube",
            cube(Model::NeoHookean, e, 0.3, false),
            base,
            Modify::StretchX(1.2),
            3.0,
            BOTH,
            quick,
        );
    }
    // Time steps.
    for (name, dt, label, duration, quick) in [
        ("cloth-dt1e-3", 1.0e-3f32, "1/1000", 1.0f32, NONE),
        ("cloth-dt1e-1", 0.1, "1/10", 3.0, CPU),
        ("sphere-dt1e-1", 0.1, "1/10", 3.0, CPU),
        ("cube-drop-dt1e-1", 0.1, "1/10", 3.0, BOTH),
    ] {
        let (scene, options, what) = match name {
            "sphere-dt1e-1" => ("cloth-sphere", cloth, "cloth 11×11 falling on a sphere"),
            "cube-drop-dt1e-1" => {
                ("cube", cube(Model::NeoHookean, 2.0e6, 0.3, true), "Neo-Hookean cube dropped on the ground")
            }
            _ => ("cloth", cloth, "hanging cloth 11×11"),
        };
        let d = format!("{what}, dt {label} s, 30 it");
        add(name, "time step", d, scene, options, Settings { dt, ..base }, Modify::None, duration, BOTH, quick);
    }
    // Iterations.
    for (name, it, quick) in [("cloth-k1e6-it1", 1u32, CPU), ("cloth-k1e6-it500", 500, NONE)] {
        add(
            name,
            "iterations",
            format!("hanging cloth 11×11, k_s = 1e6 N/m, {it} iteration(s)"),
            "cloth",
            SceneOptions { stiffness: 1.0e6, ..cloth },
            Settings { iterations: it, ..base },
            Modify::None,
            if it == 500 { 1.0 } else { 3.0 },
            BOTH,
            quick,
        );
    }
    // Mass ratio.
    add(
        "heavy-ball",
        "mass ratio",
        "hanging cloth 11×11, k_s = 1e6 N/m, central 3×3 particles 10⁴× heavier (1:10⁴)".into(),
        "cloth",
        SceneOptions { stiffness: 1.0e6, ..cloth },
        base,
        Modify::HeavyBlock { side: 3, ratio: 1.0e4 },
        3.0,
        BOTH,
        CPU,
    );
    // Inverted at start: every 3D model.
    for (name, model) in [
        ("inverted-linear", Model::Linear),
        ("inverted-stvk", Model::StVK),
        ("inverted-neo-hookean", Model::NeoHookean),
        ("inverted-mooney-rivlin", Model::MooneyRivlin),
        ("inverted-arruda-boyce", Model::ArrudaBoyce),
    ] {
        let d = format!("{} cube 3³ cells, E 2e6 Pa, mirrored (every tetrahedron inverted), no gravity", model.name());
        let quick = match model {
            Model::Linear => NONE,
            Model::NeoHookean => BOTH,
            _ => CPU,
        };
        add(name, "inverted", d, "cube", cube(model, 2.0e6, 0.3, false), base, Modify::Mirror, 3.0, BOTH, quick);
    }
    // Collapsed to a point.
    let collapse = Modify::Collapse { radius: 1.0e-6, seed: 7 };
    add(
        "collapsed-cloth",
        "collapsed",
        "free cloth 11×11 (no gravity), every particle within 1e-6 m of its centre, released".into(),
        "cloth-free",
        cloth,
        base,
        collapse,
        3.0,
        BOTH,
        BOTH,
    );
    add(
        "collapsed-aniso-cloth",
        "collapsed",
        "free anisotropic membrane cloth 11×11 (E_u 1e4, E_v 5e3, G 2e3 N/m) collapsed the same way".into(),
        "cloth-free",
        SceneOptions { membrane: Some(Orthotropic { warp: 1.0e4, weft: 5.0e3, shear: 2.0e3, poisson: 0.3 }), ..cloth },
        base,
        collapse,
        3.0,
        CPU,
        CPU,
    );
    // Nearly incompressible.
    for (name, model, quick) in [
        ("poisson-0.49-neo-hookean", Model::NeoHookean, CPU),
        ("poisson-0.49-stvk", Model::StVK, NONE),
        ("poisson-0.49-linear", Model::Linear, NONE),
    ] {
        let d = format!("{} cube 3³ cells, E 2e6 Pa, ν 0.49, dropped on the ground", model.name());
        add(name, "Poisson 0.49", d, "cube", cube(model, 2.0e6, 0.49, true), base, Modify::None, 3.0, BOTH, quick);
    }
    // Huge initial velocities.
    add(
        "cloth-velocity-100",
        "velocity",
        "hanging cloth 11×11, every particle at a random 100 m/s".into(),
        "cloth",
        cloth,
        base,
        Modify::Velocity { speed: 100.0, seed: 11 },
        3.0,
        BOTH,
        BOTH,
    );
    add(
        "cube-velocity-100",
        "velocity",
        "Neo-Hookean cube 3³ cells on the ground, every particle at a random 100 m/s".into(),
        "cube",
        cube(Model::NeoHookean, 2.0e6, 0.3, true),
        base,
        Modify::Velocity { speed: 100.0, seed: 13 },
        3.0,
        BOTH,
        CPU,
    );
    // The bunny: the volumetric Neo-Hookean body (an 8-cell lattice, 648 tetrahedra, to keep the
    // full study short) under the same hard conditions.
    let bunny =
        |young: f64, gravity: bool| SceneOptions { lattice: Some(8), young, gravity, ..SceneOptions::default() };
    let bunny_cases: [(&'static str, &'static str, &str, SceneOptions, Settings, Modify); 5] = [
        ("bunny-drop", "bunny", "dropped on the ground, E 2e6 Pa", bunny(2.0e6, true), base, Modify::None),
        ("bunny-E1e9", "bunny", "dropped on the ground, E 1e9 Pa", bunny(1.0e9, true), base, Modify::None),
        (
            "bunny-dt1e-1",
            "bunny",
            "dropped on the ground, E 2e6 Pa, dt 1/10",
            bunny(2.0e6, true),
            Settings { dt: 0.1, ..base },
            Modify::None,
        ),
        (
            "bunny-inverted",
            "bunny",
            "mirrored (every tetrahedron inverted), E 2e6 Pa, no gravity",
            bunny(2.0e6, false),
            base,
            Modify::Mirror,
        ),
        (
            "bunny-velocity-100",
            "bunny",
            "on the ground, every particle at a random 100 m/s",
            bunny(2.0e6, true),
            base,
            Modify::Velocity { speed: 100.0, seed: 17 },
        ),
    ];
    for (name, group, what, options, settings, modify) in bunny_cases {
        let d = format!("volumetric Neo-Hookean bunny (lattice 8, 648 tets), {what}");
        add(name, group, d, "bunny", options, settings, modify, 3.0, BOTH, NONE);
    }
    out
}

/// The cases and backends of `--quick` mode: the same cases as the full study (same frames, so
/// the same results) on a cheap subset of their backends.
pub fn quick_cases() -> Vec<Case> {
    cases().into_iter().filter(|c| !c.quick.is_empty()).map(|c| Case { backends: c.quick, ..c }).collect()
}
