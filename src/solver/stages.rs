//! The stage list: one frame of the solver as the ordered stages every backend runs
//! (docs/algorithm.md §1). The CPU solver executes it ([`super::CpuSolver`]), the GPU solver
//! encodes it ([`crate::gpu::GpuSolver`]), and what is counted from it (the GPU's dispatches per
//! frame) is derived from it rather than kept by hand.
//!
//! A backend may run two adjacent stages in one visit of each particle when that gives the same
//! bits as running them one after the other: the CPU's finish pass makes the next substep's
//! prediction when [`Stage::Predict`] follows [`Stage::Finish`] directly (every mode but the
//! global balance, whose [`Stage::Balance`] comes between), and the finish pass makes the last
//! iteration's contact pass on both backends (so the list has no [`Stage::Contacts`] after the
//! last iteration).

use crate::scene::{FAMILY_COUNT, Scene};

use super::energy::EnergyAware;
use super::{Method, Settings};

/// One stage of a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// The energy-momentum projection's starting budget, before the first substep
    /// ([`EnergyAware::Project`] on a solver whose budget has not started).
    ProjectionStart,
    /// The global balance's starting energy, before the first substep ([`EnergyAware::Global`]
    /// on a solver that carries none).
    BalanceStart,
    /// `x_prev = x`, `v += h g`, `x += h v` (free particles).
    Predict,
    /// Every family's multipliers to zero.
    Clear,
    /// The local mode's snapshots and every element's energy at the substep's start.
    LocalBegin,
    /// The local mode's snapshot of the last iterate (each iteration after the first).
    LocalSnapshot,
    /// Gauss-Seidel over color group `color` of family `family` (index as in
    /// [`crate::for_each_family`]).
    Sweep {
        /// The family.
        family: usize,
        /// The color group, in solve order.
        color: usize,
    },
    /// One Jacobi iteration: every family's scaled corrections against the same iterate, then
    /// each particle adds up its own.
    Jacobi,
    /// The self-collision's check of its references at the predicted positions, renewing those
    /// that strayed and their candidate pairs ([`crate::scene::SelfCollision`]).
    SelfPairs,
    /// The self-collision's projection of its candidate pairs (every iteration, after the
    /// sweeps).
    SelfCollision,
    /// The contact projection (every iteration but the last).
    Contacts,
    /// The last iteration's contact pass, `v = (x − x_prev) / h`, the velocity damping and the
    /// substep's dissipated work.
    Finish,
    /// The global balance: scales the velocities to the energy carried from the last substep.
    Balance,
    /// The energy-momentum projection, after the last substep.
    Projection,
}

/// What a solver knows at the start of a frame that changes the list: stages run only when the
/// solver's own state asks for them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FrameStart {
    /// The projection's budget has yet to start ([`Stage::ProjectionStart`]).
    pub projection_start: bool,
    /// The global balance carries no energy yet ([`Stage::BalanceStart`]).
    pub balance_start: bool,
    /// The scene's cloth collides with itself ([`Stage::SelfPairs`], [`Stage::SelfCollision`]).
    pub self_collision: bool,
}

/// The color groups of each family of `scene` (0 where it has none), the shape of a frame's
/// sweeps.
pub fn color_counts(scene: &Scene) -> [usize; FAMILY_COUNT] {
    let mut colors = [0; FAMILY_COUNT];
    crate::for_each_family!(scene, |i, f| colors[i] = f.colors.len());
    colors
}

/// The stages of one frame at `s` over families with `colors` color groups each
/// ([`color_counts`]), in order.
pub fn frame(colors: &[usize; FAMILY_COUNT], s: &Settings, start: FrameStart) -> Vec<Stage> {
    let mut out = Vec::new();
    frame_into(&mut out, colors, s, start);
    out
}

/// [`frame`] into `out` (cleared first; no allocation once it has held as long a list).
pub fn frame_into(out: &mut Vec<Stage>, colors: &[usize; FAMILY_COUNT], s: &Settings, start: FrameStart) {
    out.clear();
    let (local, global) = (s.energy_aware == EnergyAware::Local, s.energy_aware == EnergyAware::Global);
    let project = s.energy_aware == EnergyAware::Project;
    if project && start.projection_start {
        out.push(Stage::ProjectionStart);
    }
    if global && start.balance_start {
        out.push(Stage::BalanceStart);
    }
    for _ in 0..s.substeps {
        out.extend([Stage::Predict, Stage::Clear]);
        if start.self_collision {
            out.push(Stage::SelfPairs);
        }
        if local {
            out.push(Stage::LocalBegin);
        }
        for iteration in 0..s.iterations {
            if local && iteration > 0 {
                out.push(Stage::LocalSnapshot);
            }
            match s.method {
                Method::GaussSeidel => {
                    for (family, &n) in colors.iter().enumerate() {
                        out.extend((0..n).map(|color| Stage::Sweep { family, color }));
                    }
                }
                Method::Jacobi => out.push(Stage::Jacobi),
            }
            if start.self_collision {
                out.push(Stage::SelfCollision);
            }
            if s.contacts_in_loop(iteration) {
                out.push(Stage::Contacts);
            }
        }
        out.push(Stage::Finish);
        if global {
            out.push(Stage::Balance);
        }
    }
    if project {
        out.push(Stage::Projection);
    }
}

/// The range of `stages` that holds the substeps (from the first [`Stage::Predict`] to the last
/// [`Stage::Finish`] or [`Stage::Balance`]); the stages before and after it run once a frame.
pub fn substeps(stages: &[Stage]) -> std::ops::Range<usize> {
    let first = stages.iter().position(|s| *s == Stage::Predict).unwrap_or(stages.len());
    let last = stages.iter().rposition(|s| matches!(s, Stage::Finish | Stage::Balance)).map_or(first, |i| i + 1);
    first..last.max(first)
}

/// `true` when the stage at `i` of `stages` is a [`Stage::Finish`] directly followed by a
/// [`Stage::Predict`], which the CPU's finish pass then makes in the same visit of each particle.
pub fn finish_predicts(stages: &[Stage], i: usize) -> bool {
    stages[i] == Stage::Finish && stages.get(i + 1) == Some(&Stage::Predict)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_lists_its_substeps_in_order() {
        let s = Settings { substeps: 2, iterations: 2, ..Settings::default() };
        let stages = frame(&[2, 1, 0, 0], &s, FrameStart::default());
        use Stage::*;
        let sweeps = [Sweep { family: 0, color: 0 }, Sweep { family: 0, color: 1 }, Sweep { family: 1, color: 0 }];
        let substep: Vec<Stage> =
            [&[Predict, Clear][..], &sweeps, &[Contacts], &sweeps, &[Finish]].into_iter().flatten().copied().collect();
        assert_eq!(stages, [substep.clone(), substep].concat());
        assert!(finish_predicts(&stages, substep_len(&stages) - 1));
        assert!(!finish_predicts(&stages, stages.len() - 1));
        assert_eq!(substeps(&stages), 0..stages.len());
    }

    fn substep_len(stages: &[Stage]) -> usize {
        stages.iter().position(|s| *s == Stage::Finish).expect("a finish") + 1
    }

    #[test]
    fn the_global_balance_keeps_finish_and_predict_apart() {
        let s = Settings { substeps: 2, iterations: 1, energy_aware: EnergyAware::Global, ..Settings::default() };
        let stages =
            frame(&[1, 0, 0, 0], &s, FrameStart { balance_start: true, projection_start: true, self_collision: false });
        assert_eq!(stages[0], Stage::BalanceStart);
        assert!((0..stages.len()).all(|i| !finish_predicts(&stages, i)));
        assert_eq!(stages.iter().filter(|s| **s == Stage::Balance).count(), 2);
        assert!(!stages.contains(&Stage::Contacts), "one iteration: its contact pass is the finish's");
    }

    #[test]
    fn local_jacobi_and_projection_stages() {
        let s = Settings {
            substeps: 1,
            iterations: 3,
            method: Method::Jacobi,
            energy_aware: EnergyAware::Local,
            ..Settings::default()
        };
        use Stage::*;
        let want = [
            Predict,
            Clear,
            LocalBegin,
            Jacobi,
            Contacts,
            LocalSnapshot,
            Jacobi,
            Contacts,
            LocalSnapshot,
            Jacobi,
            Finish,
        ];
        assert_eq!(frame(&[3, 0, 0, 0], &s, FrameStart::default()), want);
        let s = Settings { substeps: 1, iterations: 1, energy_aware: EnergyAware::Project, ..Settings::default() };
        let start = FrameStart { projection_start: true, balance_start: true, self_collision: false };
        let stages = frame(&[0; 4], &s, start);
        assert_eq!(stages, [ProjectionStart, Predict, Clear, Finish, Projection]);
        assert_eq!(substeps(&stages), 1..4);
    }
}
