//! The same scene on the GPU solver and on the CPU reference solver: open a device
//! ([`eapbd::gpu::GpuContext`]), build the compute pipelines once ([`eapbd::gpu::Kernels`]),
//! upload the scene ([`eapbd::gpu::GpuSolver`]), run both for two seconds and compare the final
//! positions and energies. A swinging cloth amplifies tiny differences, so the distance is set
//! beside the CPU's own spread when one particle starts 1 µm away.
//!
//! ```sh
//! cargo run --release --example gpu_cloth
//! ```
//!
//! Without a GPU, Mesa's lavapipe (`mesa-vulkan-drivers`) runs the kernels on the CPU
//! (`WGPU_BACKEND=vulkan` skips probing GL). With no adapter at all the example says so and
//! exits successfully without comparing.

use std::sync::Arc;
use std::time::Instant;

use eapbd::Error;
use eapbd::gpu::{GpuContext, GpuSolver, Kernels};
use eapbd::metrics::FrameStats;
use eapbd::scene::{self, SceneOptions};
use eapbd::solver::{CpuSolver, Settings};
use glam::Vec3;

const FRAMES: u32 = 120;

fn main() -> eapbd::Result<()> {
    let ctx = match GpuContext::new() {
        Ok(ctx) => ctx,
        Err(e @ Error::NoAdapter(_)) => {
            println!("{e}\nno GPU comparison made");
            return Ok(());
        }
        Err(e) => return Err(e),
    };
    println!("GPU: {}", ctx.describe());
    let kernels = Arc::new(Kernels::new(&ctx.device));

    // The hanging cloth: 41 × 41 particles, 4880 springs (k_s = 1e4 N/m) and 4720 bending
    // elements; 1/60 s frames of 10 substeps × 3 iterations. (Without bending, `cloth-paper`
    // crumples, and crumpling is chaotic: rounding differences between the backends grow to
    // centimetres.)
    let scene = scene::build("cloth", &SceneOptions::default())?;
    let settings = Settings { substeps: 10, iterations: 3, ..Settings::default() };
    settings.validate()?;
    let mut gpu = GpuSolver::new(kernels, &ctx.device, &ctx.queue, scene.clone())?;
    let mut cpu = CpuSolver::<Vec3>::new(scene);
    // A second CPU run with one particle moved by 1 µm: how much the motion itself amplifies
    // a tiny difference, which is the scale any two backends' rounding can reach.
    let mut nudged = cpu.clone();
    let mid = nudged.particles.len() / 2;
    nudged.particles.x[mid].x += 1e-6;

    let t = Instant::now();
    for _ in 0..FRAMES {
        cpu.step_frame(&settings);
    }
    let cpu_ms = t.elapsed().as_secs_f64() * 1e3 / FRAMES as f64;
    let t = Instant::now();
    for _ in 0..FRAMES {
        gpu.step_frame(&settings); // records and submits; does not wait
    }
    let x_gpu = gpu.read_positions()?; // waits for the queue
    let gpu_ms = t.elapsed().as_secs_f64() * 1e3 / FRAMES as f64;
    for _ in 0..FRAMES {
        nudged.step_frame(&settings);
    }

    let x = &cpu.particles.x;
    let max_distance = |y: &[Vec3]| x.iter().zip(y).map(|(a, b)| a.distance(*b)).fold(0.0f32, f32::max);
    let (d_gpu, d_self) = (max_distance(&x_gpu), max_distance(&nudged.particles.x));
    let (c, g) = (FrameStats::measure(&cpu, FRAMES, 0.0), gpu.stats(FRAMES, 0.0)?);
    println!("{FRAMES} frames of {} ({} particles):", cpu.scene().name, x.len());
    println!("  CPU {cpu_ms:.2} ms/frame, GPU {gpu_ms:.2} ms/frame (submission to read-back)");
    println!("  largest distance GPU - CPU: {d_gpu:.3e} m; CPU - CPU moved by 1 µm: {d_self:.3e} m");
    println!("  total energy: CPU {:.6} J, GPU {:.6} J", c.total(), g.total());
    println!("  mean stretch: CPU {:.5}, GPU {:.5}", c.stretch_mean, g.stretch_mean);
    // The criterion of tests/gpu_parity.rs for motions this sensitive.
    if d_gpu <= 10.0 * d_self + 1e-4 {
        println!("the backends agree (within ten times the CPU's own spread + 1e-4 m)");
    } else {
        println!("the backends differ by more than the CPU's own spread explains");
    }
    Ok(())
}
