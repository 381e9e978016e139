//! The scaling series: time per frame of cloths from thousands to a million constraints, the
//! cost per projection and its ratio to the smallest cloth's, and the log–log plot.

use std::path::Path;

use eapbd::report::plot::{Legend, Line, Panel, save_log_log};

use super::cases::Backend;
use super::measure::Row;

/// One scaled cloth on one backend.
#[derive(Clone, Debug, PartialEq)]
pub struct ScalePoint {
    /// Particles per side.
    pub resolution: u32,
    /// Particles.
    pub particles: usize,
    /// Constraints (springs + bending).
    pub constraints: usize,
    /// Where it ran.
    pub backend: Backend,
    /// Median time per frame (ms).
    pub ms: f64,
    /// Time per constraint projection (ns).
    pub ns_per_projection: f64,
    /// `ns_per_projection` over the smallest cloth's on the same backend (1 = linear scaling).
    pub ratio: f64,
}

/// The scaled rows of `rows`, by backend and then size.
pub fn series(rows: &[Row]) -> Vec<ScalePoint> {
    let mut out = Vec::new();
    for backend in Backend::ALL {
        let mut v: Vec<&Row> = rows.iter().filter(|r| r.scaled && r.backend == backend).collect();
        v.sort_by_key(|r| r.constraints);
        let Some(first) = v.first() else { continue };
        let base = first.ns_per_projection();
        for r in v {
            out.push(ScalePoint {
                resolution: r.resolution.unwrap_or(0),
                particles: r.particles,
                constraints: r.constraints,
                backend,
                ms: r.timing.median_ms,
                ns_per_projection: r.ns_per_projection(),
                ratio: r.ns_per_projection() / base,
            });
        }
    }
    out
}

/// Writes the log–log plot of time per frame against constraints, one line per backend and a
/// line of slope 1 through the smallest single-threaded cloth.
pub fn plot(path: &Path, points: &[ScalePoint], gpu_name: &str) -> eapbd::Result<()> {
    let mut lines: Vec<Line> = Backend::ALL
        .iter()
        .enumerate()
        .filter_map(|(i, &b)| {
            let pts: Vec<(f64, f64)> =
                points.iter().filter(|p| p.backend == b).map(|p| (p.constraints as f64, p.ms)).collect();
            let label = match b {
                Backend::CpuSingle => "CPU, 1 thread".to_string(),
                Backend::CpuAll => "CPU, all threads".to_string(),
                Backend::Gpu => format!("GPU ({gpu_name})"),
            };
            (!pts.is_empty()).then_some(Line { label, points: pts, color: i, markers: true })
        })
        .collect();
    let single: Vec<&ScalePoint> = points.iter().filter(|p| p.backend == Backend::CpuSingle).collect();
    if let (Some(first), Some(last)) = (single.first(), single.last()) {
        let slope = first.ms / first.constraints as f64;
        lines.push(Line {
            label: "linear from the smallest cloth (CPU, 1 thread)".into(),
            points: [first, last].iter().map(|p| (p.constraints as f64, slope * p.constraints as f64)).collect(),
            color: 4,
            markers: false,
        });
    }
    let panel = Panel {
        title: "Cloth (springs + bending), 30 iterations: time per frame against constraints".into(),
        x_label: "constraints".into(),
        y_label: "ms per frame (median)".into(),
        lines,
        legend: Legend::LowerRight,
    };
    save_log_log(path, &panel, (900, 600))
}
