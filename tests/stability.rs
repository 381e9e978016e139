//! `eapbd report stability --quick`: its CSV parses, and every case that the committed study
//! (`docs/stability/stability.csv`) lists as passing still passes.
#![cfg(feature = "cli")]

mod common;

use std::collections::HashMap;
use std::path::Path;

use eapbd::report::stability::{CSV_HEADER, quick_cases};

/// Rows of a stability CSV keyed by `(case, backend)`, as column name → value.
fn read_csv(path: &Path) -> HashMap<(String, String), HashMap<String, String>> {
    common::read_csv(path, CSV_HEADER)
        .into_iter()
        .map(|row| ((row["case"].clone(), row["backend"].clone()), row))
        .collect()
}

#[test]
fn quick_stability_report_keeps_every_documented_pass() {
    let dir = std::env::temp_dir().join(format!("eapbd-stability-test-{}", std::process::id()));
    common::run_report(&["stability", "--quick"], &dir);
    let md = std::fs::read_to_string(dir.join("stability.md")).expect("stability.md");
    assert!(md.contains("| group | case |") && md.contains("## Failing cases"), "{md}");

    let quick = read_csv(&dir.join("stability.csv"));
    assert_eq!(quick.len(), quick_cases().iter().map(|c| c.backends.len()).sum::<usize>());
    for row in quick.values() {
        // Like the other GPU tests, a missing adapter fails rather than skips (CI has lavapipe).
        assert!(["pass", "fail"].contains(&row["status"].as_str()), "{row:?}");
        for col in ["energy_ratio", "settle_ratio", "end_stretch_mean", "wall_s"] {
            let v: f64 = row[col].parse().unwrap_or_else(|_| panic!("{col} of {row:?}"));
            assert!(v.is_nan() || v >= 0.0, "{col} of {row:?}");
        }
    }

    let docs = read_csv(&Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/stability/stability.csv"));
    let mut checked = 0;
    for (key, doc) in &docs {
        let Some(now) = quick.get(key) else { continue };
        if doc["status"] != "pass" {
            continue;
        }
        assert_eq!(now["finite"], "true", "{key:?} is documented as passing but is no longer finite: {now:?}");
        assert_eq!(now["status"], "pass", "{key:?} is documented as passing but fails: {}", now["failures"]);
        checked += 1;
    }
    let documented_cpu_passes = docs
        .iter()
        .filter(|((c, b), r)| b == "cpu" && r["status"] == "pass" && quick.contains_key(&(c.clone(), b.clone())));
    assert!(documented_cpu_passes.count() >= 8, "the quick subset covers too few documented passes");
    assert!(checked >= 18, "only {checked} documented passes were checked");
    let _ = std::fs::remove_dir_all(&dir);
}
