//! Helpers shared by the tests: random vectors and central finite differences (the constraint
//! tests), and the GPU context with its kernels (the GPU tests).
#![allow(dead_code)]

use std::sync::Arc;

use eapbd::gpu::{GpuContext, Kernels};

use eapbd::constraints::{Element, Form};
use glam::DVec3;
use rand::Rng;
use rand::rngs::SmallRng;

/// A vector with coordinates uniform in `(-s, s)`.
pub fn rand_vec(rng: &mut SmallRng, s: f64) -> DVec3 {
    DVec3::new(rng.random_range(-s..s), rng.random_range(-s..s), rng.random_range(-s..s))
}

/// Central differences of `f` with respect to every coordinate of every particle.
pub fn fd_gradient<const N: usize>(x: &[DVec3; N], f: impl Fn(&[DVec3; N]) -> f64) -> [DVec3; N] {
    let h = 1e-6;
    let mut g = [DVec3::ZERO; N];
    for n in 0..N {
        for k in 0..3 {
            let (mut xp, mut xm) = (*x, *x);
            xp[n][k] += h;
            xm[n][k] -= h;
            g[n][k] = (f(&xp) - f(&xm)) / (2.0 * h);
        }
    }
    g
}

/// Asserts `a ≈ b` particle by particle, relative to the largest of `b` (at least 1e-3).
pub fn assert_close<const N: usize>(what: &str, a: &[DVec3; N], b: &[DVec3; N]) {
    let scale = b.iter().map(|v| v.length()).fold(1e-3, f64::max);
    for n in 0..N {
        let err = (a[n] - b[n]).length();
        assert!(err <= 1e-5 * scale, "{what}: particle {n}: analytic {:?} vs finite differences {:?}", a[n], b[n]);
    }
}

/// Checks energy, energy gradient and compliant-form gradient of `e` at `x` against finite
/// differences.
pub fn check_gradients<E: Element<N>, const N: usize>(what: &str, e: &E, p: &E::Params, x: &[DVec3; N]) {
    let g = e.energy_gradient(p, x);
    let fd = fd_gradient(x, |y| e.energy(p, y));
    assert_close(&format!("{what} energy gradient"), &g, &fd);
    let proj = e.compliant(p, x);
    let fd_c = fd_gradient(x, |y| e.compliant(p, y).c);
    assert_close(&format!("{what} compliant gradient"), &proj.grad, &fd_c);
    // The compliant form's energy C²/(2α) is the material energy.
    let e_c = proj.c * proj.c / (2.0 * proj.alpha);
    let e_m = e.energy(p, x);
    assert!((e_c - e_m).abs() <= 1e-9 * e_m.abs().max(1e-9), "{what}: C²/2α = {e_c} but E = {e_m}");
    // The energy form projects on C = E.
    let pe = e.constraint(p, x, Form::Energy, 1e-5);
    assert_eq!(pe.c, e_m);
    assert_eq!(pe.alpha, 1e-5);
}

/// The GPU context and its kernels; the GPU tests need an adapter (Mesa lavapipe in CI) and fail
/// without one.
pub fn gpu() -> (GpuContext, Arc<Kernels>) {
    let ctx = GpuContext::new().unwrap_or_else(|e| panic!("GPU tests need an adapter: {e}"));
    let kernels = Arc::new(Kernels::new(&ctx.device));
    (ctx, kernels)
}

/// Mean absolute difference per channel (0–255) of two images of one size.
pub fn mean_abs_diff(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    let sum: u64 = a.as_raw().iter().zip(b.as_raw()).map(|(x, y)| x.abs_diff(*y) as u64).sum();
    sum as f64 / a.as_raw().len() as f64
}

/// Compares `img` with the stored `tests/golden/{file}`: the mean absolute difference per channel
/// (0–255) must stay below `tolerance`. With `EAPBD_UPDATE_SNAPSHOTS` set, `img` is stored first
/// (regenerating the references is always on purpose). A failing image is written to the temp
/// directory as `{file}_actual.png`.
pub fn check_golden(img: &image::RgbaImage, file: &str, tolerance: f64) {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden").join(file);
    if std::env::var_os("EAPBD_UPDATE_SNAPSHOTS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        eapbd::render::save_png(img, &path).unwrap();
        eprintln!("updated {}", path.display());
    }
    let reference = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; create it with EAPBD_UPDATE_SNAPSHOTS=1", path.display()))
        .to_rgba8();
    assert_eq!(reference.dimensions(), img.dimensions());
    let diff = mean_abs_diff(img, &reference);
    eprintln!("{file}: mean difference from the reference {diff:.3} of 255");
    if diff >= tolerance {
        let out = std::env::temp_dir().join(file.replace(".png", "_actual.png"));
        eapbd::render::save_png(img, &out).unwrap();
        panic!("{file}: mean difference {diff:.3} (limit {tolerance}); actual image at {}", out.display());
    }
}

/// A CSV file's rows as column name → value, after checking its header is `header`.
pub fn read_csv(path: &std::path::Path, header: &str) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let names: Vec<&str> = lines.next().expect("a header").split(',').collect();
    assert_eq!(names.join(","), header, "{}", path.display());
    lines
        .map(|l| {
            let cols: Vec<&str> = l.splitn(names.len(), ',').collect();
            assert_eq!(cols.len(), names.len(), "{l}");
            names.iter().zip(&cols).map(|(h, v)| (h.to_string(), v.to_string())).collect()
        })
        .collect()
}

/// Runs `eapbd report {args} --out {dir}` and returns its standard output, failing with its
/// output when it fails.
#[cfg(feature = "cli")]
pub fn run_report(args: &[&str], dir: &std::path::Path) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_eapbd"))
        .arg("report")
        .args(args)
        .arg("--out")
        .arg(dir)
        .output()
        .expect("the binary runs");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    stdout
}
