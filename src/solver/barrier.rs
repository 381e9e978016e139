//! Spin barriers and even shares: what the threads of a team ([`super::cpu`]) need to sweep the
//! color groups together. A frame has hundreds of groups, and a spin barrier costs far less than
//! a fork and join of a thread pool per group.

use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// How long a waiting thread spins before it sleeps: well past the imbalance of a color group's
/// shares on a quiet machine (a wake-up from sleep costs tens of microseconds, and a frame has
/// hundreds of barriers), short enough that a team on cores busy with other work, whose waits
/// last whole scheduler time slices, soon sleeps and is noticed ([`SpinBarrier::slept`]).
const SPIN_TIME: Duration = Duration::from_micros(200);

/// A reusable barrier for a fixed number of threads that waits by spinning, then sleeping.
///
/// Everything a thread wrote before [`SpinBarrier::wait`] is visible to every thread after it:
/// the arrivals are acquire-release read-modify-writes and the last one's release of the new
/// round is acquired by the waiters. A waiter that sleeps announces itself (`sleepers`) before it
/// checks the round a last time, and the last arrival checks `sleepers` after it opens the round,
/// both sequentially consistent, so one of the two always sees the other: no wake-up is lost.
#[derive(Debug)]
pub(crate) struct SpinBarrier {
    threads: usize,
    arrived: AtomicUsize,
    generation: AtomicUsize,
    sleepers: AtomicUsize,
    /// Waits that ended in sleep, since the barrier was made.
    slept: AtomicUsize,
    lock: Mutex<()>,
    wake: Condvar,
}

impl SpinBarrier {
    /// A barrier for `threads` ≥ 1 threads.
    pub fn new(threads: usize) -> Self {
        SpinBarrier {
            threads: threads.max(1),
            arrived: AtomicUsize::new(0),
            generation: AtomicUsize::new(0),
            sleepers: AtomicUsize::new(0),
            slept: AtomicUsize::new(0),
            lock: Mutex::new(()),
            wake: Condvar::new(),
        }
    }

    /// Blocks until all the threads have called `wait` (once each per round); returns how long
    /// this thread waited (nothing for the last to arrive).
    pub fn wait(&self) -> Waited {
        let generation = self.generation.load(Ordering::Acquire);
        if self.arrived.fetch_add(1, Ordering::AcqRel) + 1 == self.threads {
            // The reset is ordered before the new round, so a thread that sees the new round
            // also sees the count back at zero.
            self.arrived.store(0, Ordering::Relaxed);
            self.generation.fetch_add(1, Ordering::SeqCst);
            if self.sleepers.load(Ordering::SeqCst) > 0 {
                let _guard = self.lock.lock().unwrap_or_else(PoisonError::into_inner);
                self.wake.notify_all();
            }
            return Waited::default();
        }
        let start = Instant::now();
        let mut spins = 0u32;
        loop {
            if self.generation.load(Ordering::Acquire) != generation {
                return Waited { time: start.elapsed(), slept: false };
            }
            std::hint::spin_loop();
            spins = spins.wrapping_add(1);
            if spins.is_multiple_of(64) && start.elapsed() > SPIN_TIME {
                break;
            }
        }
        self.slept.fetch_add(1, Ordering::Relaxed);
        let mut guard = self.lock.lock().unwrap_or_else(PoisonError::into_inner);
        self.sleepers.fetch_add(1, Ordering::SeqCst);
        while self.generation.load(Ordering::SeqCst) == generation {
            guard = self.wake.wait(guard).unwrap_or_else(PoisonError::into_inner);
        }
        self.sleepers.fetch_sub(1, Ordering::SeqCst);
        Waited { time: start.elapsed(), slept: true }
    }

    /// Waits that ended in sleep so far: a team whose threads sleep at its barriers is sharing
    /// the cores with other work.
    pub fn slept(&self) -> usize {
        self.slept.load(Ordering::Relaxed)
    }
}

/// What one wait of a thread took.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Waited {
    /// Time spent waiting (zero when nothing was awaited).
    pub time: Duration,
    /// The wait ended in sleep: it outlasted [`SPIN_TIME`].
    pub slept: bool,
}

/// Each thread's count of finished steps, for threads that order only some of their work (the
/// team's boundary parts, `cpu/plan.rs`): thread `t` publishes `n` once it has finished its
/// boundary parts of steps `0..n`, and waits, before the boundary part of step `s`, until every
/// other thread has published `s`. A publication is a release store and a wait's check an acquire
/// load, so what a thread wrote before publishing is visible to a thread that waited for it, and
/// what a thread read before publishing was read before the waiter writes.
#[derive(Debug)]
pub(crate) struct Progress {
    done: Vec<Padded>,
}

impl Clone for Progress {
    /// Fresh counters for as many threads (a copied solver runs its frames on its own).
    fn clone(&self) -> Self {
        Progress::new(self.done.len())
    }
}

/// A counter on a cache line of its own, so one thread's publications do not slow another's.
#[derive(Debug, Default)]
#[repr(align(128))]
struct Padded(AtomicUsize);

impl Progress {
    /// Counters for `threads` threads, at zero.
    pub fn new(threads: usize) -> Self {
        Progress { done: (0..threads).map(|_| Padded::default()).collect() }
    }

    /// Every counter back to zero (before a frame, while no thread uses them).
    pub fn reset(&mut self) {
        for d in &mut self.done {
            *d.0.get_mut() = 0;
        }
    }

    /// Thread `t` has finished the boundary parts of steps `0..n`.
    #[inline]
    pub fn publish(&self, t: usize, n: usize) {
        self.done[t].0.store(n, Ordering::Release);
    }

    /// Blocks thread `t` until every other thread has published at least `n`: spins, then, past
    /// [`SPIN_TIME`], sleeps in short naps.
    #[inline]
    pub fn wait(&self, t: usize, n: usize) -> Waited {
        let mut waited = Waited::default();
        for (u, d) in self.done.iter().enumerate() {
            if u == t || d.0.load(Ordering::Acquire) >= n {
                continue;
            }
            let start = Instant::now();
            let mut spins = 0u32;
            while d.0.load(Ordering::Acquire) < n {
                spins = spins.wrapping_add(1);
                if waited.slept || (spins.is_multiple_of(64) && start.elapsed() > SPIN_TIME) {
                    waited.slept = true;
                    std::thread::sleep(NAP);
                } else {
                    std::hint::spin_loop();
                }
            }
            waited.time += start.elapsed();
        }
        waited
    }
}

/// A sleeping [`Progress::wait`]'s nap between checks.
const NAP: Duration = Duration::from_micros(50);

/// Thread `t`'s share of `range` when `threads` threads split it: consecutive chunks of a multiple
/// of `align` items (the SIMD width for elements: whole SIMD batches), the last one shorter,
/// possibly empty.
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
    fn a_late_thread_puts_the_others_to_sleep() {
        let barrier = SpinBarrier::new(3);
        std::thread::scope(|s| {
            for t in 0..3 {
                let b = &barrier;
                s.spawn(move || {
                    if t == 0 {
                        std::thread::sleep(std::time::Duration::from_millis(50));
                    }
                    b.wait();
                });
            }
        });
        assert_eq!(barrier.slept(), 2, "the two early threads spin, then sleep until the late one arrives");
        // The waits report their time: the early thread waited through the late one's sleep.
        let waits = Mutex::new(Vec::new());
        let barrier = SpinBarrier::new(2);
        std::thread::scope(|s| {
            for t in 0..2 {
                let (b, waits) = (&barrier, &waits);
                s.spawn(move || {
                    if t == 0 {
                        std::thread::sleep(Duration::from_millis(30));
                    }
                    let waited = b.wait();
                    waits.lock().expect("waits").push(waited);
                });
            }
        });
        let mut waits = waits.into_inner().expect("waits");
        waits.sort_by_key(|w| w.time);
        assert_eq!(waits[0], Waited::default(), "the last to arrive does not wait");
        assert!(waits[1].slept && waits[1].time >= Duration::from_millis(20), "{waits:?}");
    }

    #[test]
    fn progress_orders_the_steps_of_two_threads() {
        // Each thread appends to a log in steps; a step may start only once the other thread has
        // finished the one before, so the log's entries never run more than one step apart.
        let progress = Progress::new(2);
        let log = Mutex::new(Vec::new());
        std::thread::scope(|s| {
            for t in 0..2 {
                let (progress, log) = (&progress, &log);
                s.spawn(move || {
                    for step in 0..500 {
                        progress.wait(t, step);
                        log.lock().expect("log").push(step);
                        progress.publish(t, step + 1);
                    }
                });
            }
        });
        let log = log.into_inner().expect("log");
        assert_eq!(log.len(), 1000);
        for (k, &step) in log.iter().enumerate() {
            // A thread logs step s only after both threads logged steps 0..s: at least 2s entries.
            assert!(2 * step <= k, "entry {k} is step {step}: a thread ran ahead");
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
