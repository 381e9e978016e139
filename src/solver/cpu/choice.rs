//! Whether a frame runs on the team or on one thread. A team frame is checked against one frame
//! on one thread after the first [`COLD_FRAMES`] of a run, again after every [`TRUSTED_FRAMES`]
//! frames the team ran unchecked, and at once after a team frame whose threads slept at many
//! waits (the cores may be busy with other work) or waited longer than they worked; a faster
//! frame on one thread is checked against one more team frame (the team frame may only have met
//! the host taking a core away for a while). Where the team loses (cores busy with other work,
//! small groups on cores whose every meeting costs more than the work it splits, or cores that
//! pass a cache line to each other slowly) the frames run on one thread.
//!
//! The frame that follows a switch, from the team to one thread or back, is not timed for the
//! comparison: it pays for moving the particles into the other core's cache, as the first frames
//! of a run pay for cold caches and cores still speeding up. Compared, such frames kept the team
//! for 120 frames on a host where it took 2.4 ms a frame against 1.45 ms on one thread: the
//! first team frame took 4.9 ms, the first frame on one thread 4.7 ms and the second team frame
//! 4.4 ms.

use std::time::Duration;

/// The first frames of a solver, run on the team and not compared (cold caches, cores still
/// speeding up: the bunny's first ten frames on two threads took 1.5–5 times the later ones).
const COLD_FRAMES: u32 = 10;

/// Frames run on one thread once one thread was found faster than the team: a check of the team
/// takes three team frames (two of them after a switch), so a losing team then runs about one
/// frame in twenty.
const ALONE_FRAMES: u32 = 60;

/// Frames the team runs unchecked once it was found faster than one thread.
const TRUSTED_FRAMES: u32 = 120;

/// How the next frame runs: the team, unless a checked team frame was followed by a faster frame
/// on one thread, and that by a team frame slower than it. The positions are the same either way;
/// only the time changes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Choice {
    /// The team, for one frame that is then checked.
    Team,
    /// One frame on one thread after the checked team frame (its time), not compared.
    Settle(Duration),
    /// One frame on one thread, to compare with the checked team frame's time.
    Check(Duration),
    /// One team frame after the faster frame on one thread (its time), not compared.
    SettleRetry(Duration),
    /// One more team frame, to compare with the faster frame on one thread (its time): a team
    /// frame slowed by one stall of the host's is followed by a normal one, while cores busy
    /// with other work slow the next one too.
    Retry(Duration),
    /// One thread for this many more frames.
    Alone(u32),
    /// The team, unchecked for this many more frames.
    Trusted(u32),
}

impl Default for Choice {
    /// The team, unchecked for the first [`COLD_FRAMES`].
    fn default() -> Self {
        Choice::Trusted(COLD_FRAMES)
    }
}

impl Choice {
    /// `true` when the next frame runs on the team.
    pub fn team(self) -> bool {
        matches!(self, Choice::Team | Choice::SettleRetry(_) | Choice::Retry(_) | Choice::Trusted(_))
    }

    /// The choice after a frame that took `time`; `busy`: a team frame whose threads slept at
    /// many waits (see `team::BUSY_FRACTION`) or waited longer than they worked.
    pub fn next(self, time: Duration, busy: bool) -> Choice {
        match self {
            Choice::Team => Choice::Settle(time),
            Choice::Trusted(_) if busy => Choice::Settle(time),
            Choice::Trusted(1) | Choice::Alone(1) => Choice::Team,
            Choice::Trusted(n) => Choice::Trusted(n - 1),
            Choice::Alone(n) => Choice::Alone(n - 1),
            Choice::Settle(team) => Choice::Check(team),
            Choice::Check(team) if time < team => Choice::SettleRetry(time),
            Choice::Check(_) => Choice::Trusted(TRUSTED_FRAMES),
            Choice::SettleRetry(alone) => Choice::Retry(alone),
            Choice::Retry(alone) if time > alone => Choice::Alone(ALONE_FRAMES),
            Choice::Retry(_) => Choice::Trusted(TRUSTED_FRAMES),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_team_frame_is_checked_against_one_thread() {
        let ms = Duration::from_millis;
        // Every team frame in the `Team` state is checked, busy or not, after one frame on one
        // thread that is not compared.
        assert_eq!(Choice::Team.next(ms(10), false), Choice::Settle(ms(10)));
        let settle = Choice::Team.next(ms(36), true);
        assert_eq!(settle, Choice::Settle(ms(36)));
        assert!(!settle.team());
        let check = settle.next(ms(90), false);
        assert_eq!(check, Choice::Check(ms(36)), "the frame after the switch is not compared");
        assert!(!check.team());
        // One thread was faster: the team runs two more frames, the second compared; slower
        // again, one thread keeps the frames for a while, then the team is tried again.
        let settle_retry = check.next(ms(17), false);
        assert_eq!(settle_retry, Choice::SettleRetry(ms(17)));
        assert!(settle_retry.team());
        let retry = settle_retry.next(ms(90), false);
        assert_eq!(retry, Choice::Retry(ms(17)));
        assert!(retry.team());
        let mut c = retry.next(ms(30), false);
        assert_eq!(c, Choice::Alone(ALONE_FRAMES));
        for _ in 0..ALONE_FRAMES {
            assert!(!c.team());
            c = c.next(ms(17), false);
        }
        assert_eq!(c, Choice::Team);
        // The retried team frame was faster than one thread (the checked frame met one stall of
        // the host's): the team runs unchecked for a while.
        assert_eq!(Choice::Retry(ms(8)).next(ms(5), false), Choice::Trusted(TRUSTED_FRAMES));
        // The team was faster: it runs unchecked for a while, then is checked again.
        let mut c = Choice::Check(ms(160)).next(ms(260), false);
        assert_eq!(c, Choice::Trusted(TRUSTED_FRAMES));
        for _ in 0..TRUSTED_FRAMES {
            assert!(c.team());
            c = c.next(ms(160), false);
        }
        assert_eq!(c, Choice::Team);
        assert_eq!(c.next(ms(160), false), Choice::Settle(ms(160)));
        // A team frame that slept at many waits is checked at once, trusted or not.
        assert_eq!(Choice::Trusted(50).next(ms(40), true), Choice::Settle(ms(40)));
    }

    /// The frames of a run on a host as measured (µs): the first three cold, then `team` or
    /// `alone` a frame, and a frame just after a switch 1 ms slower. Returns the team's frames.
    fn team_frames(team: u64, alone: u64, frames: usize) -> usize {
        let (mut c, mut last, mut count) = (Choice::default(), None, 0);
        for frame in 0..frames {
            let on_team = c.team();
            let mut t = if on_team { team } else { alone };
            if frame < 3 {
                t = 4_700;
            } else if last.is_some_and(|l| l != on_team) {
                t += 1_000;
            }
            count += usize::from(on_team);
            last = Some(on_team);
            c = c.next(Duration::from_micros(t), false);
        }
        count
    }

    /// Where the team is slower, most frames run on one thread, the cold first frames and the
    /// frames after a switch notwithstanding (they kept a 2.4 ms team against 1.45 ms on one
    /// thread when compared); where it is faster, most run on the team.
    #[test]
    fn cold_frames_and_switches_do_not_decide() {
        let slow_team = team_frames(2_450, 1_450, 300);
        assert!(slow_team <= 30, "a slower team ran {slow_team} of 300 frames");
        let fast_team = team_frames(850, 1_450, 300);
        assert!(fast_team >= 280, "a faster team ran {fast_team} of 300 frames");
    }
}
