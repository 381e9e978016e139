//! The peer scene's splits of 30 projections per frame into iterations × substeps: time and
//! accuracy on the CPU solver.

use std::time::{Duration, Instant};

use eapbd::metrics;
use eapbd::scene;
use eapbd::solver::{CpuSolver, Settings};
use glam::Vec3A;

use super::cases::{Backend, peer_options};
use super::timing::{BLOCK_FRAMES, TURN_WARM_FRAMES, median};

/// One split of the peer scene on one CPU backend.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Split {
    /// Constraint iterations per substep.
    pub iterations: u32,
    /// Substeps per frame.
    pub substeps: u32,
    /// `CpuSingle` or `CpuAll`.
    pub backend: Backend,
    /// Frames simulated from the initial state.
    pub frames: u32,
    /// Mean wall time of a timed frame (ms), measurement excluded: every frame but the first
    /// [`TURN_WARM_FRAMES`] of each turn.
    pub mean_ms: f64,
    /// Median wall time of a frame (ms): unlike the mean, not moved by the odd frame in which
    /// the host took a core away for tens of milliseconds.
    pub median_ms: f64,
    /// Time average over the frames of the mean relative stretch `||d| − l₀| / l₀` of the grid
    /// edges (warp and weft, no diagonals): the performance issue's accuracy measure.
    pub stretch_grid: f64,
    /// The same over every spring edge, diagonals included (the `simulate` command's measure).
    pub stretch_all: f64,
    /// The fraction of the team's thread time spent waiting for one another in the timed frames
    /// ([`eapbd::solver::TeamTime::wait_fraction`]); `None` where no timed frame ran on the team.
    pub team_wait: Option<f64>,
}

/// Simulates the peer scene for `frames` frames at `iterations × substeps` on each of
/// `backends`, [`BLOCK_FRAMES`] frames each in turn (so a change in the machine's speed falls on
/// all alike); one split per backend, in order. Every frame
/// counts in the stretch; the first
/// [`TURN_WARM_FRAMES`] of each turn are not timed, as in the bench's other interleaved timings: a
/// team whose second core sat idle during the other backend's turn starts slowly, and the first
/// turn's first frame builds the solver's thread pool.
pub fn run_split(iterations: u32, substeps: u32, backends: &[Backend], frames: u32) -> anyhow::Result<Vec<Split>> {
    let scene = scene::build("cloth", &peer_options())?;
    let (grid, grid_rest) = metrics::axis_aligned_edges(&scene);
    let mut runs: Vec<_> = backends
        .iter()
        .map(|&backend| {
            let s = Settings { iterations, substeps, threads: backend.threads(), ..Settings::default() };
            let split = Split {
                iterations,
                substeps,
                backend,
                frames,
                mean_ms: 0.0,
                median_ms: 0.0,
                stretch_grid: 0.0,
                stretch_all: 0.0,
                team_wait: None,
            };
            let team = TeamSums::default();
            (CpuSolver::<Vec3A>::new(scene.clone()), s, split, Vec::with_capacity(frames as usize), team)
        })
        .collect();
    for first in (0..frames).step_by(BLOCK_FRAMES) {
        for (sv, s, split, times, team) in &mut runs {
            let turn = first..(first + BLOCK_FRAMES as u32).min(frames);
            let timed_from = first + TURN_WARM_FRAMES as u32;
            for frame in turn.clone() {
                if frame == timed_from {
                    // The team's time from here to the turn's end is what the timed frames took.
                    sv.reset_team_time();
                }
                let t0 = Instant::now();
                sv.step_frame(s);
                if frame >= timed_from {
                    times.push(t0.elapsed().as_secs_f64() * 1e3);
                }
                let x = &sv.particles.x;
                split.stretch_grid += metrics::stretch(&grid, &grid_rest, x).0;
                split.stretch_all += metrics::stretch(&sv.scene().edges, &sv.scene().edge_rest, x).0;
            }
            if turn.end > timed_from {
                team.add(TeamSums::of(sv));
            }
        }
    }
    let n = frames.max(1) as f64;
    Ok(runs
        .into_iter()
        .map(|(_, _, s, mut times, team)| Split {
            team_wait: team.wait_fraction(),
            mean_ms: times.iter().sum::<f64>() / times.len().max(1) as f64,
            median_ms: median(&mut times),
            stretch_grid: s.stretch_grid / n,
            stretch_all: s.stretch_all / n,
            ..s
        })
        .collect())
}

/// The team's time in some of a solver's frames: the threads' time working and waiting, summed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct TeamSums {
    frames: u32,
    busy: Duration,
    waited: Duration,
}

impl TeamSums {
    /// `sv`'s team time so far ([`CpuSolver::team_time`]), summed over the threads.
    fn of(sv: &CpuSolver<Vec3A>) -> Self {
        let t = sv.team_time();
        TeamSums { frames: t.frames, busy: t.busy.iter().sum(), waited: t.waited.iter().sum() }
    }

    /// Adds `other`'s sums.
    fn add(&mut self, other: TeamSums) {
        self.frames += other.frames;
        self.busy += other.busy;
        self.waited += other.waited;
    }

    /// The share of the summed time spent waiting; `None` without a team frame.
    fn wait_fraction(&self) -> Option<f64> {
        let total = (self.busy + self.waited).as_secs_f64();
        (self.frames > 0 && total > 0.0).then(|| self.waited.as_secs_f64() / total)
    }
}

/// The split with the smallest grid stretch on `backend` (the most accurate).
pub fn most_accurate(splits: &[Split], backend: Backend) -> Option<&Split> {
    splits.iter().filter(|s| s.backend == backend).min_by(|a, b| a.stretch_grid.total_cmp(&b.stretch_grid))
}
