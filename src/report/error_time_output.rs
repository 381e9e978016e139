//! Outputs of the error-against-run-time study: `error_vs_time.csv` (one row per variant and
//! iterations × substeps), `error_vs_frame.csv` (one row per variant, shape and frame of the
//! track runs), PNG plots and `error_vs_time.md` (tables and findings computed from the runs).

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use super::error_time::{Row, Split, Study, TrackPoint, Variant};
use super::plot::{Legend, Line, Panel, save_panels};
use crate::constraints::Form;
use crate::error::{Error, Result};
use crate::simulation::Backend;
use crate::solver::{EnergyAware, Method};

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io { path: path.to_path_buf(), source }
}

/// Column names of `error_vs_time.csv`.
pub const SWEEP_CSV_HEADER: &str = "scene,variant,backend,method,form,energy_aware,sor,iterations,substeps,budget,\
frames,seconds_per_frame,error,rms_error_m,finite";

/// Column names of `error_vs_frame.csv`.
pub const FRAME_CSV_HEADER: &str =
    "scene,variant,backend,method,form,energy_aware,sor,iterations,substeps,budget,frame,error,rms_error_m,finite";

fn variant_columns(v: &Variant) -> String {
    format!(
        "{},{},{},{},{},{}",
        v.name(),
        v.backend.name(),
        v.method.name(),
        v.form.name(),
        v.energy_aware.name(),
        v.sor
    )
}

fn write_csv(path: &Path, header: &str, rows: impl Iterator<Item = String>) -> Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(io(path))?);
    writeln!(f, "{header}").map_err(io(path))?;
    for r in rows {
        writeln!(f, "{r}").map_err(io(path))?;
    }
    f.flush().map_err(io(path))
}

/// The columns that name a run: scene, the variant's columns, iterations, substeps and their
/// product (the budget of projections per frame).
fn run_columns(scene: &str, variant: &Variant, iterations: u32, substeps: u32) -> String {
    format!("{scene},{},{iterations},{substeps},{}", variant_columns(variant), iterations * substeps)
}

/// Writes `error_vs_time.csv`, `error_vs_frame.csv`, `error_vs_time.png`,
/// `error_vs_budget.png`, `error_vs_frame.png` and `error_vs_time.md` into `dir`.
pub fn write_outputs(dir: &Path, study: &Study) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let o = &study.options;
    write_csv(
        &dir.join("error_vs_time.csv"),
        SWEEP_CSV_HEADER,
        study.rows.iter().map(|r| {
            let run = run_columns(&o.scene, &r.variant, r.iterations, r.substeps);
            format!("{run},{},{:.6e},{:.6e},{:.6e},{}", o.frames, r.seconds_per_frame, r.error, r.rms, r.finite())
        }),
    )?;
    write_csv(
        &dir.join("error_vs_frame.csv"),
        FRAME_CSV_HEADER,
        study.track.iter().map(|p| {
            let run = run_columns(&o.scene, &p.variant, p.iterations, p.substeps);
            format!("{run},{},{:.6e},{:.6e},{}", p.frame, p.error, p.rms, p.error.is_finite())
        }),
    )?;
    plots(dir, study)?;
    let md = dir.join("error_vs_time.md");
    std::fs::write(&md, markdown(study)).map_err(io(&md))
}

/// A table of one figure per variant and split (rows) and budget (columns), "–" where that
/// run is missing.
fn budget_table(s: &mut String, study: &Study, vs: &[Variant], cell: impl Fn(&Row) -> String) {
    let budgets = &study.options.budgets;
    let header: String = budgets.iter().map(|b| format!(" B = {b} |")).collect();
    let _ = writeln!(s, "| variant | split |{header}\n|---|---|{}", "---|".repeat(budgets.len()));
    for v in vs {
        for &sp in &study.options.splits {
            let c = curve(study, v, sp);
            let cells: String = budgets
                .iter()
                .map(|&b| c.iter().find(|r| r.budget() == b).map_or(" – |".into(), |r| format!(" {} |", cell(r))))
                .collect();
            let _ = writeln!(s, "| {} | {} |{cells}", v.name(), sp.name());
        }
    }
}

fn variants(study: &Study) -> Vec<Variant> {
    let mut out: Vec<Variant> = Vec::new();
    for r in &study.rows {
        if !out.contains(&r.variant) {
            out.push(r.variant);
        }
    }
    out
}

/// The rows of `v` in `split`, by budget.
fn curve<'a>(study: &'a Study, v: &Variant, split: Split) -> Vec<&'a Row> {
    let mut rows: Vec<&Row> =
        study.rows.iter().filter(|r| r.variant == *v && split.contains(r.iterations, r.substeps)).collect();
    rows.sort_by_key(|r| r.budget());
    rows
}

fn plots(dir: &Path, study: &Study) -> Result<()> {
    let o = &study.options;
    let vs = variants(study);
    let sweep_panel = |split: Split, x: &dyn Fn(&Row) -> f64, x_label: &str| Panel {
        title: split.name(),
        x_label: x_label.into(),
        y_label: "log₁₀ error".into(),
        lines: vs
            .iter()
            .map(|v| Line {
                label: v.name(),
                points: curve(study, v, split).iter().map(|r| (x(r), r.error.log10())).collect(),
                color: v.index(),
                markers: true,
            })
            .filter(|l| !l.points.is_empty())
            .collect(),
        legend: Legend::LowerLeft,
    };
    let title = |what: &str| format!("{}: {what}, error after {} frames against the f64 reference", o.scene, o.frames);
    let cols = o.splits.len().min(2);
    let panels: Vec<Panel> = o
        .splits
        .iter()
        .map(|&s| sweep_panel(s, &|r: &Row| r.seconds_per_frame.log10(), "log₁₀ wall-clock time per frame (s)"))
        .collect();
    save_panels(&dir.join("error_vs_time.png"), &title("error against run time"), &panels, cols, (760, 560))?;
    let panels: Vec<Panel> = o
        .splits
        .iter()
        .map(|&s| sweep_panel(s, &|r: &Row| (r.budget() as f64).log10(), "log₁₀ budget (iterations × substeps)"))
        .collect();
    save_panels(&dir.join("error_vs_budget.png"), &title("error against budget"), &panels, cols, (760, 560))?;

    let shapes = o.track_shapes();
    let panels: Vec<Panel> = shapes
        .iter()
        .map(|&(it, sub)| Panel {
            title: format!("{it} iteration(s) × {sub} substep(s)"),
            x_label: "frames after the start".into(),
            y_label: "log₁₀ error".into(),
            lines: vs
                .iter()
                .map(|v| Line {
                    label: v.name(),
                    points: track(study, v, (it, sub)).iter().map(|p| (p.frame as f64, p.error.log10())).collect(),
                    color: v.index(),
                    markers: false,
                })
                .filter(|l| !l.points.is_empty())
                .collect(),
            legend: Legend::LowerRight,
        })
        .collect();
    let title = format!("{}: error against frame number, budget {}", o.scene, o.track_budget);
    save_panels(&dir.join("error_vs_frame.png"), &title, &panels, shapes.len().clamp(1, 2), (760, 560))
}

fn track<'a>(study: &'a Study, v: &Variant, (it, sub): (u32, u32)) -> Vec<&'a TrackPoint> {
    study.track.iter().filter(|p| p.variant == *v && p.iterations == it && p.substeps == sub).collect()
}

/// A value with 2 significant digits.
fn e2(v: f64) -> String {
    if v.is_finite() { format!("{v:.2e}") } else { "NaN".into() }
}

fn ms(v: f64) -> String {
    let m = v * 1e3;
    if m >= 100.0 {
        format!("{m:.0}")
    } else if m >= 10.0 {
        format!("{m:.1}")
    } else {
        format!("{m:.2}")
    }
}

fn shape(r: &Row) -> String {
    format!("{} it × {} sub", r.iterations, r.substeps)
}

/// The fastest row reaching `target` among `rows`.
fn fastest<'a>(rows: impl Iterator<Item = &'a Row>, target: f64) -> Option<&'a Row> {
    rows.filter(|r| r.error <= target).min_by(|a, b| a.seconds_per_frame.total_cmp(&b.seconds_per_frame))
}

fn describe(r: Option<&Row>) -> String {
    r.map_or("–".into(), |r| {
        format!("{}, {} ({} ms/frame, e = {})", r.variant.name(), shape(r), ms(r.seconds_per_frame), e2(r.error))
    })
}

/// Pairs `(base, other)` of variants that differ in exactly one setting, `base` having the
/// plain value of it; with the name of the change.
fn pairs(vs: &[Variant]) -> Vec<(Variant, Variant, String)> {
    let mut out = Vec::new();
    for b in vs {
        let resets: [(bool, Variant, String); 5] = [
            (
                b.energy_aware != EnergyAware::Off,
                Variant { energy_aware: EnergyAware::Off, ..*b },
                format!("energy-aware {}", b.energy_aware.name()),
            ),
            (b.sor != 1.0, Variant { sor: 1.0, ..*b }, format!("SOR ω = {}", b.sor)),
            (
                b.method != Method::GaussSeidel,
                Variant { method: Method::GaussSeidel, ..*b },
                "Jacobi instead of GS".into(),
            ),
            (b.backend != Backend::Cpu, Variant { backend: Backend::Cpu, ..*b }, "GPU instead of CPU".into()),
            (
                b.form != Form::Compliant,
                Variant { form: Form::Compliant, ..*b },
                "energy form instead of compliant".into(),
            ),
        ];
        for (differs, a, what) in resets {
            if differs && vs.contains(&a) {
                out.push((a, *b, what));
            }
        }
    }
    out
}

fn geo_mean(v: &[f64]) -> f64 {
    (v.iter().map(|x| x.ln()).sum::<f64>() / v.len().max(1) as f64).exp()
}

/// Summary of `curve`: error at its smallest and largest budget.
fn decreases(curve: &[&Row]) -> Option<(f64, f64)> {
    match (curve.first(), curve.last()) {
        (Some(a), Some(b)) if curve.len() >= 2 => Some((a.error, b.error)),
        _ => None,
    }
}

fn markdown(study: &Study) -> String {
    let o = &study.options;
    let r = &study.reference;
    let vs = variants(study);
    let mut s = String::new();
    let _ = writeln!(s, "# Error against run time: `{}`\n", o.scene);
    let _ = writeln!(
        s,
        "Written by `eapbd report error-vs-time --scene {}{}` in {:.0} s. What the error means and the \
         discussion are in [../README.md](../README.md).\n",
        o.scene,
        if o.quick { " --quick" } else { "" },
        study.wall
    );
    let _ = writeln!(
        s,
        "- scene: `{}`, {} particles, {} constraints{}; dt = 1/{:.0} s;\n\
         - start state: frame {} of a run at {} substeps × 1 iteration (CPU, f32, Gauss-Seidel, compliant);\n\
         - reference: the next {} frames in f64, Gauss-Seidel, compliant form, {} substeps × 1 iteration per frame \
         ({:.2} s per frame); ‖x_ref − x_start‖ after {} frames = {:.4} m (RMS {:.4} m per free particle); the same run at {} substeps differs from it \
         by e = {} (the reference's own error is about this or less);\n\
         - error e = ‖x − x_ref‖ / ‖x_ref − x_start‖ after {} frames (norms over all particles); time = median \
         wall-clock seconds per frame of the {} frames (GPU: each frame submitted and waited for), on a shared \
         2-core machine whose load varied during the runs, so a single time can be off by up to 2× (compare trends, \
         not single cells);\n\
         - budgets B = iterations × substeps = {:?} projection sweeps per frame; splits: {};\n\
         - GPU: {}.\n",
        o.scene,
        study.particles,
        study.constraints,
        o.options.lattice.map_or(String::new(), |l| format!(" (lattice of {l} cells along the longest side)")),
        1.0 / o.dt,
        o.start_frame,
        super::error_time::WARMUP_SUBSTEPS,
        o.track_frames.max(o.frames),
        r.substeps,
        r.seconds_per_frame,
        o.frames,
        r.displacement,
        r.displacement_rms,
        r.substeps / 2,
        e2(r.check_error),
        o.frames,
        o.frames,
        o.budgets,
        o.splits.iter().map(|s| s.name()).collect::<Vec<_>>().join(", "),
        study.gpu.as_deref().unwrap_or("none (GPU variants skipped)"),
    );
    if !study.skipped.is_empty() {
        let names: Vec<String> = study.skipped.iter().map(|v| v.name()).collect();
        let _ = writeln!(s, "Skipped (no GPU adapter): {}.\n", names.join(", "));
    }
    let nonfinite: Vec<String> =
        study.rows.iter().filter(|r| !r.finite()).map(|r| format!("{} {}", r.variant.name(), shape(r))).collect();
    let _ = writeln!(
        s,
        "Non-finite results: {}.\n",
        if nonfinite.is_empty() { "none".to_string() } else { nonfinite.join(", ") }
    );

    let _ = writeln!(s, "## Fastest to a given error\n");
    let _ =
        writeln!(s, "| error ≤ | fastest | fastest on the GPU | fastest compliant-form Jacobi |\n|---|---|---|---|");
    let finite = || study.rows.iter().filter(|r| r.finite());
    for target in [0.5, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001] {
        if fastest(finite(), target).is_none() {
            continue;
        }
        let _ = writeln!(
            s,
            "| {target} | {} | {} | {} |",
            describe(fastest(finite(), target)),
            describe(fastest(finite().filter(|r| r.variant.backend == Backend::Gpu), target)),
            describe(fastest(
                finite().filter(|r| r.variant.method == Method::Jacobi && r.variant.form == Form::Compliant),
                target
            )),
        );
    }
    let best = finite().min_by(|a, b| a.error.total_cmp(&b.error));
    let _ = writeln!(s, "\nSmallest error of any run: {}.\n", describe(best));

    let _ = writeln!(s, "## Error after {} frames\n", o.frames);
    budget_table(&mut s, study, &vs, |r| e2(r.error));
    let _ = writeln!(s, "\n## Milliseconds per frame\n");
    budget_table(&mut s, study, &vs, |r| ms(r.seconds_per_frame));
    let _ = writeln!(s, "\n![error against time](error_vs_time.png)\n\n![error against budget](error_vs_budget.png)\n");

    let _ = writeln!(s, "## Does the error fall with the budget?\n");
    let _ = writeln!(
        s,
        "Error at the smallest and the largest budget of each curve, and the number of budget steps where it \
         did not fall. Compliant-form variants should approach the reference; energy-form variants converge to another \
         model (XPBD minimises E²/(2α)), so their error is model error and plateaus.\n"
    );
    let _ = writeln!(
        s,
        "| variant | split | smallest B | largest B | ratio | steps not falling | falls overall |\n|---|---|---|---|---|---|---|"
    );
    for v in &vs {
        for &sp in &o.splits {
            let c = curve(study, v, sp);
            let Some((first, last)) = decreases(&c) else { continue };
            let rises =
                c.windows(2).filter(|w| w[1].error.partial_cmp(&w[0].error) != Some(std::cmp::Ordering::Less)).count();
            let _ = writeln!(
                s,
                "| {} | {} | {} (B = {}) | {} (B = {}) | {:.3} | {} of {} | {} |",
                v.name(),
                sp.name(),
                e2(first),
                c[0].budget(),
                e2(last),
                c[c.len() - 1].budget(),
                last / first,
                rises,
                c.len() - 1,
                if last < first { "yes" } else { "**no**" }
            );
        }
    }

    let _ = writeln!(s, "\n## What each setting changes\n");
    let _ = writeln!(
        s,
        "Each line compares two variants that differ in one setting, over the shapes both ran: the error \
         ratio (changed / plain; below 1 the change helps) and the time ratio, as geometric means with the \
         range of the error ratio.\n"
    );
    let _ = writeln!(
        s,
        "| change | on | shapes | error ratio | range | smaller error in | time ratio |\n|---|---|---|---|---|---|---|"
    );
    for (a, b, what) in pairs(&vs) {
        let mut er = Vec::new();
        let mut tr = Vec::new();
        for ra in study.rows.iter().filter(|r| r.variant == a && r.finite()) {
            if let Some(rb) = study
                .rows
                .iter()
                .find(|r| r.variant == b && r.iterations == ra.iterations && r.substeps == ra.substeps)
                .filter(|r| r.finite())
            {
                er.push(rb.error / ra.error);
                tr.push(rb.seconds_per_frame / ra.seconds_per_frame);
            }
        }
        if er.is_empty() {
            continue;
        }
        let (lo, hi) = er.iter().fold((f64::MAX, f64::MIN), |(l, h), &x| (l.min(x), h.max(x)));
        let _ = writeln!(
            s,
            "| {what} | {} | {} | {:.3} | {:.3} … {:.3} | {} of {} | {:.2} |",
            a.name(),
            er.len(),
            geo_mean(&er),
            lo,
            hi,
            er.iter().filter(|&&x| x < 1.0).count(),
            er.len(),
            geo_mean(&tr)
        );
    }

    let _ = writeln!(s, "\n## Error against frame number\n");
    let _ = writeln!(
        s,
        "Each variant at budget {} runs {} frames from the start state; its error after every frame against the \
         reference at that frame (the denominator ‖x_ref(t) − x_start‖ is small in the first frames, so the \
         relative error starts high there). RMS is the root-mean-square distance to the reference over the free \
         particles.\n",
        o.track_budget, o.track_frames
    );
    let mid = (o.track_frames / 2).max(1);
    let _ = writeln!(
        s,
        "| variant | shape | e at frame {} | e at frame {mid} | e at frame {} | largest e after frame {} | RMS at frame {} (m) |\n|---|---|---|---|---|---|---|",
        o.frames, o.track_frames, o.frames, o.track_frames
    );
    for v in &vs {
        for sh in o.track_shapes() {
            let t = track(study, v, sh);
            let at = |f: u32| t.iter().find(|p| p.frame == f).map_or(f64::NAN, |p| p.error);
            let worst = t
                .iter()
                .filter(|p| p.frame >= o.frames)
                .map(|p| p.error)
                .fold(f64::NAN, |m, e| if m.is_nan() || e > m || e.is_nan() { e } else { m });
            let rms = t.last().map_or(f64::NAN, |p| p.rms);
            let _ = writeln!(
                s,
                "| {} | {} it × {} sub | {} | {} | {} | {} | {} |",
                v.name(),
                sh.0,
                sh.1,
                e2(at(o.frames)),
                e2(at(mid)),
                e2(at(o.track_frames)),
                e2(worst),
                e2(rms)
            );
        }
    }
    let _ = writeln!(s, "\n![error against frame](error_vs_frame.png)");
    s
}
