//! Two runs of one scene that differ in one setting, side by side: what `eapbd render
//! --compare SETTING` draws, to see what that setting does.

use crate::constraints::Form;
use crate::error::{Error, Result};
use crate::solver::{EnergyAware, Method, Settings};

/// The setting a comparison varies; everything else is the base settings'.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compare {
    /// Energy-aware off against `project` (what "on" means).
    EnergyAware,
    /// The same 30 projections a frame as 1 substep × 30 iterations against 30 × 1.
    Split,
    /// Gauss-Seidel against Jacobi.
    Solver,
    /// The compliant form against the energy form.
    Form,
    /// Over-relaxation ω = 1 against 1.5.
    Sor,
}

impl Compare {
    /// Every comparison with its command-line name.
    pub const ALL: [(&'static str, Compare); 5] = [
        ("energy-aware", Compare::EnergyAware),
        ("split", Compare::Split),
        ("solver", Compare::Solver),
        ("form", Compare::Form),
        ("sor", Compare::Sor),
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Compare::ALL.iter().find(|(_, c)| *c == self).map_or("", |(n, _)| n)
    }

    /// The two sides, left then right: a label saying what differs, and the settings (`base`
    /// with the one setting changed).
    pub fn sides(self, base: &Settings) -> [(&'static str, Settings); 2] {
        let with = |f: &dyn Fn(&mut Settings)| {
            let mut s = *base;
            f(&mut s);
            s
        };
        match self {
            Compare::EnergyAware => [
                ("energy-aware off", with(&|s| s.energy_aware = EnergyAware::Off)),
                ("energy-aware on (project)", with(&|s| s.energy_aware = EnergyAware::Project)),
            ],
            Compare::Split => [
                ("1 substep x 30 iterations", with(&|s| (s.substeps, s.iterations) = (1, 30))),
                ("30 substeps x 1 iteration", with(&|s| (s.substeps, s.iterations) = (30, 1))),
            ],
            Compare::Solver => [
                ("Gauss-Seidel", with(&|s| s.method = Method::GaussSeidel)),
                ("Jacobi", with(&|s| s.method = Method::Jacobi)),
            ],
            Compare::Form => [
                ("compliant form", with(&|s| s.form = Form::Compliant)),
                ("energy form", with(&|s| s.form = Form::Energy)),
            ],
            Compare::Sor => [("SOR 1", with(&|s| s.sor = 1.0)), ("SOR 1.5", with(&|s| s.sor = 1.5))],
        }
    }
}

impl std::str::FromStr for Compare {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        Error::lookup("compare", s, &Compare::ALL)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_comparison_changes_only_its_setting() {
        let base = Settings { substeps: 10, iterations: 3, damping: 0.5, ..Settings::default() };
        for (name, c) in Compare::ALL {
            assert_eq!(name.parse::<Compare>().unwrap(), c);
            assert_eq!(c.name(), name);
            let [(l, a), (r, b)] = c.sides(&base);
            assert_ne!(l, r);
            assert_ne!(a, b, "{name}: the two sides differ");
            for s in [a, b] {
                assert_eq!((s.damping, s.dt, s.threads), (base.damping, base.dt, base.threads), "{name}");
            }
        }
        assert!("colour".parse::<Compare>().is_err());
    }
}
