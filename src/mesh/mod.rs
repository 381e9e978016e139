//! Triangle meshes: generation, topology (edges, dihedral pairs), lumped masses, OBJ export.

mod crossings;
mod grid;
mod lattice;
mod load;
mod obj;
mod order;
mod refine;
mod tetgen;
mod tetmesh;
mod topology;

pub use crossings::crossing_pairs;
pub use grid::{Diagonals, grid};
pub use lattice::{Binding, EmbeddedTets, embedded_positions, winding_number};
pub use load::{load_obj, parse_obj};
pub use obj::write_obj;
pub use tetgen::{load_tetgen, parse_tetgen};
pub use tetmesh::TetMesh;
pub use topology::{closed_surface_problem, dihedral_pairs, unique_edges};

use glam::Vec3;

use crate::error::{Error, Result};

/// A triangle mesh in metres.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions (m).
    pub positions: Vec<Vec3>,
    /// Counter-clockwise triangles (vertex indices).
    pub triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Checks indices and rejects zero-area triangles, naming the first offender.
    pub fn validate(&self) -> Result<()> {
        let n = self.positions.len() as u32;
        if let Some(i) = self.positions.iter().position(|p| !p.is_finite()) {
            return Err(Error::InvalidMesh(format!("vertex {i} is not finite")));
        }
        for (t, tri) in self.triangles.iter().enumerate() {
            if let Some(&i) = tri.iter().find(|&&i| i >= n) {
                return Err(Error::InvalidMesh(format!("triangle {t} uses vertex {i} of {n}")));
            }
            if self.area(t) <= 1e-12 {
                return Err(Error::InvalidMesh(format!("triangle {t} {tri:?} has zero area")));
            }
        }
        Ok(())
    }

    /// Checks that the mesh is a closed, consistently oriented 2-manifold (every edge shared by
    /// exactly two triangles running it in opposite directions), as a solid's surface must be.
    pub fn validate_closed(&self) -> Result<()> {
        match closed_surface_problem(&self.triangles) {
            Some(p) => Err(Error::InvalidMesh(format!("not a closed surface: {p}"))),
            None => Ok(()),
        }
    }

    /// Volume enclosed by a closed, outward-oriented surface (m³): `Σ a·(b × c)/6`.
    pub fn enclosed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.positions[i as usize].as_dvec3());
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// Area of triangle `t` in m².
    pub fn area(&self, t: usize) -> f32 {
        let [a, b, c] = self.triangles[t].map(|i| self.positions[i as usize]);
        0.5 * (b - a).cross(c - a).length()
    }

    /// Lumped vertex masses for a total mass (kg): each triangle gives a third of its share of
    /// the total area to each of its corners.
    pub fn lumped_masses(&self, total: f32) -> Vec<f32> {
        let areas: Vec<f32> = (0..self.triangles.len()).map(|t| self.area(t)).collect();
        let sum: f32 = areas.iter().sum();
        let mut m = vec![0.0; self.positions.len()];
        for (tri, a) in self.triangles.iter().zip(&areas) {
            for &i in tri {
                m[i as usize] += total * a / (3.0 * sum);
            }
        }
        m
    }
}
