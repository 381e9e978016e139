//! `eapbd render`: simulate headless and write frames as PNG, or as one animated GIF.

use std::path::PathBuf;
use std::sync::Arc;

use anyhow::Context;
use clap::Args;
use eapbd::compare::Compare;
use eapbd::gpu::{GpuContext, Kernels};
use eapbd::render::{Snapshotter, save_png};
use eapbd::simulation::{Backend, Simulation};
use image::codecs::gif::{GifEncoder, Repeat};

use super::{SceneArgs, named};

/// Arguments of `eapbd render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene and solver options.
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Frames to simulate.
    #[arg(long, default_value_t = 240)]
    pub frames: u32,
    /// Write a PNG every N frames.
    #[arg(long, default_value_t = 60)]
    pub every: u32,
    /// Output directory (created if missing).
    #[arg(long, default_value = "frames")]
    pub out: PathBuf,
    /// Solver backend: gpu or cpu (the image is drawn on the GPU either way).
    #[arg(long, default_value = "gpu", value_parser = named::<Backend>)]
    pub backend: Backend,
    /// Image width (px).
    #[arg(long, default_value_t = 800)]
    pub width: u32,
    /// Image height (px).
    #[arg(long, default_value_t = 600)]
    pub height: u32,
    /// Two runs side by side that differ in one setting, each half `--width` wide and
    /// labelled: energy-aware (off | on), split (1 × 30 | 30 × 1), solver (Gauss-Seidel |
    /// Jacobi), form (compliant | energy) or sor (1 | 1.5).
    #[arg(long, value_parser = named::<Compare>)]
    pub compare: Option<Compare>,
    /// Write the frames (every `--every`) into one looping animated GIF at this path instead of
    /// PNGs in `--out`, each shown for `--every` × dt (rounded to GIF's 10 ms).
    #[arg(long)]
    pub gif: Option<PathBuf>,
}

/// Runs the command.
pub fn run(a: &RenderArgs) -> anyhow::Result<()> {
    anyhow::ensure!(a.frames > 0, "--frames must be at least 1");
    anyhow::ensure!(a.every > 0, "--every must be at least 1");
    let settings = a.scene.settings()?;
    let scene = a.scene.build_scene()?;
    super::warn_about(&scene, &settings);
    let ctx = GpuContext::new()?;
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let mut gif = match &a.gif {
        Some(path) => Some(gif_encoder(path)?),
        None => {
            std::fs::create_dir_all(&a.out).with_context(|| format!("cannot create {}", a.out.display()))?;
            None
        }
    };
    // GIF counts delays in hundredths of a second: the nearest one.
    let delay = image::Delay::from_numer_denom_ms((a.every as f32 * settings.dt * 100.0).round() as u32 * 10, 1);
    let sides = match a.compare {
        Some(c) => c.sides(&settings).to_vec(),
        None => vec![("", settings)],
    };
    let mut runs = Vec::with_capacity(sides.len());
    for (label, s) in sides {
        let sim = Simulation::new(a.backend, scene.clone(), Some((&ctx, &kernels)))?;
        sim.check_settings(&s)?;
        let snap = Snapshotter::new(&ctx, &sim, a.width, a.height)?;
        runs.push((label, s, sim, snap));
    }
    let what = a.compare.map_or(String::new(), |c| format!(", comparing {}", c.name()));
    eprintln!("rendering {} on {} with the {} solver{what}", scene.name, ctx.describe(), a.backend.name());
    let bar = indicatif::ProgressBar::new(a.frames as u64);
    for frame in 1..=a.frames {
        for (_, s, sim, _) in &mut runs {
            sim.step_frame(s);
        }
        if frame % a.every == 0 {
            let mut img = image::RgbaImage::new(a.width * runs.len() as u32, a.height);
            for (i, (label, _, sim, snap)) in runs.iter().enumerate() {
                let x = a.width * i as u32;
                image::imageops::replace(&mut img, &snap.capture(&ctx, sim)?, x as i64, 0);
                if !label.is_empty() {
                    eapbd::report::plot::label(&mut img, (x as i32 + 8, 8), label, 18.0)?;
                }
            }
            if let Some(enc) = &mut gif {
                enc.encode_frame(image::Frame::from_parts(img, 0, 0, delay)).context("writing the GIF")?;
            } else {
                let path = a.out.join(format!("frame_{frame:05}.png"));
                save_png(&img, &path)?;
                bar.suspend(|| say!("wrote {}", path.display()));
            }
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    if let (Some(enc), Some(path)) = (gif, &a.gif) {
        drop(enc);
        say!("wrote {}", path.display());
    }
    Ok(())
}

/// A looping GIF encoder writing to `path` (its folder created if missing).
fn gif_encoder(path: &std::path::Path) -> anyhow::Result<GifEncoder<std::io::BufWriter<std::fs::File>>> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    }
    let file = std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    // Speed 10 of NeuQuant's 1..30: a good palette in a fraction of the slowest one's time.
    let mut enc = GifEncoder::new_with_speed(std::io::BufWriter::new(file), 10);
    enc.set_repeat(Repeat::Infinite).context("writing the GIF")?;
    Ok(enc)
}
