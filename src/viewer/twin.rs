//! Compare mode in the window: a second session, the twin, beside the first on the same device,
//! differing in one setting ([`crate::compare::Compare`]). Every frame it takes the first
//! session's scene, settings, pause, step, reset, camera and grab (the same particle pulled in
//! both), and each side runs its setting.

use super::session::Session;
use crate::error::Result;
use crate::gpu::GpuContext;

/// Brings `twin` in line with `main` for the coming frame (after the panels ran, before
/// [`Session::apply_changes`]): made when the panels turn compare mode on, both runs then
/// starting again from the scene's start; dropped when they turn it off; otherwise given the
/// main session's state, camera and grab. `format` and `samples` are the window's.
pub fn sync(
    twin: &mut Option<Session>,
    main: &mut Session,
    ctx: &GpuContext,
    format: wgpu::TextureFormat,
    samples: u32,
) -> Result<()> {
    let Some(c) = main.state.compare else {
        *twin = None;
        main.side = None;
        return Ok(());
    };
    main.side = Some((c, 0));
    let t = match twin {
        Some(t) => t,
        None => {
            main.state.requests.reset = true;
            let mut t = Session::new(ctx, format, samples, main.state.clone())?;
            t.draw_over = true;
            twin.insert(t)
        }
    };
    t.side = Some((c, 1));
    t.state = main.state.clone();
    t.orbit = main.orbit;
    t.share_grab(main.grab());
    Ok(())
}

/// The halves of the scene's `viewport` (`[x, y, width, height]`): the main session's on the
/// left, the twin's on the right.
pub fn halves([x, y, w, h]: [f32; 4]) -> [[f32; 4]; 2] {
    let half = (w / 2.0).floor();
    [[x, y, half, h], [x + half, y, w - half, h]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_halves_tile_the_viewport() {
        let [l, r] = halves([290.0, 0.0, 701.0, 800.0]);
        assert_eq!(l, [290.0, 0.0, 350.0, 800.0]);
        assert_eq!(r, [640.0, 0.0, 351.0, 800.0]);
    }
}
