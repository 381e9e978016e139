//! Whether a frame runs on the team or on one thread. A team frame is checked against one frame
//! on one thread at the start, again after every [`TRUSTED_FRAMES`] frames the team ran
//! unchecked, and at once after a team frame whose threads slept at many waits (the cores may be
//! busy with other work) or waited longer than they worked; a faster frame on one thread is
//! checked against one more team frame (the team frame may only have met the host taking a core
//! away for a while). Where the team loses (cores busy with other work, or small groups on cores
//! whose every meeting costs more than the work it splits) the frames run on one thread.

use std::time::Duration;

/// Frames run on one thread once one thread was found faster than the team.
const ALONE_FRAMES: u32 = 30;

/// Frames the team runs unchecked once it was found faster than one thread.
const TRUSTED_FRAMES: u32 = 120;

/// How the next frame runs: the team, unless a checked team frame was followed by a faster frame
/// on one thread, and that by a team frame slower than it. The positions are the same either way;
/// only the time changes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) enum Choice {
    /// The team, for one frame that is then checked.
    #[default]
    Team,
    /// One frame on one thread, to compare with the checked team frame's time.
    Check(Duration),
    /// One more team frame, to compare with the faster frame on one thread (its time): a team
    /// frame slowed by one stall of the host's is followed by a normal one, while cores busy
    /// with other work slow the next one too.
    Retry(Duration),
    /// One thread for this many more frames.
    Alone(u32),
    /// The team, unchecked for this many more frames.
    Trusted(u32),
}

impl Choice {
    /// `true` when the next frame runs on the team.
    pub fn team(self) -> bool {
        matches!(self, Choice::Team | Choice::Retry(_) | Choice::Trusted(_))
    }

    /// The choice after a frame that took `time`; `busy`: a team frame whose threads slept at
    /// many waits (see `team::BUSY_FRACTION`) or waited longer than they worked.
    pub fn next(self, time: Duration, busy: bool) -> Choice {
        match self {
            Choice::Team => Choice::Check(time),
            Choice::Trusted(_) if busy => Choice::Check(time),
            Choice::Trusted(1) | Choice::Alone(1) => Choice::Team,
            Choice::Trusted(n) => Choice::Trusted(n - 1),
            Choice::Alone(n) => Choice::Alone(n - 1),
            Choice::Check(team) if time < team => Choice::Retry(time),
            Choice::Check(_) => Choice::Trusted(TRUSTED_FRAMES),
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
        // Every team frame in the `Team` state is checked, busy or not.
        assert_eq!(Choice::Team.next(ms(10), false), Choice::Check(ms(10)));
        let check = Choice::Team.next(ms(36), true);
        assert_eq!(check, Choice::Check(ms(36)));
        assert!(!check.team());
        // One thread was faster: the team runs one more frame; slower again, one thread keeps
        // the frames for a while, then the team is tried again.
        let retry = check.next(ms(17), false);
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
        assert_eq!(c.next(ms(160), false), Choice::Check(ms(160)));
        // A team frame that slept at many waits is checked at once, trusted or not.
        assert_eq!(Choice::Trusted(50).next(ms(40), true), Choice::Check(ms(40)));
    }
}
