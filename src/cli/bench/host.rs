//! The host check: how much the machine's second core adds while both cores work.
//!
//! On a virtual machine the host decides where the guest's cores run, and on the development
//! machine it switches within minutes between giving two cores their full speed and a state in
//! which two threads together do little more than one alone (BENCHMARKS.md, "What next"). The
//! team's two-core timings move with it, so the bench measures the state next to them: the peer
//! scene at its most accurate split on one thread, alone and as two independent solvers at once,
//! each pinned to its own core, in alternating rounds.

use std::sync::Barrier;
use std::time::Instant;

use eapbd::scene::{self, Scene};
use eapbd::solver::{CpuSolver, Settings};
use glam::Vec3A;

use super::cases::peer_options;
use super::timing::median;

/// Frames each solver runs before its timed frames.
const WARM_FRAMES: usize = 2;

/// The peer scene's frame on one thread alone and with a second solver on the other core.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HostCheck {
    /// Median frame (ms) of one solver alone.
    pub alone_ms: f64,
    /// Median frame (ms) of two solvers running at once, one per core (both solvers' frames).
    pub together_ms: f64,
}

impl HostCheck {
    /// The work two cores do in the time one does one solver's: `2 · alone / together` (2 for
    /// two full cores, 1 when the pair does only what one core does alone).
    pub fn pair_speedup(&self) -> f64 {
        2.0 * self.alone_ms / self.together_ms
    }
}

/// Times `rounds` rounds of `frames` frames alone, then as a pair; `None` on a machine (or an
/// affinity mask) with fewer than two cores.
pub fn check(frames: usize, rounds: usize) -> anyhow::Result<Option<HostCheck>> {
    let cores = core_affinity::get_core_ids().unwrap_or_default();
    if cores.len() < 2 {
        return Ok(None);
    }
    let scene = scene::build("cloth", &peer_options())?;
    let (mut alone, mut together) = (Vec::new(), Vec::new());
    for _ in 0..rounds.max(1) {
        alone.extend(run_pinned(&scene, &cores[..1], frames));
        together.extend(run_pinned(&scene, &cores[..2], frames));
    }
    Ok(Some(HostCheck { alone_ms: median(&mut alone), together_ms: median(&mut together) }))
}

/// One solver of the peer scene at 1 × 30 on one thread per core of `cores`, started together;
/// every solver's timed frame times (ms), pooled.
fn run_pinned(scene: &Scene, cores: &[core_affinity::CoreId], frames: usize) -> Vec<f64> {
    let s = Settings { iterations: 1, substeps: 30, threads: 1, ..Settings::default() };
    let start = Barrier::new(cores.len());
    std::thread::scope(|sc| {
        let runs: Vec<_> = cores
            .iter()
            .map(|&core| {
                let start = &start;
                sc.spawn(move || {
                    let _ = core_affinity::set_for_current(core);
                    let mut sv = CpuSolver::<Vec3A>::new(scene.clone());
                    for _ in 0..WARM_FRAMES {
                        sv.step_frame(&s);
                    }
                    start.wait();
                    (0..frames.max(1))
                        .map(|_| {
                            let t0 = Instant::now();
                            sv.step_frame(&s);
                            t0.elapsed().as_secs_f64() * 1e3
                        })
                        .collect::<Vec<f64>>()
                })
            })
            .collect();
        runs.into_iter().flat_map(|r| r.join().unwrap_or_default()).collect()
    })
}

/// The bench's line on the host: the check before the CPU timings and after them.
pub fn line(before: Option<HostCheck>, after: Option<HostCheck>) -> String {
    let (Some(b), Some(a)) = (before, after) else {
        return "Host check: not made (fewer than two cores).\n".into();
    };
    format!(
        "Host check (`cli/bench/host.rs`): the peer scene at 1 × 30 on one thread, alone and as two solvers at \
         once, one per core; two cores did {:.2}× the work of one before the CPU timings (frames {:.2} ms alone, \
         {:.2} ms as a pair) and {:.2}× after them ({:.2}, {:.2} ms). 2 is two full cores; near 1 the host gave \
         the pair little more than one core, and the two-core timings of those minutes run slower.\n",
        b.pair_speedup(),
        b.alone_ms,
        b.together_ms,
        a.pair_speedup(),
        a.alone_ms,
        a.together_ms
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pair_speedup_is_twice_alone_over_together() {
        let full = HostCheck { alone_ms: 4.0, together_ms: 4.0 };
        let shared = HostCheck { alone_ms: 4.0, together_ms: 8.0 };
        assert_eq!(full.pair_speedup(), 2.0);
        assert_eq!(shared.pair_speedup(), 1.0);
        let l = line(Some(full), Some(shared));
        assert!(l.contains("2.00× the work of one before the CPU timings (frames 4.00 ms alone, 4.00 ms"), "{l}");
        assert!(l.contains("1.00× after them (4.00, 8.00 ms)"), "{l}");
        assert!(line(None, Some(full)).contains("not made"));
    }

    /// Both modes time every frame they were asked for and give a finite positive median.
    #[test]
    fn the_check_times_one_solver_and_a_pair() {
        let Some(c) = check(2, 1).unwrap() else { return };
        assert!(c.alone_ms.is_finite() && c.alone_ms > 0.0, "{c:?}");
        assert!(c.together_ms.is_finite() && c.together_ms > 0.0, "{c:?}");
        let cores = core_affinity::get_core_ids().unwrap();
        let scene = scene::build("cloth", &peer_options()).unwrap();
        assert_eq!(run_pinned(&scene, &cores[..2], 3).len(), 6);
    }
}
