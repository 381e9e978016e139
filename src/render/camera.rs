//! A look-at camera that frames a scene. Keep `CameraUniform` in sync with
//! `shaders/render/common.wgsl` (Camera).

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec3};

use crate::scene::Scene;

/// A perspective camera (m, radians).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position (m).
    pub eye: Vec3,
    /// Point looked at (m).
    pub target: Vec3,
    /// Vertical field of view (rad).
    pub fov_y: f32,
    /// Near and far planes (m).
    pub near: f32,
    /// Far plane (m).
    pub far: f32,
}

/// The camera as the shaders see it.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct CameraUniform {
    /// Projection × view.
    pub view_proj: [[f32; 4]; 4],
    /// Eye position (m).
    pub eye: [f32; 4],
    /// Direction towards the light (unit).
    pub light_dir: [f32; 4],
}

impl Camera {
    /// A camera looking at the scene's start bounds (particles, spheres and the ground below
    /// them) from the front, a little from the right and above.
    pub fn framing(scene: &Scene) -> Self {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in &scene.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        for s in &scene.spheres {
            lo = lo.min(s.center - Vec3::splat(s.radius));
            hi = hi.max(s.center + Vec3::splat(s.radius));
        }
        if let Some(g) = scene.ground {
            lo.y = lo.y.min(g.height);
        }
        if lo.x > hi.x {
            (lo, hi) = (Vec3::splat(-1.0), Vec3::splat(1.0));
        }
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(0.1);
        let fov_y = 40f32.to_radians();
        let distance = radius / (fov_y * 0.5).sin() * 1.05;
        let dir = Vec3::new(0.55, 0.45, 1.0).normalize();
        Camera { eye: center + dir * distance, target: center, fov_y, near: distance * 0.02, far: distance * 20.0 }
    }

    /// Projection × view for an aspect ratio (width / height). In a viewport taller than wide
    /// (a half of the scene in compare mode) the vertical field of view widens to
    /// `2 atan(tan(fov_y / 2) / aspect)`, so that the horizontal one is `fov_y` and what
    /// [`Camera::framing`] fits stays in view.
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        // wgpu's clip space has y up and depth in [0, 1], as Direct3D's.
        let view = glam::camera::rh::view::look_at_mat4(self.eye, self.target, Vec3::Y);
        let fov = if aspect < 1.0 { 2.0 * ((self.fov_y * 0.5).tan() / aspect).atan() } else { self.fov_y };
        glam::camera::rh::proj::directx::perspective(fov, aspect, self.near, self.far) * view
    }

    /// The uniform for an aspect ratio.
    pub fn uniform(&self, aspect: f32) -> CameraUniform {
        CameraUniform {
            view_proj: self.view_proj(aspect).to_cols_array_2d(),
            eye: self.eye.extend(1.0).to_array(),
            light_dir: Vec3::new(0.35, 1.0, 0.55).normalize().extend(0.0).to_array(),
        }
    }
}
