//! Output of `eapbd report splits`: `splits.csv`, `splits.md` and the figures `splits_n.png`
//! and `splits_unresolved.png`.

use std::fmt::Write as _;
use std::path::Path;

use super::splits::{EQUAL_MOTION, FreeRun, Reference, SPLITS, SplitRun, SplitsOptions, write_plots};
use crate::error::{Error, Result};
use crate::solver::EnergyAware;

/// Column names of `splits.csv`.
pub const CSV_HEADER: &str = "substeps,iterations,setting,n_end,n_max,kinetic_ratio,stretch_end,stretch_late,stretch_equal_motion,unresolved_max,ms_per_frame";

/// Writes the study's files into `dir`.
pub fn write_outputs(
    dir: &Path,
    opts: &SplitsOptions,
    r: &Reference,
    runs: &[SplitRun],
    free: &[FreeRun],
) -> Result<()> {
    let write = |name: &str, text: String| {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|source| Error::Io { path, source })
    };
    std::fs::create_dir_all(dir).map_err(|source| Error::Io { path: dir.to_path_buf(), source })?;
    let w = opts.window();
    let mut csv = format!("{CSV_HEADER}\n");
    for run in runs {
        let equal = off_of(runs, run).and_then(|o| run.stretch_at_equal_motion(o, w));
        let _ = writeln!(
            csv,
            "{},{},{},{:.6},{:.6},{:.6},{:.6e},{:.6e},{:.4},{:.6e},{:.4}",
            run.substeps,
            run.iterations,
            run.variant.name(),
            run.n_end(),
            run.n_max(),
            run.kinetic_ratio,
            run.stretch_end,
            run.stretch_late,
            equal.map_or(f64::NAN, |e| e.0),
            run.u_max(),
            run.ms
        );
    }
    write("splits.csv", csv)?;
    write_plots(dir, opts, runs)?;
    write("splits.md", markdown(opts, r, runs, free))
}

/// The `off` run at `run`'s split.
fn off_of<'a>(runs: &'a [SplitRun], run: &SplitRun) -> Option<&'a SplitRun> {
    runs.iter().find(|o| (o.substeps, o.iterations) == (run.substeps, run.iterations) && o.variant == EnergyAware::Off)
}

fn markdown(opts: &SplitsOptions, r: &Reference, runs: &[SplitRun], free: &[FreeRun]) -> String {
    let mut s = String::new();
    let w = opts.window() as f64 / 60.0;
    let _ = writeln!(s, "# Energy at real-time settings\n");
    let _ = writeln!(
        s,
        "Produced by `eapbd report splits`: the hanging `cloth`, {n}×{n}, k_s = {k} N/m, bending {b} N·m/rad, \
         dt = 1/60 s, {f} frames, CPU solver on one thread (f32), Gauss-Seidel, compliant form.\n\n\
         - **n** = (H − E_eq) / (E0 − E_eq): H is the honest total (kinetic + gravitational from the ground + \
         the elastic energy the constraint forces hold), E0 = {e0:.4} J the energy at the start, E_eq = {eq:.4} J the \
         same cloth hanging at rest (damped, 40 substeps × 2 iterations). 1 keeps all the energy the fall makes \
         available; 0 is a cloth at rest.\n\
         - **kinetic** = mean kinetic energy over the last {w:.0} s over that of the first {w:.0} s.\n\
         - **stretch**: mean relative stretch at the last frame, and its average over the last {w:.0} s; \
         `×off` is the ratio to `off` at the same split.\n\
         - **at equal motion**: the late stretch against `off`'s at the same kinetic energy (each of the last \
         {w:.0} s's frames matched with `off`'s frames after its first {w:.0} s whose kinetic energy is within \
         {tol:.0}%; Σ stretch / Σ matched `off` stretch, and the share of frames matched). A cloth that keeps its \
         motion stretches more than one that has come to rest under the same under-converged solve; this column \
         separates the stretch a setting adds from that of the motion it keeps. `off` against itself shows the \
         matching's own bias.\n\
         - **u max**: the largest unresolved elastic energy (stretch that no constraint force holds, not counted \
         in H), in units of E0 − E_eq.\n\
         - **ms**: median solve time per frame; `×off` against `off` at the same split, measured in the same run.\n",
        n = opts.resolution,
        k = opts.stiffness,
        b = opts.bending,
        f = opts.frames,
        e0 = r.e0,
        eq = r.e_eq,
        tol = 100.0 * EQUAL_MOTION,
    );
    for (sub, it) in SPLITS {
        let _ = writeln!(s, "## {sub} substeps × {it} iterations\n");
        let _ = writeln!(
            s,
            "| setting | n at end | n peak | kinetic | stretch at end (×off) | stretch late (×off) | at equal motion (×off, matched) | u max | ms (×off) |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
        let ratio = |v: f64, b: Option<f64>| b.map_or(String::new(), |b| format!(" ({:.2}×)", v / b));
        for run in runs.iter().filter(|o| (o.substeps, o.iterations) == (sub, it)) {
            let base = off_of(runs, run);
            let equal = base.and_then(|o| run.stretch_at_equal_motion(o, opts.window()));
            let _ = writeln!(
                s,
                "| {} | {:.3} | {:.3} | {:.3} | {:.4}{} | {:.4}{} | {} | {:.3} | {:.2}{} |",
                run.variant.name(),
                run.n_end(),
                run.n_max(),
                run.kinetic_ratio,
                run.stretch_end,
                ratio(run.stretch_end, base.map(|b| b.stretch_end)),
                run.stretch_late,
                ratio(run.stretch_late, base.map(|b| b.stretch_late)),
                equal.map_or("–".into(), |(r, m)| format!("{r:.2}× ({:.0}%)", 100.0 * m)),
                run.u_max(),
                run.ms,
                ratio(run.ms, base.map(|b| b.ms)),
            );
        }
        let _ = writeln!(s);
    }
    let _ =
        writeln!(s, "![n against time](splits_n.png)\n\n![unresolved stretch against time](splits_unresolved.png)\n");
    let _ = writeln!(
        s,
        "## cloth-free, 3 substeps × 10 iterations\n\n\
         No pins, no gravity, stretched by 10% at the start, same cloth and stiffness. The honest energy after the \
         first frame is the reference (before a step nothing says what the forces hold); momentum drift is the \
         largest change since then over the scales Σ m|v| and Σ m|x − c||v|.\n\n\
         | setting | energy after frame 1 (J) | lowest | highest | at end | P drift | L drift |\n|---|---|---|---|---|---|---|"
    );
    for f in free {
        let _ = writeln!(
            s,
            "| {} | {:.4} | {:.3} | {:.3} | {:.3} | {:.1e} | {:.1e} |",
            f.variant.name(),
            f.start,
            f.range.0,
            f.range.1,
            f.end,
            f.momentum_drift.0,
            f.momentum_drift.1
        );
    }
    s
}
