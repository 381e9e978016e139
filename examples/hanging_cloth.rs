//! The hanging cloth on the CPU reference solver, used as a library: build the `cloth` scene,
//! step it frame by frame with plain XPBD and with the global energy balance, and print the
//! stretch and the energies.
//!
//! ```sh
//! cargo run --release --example hanging_cloth
//! ```
//!
//! The cloth is 1 m wide, 1 kg, 21 × 21 particles, pinned at two corners of one edge, with
//! Hookean springs of small-strain stiffness 1000 N/m and dihedral bending of 1e-3 N·m/rad. It
//! falls and swings; `total` is kinetic + gravitational (heights from the ground) + elastic
//! energy in joules, which an exact integrator would keep constant.

use std::time::Instant;

use eapbd::metrics::FrameStats;
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, EnergyAware, Settings};
use glam::Vec3;

fn main() -> eapbd::Result<()> {
    let options = SceneOptions { resolution: Some(21), stiffness: 1000.0, ..SceneOptions::default() };
    let scene = scene::build("cloth", &options)?;
    println!("scene {}: {} particles, {} constraints", scene.name, scene.num_particles(), scene.num_constraints());

    for energy_aware in [EnergyAware::Off, EnergyAware::Global] {
        // 1/120 s frames, 30 Gauss-Seidel iterations, compliant form (the defaults otherwise).
        let settings = Settings { dt: 1.0 / 120.0, iterations: 30, energy_aware, ..Settings::default() };
        settings.validate()?;
        let mut solver = CpuSolver::<Vec3>::new(scene.clone());
        let start = FrameStats::measure(&solver, 0, 0.0).total();
        println!("\nenergy-aware {}:", energy_aware.name());
        println!("frame  time (s)  stretch mean  stretch max  kinetic (J)  elastic (J)  total (J)  solve (ms)");
        for frame in 1..=600u32 {
            let t = Instant::now();
            solver.step_frame(&settings);
            let ms = t.elapsed().as_secs_f64() * 1e3;
            if frame % 60 == 0 {
                let s = FrameStats::measure(&solver, frame, ms);
                println!(
                    "{:5}  {:8.2}  {:12.4}  {:11.4}  {:11.4}  {:11.5}  {:9.4}  {:10.2}",
                    frame,
                    frame as f32 * settings.dt,
                    s.stretch_mean,
                    s.stretch_max,
                    s.kinetic,
                    s.elastic,
                    s.total(),
                    ms
                );
            }
        }
        let end = FrameStats::measure(&solver, 600, 0.0).total();
        println!("total energy after 5 s: {:+.1}% of the start", 100.0 * (end - start) / start.abs());
    }
    Ok(())
}
