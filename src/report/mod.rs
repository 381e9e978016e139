//! Reports: studies run headless that write CSV, Markdown and PNG plots.
//!
//! - [`energy`]: energy-aware settings and SOR on the cloth scenes (`eapbd report energy`);
//! - [`beam`]: the cantilever's tip deflection against Euler–Bernoulli (`eapbd report beam`),
//!   with the closed-form references of [`cantilever`] and the static solver of [`equilibrium`];
//! - [`error_time`]: error against a converged f64 reference and wall-clock time for every solver
//!   variant over iterations × substeps budgets (`eapbd report error-vs-time`);
//! - [`stability`]: hard cases on both backends, each judged pass or fail (`eapbd report stability`);
//! - [`plot`]: line plots written as PNG.

pub mod beam;
mod beam_markdown;
mod beam_output;
pub mod cantilever;
pub mod energy;
pub mod equilibrium;
pub mod error_time;
mod error_time_output;
pub mod plot;
pub mod splits;
mod splits_output;
pub mod stability;
mod stability_cases;
mod stability_output;
