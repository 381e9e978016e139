//! Where the team's threads spend a frame: working, or waiting for one another (at the barriers
//! around the per-substep passes and before the boundary parts of the color groups, [`super::plan`]).
//! The waits are what a frame on several threads loses to its synchronization and to cores that
//! run at different speeds or are taken away by the host.

use std::time::Duration;

/// The team's time, summed over its frames since the solver was made or
/// [`super::CpuSolver::reset_team_time`] was called.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TeamTime {
    /// Frames run on the team (frames run on one thread are not counted).
    pub frames: u32,
    /// Per thread: its time in the team's frames less its waits.
    pub busy: Vec<Duration>,
    /// Per thread: its time spent waiting for the other threads.
    pub waited: Vec<Duration>,
    /// Per thread: the part of `waited` spent at the team's barriers around the per-substep
    /// passes (the rest went to waits before the boundary parts of the steps).
    pub at_barriers: Vec<Duration>,
}

impl TeamTime {
    /// Adds one team frame: `(busy, waited, at barriers)` per thread.
    pub(super) fn add(&mut self, threads: impl ExactSizeIterator<Item = (Duration, Duration, Duration)>) {
        if self.busy.len() != threads.len() {
            let zero = vec![Duration::ZERO; threads.len()];
            *self = TeamTime { frames: 0, busy: zero.clone(), waited: zero.clone(), at_barriers: zero };
        }
        let sums = self.busy.iter_mut().zip(&mut self.waited).zip(&mut self.at_barriers);
        for (((busy, waited), at_barriers), (b, w, a)) in sums.zip(threads) {
            *busy += b;
            *waited += w;
            *at_barriers += a;
        }
        self.frames += 1;
    }

    /// Every sum back to zero, for as many threads.
    pub(super) fn clear(&mut self) {
        self.frames = 0;
        self.busy.fill(Duration::ZERO);
        self.waited.fill(Duration::ZERO);
        self.at_barriers.fill(Duration::ZERO);
    }

    /// The fraction of the threads' time spent waiting, `Σ waited / Σ (busy + waited)` over the
    /// threads (0 before any team frame).
    pub fn wait_fraction(&self) -> f64 {
        let waited: Duration = self.waited.iter().sum();
        let total = waited + self.busy.iter().sum::<Duration>();
        match total.is_zero() {
            true => 0.0,
            false => waited.as_secs_f64() / total.as_secs_f64(),
        }
    }

    /// The share of the threads' waiting time spent at the barriers, `Σ at_barriers / Σ waited`
    /// (0 without waits).
    pub fn barrier_fraction(&self) -> f64 {
        let waited: Duration = self.waited.iter().sum();
        match waited.is_zero() {
            true => 0.0,
            false => self.at_barriers.iter().sum::<Duration>().as_secs_f64() / waited.as_secs_f64(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_add_up_per_thread() {
        let ms = Duration::from_millis;
        let mut t = TeamTime::default();
        assert_eq!((t.wait_fraction(), t.barrier_fraction()), (0.0, 0.0));
        t.add([(ms(3), ms(1), ms(1)), (ms(4), ms(0), ms(0))].into_iter());
        t.add([(ms(3), ms(1), ms(0)), (ms(2), ms(2), ms(1))].into_iter());
        assert_eq!(t.frames, 2);
        assert_eq!(t.busy, [ms(6), ms(6)]);
        assert_eq!(t.waited, [ms(2), ms(2)]);
        assert_eq!(t.at_barriers, [ms(1), ms(1)]);
        assert!((t.wait_fraction() - 0.25).abs() < 1e-12);
        assert!((t.barrier_fraction() - 0.5).abs() < 1e-12);
        // Another thread count starts the sums again.
        let one = (ms(1), ms(1), ms(0));
        t.add([one, one, one].into_iter());
        assert_eq!((t.frames, t.busy.len(), t.at_barriers.len()), (1, 3, 3));
        assert!((t.wait_fraction() - 0.5).abs() < 1e-12);
        assert_eq!(t.barrier_fraction(), 0.0);
        t.clear();
        assert_eq!((t.frames, t.busy.len(), t.wait_fraction(), t.barrier_fraction()), (0, 3, 0.0, 0.0));
    }
}
