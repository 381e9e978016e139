//! Outputs of the cantilever study: `beam.csv` (one row per XPBD run), `beam_static.csv` (one
//! row per static solve), `beam.md` and `beam.png`.

use std::io::Write as _;
use std::path::Path;

use super::beam::{MODELS, Precision, REFERENCE, RunResult, StudyOptions, StudyResults, Sweep, cantilever};
use super::beam_markdown::markdown;
use super::plot::{Legend, Line, Panel, save_panels};
use crate::error::{Error, Result};
use crate::material::Model;

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io { path: path.to_path_buf(), source }
}

/// Writes `beam.csv`, `beam_static.csv`, `beam.md` and `beam.png` into `dir`.
pub fn write_outputs(dir: &Path, opts: &StudyOptions, results: &StudyResults) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    write_runs_csv(&dir.join("beam.csv"), results)?;
    write_static_csv(&dir.join("beam_static.csv"), results)?;
    plot(&dir.join("beam.png"), opts, results)?;
    let md = dir.join("beam.md");
    std::fs::write(&md, markdown(opts, results)?).map_err(io(&md))
}

fn write_runs_csv(path: &Path, results: &StudyResults) -> Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(io(path))?);
    writeln!(
        f,
        "sweep,material,resolution,cells_across,tets,precision,substeps,iterations,damping_per_s,dt_s,\
         tip_deflection_m,euler_bernoulli_m,ratio,static_fe_m,ratio_to_static,xpbd_residual_rms,force_residual,\
         window_change,settled,converged,simulated_s,wall_s"
    )
    .map_err(io(path))?;
    for r in &results.runs {
        let c = &r.config;
        writeln!(
            f,
            "{},{},{},{},{},{},{},{},{:.3},{:.6},{:.6e},{:.6e},{:.5},{:.6e},{:.5},\
             {:.3e},{:.3e},{:.3e},{},{},{:.3},{:.3}",
            c.sweep.name(),
            c.model.name(),
            c.resolution,
            r.cells[1],
            r.tets,
            c.precision.name(),
            c.substeps,
            c.iterations,
            c.damping,
            r.dt,
            r.deflection,
            r.euler_bernoulli,
            r.ratio(),
            r.static_deflection.unwrap_or(f64::NAN),
            r.ratio_to_static(),
            r.xpbd_residual,
            r.force_residual,
            r.window_change,
            r.settled,
            r.converged(),
            r.simulated,
            r.wall
        )
        .map_err(io(path))?;
    }
    f.flush().map_err(io(path))
}

fn write_static_csv(path: &Path, results: &StudyResults) -> Result<()> {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(io(path))?);
    writeln!(
        f,
        "material,resolution,tets,tip_deflection_m,euler_bernoulli_m,ratio,newton_steps,cg_iterations,\
         force_residual,wall_s"
    )
    .map_err(io(path))?;
    for s in &results.statics {
        writeln!(
            f,
            "{},{},{},{:.6e},{:.6e},{:.5},{},{},{:.3e},{:.3}",
            s.model.name(),
            s.resolution,
            s.tets,
            s.deflection,
            s.euler_bernoulli,
            s.ratio(),
            s.newton_steps,
            s.cg_iterations,
            s.residual,
            s.wall
        )
        .map_err(io(path))?;
    }
    f.flush().map_err(io(path))
}

/// Runs of the resolution sweep for `model`, by resolution.
pub(super) fn resolution_runs(results: &StudyResults, model: Model) -> Vec<&RunResult> {
    let mut v: Vec<&RunResult> =
        results.runs.iter().filter(|r| r.config.sweep == Sweep::Resolution && r.config.model == model).collect();
    v.sort_by_key(|r| r.config.resolution);
    v
}

fn plot(path: &Path, opts: &StudyOptions, results: &StudyResults) -> Result<()> {
    let beam = cantilever(opts)?;
    let timoshenko = beam.timoshenko(opts.young, opts.poisson) / beam.euler_bernoulli(opts.young);
    let mut statics: Vec<_> = results.statics.iter().filter(|s| s.model == Model::Linear).collect();
    statics.sort_by_key(|s| s.resolution);
    let n_max = statics.last().map_or(1.0, |s| s.resolution as f64);
    let flat = |label: &str, y: f64, color, x_max| Line {
        label: label.into(),
        points: vec![(0.0, y), (x_max, y)],
        color,
        markers: false,
    };
    // The static answer first, so the XPBD points (on top of it) stay visible.
    let mut lines = vec![Line {
        label: "static FE (linear)".into(),
        points: statics.iter().map(|s| (s.resolution as f64, s.ratio())).collect(),
        color: 3,
        markers: false,
    }];
    let mut to_static = Vec::new();
    for (i, &m) in MODELS.iter().enumerate() {
        let runs = resolution_runs(results, m);
        let label = format!("{} (XPBD)", m.name());
        let points = runs.iter().map(|r| (r.config.resolution as f64, r.ratio())).collect();
        lines.push(Line { label: label.clone(), points, color: i, markers: true });
        let points = runs.iter().map(|r| (r.config.resolution as f64, r.ratio_to_static())).collect();
        to_static.push(Line { label, points, color: i, markers: true });
    }
    lines.push(flat("Euler–Bernoulli", 1.0, 4, n_max));
    lines.push(flat("Timoshenko", timoshenko, 5, n_max));
    let by_resolution = Panel {
        title: "tip deflection / Euler–Bernoulli".into(),
        x_label: "cells along the beam".into(),
        y_label: "δ / δ_EB".into(),
        lines,
        legend: Legend::LowerRight,
    };
    let n_runs = results.runs.iter().map(|r| r.config.resolution as f64).fold(1.0, f64::max);
    to_static.push(flat("static FE", 1.0, 3, n_runs));
    let solver_error = Panel {
        title: format!("XPBD / static FE, {} × {} (f64)", REFERENCE.0, REFERENCE.1),
        x_label: "cells along the beam".into(),
        y_label: "δ / δ_static".into(),
        lines: to_static,
        legend: Legend::LowerLeft,
    };

    let n_solver = results.runs.iter().filter(|r| r.config.sweep == Sweep::Solver).map(|r| r.config.resolution).min();
    let mut solver_lines = Vec::new();
    let mut s_max = 1.0f64;
    for (i, precision) in [Precision::F64, Precision::F32].into_iter().enumerate() {
        let mut points: Vec<(f64, f64)> = results
            .runs
            .iter()
            .filter(|r| {
                let c = &r.config;
                Some(c.resolution) == n_solver
                    && c.model == Model::Linear
                    && c.iterations == REFERENCE.1
                    && c.precision == precision
                    && c.damping > 0.0
            })
            .map(|r| (r.config.substeps as f64, r.ratio_to_static()))
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        points.dedup_by(|a, b| a.0 == b.0);
        s_max = points.iter().fold(s_max, |m, p| m.max(p.0));
        let label = format!("{}, {} iterations", precision.name(), REFERENCE.1);
        solver_lines.push(Line { label, points, color: i, markers: true });
    }
    solver_lines.push(Line {
        label: "static FE".into(),
        points: vec![(0.0, 1.0), (s_max, 1.0)],
        color: 3,
        markers: false,
    });
    let by_substeps = Panel {
        title: format!("{}-cell linear beam: XPBD / static FE", n_solver.unwrap_or(0)),
        x_label: "substeps per 1/60 s frame".into(),
        y_label: "δ / δ_static".into(),
        lines: solver_lines,
        legend: Legend::UpperRight,
    };
    let title = format!("Cantilever under its own weight, E = {:.0e} Pa", opts.young);
    save_panels(path, &title, &[by_resolution, solver_error, by_substeps], 3, (480, 400))
}
