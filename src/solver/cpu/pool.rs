//! The solver's own thread pool, each thread pinned to a core when the pool takes them all.
//!
//! A team waits for its threads at spin barriers, so two of its threads on one core run a frame
//! two to three times slower than one thread alone. The system's scheduler does that now and then:
//! a pool woken after its cores did other work (a frame loop that draws or sleeps between frames)
//! often finds its threads on the same core (measured on the 2-core development machine, the peer
//! scene with the main thread busy for 10 ms between frames: 20 ms a frame on the team against
//! 7.8 ms with the threads pinned, 11.6 ms on one thread). A pool as large as the set of cores the
//! process may use therefore pins thread `i` to core `i`; a smaller pool is left to the scheduler,
//! which has free cores to place it on (pinning it would pile two processes' pools onto the first
//! cores of a large machine).

/// The cores this process may run on (asked once: the query allocates). A team waits at
/// barriers for a thread the system has not scheduled, so the solver never runs more threads than
/// cores.
fn allowed() -> &'static [core_affinity::CoreId] {
    static CORES: std::sync::OnceLock<Vec<core_affinity::CoreId>> = std::sync::OnceLock::new();
    CORES.get_or_init(|| core_affinity::get_core_ids().unwrap_or_default())
}

/// The number of cores this process may use (at least 1).
pub(super) fn cores() -> u32 {
    static CORES: std::sync::OnceLock<u32> = std::sync::OnceLock::new();
    *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()) as u32)
}

/// A pool of `threads` threads, pinned one per core when `threads` is the number of cores this
/// process may use; `None` if the system refuses the threads.
pub(super) fn build(threads: u32) -> Option<rayon::ThreadPool> {
    let cores = allowed();
    let pin = threads as usize == cores.len() && threads > 1;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads as usize)
        .start_handler(move |i| {
            if pin && let Some(&core) = cores.get(i) {
                // A refusal leaves the thread to the scheduler, as an unpinned pool.
                let _ = core_affinity::set_for_current(core);
            }
        })
        .build()
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pool_over_every_core_has_one_thread_on_each() {
        let n = cores();
        let pool = build(n).expect("the system gives the threads");
        let seen: Vec<Vec<usize>> =
            pool.broadcast(|_| core_affinity::get_core_ids().unwrap_or_default().into_iter().map(|c| c.id).collect());
        assert_eq!(seen.len(), n as usize);
        if n > 1 && allowed().len() == n as usize {
            let mut pinned: Vec<usize> = seen.iter().map(|c| *c.first().expect("a core")).collect();
            assert!(seen.iter().all(|c| c.len() == 1), "each thread on one core: {seen:?}");
            pinned.sort_unstable();
            pinned.dedup();
            assert_eq!(pinned.len(), n as usize, "no two threads on one core: {seen:?}");
        }
        // A smaller pool is left to the scheduler.
        if n > 2 {
            let small = build(2).expect("the system gives the threads");
            let seen: Vec<usize> = small.broadcast(|_| core_affinity::get_core_ids().unwrap_or_default().len());
            assert!(seen.iter().all(|&c| c == allowed().len()), "{seen:?}");
        }
    }
}
