//! The energy-momentum projection (`--energy-aware project`) on the CPU: the honest energy held
//! to its budget on the hanging cloth, momenta and energy of the free cloth, a body at rest, the
//! thread count, the contacts' work (the GPU's projection: `tests/gpu_projection.rs`).

use eapbd::metrics::FrameStats;
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::projection::{momenta, momentum_scales};
use eapbd::solver::{CpuSolver, EnergyAware, Settings};
use glam::Vec3A;

fn solver(name: &str, opts: SceneOptions) -> CpuSolver<Vec3A> {
    CpuSolver::new(scene::build(name, &opts).unwrap())
}

/// The hanging cloth: 41×41, k = 10⁴ N/m, bending 10⁻³ N·m/rad.
fn hanging_cloth() -> CpuSolver<Vec3A> {
    solver("cloth", SceneOptions { stiffness: 1e4, bending_stiffness: Some(1e-3), ..SceneOptions::default() })
}

fn settings(substeps: u32, iterations: u32, energy_aware: EnergyAware) -> Settings {
    Settings { substeps, iterations, energy_aware, threads: 1, ..Settings::default() }
}

/// The hanging cloth after `frames` frames damped (5 /s) at `substeps` × `iterations`: at rest.
fn damped_hanging_cloth(substeps: u32, iterations: u32, frames: u32) -> CpuSolver<Vec3A> {
    let mut sv = hanging_cloth();
    let damped = Settings { damping: 5.0, ..settings(substeps, iterations, EnergyAware::Off) };
    for _ in 0..frames {
        sv.step_frame(&damped);
    }
    sv
}

#[test]
fn the_hanging_cloth_keeps_its_energy_and_its_swing_at_10_substeps_of_3_iterations() {
    // E_eq: the same cloth hanging at rest (10 s damped at 40 substeps of 2 iterations).
    let rest = damped_hanging_cloth(40, 2, 600);
    let e_eq = FrameStats::measure(&rest, 600, 0.0).total();
    let mut sv = hanging_cloth();
    let e0 = FrameStats::measure(&sv, 0, 0.0).total();
    let s = settings(10, 3, EnergyAware::Project);
    let (mut n_max, mut n, mut first, mut last) = (f64::MIN, 0.0, 0.0, 0.0);
    for frame in 1..=600 {
        sv.step_frame(&s);
        let st = FrameStats::measure(&sv, frame, 0.0);
        n = (st.total() - e_eq) / (e0 - e_eq);
        n_max = n_max.max(n);
        if frame <= 120 {
            first += st.kinetic;
        } else if frame > 480 {
            last += st.kinetic;
        }
    }
    println!(
        "E_eq {e_eq:.4} J, E0 {e0:.4} J: n at 10 s {n:.4}, peak {n_max:.4}, kinetic last/first 2 s {:.3}",
        last / first
    );
    assert!((n - 1.0).abs() <= 0.1, "n at 10 s: {n}");
    assert!(n_max <= 1.1, "n peaked at {n_max}");
    assert!(last >= 0.5 * first, "kinetic energy over the last 2 s is {:.3} of the first", last / first);
}

#[test]
fn the_free_cloth_keeps_both_momenta_and_its_energy() {
    let opts = SceneOptions { resolution: Some(21), stiffness: 1e4, ..SceneOptions::default() };
    let mut sv = solver("cloth-free", opts);
    // Set the cloth drifting and spinning, so both momenta are far from zero.
    for (x, v) in sv.particles.x.iter().zip(sv.particles.v.iter_mut()) {
        *v = Vec3A::new(0.3, -0.1, 0.2) + Vec3A::new(0.0, 2.0, 0.5).cross(*x);
    }
    let s = settings(3, 10, EnergyAware::Project);
    sv.step_frame(&s);
    let budget = sv.ledger.budget.expect("a budget after the first frame");
    let p = &sv.particles;
    let (p0, l0) = momenta(&p.x, &p.v, &p.w);
    for frame in 2..=600 {
        sv.step_frame(&s);
        let p = &sv.particles;
        let (p1, l1) = momenta(&p.x, &p.v, &p.w);
        let (scale_p, scale_l) = momentum_scales(&p.x, &p.v, &p.w);
        assert!((p1 - p0).length() <= 1e-4 * scale_p, "frame {frame}: P {p0} -> {p1} (scale {scale_p:.3e})");
        assert!((l1 - l0).length() <= 1e-4 * scale_l, "frame {frame}: L {l0} -> {l1} (scale {scale_l:.3e})");
        let e = sv.held_energy();
        assert!((e - budget).abs() <= 0.02 * budget, "frame {frame}: {e:.5} J against a budget of {budget:.5} J");
    }
    let end = sv.held_energy();
    println!("free cloth: budget {budget:.5} J, after 10 s {end:.5} J");
    assert!((end - budget).abs() <= 0.02 * budget, "budget {budget:.5} J, after 10 s {end:.5} J");
    assert_eq!(sv.ledger.budget, Some(budget), "no dissipation: the budget stays");
}

#[test]
fn a_cloth_at_rest_stays_at_rest() {
    let mut sv = damped_hanging_cloth(10, 3, 900);
    let before = FrameStats::measure(&sv, 0, 0.0).kinetic;
    let s = settings(10, 3, EnergyAware::Project);
    let mut peak: f64 = 0.0;
    for frame in 1..=300 {
        sv.step_frame(&s);
        peak = peak.max(FrameStats::measure(&sv, frame, 0.0).kinetic);
    }
    println!("at rest: kinetic energy {before:.3e} J before, at most {peak:.3e} J over 5 s of the projection");
    assert!(peak <= 1e-3, "the cloth at rest reached {peak:.3e} J of kinetic energy");
}

#[test]
fn the_projection_gives_the_same_bits_on_any_thread_count() {
    let run = |threads| {
        let mut sv = solver("cloth-paper", SceneOptions::default());
        let s = Settings {
            threads,
            energy_aware: EnergyAware::Project,
            substeps: 3,
            iterations: 10,
            ..Settings::default()
        };
        for _ in 0..60 {
            sv.step_frame(&s);
        }
        sv.particles.x.clone()
    };
    assert_eq!(run(1), run(2));
}

#[test]
#[cfg(feature = "studies")]
fn the_splits_report_writes_its_tables_and_figures() {
    use eapbd::report::splits::{self, SPLITS, SplitsOptions};
    let opts = SplitsOptions::quick();
    let (reference, runs, free) = splits::run_study(&opts, |_| {}).unwrap();
    assert!(reference.e0 > reference.e_eq, "{reference:?}");
    assert_eq!(runs.len(), SPLITS.len() * opts.variants.len());
    assert_eq!(free.len(), opts.variants.len());
    for r in &runs {
        assert_eq!(r.n.len(), opts.frames as usize);
        assert!(r.n.iter().chain(&r.u).all(|v| v.is_finite()), "{:?} at {} x {}", r.variant, r.substeps, r.iterations);
    }
    let dir = std::env::temp_dir().join(format!("eapbd-splits-{}", std::process::id()));
    splits::write_outputs(&dir, &opts, &reference, &runs, &free).unwrap();
    let csv = std::fs::read_to_string(dir.join("splits.csv")).unwrap();
    assert_eq!(csv.lines().count(), runs.len() + 1);
    assert!(csv.starts_with("substeps,iterations,setting,n_end"));
    let md = std::fs::read_to_string(dir.join("splits.md")).unwrap();
    assert!(md.contains("## 30 substeps × 1 iterations") && md.contains("| project |"));
    for png in ["splits_n.png", "splits_unresolved.png"] {
        assert!(std::fs::metadata(dir.join(png)).unwrap().len() > 1000, "{png}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_cloth_dropped_on_a_sphere_settles_and_never_gains() {
    // The in-loop contact passes' work is not in the budget yet: near a collider the projection
    // only takes gains away, so impacts dissipate and the draped cloth comes to rest.
    let mut sv = solver("cloth-sphere", SceneOptions { resolution: Some(21), ..SceneOptions::default() });
    let s = settings(3, 10, EnergyAware::Project);
    let start = FrameStats::measure(&sv, 0, 0.0).total();
    let mut peak = f64::MIN;
    for frame in 1..=300 {
        sv.step_frame(&s);
        peak = peak.max(FrameStats::measure(&sv, frame, 0.0).total());
    }
    let end = FrameStats::measure(&sv, 300, 0.0);
    println!(
        "cloth on a sphere: start {start:.4} J, peak {peak:.4} J, end {:.4} J, kinetic {:.3e} J",
        end.total(),
        end.kinetic
    );
    assert!(peak <= 1.001 * start, "the honest total rose from {start:.4} J to {peak:.4} J");
    assert!(end.kinetic < 0.01, "still moving after 5 s: {:.3e} J", end.kinetic);
}

#[test]
fn new_settings_start_the_budget_again() {
    let mut sv = hanging_cloth();
    for _ in 0..60 {
        sv.step_frame(&settings(10, 3, EnergyAware::Project));
    }
    let before = sv.ledger.budget.unwrap();
    // The same settings on more threads keep the budget; other substeps start it again after
    // the frame, from the energy measured with the new multipliers.
    sv.step_frame(&Settings { threads: 2, ..settings(10, 3, EnergyAware::Project) });
    assert_eq!(sv.ledger.budget, Some(before));
    sv.step_frame(&settings(30, 1, EnergyAware::Project));
    assert_eq!(sv.ledger.budget, Some(sv.held_energy()));
    sv.step_frame(&settings(30, 1, EnergyAware::Off));
    assert_eq!(sv.ledger.budget, None);
}

#[test]
fn the_dropped_bunny_loses_what_its_contacts_take() {
    // Every contact pass counts its work (in the loop and the final one), so after the landing
    // the energy the projection leaves is the start less that work, and never more than the start.
    let opts = SceneOptions { lattice: Some(8), ..SceneOptions::default() };
    let mut sv = solver("bunny", opts);
    let s = settings(3, 10, EnergyAware::Project);
    sv.step_frame(&s);
    let first = FrameStats::measure(&sv, 1, 0.0);
    let mut peak = f64::MIN;
    for frame in 2..=150 {
        sv.step_frame(&s);
        peak = peak.max(FrameStats::measure(&sv, frame, 0.0).total());
    }
    let last = FrameStats::measure(&sv, 150, 0.0);
    let (lost, work) = (first.total() - last.total(), first.dissipated - last.dissipated);
    println!("bunny: start {:.4} J, peak {peak:.4} J, lost {lost:.4} J, contact work {work:.4} J", first.total());
    assert!(work > 0.1 * first.total(), "the landing did contact work: {work:.4} J");
    assert!(peak <= 1.05 * first.total(), "the honest total rose to {peak:.4} J from {:.4} J", first.total());
    assert!((lost - work).abs() <= 0.05 * work, "lost {lost:.4} J against {work:.4} J of contact work");
}
