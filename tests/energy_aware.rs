//! The energy-aware settings on the CPU: stability over a matrix of hard cases, the global
//! balance's energy behaviour, and that it never undoes physical damping.

use eapbd::constraints::{Form, SpringMaterial};
use eapbd::metrics::FrameStats;
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, EnergyAware, Settings};
use glam::Vec3A;

fn solver(name: &str, opts: SceneOptions) -> CpuSolver<Vec3A> {
    CpuSolver::new(scene::build(name, &opts).unwrap())
}

/// Runs `frames` frames; returns the stats of the first and last frame.
fn run(sv: &mut CpuSolver<Vec3A>, s: &Settings, frames: u32) -> (FrameStats, FrameStats) {
    sv.step_frame(s);
    let first = FrameStats::measure(sv, 1, 0.0);
    for _ in 1..frames {
        sv.step_frame(s);
    }
    (first, FrameStats::measure(sv, frames, 0.0))
}

#[test]
fn local_and_global_stay_finite_on_every_family_form_stiffness_and_step() {
    // Springs of both materials and dihedral bending (the `cloth` scene has both).
    for mode in [EnergyAware::Local, EnergyAware::Global] {
        for material in [SpringMaterial::Hookean, SpringMaterial::StVK] {
            for form in [Form::Compliant, Form::Energy] {
                for stiffness in [10.0, 1e6] {
                    for dt in [1.0 / 30.0, 1.0 / 60.0, 1.0 / 120.0] {
                        let opts =
                            SceneOptions { resolution: Some(11), stiffness, material, ..SceneOptions::default() };
                        let mut sv = solver("cloth", opts);
                        let s = Settings { dt, form, energy_aware: mode, ..Settings::default() };
                        let (_, last) = run(&mut sv, &s, 1000);
                        let what = format!("{mode:?} {material:?} {form:?} k={stiffness} dt={dt:.4}");
                        assert!(last.is_finite() && sv.particles.x.iter().all(|x| x.is_finite()), "{what}: not finite");
                        assert!(last.stretch_mean < 1.0, "{what}: mean stretch {}", last.stretch_mean);
                    }
                }
            }
        }
    }
}

#[test]
fn global_keeps_the_energy_of_a_swinging_cloth_that_plain_xpbd_loses() {
    let opts = SceneOptions { resolution: Some(21), stiffness: 1000.0, ..SceneOptions::default() };
    let drift = |mode| {
        let mut sv = solver("cloth", opts);
        let (first, last) = run(&mut sv, &Settings { iterations: 100, energy_aware: mode, ..Settings::default() }, 600);
        (last.total() - first.total()) / first.total()
    };
    let (off, global) = (drift(EnergyAware::Off), drift(EnergyAware::Global));
    println!("10 s of swinging: off {:+.1}%, global {:+.1}%", 100.0 * off, 100.0 * global);
    assert!(off < -0.3, "plain XPBD lost only {:.1}%", -100.0 * off);
    assert!(global.abs() < 0.05, "global drifted {:+.1}%", 100.0 * global);
}

#[test]
fn global_keeps_much_more_of_a_free_stretched_cloth() {
    let opts = SceneOptions { resolution: Some(21), stiffness: 10.0, ..SceneOptions::default() };
    let kept = |mode| {
        let mut sv = solver("cloth-free", opts);
        let start = sv.total_energy();
        let (_, last) = run(&mut sv, &Settings { iterations: 100, energy_aware: mode, ..Settings::default() }, 300);
        last.total() / start
    };
    let (off, global) = (kept(EnergyAware::Off), kept(EnergyAware::Global));
    println!("cloth-free after 5 s: off keeps {:.1}%, global {:.1}%", 100.0 * off, 100.0 * global);
    assert!(off < 0.1 && global > 0.5, "off keeps {:.1}%, global {:.1}%", 100.0 * off, 100.0 * global);
}

#[test]
fn global_does_not_undo_physical_damping() {
    let opts = SceneOptions { resolution: Some(15), stiffness: 1000.0, ..SceneOptions::default() };
    let mut sv = solver("cloth", opts);
    let s = Settings { iterations: 50, damping: 1.0, energy_aware: EnergyAware::Global, ..Settings::default() };
    let (first, last) = run(&mut sv, &s, 300);
    let lost = first.total() - last.total();
    println!("damped: lost {lost:.3} J, dissipated work {:.3} J", last.dissipated);
    // The body loses energy, and what it loses is the damping's work.
    assert!(last.dissipated < -0.5, "damping did no work: {}", last.dissipated);
    assert!(lost > 0.8 * -last.dissipated, "lost {lost:.3} J of {:.3} J dissipated", -last.dissipated);
    assert!(
        (lost + last.dissipated).abs() < 0.05 * first.total(),
        "lost {lost:.3} J vs dissipated {:.3} J",
        last.dissipated
    );
}

#[test]
fn over_relaxation_changes_the_solve_and_stays_finite() {
    let mut plain = solver("cloth-paper", SceneOptions::default());
    let mut sor = solver("cloth-paper", SceneOptions::default());
    let (_, a) = run(&mut plain, &Settings::default(), 120);
    let (_, b) = run(&mut sor, &Settings { sor: 1.5, ..Settings::default() }, 120);
    assert!(b.is_finite());
    assert!(b.stretch_mean < a.stretch_mean, "SOR 1.5 stretch {} vs plain {}", b.stretch_mean, a.stretch_mean);
}
