//! A mesh from an OBJ file simulated and drawn headless: load a closed surface, turn it into a
//! volumetric body (the `bunny` scene with a user's surface), run it on the GPU, write the last
//! frame as PNG and the deformed surface as OBJ.
//!
//! ```sh
//! cargo run --release --example render_png                        # the bunny of assets/
//! cargo run --release --example render_png -- my_mesh.obj out_dir # any closed OBJ surface
//! ```
//!
//! The surface is scaled to 0.3 m tall and dropped from 0.15 m onto the ground. Output goes to
//! `target/example-render/` unless a directory is given. Needs a GPU adapter (Mesa's lavapipe
//! works); with none the error says what to install.

use std::path::PathBuf;
use std::sync::Arc;

use eapbd::gpu::{GpuContext, Kernels};
use eapbd::mesh::{load_obj, write_obj};
use eapbd::render::{Snapshotter, save_png};
use eapbd::scene::{self, SceneOptions};
use eapbd::simulation::{Backend, Simulation};
use eapbd::solver::Settings;

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let mesh = PathBuf::from(args.next().unwrap_or_else(|| "assets/bunny.obj".into()));
    let out = PathBuf::from(args.next().unwrap_or_else(|| "target/example-render".into()));

    // The loader checks the file (indices, finite coordinates, zero-area triangles); the scene
    // checks that the surface is closed, as a volumetric body needs.
    let surface = load_obj(&mesh)?;
    println!("{}: {} vertices, {} triangles", mesh.display(), surface.positions.len(), surface.triangles.len());
    let options = SceneOptions { young: 2.0e5, ..SceneOptions::default() };
    let scene = scene::build_with_surface("bunny", &options, surface)?;

    let ctx = GpuContext::new()?;
    let kernels = Arc::new(Kernels::new(&ctx.device));
    let mut sim = Simulation::new(Backend::Gpu, scene, Some((&ctx, &kernels)))?;
    let snapshotter = Snapshotter::new(&ctx, &sim, 640, 480)?;
    let settings = Settings { substeps: 2, iterations: 10, ..Settings::default() };
    settings.validate()?;
    for _ in 0..45 {
        sim.step_frame(&settings);
    }

    std::fs::create_dir_all(&out)?;
    let png = out.join("frame_00045.png");
    save_png(&snapshotter.capture(&ctx, &sim)?, &png)?;
    let (positions, triangles) = sim.scene().surface(&sim.positions()?);
    let obj = out.join("frame_00045.obj");
    write_obj(&obj, &positions, triangles)?;
    println!("wrote {} and {} ({} on {})", png.display(), obj.display(), sim.scene().name, ctx.describe());
    Ok(())
}
