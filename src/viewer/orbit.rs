//! An orbit camera: yaw and pitch about a target, a distance, panning in the view plane.

use glam::{Mat4, Vec2, Vec3};

use crate::render::Camera;

/// A camera orbiting a target point (m, radians).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Point orbited (m).
    pub target: Vec3,
    /// Angle about the vertical axis (rad).
    pub yaw: f32,
    /// Elevation above the horizontal (rad), within ±85°.
    pub pitch: f32,
    /// Distance from the target (m).
    pub distance: f32,
    /// Vertical field of view (rad).
    pub fov_y: f32,
}

const MAX_PITCH: f32 = 85.0 * std::f32::consts::PI / 180.0;

impl Orbit {
    /// The orbit that reproduces `camera`.
    pub fn from_camera(camera: &Camera) -> Self {
        let d = camera.eye - camera.target;
        let distance = d.length().max(1e-3);
        Orbit {
            target: camera.target,
            yaw: d.x.atan2(d.z),
            pitch: (d.y / distance).clamp(-1.0, 1.0).asin(),
            distance,
            fov_y: camera.fov_y,
        }
    }

    /// The eye position (m).
    pub fn eye(&self) -> Vec3 {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        self.target + Vec3::new(sy * cp, sp, cy * cp) * self.distance
    }

    /// The camera, with near and far planes scaled to the distance.
    pub fn camera(&self) -> Camera {
        Camera {
            eye: self.eye(),
            target: self.target,
            fov_y: self.fov_y,
            near: self.distance * 0.02,
            far: self.distance * 40.0,
        }
    }

    /// Turns by a mouse movement of `delta` pixels.
    pub fn rotate(&mut self, delta: Vec2) {
        self.yaw -= delta.x * 0.008;
        self.pitch = (self.pitch + delta.y * 0.008).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Moves the target in the view plane by `delta` pixels of a view `height` pixels tall, so
    /// the point under the cursor follows it.
    pub fn pan(&mut self, delta: Vec2, height: f32) {
        let forward = (self.target - self.eye()).normalize_or_zero();
        let right = forward.cross(Vec3::Y).normalize_or(Vec3::X);
        let up = right.cross(forward);
        let metres_per_pixel = 2.0 * self.distance * (self.fov_y * 0.5).tan() / height.max(1.0);
        self.target += (-right * delta.x + up * delta.y) * metres_per_pixel;
    }

    /// Zooms by `steps` wheel notches (positive: closer).
    pub fn zoom(&mut self, steps: f32) {
        self.distance = (self.distance * 0.9f32.powf(steps)).clamp(0.05, 500.0);
    }

    /// Projection × view for an aspect ratio (width / height).
    pub fn view_proj(&self, aspect: f32) -> Mat4 {
        self.camera().view_proj(aspect)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_reproduces_the_camera_it_came_from() {
        let c = Camera {
            eye: Vec3::new(1.0, 2.0, 3.0),
            target: Vec3::new(0.0, 0.5, 0.0),
            fov_y: 0.7,
            near: 0.1,
            far: 50.0,
        };
        let o = Orbit::from_camera(&c);
        assert!((o.eye() - c.eye).length() < 1e-5);
        let mut moved = o;
        moved.rotate(Vec2::new(30.0, 10.0));
        assert!(((moved.eye() - moved.target).length() - o.distance).abs() < 1e-4);
        moved.zoom(2.0);
        assert!(moved.distance < o.distance);
    }
}
