//! `eapbd report error-vs-time --quick` on the cloth and the bunny: the CSVs parse, every variant
//! ran (the GPU ones on lavapipe in CI) with finite results, the error of every compliant-form
//! variant falls from the smallest to the largest budget of each split (except SOR at one
//! iteration per substep, see below), and the error-against-frame runs agree with the sweep at
//! frame K.
#![cfg(feature = "cli")]

mod common;

use std::collections::HashMap;

use eapbd::constraints::Form;
use eapbd::report::error_time::{FRAME_CSV_HEADER, SWEEP_CSV_HEADER, Split, StudyOptions, study_scene_options};
use eapbd::scene::SceneOptions;

type Row = HashMap<String, String>;

fn num(row: &Row, col: &str) -> f64 {
    row[col].parse().unwrap_or_else(|_| panic!("{col} of {row:?}"))
}

fn int(row: &Row, col: &str) -> u32 {
    row[col].parse().unwrap_or_else(|_| panic!("{col} of {row:?}"))
}

fn quick_report(scene: &str) {
    let dir = std::env::temp_dir().join(format!("eapbd-error-test-{scene}-{}", std::process::id()));
    common::run_report(&["error-vs-time", "--scene", scene, "--quick"], &dir);
    let md = std::fs::read_to_string(dir.join("error_vs_time.md")).expect("error_vs_time.md");
    assert!(md.contains("## Fastest to a given error") && md.contains("## Error against frame number"), "{md}");
    for png in ["error_vs_time.png", "error_vs_budget.png", "error_vs_frame.png"] {
        assert!(std::fs::metadata(dir.join(png)).is_ok_and(|m| m.len() > 1000), "{png}");
    }

    let opts = StudyOptions::quick(scene, study_scene_options(scene, SceneOptions::default()));
    let sweep = common::read_csv(&dir.join("error_vs_time.csv"), SWEEP_CSV_HEADER);
    // Like the other GPU tests, a missing adapter fails rather than skips (CI has lavapipe).
    assert_eq!(sweep.len(), opts.variants.len() * opts.shapes().len(), "every variant at every shape");
    for row in &sweep {
        assert_eq!(row["finite"], "true", "{row:?}");
        assert!(num(row, "error").is_finite() && num(row, "error") > 0.0, "{row:?}");
        assert!(num(row, "seconds_per_frame") > 0.0, "{row:?}");
        assert_eq!(int(row, "budget"), int(row, "iterations") * int(row, "substeps"), "{row:?}");
    }

    // Compliant-form variants approach the reference as the budget grows (energy-form variants
    // converge to another model and may plateau). One exception, analysed in docs/error/README.md:
    // SOR with one iteration per substep over-projects every constraint once per substep, which
    // is unstable while ω k̂ > 4/3 (k̂: the fraction of a violation one plain projection removes,
    // near 1 for stiff constraints at large h); the cloth blows up between 8 and 32 substeps and
    // is stable again near 64. Its finiteness is checked above; its convergence is not claimed.
    let mut checked = 0;
    for v in opts.variants.iter().filter(|v| v.form == Form::Compliant) {
        for split in &opts.splits {
            if v.sor != 1.0 && *split == Split::PerSubstep(1) {
                continue;
            }
            let mut curve: Vec<&Row> = sweep
                .iter()
                .filter(|r| r["variant"] == v.name() && split.contains(int(r, "iterations"), int(r, "substeps")))
                .collect();
            curve.sort_by_key(|r| int(r, "budget"));
            assert_eq!(curve.len(), opts.budgets.len(), "{} {}", v.name(), split.name());
            let (first, last) = (curve[0], curve[curve.len() - 1]);
            assert!(
                num(last, "error") < num(first, "error"),
                "{scene}: {} ({}) does not converge: error {} at budget {} but {} at budget {}",
                v.name(),
                split.name(),
                first["error"],
                first["budget"],
                last["error"],
                last["budget"]
            );
            checked += 1;
        }
    }
    assert!(checked >= 13, "only {checked} compliant curves checked");

    // The error-against-frame runs: every frame finite, and at frame K the same run as the sweep's.
    let track = common::read_csv(&dir.join("error_vs_frame.csv"), FRAME_CSV_HEADER);
    let shapes = opts.track_shapes();
    assert_eq!(track.len(), opts.variants.len() * shapes.len() * opts.track_frames as usize);
    for p in &track {
        assert_eq!(p["finite"], "true", "{p:?}");
        if int(p, "frame") != opts.frames {
            continue;
        }
        let s = sweep
            .iter()
            .find(|r| {
                r["variant"] == p["variant"] && r["iterations"] == p["iterations"] && r["substeps"] == p["substeps"]
            })
            .unwrap_or_else(|| panic!("the sweep has no row for {p:?}"));
        let (a, b) = (num(p, "error"), num(s, "error"));
        assert!(
            (a - b).abs() <= 1e-4 * b,
            "{}: frame {} error {a} in the track, {b} in the sweep",
            p["variant"],
            opts.frames
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn quick_error_report_on_the_cloth() {
    quick_report("cloth");
}

#[test]
fn quick_error_report_on_the_bunny() {
    quick_report("bunny");
}
