//! A UV sphere mesh for drawing sphere colliders.

use glam::{Vec3, Vec4};

/// Positions and normals (`vec4`, w unused) and triangles of a sphere of `radius` at `center`,
/// with `rings` latitude bands and `2 rings` longitude segments.
pub fn uv_sphere(center: Vec3, radius: f32, rings: u32) -> (Vec<Vec4>, Vec<Vec4>, Vec<u32>) {
    let segments = 2 * rings;
    let (mut pos, mut nrm, mut idx) = (Vec::new(), Vec::new(), Vec::new());
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = std::f32::consts::TAU * s as f32 / segments as f32;
            let n = Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin());
            pos.push((center + n * radius).extend(1.0));
            nrm.push(n.extend(0.0));
        }
    }
    let row = segments + 1;
    for r in 0..rings {
        for s in 0..segments {
            let a = r * row + s;
            let (b, c, d) = (a + 1, a + row, a + row + 1);
            idx.extend_from_slice(&[a, b, c, b, d, c]);
        }
    }
    (pos, nrm, idx)
}
