//! The command line: outputs it writes and the errors it reports.
#![cfg(feature = "cli")]

use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn eapbd(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_eapbd")).args(args).output().expect("the binary runs")
}

/// A path of this test process under the system's temporary directory, removed (file or
/// directory) when the test is over and its assertions have passed (left for inspection when
/// one fails).
struct Scratch(PathBuf);

impl Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0).or_else(|_| std::fs::remove_file(&self.0));
        }
    }
}

fn scratch(name: &str) -> Scratch {
    Scratch(std::env::temp_dir().join(format!("eapbd-cli-test-{}-{name}", std::process::id())))
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
    let median = stdout.split("mean solve time (median ").nth(1).and_then(|r| r.split(')').next());
    assert!(median.and_then(|m| m.parse::<f64>().ok()).is_some_and(|m| m > 0.0), "a median frame time: {stdout}");
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
    for command in ["simulate", "render"] {
        let out = eapbd(&[command, "--frames", "0"]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success() && err.contains("--frames must be at least 1"), "{command}: {err}");
    }
    // A window wider than any surface (winit's X11 sizes stop at 65535) is refused before a
    // display is opened.
    let out = eapbd(&["view", "--width", "100000", "--exit-after-frames", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("--width/--height") && !err.contains("panicked"), "{err}");
    // A box scene of billions of tetrahedra is refused before anything is allocated.
    let out = eapbd(&["simulate", "--scene", "cube", "--resolution", "2048", "--frames", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("--resolution") && err.contains("at most 140"), "{err}");
    let out = eapbd(&["simulate", "--frames", "1", "--export-obj", "/nonexistent-dir/x.obj"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("/nonexistent-dir/x.obj") && !err.contains("panicked"), "{err}");
}

#[test]
fn a_neo_hookean_body_with_negative_poisson_ratio_is_warned_about() {
    let out = eapbd(&["simulate", "--scene", "cube", "--poisson", "-0.2", "--frames", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && err.contains("warning: neo-hookean") && err.contains("no lower bound"), "{err}");
    for args in [&["--poisson", "0.2"][..], &["--poisson", "-0.2", "--material", "stvk"]] {
        let out = eapbd(&[&["simulate", "--scene", "cube", "--frames", "1"][..], args].concat());
        assert!(out.status.success() && !String::from_utf8_lossy(&out.stderr).contains("warning"), "{args:?}");
    }
}

#[test]
fn substeps_too_fine_for_f32_positions_are_warned_about() {
    let out = eapbd(&["simulate", "--substeps", "250", "--iterations", "1", "--frames", "3"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && err.contains("warning: at 250 substeps") && err.contains("never start"), "{err}");
    let out = eapbd(&["simulate", "--substeps", "30", "--iterations", "1", "--frames", "3"]);
    assert!(out.status.success() && !String::from_utf8_lossy(&out.stderr).contains("warning"));
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
fn quick_beam_report_writes_its_files() {
    let dir = scratch("beam-report");
    let out = eapbd(&["report", "beam", "--quick", "--out", dir.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for f in ["beam.md", "beam.csv", "beam_static.csv", "beam.png"] {
        let meta = std::fs::metadata(dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert!(meta.len() > 100, "{f} is nearly empty");
    }
    let csv = std::fs::read_to_string(dir.join("beam.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}"));
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    // 3 materials at the reference setting + 2 solver settings, all on the 5-cell beam.
    assert_eq!(rows.len(), 5, "{csv}");
    for row in &rows {
        assert_eq!(row.len(), header.len(), "{csv}");
        for name in ["tip_deflection_m", "euler_bernoulli_m", "ratio", "static_fe_m", "ratio_to_static", "wall_s"] {
            let v: f64 = row[col(name)].parse().unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(v.is_finite(), "{name} = {v}");
        }
        // Euler–Bernoulli for the 1 m × 0.2 m × 0.2 m beam at E = 1e8 Pa: 3.68 mm.
        let eb: f64 = row[col("euler_bernoulli_m")].parse().unwrap();
        assert!((eb - 3.679e-3).abs() < 1e-5, "{eb}");
    }
    // The reference runs settle on the static answer of their mesh; the coarse mesh locks (≈ 0.25 δ_EB).
    for row in rows.iter().filter(|r| r[col("sweep")] == "resolution") {
        let to_static: f64 = row[col("ratio_to_static")].parse().unwrap();
        let ratio: f64 = row[col("ratio")].parse().unwrap();
        assert!((to_static - 1.0).abs() < 0.01 && row[col("settled")] == "true", "{row:?}");
        assert!(ratio > 0.2 && ratio < 0.3, "{row:?}");
    }
    let md = std::fs::read_to_string(dir.join("beam.md")).unwrap();
    assert!(md.contains("Euler–Bernoulli") && md.contains("| 5 × 1² |"), "{md}");
}

#[test]
fn scene_files_round_trip_and_command_line_flags_override_them() {
    let saved = scratch("saved.toml");
    let out = eapbd(&[
        "simulate",
        "--scene-file",
        "assets/scenes/bunny-paper.toml",
        "--iterations",
        "3",
        "--no-gravity",
        "--frames",
        "1",
        "--print-every",
        "0",
        "--save-scene",
        saved.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("scene bunny-paper: 4098 particles") && stdout.contains("3 iterations"), "{stdout}");
    let text = std::fs::read_to_string(&saved).unwrap();
    for line in ["scene = \"bunny-paper\"", "iterations = 3", "no-gravity = true", "body = \"springs\""] {
        assert!(text.contains(line), "{line} missing from\n{text}");
    }
    assert!(!text.contains("frames"), "only scene and solver flags are saved:\n{text}");
    let again = eapbd(&["simulate", "--scene-file", saved.to_str().unwrap(), "--frames", "1", "--print-every", "0"]);
    let stdout = String::from_utf8_lossy(&again.stdout);
    assert!(again.status.success() && stdout.contains("3 iterations"), "{stdout}");
    // Every example parses and builds.
    for entry in std::fs::read_dir("assets/scenes").unwrap() {
        let path = entry.unwrap().path();
        let out = eapbd(&["simulate", "--scene-file", path.to_str().unwrap(), "--frames", "1", "--print-every", "0"]);
        assert!(out.status.success(), "{}: {}", path.display(), String::from_utf8_lossy(&out.stderr));
    }
    // A broken file is named.
    let bad = scratch("bad.toml");
    std::fs::write(&bad, "scene = [1, 2]\n").unwrap();
    let out = eapbd(&["simulate", "--scene-file", bad.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("bad.toml"));
    // A negative number reaches its flag's check; a file naming another file is refused.
    std::fs::write(&bad, "damping = -5\n").unwrap();
    let out = eapbd(&["simulate", "--scene-file", bad.to_str().unwrap(), "--frames", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("--damping = -5"), "{err}");
    std::fs::write(&bad, "scene-file = \"other.toml\"\n").unwrap();
    let out = eapbd(&["simulate", "--scene-file", bad.to_str().unwrap(), "--frames", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("cannot read another"), "{err}");
}

#[test]
fn meshes_from_files_replace_the_bunny() {
    // An OBJ cube as the bunny's surface, a TetGen tetrahedron as its body, and the errors.
    let obj = scratch("cube.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
         f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n",
    )
    .unwrap();
    let dir = scratch("sequence");
    let out = eapbd(&[
        "simulate",
        "--scene",
        "bunny",
        "--mesh",
        obj.to_str().unwrap(),
        "--frames",
        "4",
        "--export-obj-dir",
        dir.to_str().unwrap(),
        "--export-every",
        "2",
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("embedded surface of 8 vertices, 12 triangles"), "{stdout}");
    // The sequence holds the embedded surface as drawn: 8 vertices and 12 faces per file.
    for frame in [2, 4] {
        let text = std::fs::read_to_string(dir.join(format!("frame_{frame:05}.obj"))).unwrap();
        assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 8);
        assert_eq!(text.lines().filter(|l| l.starts_with("f ")).count(), 12);
    }
    let node = scratch("tet.node");
    std::fs::write(&node, "# one tetrahedron\n4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n").unwrap();
    std::fs::write(node.with_extension("ele"), "1 4 0\n1 1 2 3 4\n").unwrap();
    let out = eapbd(&["simulate", "--scene", "bunny", "--mesh", node.to_str().unwrap(), "--frames", "3"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("4 particles, 1 constraints"), "{stdout}");
    std::fs::write(node.with_extension("ele"), "1 4 0\n1 1 2 3 9\n").unwrap();
    let out = eapbd(&["simulate", "--scene", "bunny", "--mesh", node.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("node 9 is not a point"), "{stderr}");
    let out = eapbd(&["simulate", "--scene", "cloth", "--mesh", obj.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("bunny"), "--mesh needs a bunny scene");
    let out = eapbd(&["simulate", "--scene", "bunny", "--mesh", "/nonexistent.obj"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("/nonexistent.obj"));
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
    let out = eapbd(&["view", "--msaa", "3", "--exit-after-frames", "1"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && err.contains("--msaa") && err.contains("1, 2 or 4"), "{err}");
}

#[test]
fn an_adapter_name_that_matches_nothing_is_an_error_not_a_panic() {
    let out = Command::new(env!("CARGO_BIN_EXE_eapbd"))
        .args(["simulate", "--scene", "cloth", "--resolution", "5", "--frames", "1", "--backend", "gpu"])
        .env("WGPU_ADAPTER_NAME", "no-such-adapter-anywhere")
        .output()
        .expect("the binary runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("WGPU_ADAPTER_NAME") && err.contains("matches none"), "{err}");
}

#[test]
fn a_reader_that_stops_early_ends_the_output_without_a_panic() {
    // `eapbd simulate … | head -1`: the reader closes the pipe after one line.
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_eapbd"))
        .args(["simulate", "--scene", "cloth", "--resolution", "9", "--frames", "2000", "--print-every", "1"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut first = String::new();
    BufReader::new(child.stdout.take().expect("stdout")).read_line(&mut first).expect("one line");
    assert!(first.starts_with("scene cloth"), "{first}");
    let out = child.wait_with_output().expect("the binary ends");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success() && !stderr.contains("panicked"), "{:?}\n{stderr}", out.status);
}
