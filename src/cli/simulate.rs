//! `eapbd simulate`: run a scene on the CPU solver and report per frame.

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use clap::Args;
use std::sync::Arc;

use eapbd::gpu::{GpuContext, Kernels};
use eapbd::metrics::FrameStats;
use eapbd::simulation::{Backend, Simulation};

use super::bench::timing::median;
use super::{SceneArgs, named};

/// Arguments of `eapbd simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    /// Scene and solver options.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Frames to simulate.
    #[arg(long, default_value_t = 300)]
    pub frames: u32,
    /// Print a line every N frames (0: summary only).
    #[arg(long, default_value_t = 1)]
    pub print_every: u32,
    /// Write every frame's figures as CSV to this file.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write the final surface (as drawn: the embedded surface where there is one) as Wavefront
    /// OBJ to this file.
    #[arg(long)]
    pub export_obj: Option<PathBuf>,
    /// Write the surface as an OBJ sequence into this directory (frame_00010.obj, ...), for
    /// Blender and other tools.
    #[arg(long)]
    pub export_obj_dir: Option<PathBuf>,
    /// Frames between the files of --export-obj-dir.
    #[arg(long, default_value_t = 10)]
    pub export_every: u32,
    /// Solver backend: cpu or gpu.
    #[arg(long, default_value = "cpu", value_parser = named::<Backend>)]
    pub backend: Backend,
}

/// Runs the command.
pub fn run(a: &SimulateArgs) -> anyhow::Result<()> {
    anyhow::ensure!(a.frames > 0, "--frames must be at least 1");
    anyhow::ensure!(a.export_every > 0, "--export-every must be at least 1");
    let settings = a.scene.settings()?;
    let scene = a.scene.build_scene()?;
    super::warn_about(&scene, &settings);
    let gpu = match a.backend {
        Backend::Gpu => {
            let ctx = GpuContext::new()?;
            let kernels = Arc::new(Kernels::new(&ctx.device));
            say!("GPU: {}", ctx.describe());
            Some((ctx, kernels))
        }
        Backend::Cpu => None,
    };
    say!(
        "scene {}: {} particles, {} constraints ({}), {} form, {}, {} iterations x {} substeps, dt {:.6} s, {} backend",
        scene.name,
        scene.num_particles(),
        scene.num_constraints(),
        families(&scene),
        settings.form.name(),
        settings.method.name(),
        settings.iterations,
        settings.substeps,
        settings.dt,
        a.backend.name()
    );
    let mut csv = match &a.csv {
        Some(path) => {
            let mut f = std::io::BufWriter::new(
                std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?,
            );
            writeln!(f, "{}", FrameStats::CSV_HEADER)?;
            Some(f)
        }
        None => None,
    };
    if let Some(dir) = &a.export_obj_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let mut sim = Simulation::new(a.backend, scene, gpu.as_ref().map(|(c, k)| (c, k)))?;
    sim.check_settings(&settings)?;
    // Each frame's solve time (ms): the mean, and the median, which the odd frame in which the
    // host takes a core away does not move.
    let mut times = Vec::with_capacity(a.frames as usize);
    let mut last = FrameStats::default();
    for frame in 1..=a.frames {
        let t = Instant::now();
        sim.step_frame(&settings);
        if let Some((ctx, _)) = &gpu {
            ctx.wait()?;
        }
        let ms = t.elapsed().as_secs_f64() * 1e3;
        times.push(ms);
        if let Some(dir) = &a.export_obj_dir
            && frame % a.export_every == 0
        {
            let (x, triangles) = sim.scene().surface(&sim.positions()?);
            eapbd::mesh::write_obj(&dir.join(format!("frame_{frame:05}.obj")), &x, triangles)?;
        }
        let printing = a.print_every > 0 && frame % a.print_every == 0;
        if printing || csv.is_some() || frame == a.frames {
            last = sim.stats(frame, ms)?;
            if printing {
                say!("{last}");
            }
            if let Some(f) = &mut csv {
                writeln!(f, "{}", last.csv_row())?;
            }
        }
    }
    if let Some(mut f) = csv {
        f.flush()?;
    }
    let x = sim.positions()?;
    let finite = x.iter().all(|x| x.is_finite()) && last.is_finite();
    say!(
        "summary: {} frames, {:.3} ms/frame mean solve time (median {:.3}), final stretch mean {:.3e} max {:.3e}, total energy {:.4e} J, {}",
        a.frames,
        times.iter().sum::<f64>() / a.frames as f64,
        median(&mut times),
        last.stretch_mean,
        last.stretch_max,
        last.total(),
        if finite { "all finite" } else { "NON-FINITE VALUES" }
    );
    if let Some(sc) = sim.self_collision_counts()? {
        say!(
            "self-collision: {} candidate pairs, references renewed at {} checks ({:.2} a frame), {} candidates dropped at the last search",
            sc.pairs,
            sc.builds,
            sc.builds as f64 / a.frames as f64,
            sc.dropped
        );
    }
    if let Simulation::Cpu(c) = &sim
        && let Some(line) = team_line(c.team_time())
    {
        say!("{line}");
    }
    if let Some(path) = &a.export_obj {
        let (x, triangles) = sim.scene().surface(&x);
        eapbd::mesh::write_obj(path, &x, triangles)?;
        say!("wrote {}", path.display());
    }
    anyhow::ensure!(finite, "the simulation produced non-finite values");
    Ok(())
}

/// Where the team's threads spent their frames, when some frames ran on several threads.
fn team_line(t: &eapbd::solver::TeamTime) -> Option<String> {
    if t.frames == 0 {
        return None;
    }
    let ms = |d: &std::time::Duration| d.as_secs_f64() * 1e3 / f64::from(t.frames);
    let each: Vec<String> = t.busy.iter().zip(&t.waited).map(|(b, w)| format!("{:.3}/{:.3}", ms(b), ms(w))).collect();
    Some(format!(
        "team: {} frames on {} threads, waiting {:.1} % of their time ({:.0} % of the waits at the barriers, the \
         rest before boundary parts); ms/frame working/waiting per thread: {}",
        t.frames,
        t.busy.len(),
        100.0 * t.wait_fraction(),
        100.0 * t.barrier_fraction(),
        each.join(", ")
    ))
}

fn families(scene: &eapbd::scene::Scene) -> String {
    let mut parts = Vec::new();
    eapbd::for_each_family!(scene, |i, f| parts.push(format!(
        "{} {}, {}",
        f.len(),
        eapbd::scene::FAMILY_LABELS[i],
        f.stats
    )));
    if let Some(e) = &scene.embedding {
        parts.push(format!("embedded surface of {} vertices, {} triangles", e.bindings.len(), e.triangles.len()));
    }
    parts.join("; ")
}
