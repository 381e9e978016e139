//! Ray picking: the ray under a pixel, its first hit on the surface triangles, and the plane a
//! grabbed particle is dragged in.

use glam::{Mat4, Vec2, Vec3, Vec4Swizzles};

/// A ray `origin + t · dir` (m), `dir` of unit length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start (m).
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
}

impl Ray {
    /// The ray through `pixel` (origin top left) of a view `size` pixels large drawn with
    /// `view_proj` (wgpu clip space: depth 0 at the near plane, 1 at the far plane).
    pub fn through_pixel(view_proj: Mat4, pixel: Vec2, size: Vec2) -> Option<Ray> {
        let ndc = Vec2::new(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y);
        let inv = view_proj.inverse();
        let near = inv * ndc.extend(0.0).extend(1.0);
        let far = inv * ndc.extend(1.0).extend(1.0);
        if near.w.abs() < 1e-12 || far.w.abs() < 1e-12 {
            return None;
        }
        let (a, b) = (near.xyz() / near.w, far.xyz() / far.w);
        let dir = (b - a).try_normalize()?;
        Some(Ray { origin: a, dir })
    }

    /// The point at parameter `t` (m).
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }

    /// Parameter of the hit with triangle `(a, b, c)` (Möller–Trumbore, both sides), if any.
    pub fn triangle(&self, a: Vec3, b: Vec3, c: Vec3) -> Option<f32> {
        let (e1, e2) = (b - a, c - a);
        let p = self.dir.cross(e2);
        let det = e1.dot(p);
        if det.abs() < 1e-12 {
            return None;
        }
        let inv = 1.0 / det;
        let s = self.origin - a;
        let u = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(e1);
        let v = self.dir.dot(q) * inv;
        if v < 0.0 || u + v > 1.0 {
            return None;
        }
        let t = e2.dot(q) * inv;
        (t > 0.0).then_some(t)
    }

    /// Parameter where the ray meets the plane through `point` with normal `normal`.
    pub fn plane(&self, point: Vec3, normal: Vec3) -> Option<f32> {
        let d = self.dir.dot(normal);
        if d.abs() < 1e-9 {
            return None;
        }
        let t = (point - self.origin).dot(normal) / d;
        (t > 0.0).then_some(t)
    }
}

/// The first surface hit of `ray`: the particle of the hit triangle nearest the hit point, and
/// the hit point (m).
pub fn pick(ray: &Ray, positions: &[Vec3], triangles: &[[u32; 3]]) -> Option<(u32, Vec3)> {
    let mut best: Option<(f32, [u32; 3])> = None;
    for t in triangles {
        if t.iter().any(|&i| i as usize >= positions.len()) {
            continue;
        }
        let [a, b, c] = t.map(|i| positions[i as usize]);
        if let Some(d) = ray.triangle(a, b, c)
            && best.is_none_or(|(bd, _)| d < bd)
        {
            best = Some((d, *t));
        }
    }
    let (d, tri) = best?;
    let hit = ray.at(d);
    let nearest = tri.into_iter().min_by(|&i, &j| {
        let (di, dj) = (positions[i as usize].distance_squared(hit), positions[j as usize].distance_squared(hit));
        di.total_cmp(&dj)
    })?;
    Some((nearest, hit))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ray_through_the_centre_hits_the_nearest_triangle() {
        let view = glam::camera::rh::view::look_at_mat4(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y);
        let proj = glam::camera::rh::proj::directx::perspective(0.8, 1.0, 0.1, 100.0);
        let ray = Ray::through_pixel(proj * view, Vec2::new(50.0, 50.0), Vec2::new(100.0, 100.0)).unwrap();
        assert!((ray.dir - Vec3::NEG_Z).length() < 1e-4, "{ray:?}");
        // Two parallel triangles at z = 0 and z = 1: the one at z = 1 is nearer the eye.
        let x = vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0, -1.0, 1.0),
            Vec3::new(1.0, -1.0, 1.0),
            Vec3::new(0.1, 0.2, 1.0),
        ];
        let (i, hit) = pick(&ray, &x, &[[0, 1, 2], [3, 4, 5]]).unwrap();
        assert_eq!(i, 5);
        assert!((hit - Vec3::new(0.0, 0.0, 1.0)).length() < 1e-4);
        let t = ray.plane(Vec3::new(0.0, 0.0, -2.0), Vec3::Z).unwrap();
        assert!((ray.at(t) - Vec3::new(0.0, 0.0, -2.0)).length() < 1e-4);
        assert!(pick(&ray, &x, &[[0, 1, 5]]).is_some());
        assert!(pick(&Ray { origin: Vec3::new(5.0, 5.0, 5.0), dir: Vec3::NEG_Z }, &x, &[[0, 1, 2]]).is_none());
    }
}
