//! The statistics history behind the live plots: the last few hundred measured frames.

use std::collections::VecDeque;

use crate::metrics::FrameStats;

/// Frames kept for the plots.
pub const HISTORY_LEN: usize = 600;

/// One measured frame as plotted.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Sample {
    /// Frame number since the last reset.
    pub frame: u32,
    /// Kinetic energy (J).
    pub kinetic: f64,
    /// Elastic energy the constraint forces hold (J).
    pub elastic: f64,
    /// The iterate's elastic energy that no constraint force holds (J): unresolved stretch,
    /// not part of the total.
    pub unresolved: f64,
    /// Gravitational energy, heights from the ground (J).
    pub gravitational: f64,
    /// Kinetic + gravitational + held elastic (J).
    pub total: f64,
    /// RMS of the XPBD residual `|C + α̃λ|`.
    pub residual: f64,
}

impl From<&FrameStats> for Sample {
    fn from(s: &FrameStats) -> Self {
        Sample {
            frame: s.frame,
            kinetic: s.kinetic,
            elastic: s.elastic,
            unresolved: s.unresolved,
            gravitational: s.gravitational,
            total: s.total(),
            residual: s.residual_rms,
        }
    }
}

/// A bounded history of samples, oldest first.
#[derive(Clone, Debug, Default)]
pub struct History {
    samples: VecDeque<Sample>,
}

impl History {
    /// Appends a sample, dropping the oldest beyond [`HISTORY_LEN`]. A sample of the last
    /// frame again (paused) replaces it; an earlier frame starts a new history (a reset).
    pub fn push(&mut self, s: Sample) {
        if let Some(last) = self.samples.back_mut() {
            if s.frame == last.frame {
                *last = s;
                return;
            }
            if s.frame < last.frame {
                self.samples.clear();
            }
        }
        if self.samples.len() == HISTORY_LEN {
            self.samples.pop_front();
        }
        self.samples.push_back(s);
    }

    /// Forgets every sample.
    pub fn clear(&mut self) {
        self.samples.clear();
    }

    /// The samples, oldest first.
    pub fn samples(&self) -> impl ExactSizeIterator<Item = &Sample> {
        self.samples.iter()
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// `true` when there is no sample.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// `(frame, value)` points of one quantity.
    pub fn series(&self, value: impl Fn(&Sample) -> f64) -> Vec<[f64; 2]> {
        self.samples.iter().map(|s| [s.frame as f64, value(s)]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn history_is_bounded_and_restarts_after_a_reset() {
        let mut h = History::default();
        for f in 1..=(HISTORY_LEN as u32 + 10) {
            h.push(Sample { frame: f, total: f as f64, ..Sample::default() });
        }
        assert_eq!(h.len(), HISTORY_LEN);
        assert_eq!(h.samples().next().unwrap().frame, 11);
        h.push(Sample { frame: HISTORY_LEN as u32 + 10, total: -1.0, ..Sample::default() });
        assert_eq!(h.len(), HISTORY_LEN, "the same frame again replaces the last sample");
        assert_eq!(h.samples().last().unwrap().total, -1.0);
        h.push(Sample { frame: 1, ..Sample::default() });
        assert_eq!(h.len(), 1);
        assert_eq!(h.series(|s| s.total), vec![[1.0, 0.0]]);
    }
}
