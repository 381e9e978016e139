//! Whether a frame runs on the team or on one thread: a team frame whose threads slept at many
//! waits (the cores may be busy with other work) is checked against one frame on one thread.

use std::time::Duration;

/// Frames run on one thread once one thread was found faster than the team.
const ALONE_FRAMES: u32 = 30;

/// Frames the team runs unchecked once it was found faster than one thread.
const TRUSTED_FRAMES: u32 = 120;

/// How the next frame runs: the team, unless a suspect team frame (see `team::BUSY_FRACTION`) was
/// followed by a faster frame on one thread. The positions are the same either way; only the
/// time changes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) enum Choice {
    /// The team, checked after each frame.
    #[default]
    Team,
    /// One frame on one thread, to compare with the suspect team frame's time.
    Check(Duration),
    /// One thread for this many more frames.
    Alone(u32),
    /// The team, unchecked for this many more frames.
    Trusted(u32),
}

impl Choice {
    /// `true` when the next frame runs on the team.
    pub fn team(self) -> bool {
        matches!(self, Choice::Team | Choice::Trusted(_))
    }

    /// The choice after a frame that took `time`; `busy`: a team frame that slept at many
    /// barriers.
    pub fn next(self, time: Duration, busy: bool) -> Choice {
        match self {
            Choice::Team if busy => Choice::Check(time),
            Choice::Team | Choice::Trusted(1) | Choice::Alone(1) => Choice::Team,
            Choice::Trusted(n) => Choice::Trusted(n - 1),
            Choice::Alone(n) => Choice::Alone(n - 1),
            Choice::Check(team) if time < team => Choice::Alone(ALONE_FRAMES),
            Choice::Check(_) => Choice::Trusted(TRUSTED_FRAMES),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_suspect_team_frame_is_checked_against_one_thread() {
        let ms = Duration::from_millis;
        assert_eq!(Choice::Team.next(ms(10), false), Choice::Team);
        let check = Choice::Team.next(ms(36), true);
        assert_eq!(check, Choice::Check(ms(36)));
        assert!(!check.team());
        // One thread was faster: it keeps the frames for a while, then the team is tried again.
        let mut c = check.next(ms(17), false);
        assert_eq!(c, Choice::Alone(ALONE_FRAMES));
        for _ in 0..ALONE_FRAMES {
            assert!(!c.team());
            c = c.next(ms(17), false);
        }
        assert_eq!(c, Choice::Team);
        // The team was faster (long groups, not busy cores): it runs unchecked for a while.
        let mut c = Choice::Check(ms(160)).next(ms(260), false);
        assert_eq!(c, Choice::Trusted(TRUSTED_FRAMES));
        for _ in 0..TRUSTED_FRAMES {
            assert!(c.team());
            c = c.next(ms(160), true);
        }
        assert_eq!(c, Choice::Team);
    }
}
