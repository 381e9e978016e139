//! Outputs of the stability study: `stability.csv` (one row per case and backend) and
//! `stability.md` (the matrix with pass/fail, and every failure with what happened).

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

use super::stability::{
    Case, DAMPING, EDGE_TOLERANCE, ENERGY_FACTOR, Entry, Outcome, RIGID_MEASURE_K, SETTLE_FRACTION, STRETCH_LIMIT,
};
use crate::error::{Error, Result};

fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::Io { path: path.to_path_buf(), source }
}

/// Column names of `stability.csv`.
pub const CSV_HEADER: &str = "case,group,backend,status,frames,finite,energy_ratio,settle_ratio,end_stretch_mean,\
end_stretch_max,edge_ratio,inverted_start,inverted_end,start_energy_j,gravity_work_j,peak_energy_j,peak_kinetic_j,\
end_kinetic_j,wall_s,failures";

/// Writes `stability.csv` and `stability.md` into `dir`.
pub fn write_outputs(dir: &Path, cases: &[Case], entries: &[Entry], quick: bool) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let csv = dir.join("stability.csv");
    let mut f = std::io::BufWriter::new(std::fs::File::create(&csv).map_err(io(&csv))?);
    writeln!(f, "{CSV_HEADER}").map_err(io(&csv))?;
    for e in entries {
        writeln!(f, "{}", csv_row(cases, e)).map_err(io(&csv))?;
    }
    f.flush().map_err(io(&csv))?;
    let md = dir.join("stability.md");
    std::fs::write(&md, markdown(cases, entries, quick)).map_err(io(&md))
}

fn group_of<'a>(cases: &'a [Case], name: &str) -> &'a str {
    cases.iter().find(|c| c.name == name).map_or("", |c| c.group)
}

fn csv_row(cases: &[Case], e: &Entry) -> String {
    match e {
        Entry::Ran(o) => format!(
            "{},{},{},{},{},{},{:.4e},{:.4e},{:.4e},{:.4e},{:.5},{},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.3},{}",
            o.case,
            o.group,
            o.backend.name(),
            if o.passed() { "pass" } else { "fail" },
            o.frames,
            o.finite,
            o.energy_ratio(),
            o.settle_ratio(),
            o.end_stretch,
            o.end_stretch_max,
            o.edge_ratio,
            o.inverted_start,
            o.inverted_end,
            o.start_energy,
            o.gravity_work,
            o.peak_energy,
            o.peak_kinetic,
            o.end_kinetic,
            o.wall,
            o.failures().join("; ")
        ),
        Entry::Skipped { case, backend, reason } => {
            format!("{case},{},{},skipped,0,,,,,,,,,,,,,,,{reason}", group_of(cases, case), backend.name())
        }
    }
}

/// A ratio printed with 3 significant digits, in exponent form beyond 1000.
struct Sig(f64);

impl std::fmt::Display for Sig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0.abs() >= 1000.0 { write!(f, "{:.2e}", self.0) } else { write!(f, "{:.3}", self.0) }
    }
}

fn verdict(o: &Outcome) -> String {
    if !o.finite {
        return format!("**fail** (NaN at frame {})", o.nonfinite_frame.unwrap_or(0));
    }
    let edge = if o.edge_check { format!(", edge {:.3}", o.edge_ratio) } else { String::new() };
    let inv =
        if o.inverted_start > 0 { format!(", inv {}→{}", o.inverted_start, o.inverted_end) } else { String::new() };
    format!(
        "{} (E {}, KE {:.1e}, str {:.1e}{edge}{inv})",
        if o.passed() { "pass" } else { "**fail**" },
        Sig(o.energy_ratio()),
        o.settle_ratio(),
        o.end_stretch
    )
}

fn markdown(cases: &[Case], entries: &[Entry], quick: bool) -> String {
    let mut s = String::new();
    let ran: Vec<&Outcome> = entries
        .iter()
        .filter_map(|e| match e {
            Entry::Ran(o) => Some(o),
            Entry::Skipped { .. } => None,
        })
        .collect();
    let passed = ran.iter().filter(|o| o.passed()).count();
    let _ = writeln!(s, "# Stability study\n");
    let _ = writeln!(
        s,
        "Written by `eapbd report stability{}`: {} runs, {} pass, {} fail, {} skipped.\n",
        if quick { " --quick" } else { "" },
        entries.len(),
        passed,
        ran.len() - passed,
        entries.len() - ran.len()
    );
    let _ = writeln!(
        s,
        "Every case uses velocity damping β_v = {DAMPING} /s and otherwise the default solver (compliant form, \
         Gauss-Seidel, energy-aware off, 1 substep, 30 iterations, dt 1/60 s) unless its description says \
         otherwise. A case passes when\n\n\
         1. every figure stays finite;\n\
         2. **E** = peak (KE + E_elastic) / (start KE + E_elastic + largest work of gravity) ≤ {ENERGY_FACTOR};\n\
         3. **KE** = kinetic energy at the end / its peak ≤ {SETTLE_FRACTION};\n\
         4. **str** = mean relative edge stretch at the end ≤ {STRETCH_LIMIT} (for the collapsed cloths instead \
         **edge** = mean edge length / mean rest length within {EDGE_TOLERANCE} of 1), and no tetrahedron \
         inverted at the end (**inv** = inverted at start → end).\n\n\
         The rigid cloth's elastic energy is measured with k = {RIGID_MEASURE_K:.0e} N/m (that of k = ∞ is \
         undefined).\n"
    );
    let _ = writeln!(s, "| group | case | what | CPU | GPU |\n|---|---|---|---|---|");
    for c in cases {
        let cell = |b: crate::simulation::Backend| {
            entries
                .iter()
                .find_map(|e| match e {
                    Entry::Ran(o) if o.case == c.name && o.backend == b => Some(verdict(o)),
                    Entry::Skipped { case, backend, reason } if *case == c.name && *backend == b => {
                        Some(format!("skipped ({reason})"))
                    }
                    _ => None,
                })
                .unwrap_or_else(|| "–".into())
        };
        if !entries.iter().any(|e| matches!(e, Entry::Ran(o) if o.case == c.name)) {
            continue;
        }
        let _ = writeln!(
            s,
            "| {} | `{}` | {} | {} | {} |",
            c.group,
            c.name,
            c.description,
            cell(crate::simulation::Backend::Cpu),
            cell(crate::simulation::Backend::Gpu)
        );
    }
    let failing: Vec<&&Outcome> = ran.iter().filter(|o| !o.passed()).collect();
    let _ = writeln!(s, "\n## Failing cases\n");
    if failing.is_empty() {
        let _ = writeln!(s, "None.");
    }
    for o in failing {
        let _ = writeln!(s, "- `{}` on {}: {}.", o.case, o.backend.name(), o.failures().join("; "));
    }
    let wall: f64 = ran.iter().map(|o| o.wall).sum();
    let _ = writeln!(s, "\nRun time of the solves: {wall:.1} s.");
    s
}
