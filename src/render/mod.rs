//! Drawing scenes with wgpu: pipelines built once per device and target format ([`Renderer`]),
//! and per-scene draw data ([`SceneView`]) that reads the solver's position buffer directly.
//! Frames are drawn into [`FrameViews`], so windows and offscreen targets share one code path.

mod camera;
mod embed;
mod headless;
mod lines;
mod pipelines;
mod scene_view;
mod sphere;
mod target;

pub use camera::{Camera, CameraUniform};
pub use embed::Embedder;
pub use headless::{HEADLESS_SAMPLES, Snapshotter};
pub use lines::LineSet;
pub use pipelines::Renderer;
pub use scene_view::SceneView;
pub use sphere::uv_sphere;
pub use target::{
    DEPTH_FORMAT, FrameViews, OFFSCREEN_FORMAT, OffscreenTarget, TextureCopy, copy_texture, save_png, texture,
};

/// Background colour (linear RGB), matched by the ground's fade.
pub const SKY: wgpu::Color = wgpu::Color { r: 0.80, g: 0.84, b: 0.90, a: 1.0 };
