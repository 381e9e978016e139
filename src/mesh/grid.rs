//! A square cloth grid.

use glam::Vec3;

use super::TriMesh;

/// Which diagonal each quad of a [`grid`] is split along.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Diagonals {
    /// Every quad `(i, j)` split along the diagonal from `(i + 1, j)` to `(i, j + 1)`.
    #[default]
    Uniform,
    /// A checkerboard: quads with `i + j` odd split along the other diagonal, from `(i, j)` to
    /// `(i + 1, j + 1)`. The PositionBasedDynamics library's regular triangle model is split
    /// this way, so its cloth and ours are the same mesh.
    Alternating,
}

crate::error::command_names!(Diagonals, "diagonals", { Uniform => "uniform", Alternating => "alternating" });

/// An `n × n` grid of side `size` (m), horizontal (normal +y) at height `height`, centred on the
/// y axis, one diagonal per quad (chosen by `diagonals`): `2n(n−1) + (n−1)²` edges, `2(n−1)²`
/// triangles. Vertex `(i, j)` (i along x, j along z) has index `i + n j`.
pub fn grid(n: u32, size: f32, height: f32, diagonals: Diagonals) -> TriMesh {
    let step = size / (n - 1) as f32;
    let half = size / 2.0;
    let positions = (0..n)
        .flat_map(|j| (0..n).map(move |i| Vec3::new(i as f32 * step - half, height, j as f32 * step - half)))
        .collect();
    let mut triangles = Vec::with_capacity(2 * ((n - 1) * (n - 1)) as usize);
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = i + n * j;
            let (b, c, d) = (a + 1, a + n, a + n + 1);
            if diagonals == Diagonals::Alternating && (i + j) % 2 == 1 {
                triangles.push([a, c, d]);
                triangles.push([a, d, b]);
            } else {
                triangles.push([a, c, b]);
                triangles.push([b, c, d]);
            }
        }
    }
    TriMesh { positions, triangles }
}
