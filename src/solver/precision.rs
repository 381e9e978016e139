//! Whether `f32` positions resolve a substep's motion. A substep moves a particle that starts
//! from rest under gravity by `g h²` (`h = dt / substeps`); positions near the scene's largest
//! coordinate `R` are `f32` numbers spaced `u = 2^(⌊log₂ R⌋ − 23)` apart, so a move under `u / 2`
//! rounds away (the particle never starts to fall, and its velocity, taken from the positions,
//! stays zero) and one under `u` is distorted by up to half of itself. The hanging `cloth`
//! (coordinates up to 1.2 m, `u` = 1.2e-7 m) at 60 frames a second, after half a second, against
//! the same run in `f64` (`‖x₃₂ − x₆₄‖ / ‖x₆₄ − x₀‖`): 0.9–6 % at 30 to 150 substeps (`g h²` of
//! 25 to 1.02 `u`; the folding cloth's own sensitivity), 33 % at 200 (0.57 `u`), and from 220 it
//! hangs still.

use std::fmt;

use super::Settings;
use crate::scene::Scene;

/// Substep moves under this many spacings `u` are reported (the measurements above).
pub const RESOLVED_SPACINGS: f64 = 1.0;

/// A substep too small for `f32` positions (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unresolved {
    /// Substeps per frame.
    pub substeps: u32,
    /// A substep's move from rest under gravity, `g h²` (m).
    pub displacement: f64,
    /// The scene's largest coordinate `R` (m).
    pub extent: f64,
    /// The spacing `u` of `f32` numbers at `R` (m).
    pub spacing: f64,
}

impl fmt::Display for Unresolved {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ratio = self.displacement / self.spacing;
        let what = if ratio < 0.5 {
            "round that move away, so particles at rest never start to fall"
        } else {
            "distort it by up to half of itself"
        };
        write!(
            f,
            "at {} substeps a particle at rest moves {:.1e} m a substep under gravity, {ratio:.2} times the \
             spacing of f32 positions at {:.2} m ({:.1e} m): the positions {what}; use fewer substeps, or \
             the library's f64 solver (CpuSolver<DVec3>)",
            self.substeps, self.displacement, self.extent, self.spacing
        )
    }
}

/// `Some` when a substep's move from rest under gravity is under [`RESOLVED_SPACINGS`] spacings
/// of `f32` positions at the scene's largest coordinate; `None` without gravity.
pub fn unresolved_substep(scene: &Scene, s: &Settings) -> Option<Unresolved> {
    let g = f64::from(scene.gravity.length());
    let extent = scene.positions.iter().map(|p| p.abs().max_element()).fold(0.0f32, f32::max);
    if g == 0.0 || extent == 0.0 || !extent.is_finite() {
        return None;
    }
    let h = f64::from(s.dt) / f64::from(s.substeps.max(1));
    let displacement = g * h * h;
    let spacing = 2f64.powi(f64::from(extent).log2().floor() as i32 - 23);
    (displacement < RESOLVED_SPACINGS * spacing).then_some(Unresolved {
        substeps: s.substeps,
        displacement,
        extent: f64::from(extent),
        spacing,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SceneOptions, build};

    #[test]
    fn the_hanging_cloth_is_resolved_up_to_150_substeps_and_not_from_200() {
        let scene = build("cloth", &SceneOptions::default()).expect("cloth");
        let at = |substeps| unresolved_substep(&scene, &Settings { substeps, ..Settings::default() });
        assert_eq!((at(30), at(150)), (None, None));
        let fine = at(250).expect("250 substeps");
        assert!(fine.displacement < 0.5 * fine.spacing, "{fine:?}");
        assert!(fine.to_string().contains("never start to fall"), "{fine}");
        let coarse = at(200).expect("200 substeps");
        assert!(coarse.displacement > 0.5 * coarse.spacing && coarse.to_string().contains("distort"), "{coarse}");
        let free = build("cloth-free", &SceneOptions::default()).expect("cloth-free");
        assert_eq!(unresolved_substep(&free, &Settings { substeps: 1000, ..Settings::default() }), None, "no gravity");
    }
}
