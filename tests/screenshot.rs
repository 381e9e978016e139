//! Screenshot tests: `cloth-paper` and `bunny` after 60 frames and `cloth-drape` after 45,
//! drawn headless on the GPU, against stored images. Regenerate the reference on purpose with `EAPBD_UPDATE_SNAPSHOTS=1 cargo test --release
//! --test screenshot`. Needs a GPU adapter (Mesa lavapipe in CI).

mod common;

use std::sync::Arc;

use common::mean_abs_diff;

use eapbd::gpu::{GpuContext, Kernels};
use eapbd::render::Snapshotter;
use eapbd::scene::{self, SceneOptions};
use eapbd::simulation::{Backend, Simulation};
use eapbd::solver::{EnergyAware, Settings};

const WIDTH: u32 = 320;
const HEIGHT: u32 = 240;
/// Mean absolute difference per channel (0–255) allowed against the reference.
const MEAN_TOLERANCE: f64 = 1.5;

/// Fraction of pixels that differ clearly from the background.
fn coverage(img: &image::RgbaImage, background: &image::RgbaImage) -> f64 {
    let changed = img
        .pixels()
        .zip(background.pixels())
        .filter(|(a, b)| a.0.iter().zip(b.0).any(|(x, y)| x.abs_diff(y) > 24))
        .count();
    changed as f64 / (img.width() * img.height()) as f64
}

/// `name` drawn after `frames` frames, and the same view without the simulated surface.
fn render_scene(name: &str, backend: Backend, frames: u32, s: &Settings) -> (image::RgbaImage, image::RgbaImage) {
    let ctx = GpuContext::new().unwrap_or_else(|e| panic!("screenshot tests need a GPU adapter: {e}"));
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let sc = scene::build(name, &SceneOptions::default()).unwrap();
    let mut sim = Simulation::new(backend, sc, Some((&ctx, &kernels))).unwrap();
    let mut snap = Snapshotter::new(&ctx, &sim, WIDTH, HEIGHT).unwrap();
    for _ in 0..frames {
        sim.step_frame(s);
    }
    let img = snap.capture(&ctx, &sim).unwrap();
    snap.view.show_surface = false;
    let background = snap.capture(&ctx, &sim).unwrap();
    (img, background)
}

fn render(backend: Backend, frames: u32) -> (image::RgbaImage, image::RgbaImage) {
    render_scene("cloth-paper", backend, frames, &Settings::default())
}

/// `img` against the stored `file`, and not blank: the body covers a fraction of the picture in
/// `covers`, where it differs clearly from what is behind it.
fn check_picture((img, background): (image::RgbaImage, image::RgbaImage), file: &str, covers: std::ops::Range<f64>) {
    common::check_golden(&img, file, MEAN_TOLERANCE);
    let fraction = coverage(&img, &background);
    assert!(covers.contains(&fraction), "{file}: the body covers {:.1}% of the image", 100.0 * fraction);
}

#[test]
fn bunny_matches_the_stored_image() {
    // The volumetric bunny's embedded surface after it has landed.
    let s = Settings { substeps: 2, iterations: 10, ..Settings::default() };
    check_picture(render_scene("bunny", Backend::Gpu, 60, &s), "bunny_60.png", 0.03..0.6);
}

#[test]
fn cloth_drape_matches_the_stored_image() {
    // The upright cloth folding onto the ground with self-collision (the CPU solver, the only
    // backend that has it so far), three quarters of a second in.
    check_picture(render_scene("cloth-drape", Backend::Cpu, 45, &Settings::default()), "cloth_drape_45.png", 0.01..0.6);
}

#[test]
fn cloth_paper_matches_the_stored_image() {
    check_picture(render(Backend::Gpu, 60), "cloth_paper_60.png", 0.05..0.6);
}

#[test]
fn cpu_backend_draws_the_same_picture() {
    // The CPU solver's positions, uploaded and drawn by the same renderer, after 20 frames
    // (before the unbent cloth starts to crumple chaotically).
    let (gpu, _) = render(Backend::Gpu, 20);
    let (cpu, background) = render(Backend::Cpu, 20);
    let diff = mean_abs_diff(&gpu, &cpu);
    assert!(diff < 0.5, "CPU- and GPU-solved frames differ by {diff:.3} on average");
    let fraction = coverage(&cpu, &background);
    assert!(fraction > 0.05, "the CPU frame's cloth covers {:.1}%", 100.0 * fraction);
}

#[test]
#[cfg(feature = "cli")]
fn render_compare_draws_both_runs_side_by_side() {
    // `eapbd render --compare energy-aware` on the hanging cloth at 10 × 3 after 5 s: off on
    // the left, on (project) on the right, each half the run it is labelled with.
    let out = std::env::temp_dir().join(format!("eapbd-compare-{}", std::process::id()));
    let (w, h) = (WIDTH.to_string(), HEIGHT.to_string());
    let args = ["render", "--compare", "energy-aware", "--scene", "cloth", "--substeps", "10", "--iterations", "3"];
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_eapbd"))
        .args(args)
        .args(["--frames", "300", "--every", "300", "--backend", "cpu", "--width", &w, "--height", &h])
        .arg("--out")
        .arg(&out)
        .status()
        .expect("the binary runs");
    assert!(status.success());
    let img = image::open(out.join("frame_00300.png")).unwrap().to_rgba8();
    let _ = std::fs::remove_dir_all(&out);
    assert_eq!(img.dimensions(), (2 * WIDTH, HEIGHT));
    common::check_golden(&img, "compare_energy_aware_300.png", MEAN_TOLERANCE);

    // Each half is its run: the same frame drawn alone differs only where the label lies.
    let base = Settings { substeps: 10, iterations: 3, ..Settings::default() };
    for (i, energy_aware) in [EnergyAware::Off, EnergyAware::Project].into_iter().enumerate() {
        let s = Settings { energy_aware, ..base };
        let (alone, _) = render_scene("cloth", Backend::Cpu, 300, &s);
        let below_label =
            |img: &image::RgbaImage, x: u32| image::imageops::crop_imm(img, x, 48, WIDTH, HEIGHT - 48).to_image();
        let diff = mean_abs_diff(&below_label(&img, WIDTH * i as u32), &below_label(&alone, 0));
        println!("half {i}: {diff:.4} from its run drawn alone");
        assert!(diff < 0.5, "half {i} differs from its run drawn alone by {diff:.3}");
    }
    let left = image::imageops::crop_imm(&img, 0, 0, WIDTH, HEIGHT).to_image();
    let right = image::imageops::crop_imm(&img, WIDTH, 0, WIDTH, HEIGHT).to_image();
    let apart = mean_abs_diff(&left, &right);
    println!("off and on: {apart:.3} apart");
    assert!(apart > 1.0, "off and on look the same after 5 s ({apart:.3})");
}

#[test]
#[cfg(feature = "cli")]
fn render_gif_writes_a_looping_animation() {
    // `eapbd render --gif`: every `--every` frames one GIF frame, shown for `--every` × dt, and
    // the last one the same picture as the PNG of that frame (within the GIF palette's rounding).
    use image::AnimationDecoder;
    let dir = std::env::temp_dir().join(format!("eapbd-gif-{}", std::process::id()));
    let gif = dir.join("run.gif");
    let run = |extra: &[&str]| {
        let status = std::process::Command::new(env!("CARGO_BIN_EXE_eapbd"))
            .args(["render", "--scene", "cloth", "--resolution", "12", "--frames", "12", "--every", "4"])
            .args(["--backend", "cpu", "--width", "96", "--height", "72"])
            .args(extra)
            .status()
            .expect("the binary runs");
        assert!(status.success());
    };
    run(&["--gif", gif.to_str().unwrap()]);
    run(&["--out", dir.join("png").to_str().unwrap()]);
    let decoder = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(std::fs::File::open(&gif).unwrap()));
    let frames = decoder.unwrap().into_frames().collect_frames().unwrap();
    assert_eq!(frames.len(), 3, "frames 4, 8 and 12");
    for f in &frames {
        assert_eq!(f.buffer().dimensions(), (96, 72));
        let (num, den) = f.delay().numer_denom_ms();
        let ms = num as f32 / den as f32;
        assert!((ms - 4000.0 / 60.0).abs() <= 5.0, "each frame shown for 4 frames of 1/60 s: {ms} ms");
    }
    let png = image::open(dir.join("png").join("frame_00012.png")).unwrap().to_rgba8();
    let diff = mean_abs_diff(frames[2].buffer(), &png);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(diff < 4.0, "the last GIF frame against the PNG of frame 12: {diff:.3}");
}
