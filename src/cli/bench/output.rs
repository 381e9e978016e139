//! The results as Markdown tables (printed and written to `bench.md`) and CSV files.

use std::fmt::Write as _;
use std::path::Path;

use super::cases::{Backend, PEER_BENDING, PEER_RESOLUTION, PEER_STIFFNESS};
use super::coloring::ColoringRow;
use super::measure::Row;
use super::peer::{Split, most_accurate};
use super::scaling::ScalePoint;
use super::timing::{BLOCK_FRAMES, TURN_WARM_FRAMES};

/// Everything one run measured.
pub struct Results {
    /// The run's heading: command, machine, adapter.
    pub header: String,
    /// Rows of the main table.
    pub rows: Vec<Row>,
    /// The peer scene's splits.
    pub splits: Vec<Split>,
    /// Frames of each split.
    pub split_frames: u32,
    /// The scaling series.
    pub scaling: Vec<ScalePoint>,
    /// Mesh coloring.
    pub coloring: Vec<ColoringRow>,
    /// Repetitions of each coloring case.
    pub coloring_reps: u32,
}

/// A time in ms with three significant figures or so.
fn ms(v: f64) -> String {
    if !v.is_finite() {
        "–".into()
    } else if v < 10.0 {
        format!("{v:.3}")
    } else if v < 100.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.1}")
    }
}

/// Bytes in KiB or MiB.
fn bytes(b: u64) -> String {
    if b >= 1 << 20 {
        format!("{:.2} MiB", b as f64 / (1u64 << 20) as f64)
    } else {
        format!("{:.1} KiB", b as f64 / 1024.0)
    }
}

fn solver(r: &Row) -> String {
    format!("{} {}", r.method.name(), r.form.name())
}

/// The main table: time, throughput and dispatches of every row.
pub fn time_table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| scene | solver | it × sub | particles | constraints | colors | backend | frames | ms/frame | projections/s | ns/projection | dispatches/frame |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} × {} | {} | {} | {} | {} | {} | {} | {:.1} M | {:.1} | {} |",
            r.label,
            solver(r),
            r.iterations,
            r.substeps,
            r.particles,
            r.constraints,
            r.colors,
            r.backend.name(),
            r.timing.frames,
            ms(r.timing.median_ms),
            r.projections_per_s() / 1e6,
            r.ns_per_projection(),
            r.dispatches.map_or("–".into(), |d| d.to_string())
        );
    }
    s
}

/// Memory of the CPU and GPU solvers per scene (the single-threaded CPU row and the GPU row of
/// each case).
pub fn memory_table(rows: &[Row]) -> String {
    let mut s = String::from(
        "| scene | solver | particles | constraints | CPU | CPU B/particle | CPU B/constraint | GPU | GPU B/particle | GPU B/constraint |\n\
         |---|---|---|---|---|---|---|---|---|---|\n",
    );
    let single = |g: &Row| {
        rows.iter()
            .any(|c| c.backend == Backend::CpuSingle && c.label == g.label && c.method == g.method && c.form == g.form)
    };
    // A GPU row stands for its case where no one-thread row was measured (`bench --gpu-only`).
    for cpu in rows.iter().filter(|r| r.backend == Backend::CpuSingle || (r.backend == Backend::Gpu && !single(r))) {
        let gpu = rows.iter().find(|g| {
            g.backend == Backend::Gpu
                && g.label == cpu.label
                && g.method == cpu.method
                && g.form == cpu.form
                && g.iterations == cpu.iterations
        });
        let (g_total, g_p, g_c) = gpu.map_or(("–".into(), "–".into(), "–".into()), |g| {
            (
                bytes(g.memory.total),
                format!("{:.0}", g.bytes_per_particle()),
                format!("{:.1}", g.bytes_per_constraint()),
            )
        });
        let (c_total, c_p, c_c) = if cpu.backend == Backend::Gpu {
            ("–".into(), "–".into(), "–".into())
        } else {
            (
                bytes(cpu.memory.total),
                format!("{:.0}", cpu.bytes_per_particle()),
                format!("{:.1}", cpu.bytes_per_constraint()),
            )
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            cpu.label,
            solver(cpu),
            cpu.particles,
            cpu.constraints,
            c_total,
            c_p,
            c_c,
            g_total,
            g_p,
            g_c
        );
    }
    s
}

/// The peer scene's splits, one line per split with both CPU backends.
pub fn peer_table(splits: &[Split]) -> String {
    let mut s = String::from(
        "| iterations × substeps | ms/frame, 1 thread (mean, median) | ms/frame, all threads (mean, median) | all threads: time waiting | grid stretch | all-edge stretch |\n\
         |---|---|---|---|---|---|\n",
    );
    let mut seen: Vec<(u32, u32)> = Vec::new();
    for sp in splits {
        let key = (sp.iterations, sp.substeps);
        if seen.contains(&key) {
            continue;
        }
        seen.push(key);
        let of = |b: Backend| split_of(splits, key, b);
        let single = of(Backend::CpuSingle).unwrap_or(sp);
        let _ = writeln!(
            s,
            "| {} × {} | {} | {} | {} | {:.4} | {:.4} |",
            sp.iterations,
            sp.substeps,
            of(Backend::CpuSingle).map_or("–".into(), mean_median),
            of(Backend::CpuAll).map_or("–".into(), mean_median),
            of(Backend::CpuAll).and_then(|x| x.team_wait).map_or("–".into(), |w| format!("{:.0} %", 100.0 * w)),
            single.stretch_grid,
            single.stretch_all,
        );
    }
    s
}

/// The split `(iterations, substeps)` measured on `backend`.
fn split_of(splits: &[Split], key: (u32, u32), backend: Backend) -> Option<&Split> {
    splits.iter().find(|x| (x.iterations, x.substeps) == key && x.backend == backend)
}

/// A split's mean and median time per frame (ms).
fn mean_median(x: &Split) -> String {
    format!("{}, {}", ms(x.mean_ms), ms(x.median_ms))
}

/// One sentence naming the most accurate split, with its times on each backend.
pub fn most_accurate_line(splits: &[Split]) -> String {
    let Some(b) = most_accurate(splits, Backend::CpuSingle) else { return "No split measured.".into() };
    let all = split_of(splits, (b.iterations, b.substeps), Backend::CpuAll)
        .map_or(String::new(), |a| format!("; {} on all threads", mean_median(a)));
    format!(
        "Most accurate split: {} × {} (grid stretch {:.4}; ms/frame, mean and median: {} on one thread{all}).",
        b.iterations,
        b.substeps,
        b.stretch_grid,
        mean_median(b)
    )
}

/// The scaling series: one line per cloth, the backends side by side.
pub fn scaling_table(points: &[ScalePoint]) -> String {
    let mut s = String::from(
        "| cloth N×N | particles | constraints | cpu-1 ms | cpu-1 ns/proj | ratio | cpu-all ms | cpu-all ns/proj | ratio | gpu ms | gpu ns/proj | ratio |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let mut sizes: Vec<u32> = points.iter().map(|p| p.resolution).collect();
    sizes.sort_unstable();
    sizes.dedup();
    for n in sizes {
        let Some(any) = points.iter().find(|p| p.resolution == n) else { continue };
        let _ = write!(s, "| {n} | {} | {} |", any.particles, any.constraints);
        for b in Backend::ALL {
            match points.iter().find(|p| p.resolution == n && p.backend == b) {
                Some(p) => {
                    let _ = write!(s, " {} | {:.1} | {:.2} |", ms(p.ms), p.ns_per_projection, p.ratio);
                }
                None => s.push_str(" – | – | – |"),
            }
        }
        s.push('\n');
    }
    s
}

/// The coloring table.
pub fn coloring_table(rows: &[ColoringRow]) -> String {
    let mut s = String::from("| elements | particles | colors | group sizes | ms |\n|---|---|---|---|---|\n");
    for r in rows {
        let _ = writeln!(
            s,
            "| {} {} | {} | {} | {}..{} | {:.1} |",
            r.elements, r.name, r.particles, r.colors, r.groups.0, r.groups.1, r.ms
        );
    }
    s
}

/// The whole report as Markdown.
pub fn markdown(r: &Results) -> String {
    let mut s = r.header.clone();
    s.push_str("\n## Time per frame\n\n");
    s.push_str(
        "Median of the measured frames after warm-up; every frame waited for (the GPU: recorded, submitted and \
         waited for). cpu-1: `threads: 1`; cpu-all: `threads: 0` (every core).\n\n",
    );
    s.push_str(&time_table(&r.rows));
    s.push_str("\n## Memory\n\n");
    s.push_str(
        "CPU: particle state, elements and multipliers, from the array lengths. GPU: the sizes of the buffers \
         the solver created (`GpuSolver::memory`). Per particle: the per-particle arrays over the particle \
         count; per constraint: the per-constraint arrays over the constraint count.\n\n",
    );
    s.push_str(&memory_table(&r.rows));
    if !r.splits.is_empty() {
        peer_section(&mut s, r);
    }
    s.push_str("\n## Scaling\n\n");
    s.push_str(
        "`cloth --resolution N` (springs k_s = 1e4 N/m on grid edges and one diagonal, dihedral bending \
         k_b = 1e-3 N·m/rad), 30 iterations; ratio: ns per projection over the smallest cloth's on the same \
         backend (1 = linear). Plot: `scaling.png`.\n\n",
    );
    s.push_str(&scaling_table(&r.scaling));
    if !r.coloring.is_empty() {
        let _ = write!(s, "\n## Mesh coloring\n\nBest of {} runs.\n\n", r.coloring_reps);
        s.push_str(&coloring_table(&r.coloring));
    }
    s
}

/// The peer scene's splits: what was run, the table and the most accurate split.
fn peer_section(s: &mut String, r: &Results) {
    let _ = write!(
        s,
        "\n## Peer scene: splits of 30\n\n`cloth --resolution {PEER_RESOLUTION} --stiffness {PEER_STIFFNESS:e} \
         --bending-stiffness {PEER_BENDING:e} --diagonals alternating` (the PositionBasedDynamics library's \
         mesh), Gauss-Seidel, compliant; {} frames from rest, the one and two-thread runs in turns of \
         {BLOCK_FRAMES} frames; mean and median time per frame over the frames of each turn but its first \
         {TURN_WARM_FRAMES} (a team whose second core sat idle during the other run's turn starts slowly; \
         the median is not moved by the odd frame in which the host takes a core away), the share of the threads' time that the team \
         spent waiting for one another (at its barriers and before the parts of its color groups that touch \
         another thread's particles) in the timed frames, and the time-averaged mean relative stretch over \
         every frame, over the grid edges (no diagonals) and over every spring edge.\n\n",
        r.split_frames
    );
    s.push_str(&peer_table(&r.splits));
    s.push('\n');
    s.push_str(&most_accurate_line(&r.splits));
    s.push('\n');
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> eapbd::Error + '_ {
    move |source| eapbd::Error::Io { path: path.to_path_buf(), source }
}

/// Writes `text` to `dir/name`.
pub fn write(dir: &Path, name: &str, text: &str) -> eapbd::Result<()> {
    let path = dir.join(name);
    std::fs::write(&path, text).map_err(io(&path))
}

/// The column names of `bench.csv`.
pub const BENCH_CSV_HEADER: &str = "label,scene,resolution,backend,method,form,iterations,substeps,particles,constraints,colors,frames,ms_per_frame,projections_per_s,ns_per_projection,dispatches_per_frame,memory_bytes,particle_bytes,constraint_bytes,bytes_per_particle,bytes_per_constraint";
/// The column names of `scaling.csv`.
pub const SCALING_CSV_HEADER: &str =
    "resolution,particles,constraints,backend,ms_per_frame,ns_per_projection,ratio_to_smallest";
/// The column names of `peer.csv`.
pub const PEER_CSV_HEADER: &str = "iterations,substeps,backend,frames,mean_ms_per_frame,stretch_grid,stretch_all_edges,median_ms_per_frame,team_wait_fraction";

/// Writes `bench.csv`, `scaling.csv` and `peer.csv` to `dir` (created if needed).
pub fn write_files(dir: &Path, r: &Results) -> eapbd::Result<()> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let mut csv = format!("{BENCH_CSV_HEADER}\n");
    for x in &r.rows {
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{},{},{},{},{},{},{},{:.6},{:.0},{:.3},{},{},{},{},{:.2},{:.2}",
            x.label,
            x.scene,
            x.resolution.map_or(String::new(), |n| n.to_string()),
            x.backend.name(),
            x.method.name(),
            x.form.name(),
            x.iterations,
            x.substeps,
            x.particles,
            x.constraints,
            x.colors,
            x.timing.frames,
            x.timing.median_ms,
            x.projections_per_s(),
            x.ns_per_projection(),
            x.dispatches.map_or(String::new(), |d| d.to_string()),
            x.memory.total,
            x.memory.particles,
            x.memory.constraints,
            x.bytes_per_particle(),
            x.bytes_per_constraint()
        );
    }
    write(dir, "bench.csv", &csv)?;
    let mut csv = format!("{SCALING_CSV_HEADER}\n");
    for p in &r.scaling {
        let _ = writeln!(
            csv,
            "{},{},{},{},{:.6},{:.3},{:.4}",
            p.resolution,
            p.particles,
            p.constraints,
            p.backend.name(),
            p.ms,
            p.ns_per_projection,
            p.ratio
        );
    }
    write(dir, "scaling.csv", &csv)?;
    let mut csv = format!("{PEER_CSV_HEADER}\n");
    for p in &r.splits {
        let _ = writeln!(
            csv,
            "{},{},{},{},{:.6},{:.6},{:.6},{:.6},{}",
            p.iterations,
            p.substeps,
            p.backend.name(),
            p.frames,
            p.mean_ms,
            p.stretch_grid,
            p.stretch_all,
            p.median_ms,
            p.team_wait.map_or(String::new(), |w| format!("{w:.4}")),
        );
    }
    write(dir, "peer.csv", &csv)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(iterations: u32, substeps: u32, backend: Backend, mean_ms: f64, median_ms: f64, stretch: f64) -> Split {
        let frames = 120;
        let team_wait = (backend == Backend::CpuAll).then_some(0.125);
        Split {
            iterations,
            substeps,
            backend,
            frames,
            mean_ms,
            median_ms,
            stretch_grid: stretch,
            stretch_all: stretch,
            team_wait,
        }
    }

    #[test]
    fn the_peer_splits_give_mean_and_median_on_both_backends() {
        let splits = [
            split(30, 1, Backend::CpuSingle, 7.5, 7.0, 0.088),
            split(30, 1, Backend::CpuAll, 5.5, 4.5, 0.088),
            split(1, 30, Backend::CpuSingle, 7.25, 6.75, 0.0065),
            split(1, 30, Backend::CpuAll, 6.5, 4.25, 0.0065),
        ];
        let table = peer_table(&splits);
        assert!(table.contains("| 30 × 1 | 7.500, 7.000 | 5.500, 4.500 | 12 % | 0.0880 | 0.0880 |"), "{table}");
        assert!(table.contains("| 1 × 30 | 7.250, 6.750 | 6.500, 4.250 | 12 % | 0.0065 |"), "{table}");
        let line = most_accurate_line(&splits);
        assert!(line.starts_with("Most accurate split: 1 × 30 (grid stretch 0.0065;"), "{line}");
        assert!(line.contains("7.250, 6.750 on one thread; 6.500, 4.250 on all threads"), "{line}");
    }
}
