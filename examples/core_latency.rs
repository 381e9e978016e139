//! How long one core takes to see a value another core wrote: two threads pass a counter back and
//! forth through two cache lines, and the time of a round trip over two is the one-way latency (ns)
//! that every meeting of the CPU team's threads pays at least once (`solver::cpu::plan`). On a
//! virtual machine it changes with where the host puts the two virtual cores (this project's
//! 2-core VM has shown 27 to 440 ns within an hour), so figures for two threads are quoted with
//! it (`docs/bench/compare_builds.sh`).
//!
//! `cargo run --release --example core_latency [round trips]` (default 1,000,000).

use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// A counter on a cache line of its own.
#[repr(align(128))]
struct Line(AtomicU64);

fn main() {
    let trips: u64 = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(1_000_000).max(1);
    let (ping, pong) = (Line(AtomicU64::new(0)), Line(AtomicU64::new(0)));
    let elapsed = std::thread::scope(|s| {
        s.spawn(|| {
            for i in 1..=trips {
                while ping.0.load(Ordering::Acquire) < i {
                    std::hint::spin_loop();
                }
                pong.0.store(i, Ordering::Release);
            }
        });
        let start = Instant::now();
        for i in 1..=trips {
            ping.0.store(i, Ordering::Release);
            while pong.0.load(Ordering::Acquire) < i {
                std::hint::spin_loop();
            }
        }
        start.elapsed()
    });
    let round_trip = elapsed.as_secs_f64() * 1e9 / trips as f64;
    println!(
        "core-to-core latency: {:.1} ns one way ({round_trip:.1} ns a round trip, {trips} round trips)",
        round_trip / 2.0
    );
}
