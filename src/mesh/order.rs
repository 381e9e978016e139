//! Vertex renumbering for memory locality: vertices along a Z-order (Morton) curve of their
//! positions, so that elements which are near in space are near in the particle arrays.

use glam::Vec3;

use super::TriMesh;

/// Bits per axis of the grid the positions are snapped to for the Z-order key.
const BITS: u32 = 10;

impl TriMesh {
    /// Renumbers the vertices in Z-order of their positions (ties in their old order) and
    /// remaps the triangles; the geometry and the triangle order are unchanged. Threads that
    /// split a color group then write mostly disjoint stretches of the particle arrays, where a
    /// mesh that lists vertices in no spatial order (or appends refinement vertices at the end)
    /// would have every cache line written by both.
    pub fn reorder_spatially(&mut self) {
        let (lo, hi) = self
            .positions
            .iter()
            .fold((Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let scale = ((1 << BITS) - 1) as f32 / (hi - lo).max_element().max(f32::MIN_POSITIVE);
        let key = |p: Vec3| {
            let q = ((p - lo) * scale).clamp(Vec3::ZERO, Vec3::splat(((1 << BITS) - 1) as f32));
            spread(q.x as u32) | (spread(q.y as u32) << 1) | (spread(q.z as u32) << 2)
        };
        let mut order: Vec<u32> = (0..self.positions.len() as u32).collect();
        order.sort_by_key(|&i| key(self.positions[i as usize]));
        let mut new_index = vec![0u32; order.len()];
        for (new, &old) in order.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        self.positions = order.iter().map(|&i| self.positions[i as usize]).collect();
        for t in &mut self.triangles {
            *t = t.map(|v| new_index[v as usize]);
        }
    }
}

/// The low `BITS` bits of `v` spread to every third bit.
fn spread(v: u32) -> u32 {
    let mut x = v & ((1 << BITS) - 1);
    x = (x | (x << 16)) & 0x0300_00ff;
    x = (x | (x << 8)) & 0x0300_f00f;
    x = (x | (x << 4)) & 0x030c_30c3;
    (x | (x << 2)) & 0x0924_9249
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spread_interleaves_bits() {
        assert_eq!(spread(0b1), 0b1);
        assert_eq!(spread(0b11), 0b1001);
        assert_eq!(spread(0b1111111111), 0x0924_9249);
    }

    #[test]
    fn reorder_keeps_the_geometry() {
        let positions = vec![Vec3::new(1.0, 1.0, 1.0), Vec3::ZERO, Vec3::X, Vec3::new(0.0, 1.0, 0.0)];
        let triangles = vec![[0, 1, 2], [1, 3, 2], [0, 2, 3]];
        let mut m = TriMesh { positions: positions.clone(), triangles: triangles.clone() };
        m.reorder_spatially();
        assert_eq!(m.positions[0], Vec3::ZERO, "the corner nearest the origin comes first");
        for (t, old) in m.triangles.iter().zip(&triangles) {
            assert_eq!(t.map(|v| m.positions[v as usize]), old.map(|v| positions[v as usize]));
        }
    }
}
