//! The command line: outputs it writes and the errors it reports.

use std::path::PathBuf;
use std::process::{Command, Output};

fn eapbd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_eapbd")).args(args).output().expect("the binary runs")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("eapbd-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

#[test]
fn simulate_writes_csv_and_obj() {
    let (csv, obj) = (scratch("run.csv"), scratch("final.obj"));
    let out = eapbd(&[
        "simulate",
        "--scene",
        "cloth",
        "--resolution",
        "9",
        "--frames",
        "5",
        "--print-every",
        "2",
        "--csv",
        csv.to_str().unwrap(),
        "--export-obj",
        obj.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(stdout.lines().filter(|l| l.starts_with("frame")).count(), 2, "{stdout}");
    assert!(stdout.contains("summary: 5 frames") && stdout.contains("all finite"), "{stdout}");
    let csv = std::fs::read_to_string(csv).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 6);
    assert!(rows[0].starts_with("frame,time_ms,residual_rms"));
    assert_eq!(rows[5].split(',').count(), rows[0].split(',').count());
    let obj = std::fs::read_to_string(obj).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), 81);
    assert_eq!(obj.lines().filter(|l| l.starts_with("f ")).count(), 128);
    // Positions after 5 frames have fallen below the start height (1.2 m) but are finite.
    let ys: Vec<f32> =
        obj.lines().filter(|l| l.starts_with("v ")).map(|l| l.split(' ').nth(2).unwrap().parse().unwrap()).collect();
    assert!(ys.iter().all(|y| y.is_finite() && *y <= 1.2 + 1e-6));
    assert!(ys.iter().any(|y| *y < 1.19));
}

#[test]
fn unknown_names_list_the_allowed_values() {
    for (flag, value, allowed) in [
        ("--material", "rubber", "hookean, stvk-spring"),
        ("--form", "weak", "compliant, energy"),
        ("--solver", "newton", "gauss-seidel, jacobi"),
    ] {
        let out = eapbd(&["simulate", flag, value, "--frames", "1"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success());
        assert!(err.contains(value) && err.contains(allowed), "{flag}: {err}");
    }
    let out = eapbd(&["simulate", "--scene", "drape", "--frames", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("cloth, cloth-paper, cloth-sphere"), "{err}");
}

#[test]
fn absurd_parameters_are_refused_with_a_reason() {
    for (flag, value) in [("--dt", "0"), ("--stiffness", "-5"), ("--jacobi-omega", "3"), ("--substeps", "0")] {
        let out = eapbd(&["simulate", flag, value, "--frames", "1"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{flag} {value} accepted");
        assert!(err.contains(flag) && !err.contains("panicked"), "{flag}: {err}");
    }
    let out = eapbd(&["simulate", "--frames", "1", "--export-obj", "/nonexistent-dir/x.obj"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("/nonexistent-dir/x.obj") && !err.contains("panicked"), "{err}");
}

#[test]
fn quick_energy_report_writes_its_files() {
    let dir = scratch("energy-report");
    let out = eapbd(&["report", "energy", "--quick", "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for f in
        ["energy.md", "energy_runs.csv", "energy_series.csv", "energy_cloth_dt60.png", "energy_cloth-free_dt60.png"]
    {
        let meta = std::fs::metadata(dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert!(meta.len() > 100, "{f} is nearly empty");
    }
    let runs = std::fs::read_to_string(dir.join("energy_runs.csv")).unwrap();
    // 2 scenes × 2 iteration counts × 1 step × 4 variants, every one finite.
    assert_eq!(runs.lines().count(), 1 + 16);
    assert!(runs.lines().skip(1).all(|l| l.ends_with(",true")), "{runs}");
    let img = image::open(dir.join("energy_cloth_dt60.png")).unwrap().to_rgb8();
    assert!(img.width() >= 800 && img.pixels().any(|p| p.0 != [255, 255, 255]));
}

#[test]
fn viewer_without_a_display_points_to_the_headless_commands() {
    let out = Command::new(env!("CARGO_BIN_EXE_eapbd"))
        .args(["view", "--exit-after-frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .expect("the binary runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(err.contains("cannot open a window") && err.contains("eapbd render") && !err.contains("panicked"), "{err}");
    let out = eapbd(&["view", "--screenshot", "x.png"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("--exit-after-frames"), "{err}");
}
