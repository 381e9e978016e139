//! The host check: how much the machine's second core adds while both cores work.
//!
//! On a virtual machine the host decides where the guest's cores run, and on the development
//! machine it switches within minutes between giving two cores their full speed and a state in
//! which two threads together do little more than one alone (BENCHMARKS.md, "The host check"). The
//! team's two-core timings move with it, so the bench measures two things next to them: the peer
//! scene at its most accurate split on one thread, alone and as two independent solvers at once,
//! each pinned to its own core, in alternating rounds; and the round trip of a cache line between
//! the two cores (two threads passing a counter back and forth), which the team pays wherever
//! it reads particles the other core wrote.

use std::sync::Barrier;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use eapbd::scene::Scene;
use eapbd::solver::{CpuSolver, Settings};
use glam::Vec3A;

use super::timing::median;

/// Frames each solver runs before its timed frames.
const WARM_FRAMES: usize = 2;
/// Round trips of the cache-line check.
const ROUND_TRIPS: u64 = 100_000;
/// The cache-line check gives up after this long (s).
const ROUND_TRIP_LIMIT_S: f64 = 1.0;

/// The peer scene's frame on one thread alone and with a second solver on the other core, and
/// the cache line's round trip between the two cores.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HostCheck {
    /// Median frame (ms) of one solver alone.
    pub alone_ms: f64,
    /// Median frame (ms) of two solvers running at once, one per core (both solvers' frames).
    pub together_ms: f64,
    /// Mean round trip (ns) of a cache line between the two cores; NaN where not measured.
    pub round_trip_ns: f64,
}

impl HostCheck {
    /// The work two cores do in the time one does one solver's: `2 · alone / together` (2 for
    /// two full cores, 1 when the pair does only what one core does alone).
    pub fn pair_speedup(&self) -> f64 {
        2.0 * self.alone_ms / self.together_ms
    }
}

/// Times the round trip, then `rounds` rounds of `frames` frames of `peer` (the peer scene, built
/// once by the caller) alone and as a pair; `None` on a machine (or an affinity mask) with fewer
/// than two cores.
pub fn check(peer: &Scene, frames: usize, rounds: usize) -> Option<HostCheck> {
    let cores = core_affinity::get_core_ids().unwrap_or_default();
    if cores.len() < 2 {
        return None;
    }
    let (mut alone, mut together) = (Vec::new(), Vec::new());
    let round_trip_ns = round_trip(cores[0], cores[1]);
    for _ in 0..rounds.max(1) {
        alone.extend(run_pinned(peer, &cores[..1], frames));
        together.extend(run_pinned(peer, &cores[..2], frames));
    }
    Some(HostCheck { alone_ms: median(&mut alone), together_ms: median(&mut together), round_trip_ns })
}

/// The mean time (ns) of [`ROUND_TRIPS`] round trips of a counter between a thread on core `a`
/// and one on core `b` (both spawned, so the caller's affinity stays as it is): each waits for
/// the other's value and answers with the next. NaN where a thread could not be pinned or the
/// exchange took longer than [`ROUND_TRIP_LIMIT_S`] (two spinning threads on one core).
fn round_trip(a: core_affinity::CoreId, b: core_affinity::CoreId) -> f64 {
    const GIVE_UP: u64 = u64::MAX;
    let counter = AtomicU64::new(0);
    let last = 2 * ROUND_TRIPS;
    let answer = |core, first: u64| -> Option<f64> {
        if !core_affinity::set_for_current(core) {
            counter.store(GIVE_UP, Ordering::Release);
            return None;
        }
        let t0 = Instant::now();
        let mut i = first;
        let mut spins = 0u32;
        while i < last {
            loop {
                match counter.load(Ordering::Acquire) {
                    c if c == i => break,
                    GIVE_UP => return None,
                    _ => {}
                }
                spins = spins.wrapping_add(1);
                if spins.is_multiple_of(4096) && t0.elapsed().as_secs_f64() > ROUND_TRIP_LIMIT_S {
                    counter.store(GIVE_UP, Ordering::Release);
                    return None;
                }
                std::hint::spin_loop();
            }
            counter.store(i + 1, Ordering::Release);
            i += 2;
        }
        Some(t0.elapsed().as_secs_f64())
    };
    std::thread::scope(|sc| {
        let other = sc.spawn(|| answer(b, 1));
        // The thread that starts times the whole exchange; it returns once it has sent the last
        // value, which the other answers at once.
        let first = sc.spawn(|| answer(a, 0));
        let other = other.join().ok().flatten();
        match (first.join().ok().flatten(), other) {
            (Some(t), Some(_)) => t * 1e9 / ROUND_TRIPS as f64,
            _ => f64::NAN,
        }
    })
}

/// A round trip (ns) as text; "not measured" for NaN.
pub fn trip(ns: f64) -> String {
    if ns.is_finite() { format!("{ns:.0} ns") } else { "not measured".into() }
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
         once, one per core, and a cache line's round trip between the two cores: before the CPU timings two cores \
         did {:.2}× the work of one (frames {:.2} ms alone, {:.2} ms as a pair) and the round trip took {}; \
         after them {:.2}× ({:.2}, {:.2} ms) and {}. 2× is two full cores, 1× a pair that does what one \
         core does. In the host's slow minutes one core alone is slower too and the round trip is most often long, \
         and the team, whose threads meet at every color group, loses more (BENCHMARKS.md, \"The host check\").\n",
        b.pair_speedup(),
        b.alone_ms,
        b.together_ms,
        trip(b.round_trip_ns),
        a.pair_speedup(),
        a.alone_ms,
        a.together_ms,
        trip(a.round_trip_ns)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pair_speedup_is_twice_alone_over_together() {
        let full = HostCheck { alone_ms: 4.0, together_ms: 4.0, round_trip_ns: 120.0 };
        let shared = HostCheck { alone_ms: 4.0, together_ms: 8.0, round_trip_ns: 480.0 };
        assert_eq!(full.pair_speedup(), 2.0);
        assert_eq!(shared.pair_speedup(), 1.0);
        let l = line(Some(full), Some(shared));
        assert!(
            l.contains(
                "did 2.00× the work of one (frames 4.00 ms alone, 4.00 ms as a pair) and the round trip took 120 ns"
            ),
            "{l}"
        );
        assert!(l.contains("after them 1.00× (4.00, 8.00 ms) and 480 ns"), "{l}");
        assert!(line(None, Some(full)).contains("not made"));
        assert_eq!(trip(f64::NAN), "not measured");
    }

    /// Both modes time every frame they were asked for and give a finite positive median, the
    /// round trip is timed, and the calling thread may still run on every core.
    #[test]
    fn the_check_times_one_solver_and_a_pair() {
        let before = core_affinity::get_core_ids().unwrap_or_default().len();
        let scene = eapbd::scene::build("cloth", &super::super::cases::peer_options()).unwrap();
        let Some(c) = check(&scene, 2, 1) else { return };
        assert_eq!(core_affinity::get_core_ids().unwrap_or_default().len(), before, "the caller was pinned");
        assert!(c.alone_ms.is_finite() && c.alone_ms > 0.0, "{c:?}");
        assert!(c.together_ms.is_finite() && c.together_ms > 0.0, "{c:?}");
        assert!(c.round_trip_ns.is_finite() && c.round_trip_ns > 0.0, "{c:?}");
        let cores = core_affinity::get_core_ids().unwrap();
        assert_eq!(run_pinned(&scene, &cores[..2], 3).len(), 6);
    }
}
