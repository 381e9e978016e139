//! Frame timing: warm-up, then the median of many frames within a time budget.

use std::time::Instant;

/// How long to time one configuration: frame counts and wall-clock limits, so that a cloth of a
/// million constraints gets a few frames and a small one a few hundred.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    /// Warm-up frames at most (at least one is run).
    pub warm_frames: u32,
    /// Warm-up stops after this many seconds.
    pub warm_seconds: f64,
    /// Measured frames at most.
    pub frames: u32,
    /// Measured frames at least, whatever the time.
    pub min_frames: u32,
    /// Measuring stops after this many seconds (once `min_frames` are in).
    pub seconds: f64,
}

/// The measured frames of one configuration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Timing {
    /// Frames measured (after the warm-up).
    pub frames: u32,
    /// Median wall time of one frame (ms).
    pub median_ms: f64,
}

/// Runs `frame` through the warm-up and the measured frames of `b`; each call is one whole frame,
/// waited for.
pub fn time_frames(b: &Budget, mut frame: impl FnMut() -> anyhow::Result<()>) -> anyhow::Result<Timing> {
    warm_up(b, &mut frame)?;
    let start = Instant::now();
    let mut t = Vec::with_capacity(b.frames as usize);
    while (t.len() as u32) < b.frames.max(1) {
        if t.len() as u32 >= b.min_frames.max(1) && start.elapsed().as_secs_f64() >= b.seconds {
            break;
        }
        let t0 = Instant::now();
        frame()?;
        t.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    Ok(Timing { frames: t.len() as u32, median_ms: median(&mut t) })
}

/// The warm-up of `b`: at least one frame, at most `b.warm_frames` or `b.warm_seconds`.
fn warm_up(b: &Budget, frame: &mut impl FnMut() -> anyhow::Result<()>) -> anyhow::Result<()> {
    let start = Instant::now();
    for i in 0..b.warm_frames.max(1) {
        if i > 0 && start.elapsed().as_secs_f64() >= b.warm_seconds {
            break;
        }
        frame()?;
    }
    Ok(())
}

/// Frames of one configuration run back to back before the next takes its turn, at most.
pub const BLOCK_FRAMES: usize = 40;
/// A turn ends early after this long (s), so a slow configuration does not hold the others off.
const BLOCK_SECONDS: f64 = 1.0;
/// Frames run unmeasured at the start of every turn after the first: a team whose cores were
/// idle during another configuration's turn starts slowly.
pub const TURN_WARM_FRAMES: usize = 2;

/// Times several configurations of one case in turn, [`BLOCK_FRAMES`] frames (or
/// [`BLOCK_SECONDS`]) each, round after round, so that a change in the machine's speed during the
/// measurement (a virtual machine's host at work) falls on all of them alike: each warms up as
/// in [`time_frames`], then every configuration takes its turns (each turn after the first
/// opening with [`TURN_WARM_FRAMES`] unmeasured frames) until each has `b.frames`, or until each
/// has `b.min_frames` and `b.seconds` per configuration have passed. Returns one timing per
/// configuration, in order.
pub fn time_interleaved(b: &Budget, frames: &mut [impl FnMut() -> anyhow::Result<()>]) -> anyhow::Result<Vec<Timing>> {
    for frame in frames.iter_mut() {
        warm_up(b, frame)?;
    }
    let (want, least) = (b.frames.max(1) as usize, b.min_frames.max(1) as usize);
    let limit = b.seconds * frames.len() as f64;
    let start = Instant::now();
    let mut t: Vec<Vec<f64>> = frames.iter().map(|_| Vec::with_capacity(want)).collect();
    loop {
        let done = |t: &Vec<Vec<f64>>| {
            t.iter().all(|t| t.len() >= want)
                || (t.iter().all(|t| t.len() >= least) && start.elapsed().as_secs_f64() >= limit)
        };
        if done(&t) {
            break;
        }
        for (frame, t) in frames.iter_mut().zip(&mut t) {
            if !t.is_empty() && t.len() < want {
                for _ in 0..TURN_WARM_FRAMES {
                    frame()?;
                }
            }
            let turn = Instant::now();
            for _ in 0..BLOCK_FRAMES {
                let enough = turn.elapsed().as_secs_f64() >= BLOCK_SECONDS || start.elapsed().as_secs_f64() >= limit;
                if t.len() >= want || (t.len() >= least && enough) {
                    break;
                }
                let t0 = Instant::now();
                frame()?;
                t.push(t0.elapsed().as_secs_f64() * 1e3);
            }
        }
    }
    Ok(t.iter_mut().map(|t| Timing { frames: t.len() as u32, median_ms: median(t) }).collect())
}

/// The median of `t` (the mean of the two middle values for an even count; NaN when empty).
pub fn median(t: &mut [f64]) -> f64 {
    if t.is_empty() {
        return f64::NAN;
    }
    t.sort_by(f64::total_cmp);
    let m = t.len() / 2;
    if t.len() % 2 == 1 { t[m] } else { 0.5 * (t[m - 1] + t[m]) }
}

#[cfg(test)]
mod tests {
    use std::cell::RefCell;

    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&mut []).is_nan());
    }

    #[test]
    fn budget_bounds_the_frame_count() {
        // Frames measured and frames run (warm-up included) under budget `b`.
        let counts = |b: &Budget| {
            let mut calls = 0;
            let t = time_frames(b, || {
                calls += 1;
                Ok(())
            })
            .unwrap();
            (t.frames, calls)
        };
        let b = Budget { warm_frames: 3, warm_seconds: 10.0, frames: 7, min_frames: 2, seconds: 10.0 };
        assert_eq!(counts(&b), (7, 10));
        // A zero time limit still measures `min_frames`.
        assert_eq!(counts(&Budget { seconds: 0.0, warm_seconds: 0.0, ..b }), (2, 3));
    }

    /// A frame that only writes `name` to `log`.
    fn recorder(log: &RefCell<Vec<char>>, name: char) -> impl FnMut() -> anyhow::Result<()> + '_ {
        move || {
            log.borrow_mut().push(name);
            Ok(())
        }
    }

    #[test]
    fn interleaved_configurations_take_turns_in_blocks() {
        let b = Budget { warm_frames: 2, warm_seconds: 10.0, frames: 25, min_frames: 2, seconds: 10.0 };
        let log = RefCell::new(Vec::new());
        let (mut a, mut c) = (recorder(&log, 'a'), recorder(&log, 'c'));
        let t = time_interleaved(&b, &mut [&mut a, &mut c]).unwrap();
        assert_eq!(t.iter().map(|t| t.frames).collect::<Vec<_>>(), [25, 25]);
        let log: String = log.borrow().iter().collect();
        // Warm-up of each, then turns of (up to) 40 frames until each has its 25.
        assert_eq!(log, ["aa", "cc", &"a".repeat(25), &"c".repeat(25)].concat());
        // With 50 wanted, the second turns open with two unmeasured frames.
        let b = Budget { frames: 50, ..b };
        let log = RefCell::new(Vec::new());
        let (mut a, mut c) = (recorder(&log, 'a'), recorder(&log, 'c'));
        time_interleaved(&b, &mut [&mut a, &mut c]).unwrap();
        let log: String = log.borrow().iter().collect();
        let turns = ["aa", "cc", &"a".repeat(40), &"c".repeat(40), &"a".repeat(12), &"c".repeat(12)];
        assert_eq!(log, turns.concat());
        // A zero time limit measures `min_frames` of each.
        let b = Budget { seconds: 0.0, warm_seconds: 0.0, ..b };
        let log = RefCell::new(Vec::new());
        let (mut a, mut c) = (recorder(&log, 'a'), recorder(&log, 'c'));
        let t = time_interleaved(&b, &mut [&mut a, &mut c]).unwrap();
        let log: String = log.borrow().iter().collect();
        assert_eq!((t[0].frames, t[1].frames, log.as_str()), (2, 2, "acaacc"));
    }
}
