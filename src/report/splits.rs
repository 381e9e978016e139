//! The energy study at the settings people run (`eapbd report splits`): the hanging cloth at
//! 1 × 30, 3 × 10, 10 × 3 and 30 × 1 (substeps × iterations per 1/60 s frame) under each
//! energy-aware setting, its energy normalised by the energy available for motion, and the free
//! stretched cloth's energy and momenta.
//!
//! Normalised energy: `n = (H − E_eq) / (E₀ − E_eq)` with `H` the honest total of
//! [`FrameStats::total`] (kinetic, gravitational from the ground, elastic energy the constraint
//! forces hold), `E₀` the energy at the start and `E_eq` that of the same cloth hanging at rest
//! (a damped run at 40 substeps of 2 iterations). `n = 1` keeps all the energy the fall makes
//! available, `n = 0` is a cloth at rest. The unresolved part is normalised the same way,
//! `u = U / (E₀ − E_eq)`.

use std::path::Path;
use std::time::Instant;

use glam::Vec3A;

use super::plot::{Legend, Line, Panel, save_panels};
use crate::error::{Error, Result};
use crate::metrics::FrameStats;
use crate::scene::{self, SceneOptions};
use crate::solver::projection::{momenta, momentum_scales};
use crate::solver::{CpuSolver, EnergyAware, Settings};

pub use super::splits_output::write_outputs;

/// The splits studied: `(substeps, iterations)` per frame, 30 projections of each constraint.
pub const SPLITS: [(u32, u32); 4] = [(1, 30), (3, 10), (10, 3), (30, 1)];

/// What the study runs.
#[derive(Clone, Debug, PartialEq)]
pub struct SplitsOptions {
    /// Particles per side of the cloth.
    pub resolution: u32,
    /// Spring stiffness `k_s` (N/m).
    pub stiffness: f32,
    /// Dihedral bending stiffness (N·m/rad).
    pub bending: f32,
    /// Frames of 1/60 s per run.
    pub frames: u32,
    /// The settings compared.
    pub variants: Vec<EnergyAware>,
}

impl SplitsOptions {
    /// The full study: the 41×41 cloth, k_s = 10⁴ N/m, bending 10⁻³ N·m/rad, 10 s per run.
    pub fn full() -> Self {
        SplitsOptions {
            resolution: 41,
            stiffness: 1e4,
            bending: 1e-3,
            frames: 600,
            variants: vec![EnergyAware::Off, EnergyAware::Local, EnergyAware::Global, EnergyAware::Project],
        }
    }

    /// A run of a few seconds (tests): an 11×11 cloth for 2 s.
    pub fn quick() -> Self {
        SplitsOptions { resolution: 11, frames: 120, ..SplitsOptions::full() }
    }

    fn scene(&self, name: &str) -> Result<crate::scene::Scene> {
        let opts = SceneOptions {
            resolution: Some(self.resolution),
            stiffness: self.stiffness,
            bending_stiffness: Some(self.bending),
            ..SceneOptions::default()
        };
        scene::build(name, &opts)
    }

    /// Frames in the windows the kinetic ratio and the late stretch average over (2 s, at most
    /// a third of the run).
    pub fn window(&self) -> usize {
        (120.min(self.frames / 3)).max(1) as usize
    }
}

/// `E₀` and `E_eq` of the hanging cloth (J).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reference {
    /// Honest total at the start (J).
    pub e0: f64,
    /// Honest total of the cloth hanging at rest (J).
    pub e_eq: f64,
}

impl Reference {
    /// `(H − E_eq) / (E₀ − E_eq)`.
    pub fn n(&self, h: f64) -> f64 {
        (h - self.e_eq) / (self.e0 - self.e_eq)
    }
}

/// One run of the hanging cloth.
#[derive(Clone, Debug)]
pub struct SplitRun {
    /// Substeps per frame.
    pub substeps: u32,
    /// Iterations per substep.
    pub iterations: u32,
    /// The setting.
    pub variant: EnergyAware,
    /// `n` per frame.
    pub n: Vec<f64>,
    /// `u` (unresolved energy over the available energy) per frame.
    pub u: Vec<f64>,
    /// Kinetic energy over the last window over that of the first.
    pub kinetic_ratio: f64,
    /// Mean relative stretch at the last frame.
    pub stretch_end: f64,
    /// Mean relative stretch averaged over the last window.
    pub stretch_late: f64,
    /// Kinetic energy per frame (J).
    pub kinetic: Vec<f64>,
    /// Mean relative stretch per frame.
    pub stretch: Vec<f64>,
    /// Median solve time per frame, one thread (ms).
    pub ms: f64,
}

impl SplitRun {
    /// `n` at the last frame.
    pub fn n_end(&self) -> f64 {
        self.n.last().copied().unwrap_or(f64::NAN)
    }

    /// Largest `n`.
    pub fn n_max(&self) -> f64 {
        self.n.iter().copied().fold(f64::NAN, f64::max)
    }

    /// Largest `u`.
    pub fn u_max(&self) -> f64 {
        self.u.iter().copied().fold(f64::NAN, f64::max)
    }

    /// This run's stretch over the last `window` frames against `off`'s at the same kinetic
    /// energy: each late frame with kinetic energy `K` is matched with the frames of `off` after
    /// its first `window` (the fall) whose kinetic energy is within [`EQUAL_MOTION`] of `K`, and
    /// the result is `Σ s / Σ s̄_off` over the matched frames (`s` the frame's mean stretch, `s̄_off`
    /// the mean over its matches), with the fraction of late frames matched. A cloth that keeps
    /// its motion stretches more than one that has come to rest under the same under-converged
    /// solve; this separates the stretch the setting adds from the stretch of the motion it keeps.
    /// `None` when no late frame has a match.
    pub fn stretch_at_equal_motion(&self, off: &SplitRun, window: usize) -> Option<(f64, f64)> {
        let late = self.kinetic.len().saturating_sub(window);
        let settled = || off.kinetic.iter().zip(&off.stretch).skip(window);
        let (mut ours, mut theirs, mut matched) = (0.0, 0.0, 0usize);
        for (&k, &s) in self.kinetic.iter().zip(&self.stretch).skip(late) {
            let (sum, count) = settled()
                .filter(|&(&ko, _)| (ko - k).abs() <= EQUAL_MOTION * k)
                .fold((0.0, 0usize), |(sum, count), (_, &so)| (sum + so, count + 1));
            if count > 0 {
                (ours, theirs, matched) = (ours + s, theirs + sum / count as f64, matched + 1);
            }
        }
        (matched > 0).then(|| (ours / theirs, matched as f64 / (self.kinetic.len() - late) as f64))
    }
}

/// Relative tolerance on the kinetic energy of frames compared "at equal motion".
pub const EQUAL_MOTION: f64 = 0.15;

/// One run of the free stretched cloth (no gravity, 3 substeps of 10 iterations).
#[derive(Clone, Debug)]
pub struct FreeRun {
    /// The setting.
    pub variant: EnergyAware,
    /// Honest energy after the first frame (J).
    pub start: f64,
    /// Lowest and highest honest energy after the first frame, over `start`.
    pub range: (f64, f64),
    /// Honest energy at the end over `start`.
    pub end: f64,
    /// Largest change of the linear and angular momentum since the first frame, over their
    /// scales `Σ m|v|` and `Σ m|x − c||v|` of the same frame.
    pub momentum_drift: (f64, f64),
}

/// `E₀` and `E_eq`: the cloth at the start, and after `frames.max(120)` damped frames at 40
/// substeps of 2 iterations.
pub fn reference(opts: &SplitsOptions) -> Result<Reference> {
    let mut sv = CpuSolver::<Vec3A>::new(opts.scene("cloth")?);
    let e0 = FrameStats::measure(&sv, 0, 0.0).total();
    let s = Settings { substeps: 40, iterations: 2, damping: 5.0, threads: 1, ..Settings::default() };
    for _ in 0..opts.frames.max(120) {
        sv.step_frame(&s);
    }
    Ok(Reference { e0, e_eq: FrameStats::measure(&sv, 0, 0.0).total() })
}

/// Runs the hanging cloth at one split under one setting.
pub fn run_split(
    opts: &SplitsOptions,
    r: &Reference,
    (substeps, iterations): (u32, u32),
    variant: EnergyAware,
) -> Result<SplitRun> {
    let mut sv = CpuSolver::<Vec3A>::new(opts.scene("cloth")?);
    let s = Settings { substeps, iterations, energy_aware: variant, threads: 1, ..Settings::default() };
    s.validate()?;
    let available = r.e0 - r.e_eq;
    let (mut n, mut u, mut kinetic, mut stretch, mut times) = (vec![], vec![], vec![], vec![], vec![]);
    for frame in 1..=opts.frames {
        let t = Instant::now();
        sv.step_frame(&s);
        times.push(t.elapsed().as_secs_f64() * 1e3);
        let st = FrameStats::measure(&sv, frame, 0.0);
        if !st.is_finite() {
            return Err(Error::Report(format!(
                "{variant:?} at {substeps} × {iterations}: not finite at frame {frame}"
            )));
        }
        n.push(r.n(st.total()));
        u.push(st.unresolved / available);
        kinetic.push(st.kinetic);
        stretch.push(st.stretch_mean);
    }
    let w = opts.window();
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let len = kinetic.len();
    times.sort_by(f64::total_cmp);
    Ok(SplitRun {
        substeps,
        iterations,
        variant,
        n,
        u,
        kinetic_ratio: mean(&kinetic[len - w..]) / mean(&kinetic[..w]).max(1e-30),
        stretch_end: stretch[len - 1],
        stretch_late: mean(&stretch[len - w..]),
        kinetic,
        stretch,
        ms: times[times.len() / 2],
    })
}

/// Runs the free stretched cloth (no gravity) at 3 substeps of 10 iterations.
pub fn run_free(opts: &SplitsOptions, variant: EnergyAware) -> Result<FreeRun> {
    let mut sv = CpuSolver::<Vec3A>::new(opts.scene("cloth-free")?);
    let s = Settings { substeps: 3, iterations: 10, energy_aware: variant, threads: 1, ..Settings::default() };
    sv.step_frame(&s);
    let start = FrameStats::measure(&sv, 1, 0.0).total();
    let p = &sv.particles;
    let (p0, l0) = momenta(&p.x, &p.v, &p.w);
    let (mut lo, mut hi, mut end, mut dp, mut dl) = (1.0f64, 1.0f64, 1.0, 0.0f64, 0.0f64);
    for frame in 2..=opts.frames {
        sv.step_frame(&s);
        let e = FrameStats::measure(&sv, frame, 0.0).total() / start;
        (lo, hi, end) = (lo.min(e), hi.max(e), e);
        let p = &sv.particles;
        let (p1, l1) = momenta(&p.x, &p.v, &p.w);
        let (scale_p, scale_l) = momentum_scales(&p.x, &p.v, &p.w);
        dp = dp.max((p1 - p0).length() / scale_p.max(1e-30));
        dl = dl.max((l1 - l0).length() / scale_l.max(1e-30));
    }
    Ok(FreeRun { variant, start, range: (lo, hi), end, momentum_drift: (dp, dl) })
}

/// Every run of the study, reporting each as it ends.
pub fn run_study(opts: &SplitsOptions, mut done: impl FnMut(&str)) -> Result<(Reference, Vec<SplitRun>, Vec<FreeRun>)> {
    let r = reference(opts)?;
    done(&format!("E0 {:.4} J, E_eq {:.4} J", r.e0, r.e_eq));
    let mut runs = Vec::new();
    for split in SPLITS {
        for &v in &opts.variants {
            let run = run_split(opts, &r, split, v)?;
            done(&format!(
                "{:2} x {:2} {:8} n {:+.3} (peak {:+.3})  kinetic ratio {:.3}  stretch {:.4}  {:.2} ms",
                split.0,
                split.1,
                v.name(),
                run.n_end(),
                run.n_max(),
                run.kinetic_ratio,
                run.stretch_end,
                run.ms
            ));
            runs.push(run);
        }
    }
    let mut free = Vec::new();
    for &v in &opts.variants {
        let f = run_free(opts, v)?;
        done(&format!("cloth-free {:8} energy {:.3} .. {:.3}, end {:.3}", v.name(), f.range.0, f.range.1, f.end));
        free.push(f);
    }
    Ok((r, runs, free))
}

/// The panels of one quantity per split, a line per setting.
pub(super) fn panels(
    opts: &SplitsOptions,
    runs: &[SplitRun],
    y_label: &str,
    value: fn(&SplitRun) -> &[f64],
) -> Vec<Panel> {
    SPLITS
        .iter()
        .map(|&(sub, it)| Panel {
            title: format!("{sub} substeps × {it} iterations"),
            x_label: "time (s)".into(),
            y_label: y_label.into(),
            lines: runs
                .iter()
                .filter(|r| (r.substeps, r.iterations) == (sub, it))
                .map(|r| Line {
                    label: r.variant.name().into(),
                    points: value(r).iter().enumerate().map(|(i, v)| ((i + 1) as f64 / 60.0, *v)).collect(),
                    color: opts.variants.iter().position(|v| *v == r.variant).unwrap_or(0),
                    markers: false,
                })
                .collect(),
            legend: Legend::LowerLeft,
        })
        .collect()
}

/// Writes the two figures: `n` and `u` against time per split.
pub(super) fn write_plots(dir: &Path, opts: &SplitsOptions, runs: &[SplitRun]) -> Result<()> {
    let n = panels(opts, runs, "n = (H − E_eq) / (E0 − E_eq)", |r| &r.n);
    save_panels(&dir.join("splits_n.png"), "Hanging cloth: normalised honest energy", &n, 2, (520, 340))?;
    let u = panels(opts, runs, "unresolved / (E0 − E_eq)", |r| &r.u);
    save_panels(&dir.join("splits_unresolved.png"), "Hanging cloth: unresolved stretch (not energy)", &u, 2, (520, 340))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(kinetic: Vec<f64>, stretch: Vec<f64>) -> SplitRun {
        SplitRun {
            substeps: 10,
            iterations: 3,
            variant: EnergyAware::Off,
            n: vec![],
            u: vec![],
            kinetic_ratio: 0.0,
            stretch_end: 0.0,
            stretch_late: 0.0,
            kinetic,
            stretch,
            ms: 0.0,
        }
    }

    #[test]
    fn stretch_at_equal_motion_compares_frames_of_like_kinetic_energy() {
        // `off` falls (frames 0 and 1, skipped), then slows down: stretch follows the motion,
        // 0.01 per J.
        let off = run(vec![9.0, 8.0, 3.0, 2.0, 1.0, 0.5], vec![0.5, 0.4, 0.03, 0.02, 0.01, 0.005]);
        // The other keeps moving: its last two frames (3 J and 1 J) stretch twice as much as
        // `off` at 3 J and as much at 1 J.
        let kept = run(vec![9.0, 8.0, 7.0, 3.0, 1.0], vec![0.5, 0.4, 0.9, 0.06, 0.01]);
        let (ratio, matched) = kept.stretch_at_equal_motion(&off, 2).unwrap();
        assert!((ratio - 0.07 / 0.04).abs() < 1e-12, "{ratio}");
        assert_eq!(matched, 1.0);
        // Over three frames, 7 J has no match and 3 J none after `off`'s first three frames.
        let (ratio, matched) = kept.stretch_at_equal_motion(&off, 3).unwrap();
        assert!((ratio - 1.0).abs() < 1e-12, "{ratio}");
        assert!((matched - 1.0 / 3.0).abs() < 1e-12, "{matched}");
        // `off` against a run that never moves as it does.
        assert_eq!(run(vec![0.0, 20.0], vec![0.0, 0.1]).stretch_at_equal_motion(&off, 1), None);
    }
}
