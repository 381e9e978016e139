//! The interactive viewer: a winit window whose device is shared by the solver's compute
//! passes, the scene renderer and egui; panels that edit the scene, material and settings;
//! live statistics and plots; a mouse that orbits the camera and drags particles.
//!
//! - [`state`]: what the widgets edit (plain data);
//! - [`session`]: the simulation and its drawing without a window (tests drive it directly);
//! - [`ui`]: the egui panels; [`run`]: the window and its event loop.

mod app;
mod capture;
pub mod grab;
pub mod orbit;
pub mod overlay;
pub mod picking;
pub mod plots;
mod readback;
pub mod session;
pub mod state;
pub mod strain;
pub mod twin;
pub mod ui;
pub mod ui_cache;
#[cfg(target_arch = "wasm32")]
mod web;

pub use app::{ViewerOptions, run};
pub use readback::{Snapshot, StatsReadback};
pub use session::Session;
pub use state::{ColorMode, MaterialChoice, SceneChoice, ViewerState};
