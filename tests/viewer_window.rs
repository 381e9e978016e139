//! The viewer for real: `eapbd view --scene cloth-paper --exit-after-frames 120 --screenshot
//! PATH` in a window on a virtual X display (Xvfb, started here; or `DISPLAY` when Xvfb is not
//! installed), drawn on the GPU adapter (lavapipe in CI). The screenshot (panels included) is
//! compared with `tests/golden/viewer_cloth_paper.png` by a tolerance; regenerate it on purpose
//! with `EAPBD_UPDATE_SNAPSHOTS=1 cargo test --release --test viewer_window`.
#![cfg(feature = "cli")]

mod common;

use std::io::{BufRead, BufReader};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const WIDTH: u32 = 1024;
const HEIGHT: u32 = 640;
/// Mean absolute difference per channel (0–255) allowed against the reference. The FPS and
/// timing figures in the panel differ between runs by about 0.02; one more row in the control
/// panel (every widget below it moved by a row) differs by about 3, and must fail.
const MEAN_TOLERANCE: f64 = 0.5;
/// The viewer must finish within this time.
const TIMEOUT: Duration = Duration::from_secs(240);

/// An X server started for the test, stopped when dropped.
struct Xvfb(Child);

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A display to open windows on: a new Xvfb, or `DISPLAY` when Xvfb is not installed.
fn display() -> (Option<Xvfb>, String) {
    let spawned = Command::new("Xvfb")
        .args(["-displayfd", "1", "-screen", "0", "1280x800x24", "-nolisten", "tcp"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn();
    match spawned {
        Ok(mut child) => {
            let mut line = String::new();
            if let Some(out) = child.stdout.take() {
                let _ = BufReader::new(out).read_line(&mut line);
            }
            let number = line.trim().to_string();
            let guard = Xvfb(child);
            assert!(!number.is_empty() && number.chars().all(|c| c.is_ascii_digit()), "Xvfb did not start: '{line}'");
            (Some(guard), format!(":{number}"))
        }
        Err(e) => match std::env::var("DISPLAY") {
            Ok(d) if !d.is_empty() => (None, d),
            _ => panic!(
                "the viewer test needs a display: Xvfb could not be started ({e}) and DISPLAY is not set; \
                 install it (Debian/Ubuntu: `apt-get install xvfb`)"
            ),
        },
    }
}

/// Pixels in `[x0, x1) × [y0, y1)` satisfying `f`, as a fraction.
fn fraction(img: &image::RgbaImage, (x0, x1): (u32, u32), (y0, y1): (u32, u32), f: impl Fn([u8; 3]) -> bool) -> f64 {
    let mut n = 0usize;
    for y in y0..y1 {
        for x in x0..x1 {
            let p = img.get_pixel(x, y).0;
            n += f([p[0], p[1], p[2]]) as usize;
        }
    }
    n as f64 / ((x1 - x0) * (y1 - y0)) as f64
}

/// Runs the viewer with `args` for 120 frames on `display`; returns its screenshot and where it
/// lies.
fn screenshot(display: &str, args: &[&str], name: &str) -> (image::RgbaImage, PathBuf) {
    let out = std::env::temp_dir().join(format!("eapbd-{name}-{}.png", std::process::id()));
    let _ = std::fs::remove_file(&out);
    let mut child = Command::new(env!("CARGO_BIN_EXE_eapbd"))
        .arg("view")
        .args(args)
        .args(["--exit-after-frames", "120", "--screenshot"])
        .arg(&out)
        .args(["--width", &WIDTH.to_string(), "--height", &HEIGHT.to_string()])
        .env("DISPLAY", display)
        .env_remove("WAYLAND_DISPLAY")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().expect("waiting for the viewer") {
            break s;
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("the viewer did not finish 120 frames within {} s", TIMEOUT.as_secs());
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let output = child.wait_with_output().expect("viewer output");
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(status.success(), "the viewer failed: {stderr}");
    eprintln!("{stderr}");
    let img = image::open(&out).unwrap_or_else(|e| panic!("{}: {e}", out.display())).to_rgba8();
    assert_eq!(img.dimensions(), (WIDTH, HEIGHT));
    (img, out)
}

/// The cloth's share of the pixels in `[x0, x1)` (red front or blue back, lit).
fn cloth(img: &image::RgbaImage, x: (u32, u32)) -> f64 {
    fraction(img, x, (0, HEIGHT), |[r, g, b]| {
        (r > 90 && r as u32 > g as u32 + 40 && r > b) || (b > 90 && b as u32 > r as u32 + 40)
    })
}

#[test]
fn viewer_window_draws_panels_and_scene() {
    let (_xvfb, display) = display();
    let (img, out) = screenshot(&display, &["--scene", "cloth-paper", "--backend", "gpu"], "viewer");
    // Not blank: many distinct colours.
    let distinct: std::collections::HashSet<[u8; 4]> = img.pixels().map(|p| p.0).collect();
    assert!(distinct.len() > 200, "only {} distinct colours", distinct.len());
    // The control panel on the left: a dark panel with light text.
    let panel = (0, 250);
    let dark = fraction(&img, panel, (0, HEIGHT), |p| p.iter().all(|&c| c < 70));
    let text = fraction(&img, panel, (0, HEIGHT), |p| p.iter().all(|&c| c > 140));
    assert!(dark > 0.5 && text > 0.01, "no control panel: {dark:.2} dark, {text:.3} light");
    // The scene in the middle: sky and the cloth.
    let middle = (320, WIDTH - 320);
    let sky = fraction(&img, middle, (0, HEIGHT), |[r, g, b]| r > 180 && g > 180 && b > 190);
    let cloth = cloth(&img, middle);
    assert!(sky > 0.1 && cloth > 0.03, "no scene: {sky:.2} sky, {cloth:.3} cloth");
    common::check_golden(&img, "viewer_cloth_paper.png", MEAN_TOLERANCE);
    let _ = std::fs::remove_file(&out);
}

#[test]
fn compare_mode_draws_both_runs_labelled() {
    // `view --compare energy-aware`: off on the left half of the scene, on on the right, each
    // with its cloth and its label.
    let (_xvfb, display) = display();
    let args =
        ["--scene", "cloth", "--substeps", "10", "--iterations", "3", "--backend", "cpu", "--compare", "energy-aware"];
    let (img, out) = screenshot(&display, &args, "compare");
    let mid = WIDTH / 2;
    let (left, right) = (cloth(&img, (300, mid - 10)), cloth(&img, (mid + 10, WIDTH - 300)));
    assert!(left > 0.01 && right > 0.01, "a half without its cloth: {left:.3}, {right:.3}");
    // The labels: light boxes at the top left of each half.
    let label = |x0: u32| fraction(&img, (x0, x0 + 80), (10, 24), |p| p.iter().all(|&c| c > 200));
    assert!(label(300) > 0.3 && label(mid + 8) > 0.3, "labels missing: {:.2}, {:.2}", label(300), label(mid + 8));
    common::check_golden(&img, "viewer_compare_energy_aware.png", MEAN_TOLERANCE);
    let _ = std::fs::remove_file(&out);
}
