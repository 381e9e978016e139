//! Spin barriers and even shares: what the threads of a team ([`super::cpu`]) need to sweep the
//! color groups together. A frame has hundreds of groups, and a spin barrier costs far less than
//! a fork and join of a thread pool per group.

use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Spins before a waiting thread starts yielding its core (a core shared with other work must not
/// be held by a thread that waits).
const SPINS: u32 = 4_000;

/// A reusable barrier for a fixed number of threads that waits by spinning (then yielding).
///
/// Everything a thread wrote before [`SpinBarrier::wait`] is visible to every thread after it
/// (the arrival is an acquire-release read-modify-write and the release of the last arrival is
/// acquired by the waiters).
#[derive(Debug)]
pub(crate) struct SpinBarrier {
    threads: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
}

impl SpinBarrier {
    /// A barrier for `threads` ≥ 1 threads.
    pub fn new(threads: usize) -> Self {
        SpinBarrier { threads: threads.max(1), arrived: AtomicUsize::new(0), generation: AtomicUsize::new(0) }
    }

    /// Blocks until all the threads have called `wait` (once each per round).
    pub fn wait(&self) {
        let generation = self.generation.load(Ordering::Acquire);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.threads {
            // The reset is ordered before the release below, so a thread that sees the new round
            // also sees the count back at zero.
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.fetch_add(1, Ordering::AcqRel);
            return;
        }
        let mut spins = 0;
        while self.generation.load(Ordering::Acquire) == generation {
            if spins < SPINS {
                spins += 1;
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
    }
}

/// Thread `t`'s share of `range` when `threads` threads split it: consecutive chunks of a multiple
/// of `align` items (4 for elements: whole SIMD batches), the last one shorter, possibly empty.
/// The shares of `t = 0..threads` cover `range` exactly, without overlap.
pub(crate) fn share(range: Range<usize>, t: usize, threads: usize, align: usize) -> Range<usize> {
    let chunk = range.len().div_ceil(threads.max(1)).next_multiple_of(align.max(1));
    let lo = (range.start + t * chunk).min(range.end);
    lo..(lo + chunk).min(range.end)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_cover_the_range_without_overlap() {
        for (len, align) in [0usize, 1, 3, 4, 5, 17, 400, 2013].into_iter().flat_map(|l| [(l, 1), (l, 4)]) {
            for threads in 1..=5 {
                let mut next = 10;
                for t in 0..threads {
                    let r = share(10..10 + len, t, threads, align);
                    assert_eq!(r.start, next, "len {len}, threads {threads}, share {t}");
                    assert!(r.start <= r.end);
                    next = r.end;
                }
                assert_eq!(next, 10 + len);
            }
        }
    }

    #[test]
    fn barrier_orders_rounds() {
        let threads = 3;
        let barrier = SpinBarrier::new(threads);
        let counter = AtomicUsize::new(0);
        std::thread::scope(|s| {
            for _ in 0..threads {
                s.spawn(|| {
                    for round in 0..200 {
                        counter.fetch_add(1, Ordering::Relaxed);
                        barrier.wait();
                        // Every thread has counted this round before any leaves the barrier.
                        assert!(counter.load(Ordering::Relaxed) >= (round + 1) * threads);
                        barrier.wait();
                    }
                });
            }
        });
        assert_eq!(counter.load(Ordering::Relaxed), 200 * threads);
    }
}
#[cfg(test)]
mod timing {
    #[test]
    #[ignore]
    fn barrier_round_trip() {
        let b = super::SpinBarrier::new(2);
        let t0 = std::time::Instant::now();
        std::thread::scope(|s| {
            for _ in 0..2 {
                s.spawn(|| {
                    for _ in 0..200_000 {
                        b.wait();
                    }
                });
            }
        });
        println!("{:.0} ns per round", t0.elapsed().as_nanos() as f64 / 200_000.0);
    }
}
