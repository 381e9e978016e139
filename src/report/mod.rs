//! Reports: studies run headless that write CSV, Markdown and PNG plots.

pub mod energy;
pub mod plot;
