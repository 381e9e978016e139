//! `eapbd view` (and `eapbd` alone): the interactive viewer.

use std::path::PathBuf;

use clap::Args;
use eapbd::compare::Compare;
use eapbd::simulation::Backend;
use eapbd::viewer::{ColorMode, SceneChoice, ViewerOptions, ViewerState};

use super::{SceneArgs, named};

/// Arguments of `eapbd view`.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// Scene and solver options at the start (all of them can be changed in the window).
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Solver backend: gpu or cpu. Default: gpu on a GPU, cpu on a software adapter (such as
    /// lavapipe), where the CPU solver is the faster of the two.
    #[arg(long, value_parser = named::<Backend>)]
    pub backend: Option<Backend>,
    /// Window width (px, at most 16384).
    #[arg(long, default_value_t = 1280)]
    pub width: u32,
    /// Window height (px, at most 16384).
    #[arg(long, default_value_t = 800)]
    pub height: u32,
    /// Surface colours at the start: shaded, groups (color groups), strain or energy.
    #[arg(long, default_value = "shaded", value_parser = named::<ColorMode>)]
    pub color: ColorMode,
    /// Draw the surface's edges at the start.
    #[arg(long)]
    pub wireframe: bool,
    /// Close the window after this many frames.
    #[arg(long)]
    pub exit_after_frames: Option<u32>,
    /// Write the last frame (panels included) to this PNG file; with --exit-after-frames.
    #[arg(long, requires = "exit_after_frames")]
    pub screenshot: Option<PathBuf>,
    /// Compare mode at the start: a second run beside the first, differing in energy-aware (off
    /// | on), split (1 × 30 | 30 × 1), solver, form or sor.
    #[arg(long, value_parser = named::<Compare>)]
    pub compare: Option<Compare>,
    /// Multisampling of the scene: 1 (off), 2 or 4 samples per pixel. Default: 4 on a GPU, 1 on
    /// a software adapter (such as lavapipe), where each sample costs CPU time.
    #[arg(long)]
    pub msaa: Option<u32>,
}

/// Runs the command.
pub fn run(a: &ViewArgs) -> anyhow::Result<()> {
    let settings = a.scene.settings()?;
    let options = a.scene.scene_options()?;
    // Refuse bad options here, with the flag's name, rather than in the window.
    let scene = eapbd::scene::build(&a.scene.scene, &options)?;
    super::warn_about(&scene, &settings);
    let choice = SceneChoice::new(&a.scene.scene, &options)?;
    let mut state = ViewerState::new(choice, settings, a.backend.unwrap_or(Backend::Gpu));
    state.color_mode = a.color;
    state.wireframe = a.wireframe;
    state.compare = a.compare;
    eapbd::viewer::run(ViewerOptions {
        state,
        width: a.width,
        height: a.height,
        exit_after_frames: a.exit_after_frames,
        screenshot: a.screenshot.clone(),
        msaa: a.msaa,
        backend_given: a.backend.is_some(),
    })?;
    Ok(())
}
