//! # eapbd
//!
//! Position-based simulation of elastic models (XPBD, Macklin et al. 2016) with the energy-aware
//! Gauss-Seidel iteration and two-step mesh coloring of Cetinaslan (Computer Graphics Forum 2019).
//!
//! - [`constraints`]: the constraint families (energy, gradient, projection in both forms);
//! - [`coloring`]: race-free color groups for parallel Gauss-Seidel;
//! - [`scene`]: scene descriptions and builders;
//! - [`solver`]: the CPU reference solver and its settings;
//! - [`metrics`]: residual, stretch and energy measures;
//! - [`viewer`]: the interactive window (winit, egui) on the solver's device.
//!
//! SI units throughout: metres, kilograms, seconds.

pub mod coloring;
pub mod constraints;
pub mod error;
pub mod gpu;
pub mod material;
pub mod math;
pub mod mesh;
pub mod metrics;
pub mod render;
pub mod report;
pub mod scene;
pub mod simulation;
pub mod solver;
pub mod viewer;

pub use error::{Error, Result};
