//! Tetrahedral meshes: a box split into tetrahedra, the paper's centroid tetrahedra of a closed
//! surface, and the boundary surface for drawing.

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use crate::error::{Error, Result};

/// A tetrahedral mesh in metres.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TetMesh {
    /// Vertex positions (m).
    pub positions: Vec<Vec3>,
    /// Tetrahedra (vertex indices).
    pub tets: Vec<[u32; 4]>,
}

impl TetMesh {
    /// A box of `cells` cells per axis spanning `min..max`, each cell split into six tetrahedra
    /// around its main diagonal (the Freudenthal split, conforming across cells), each ordered
    /// for a positive volume. The cells (and their tetrahedra) run with x fastest and z slowest,
    /// the vertices with z fastest and x slowest. The coloring's balancing sweep moves elements
    /// in their order (`crate::coloring`), which leaves each color group's elements spread
    /// unevenly along z; the CPU team splits a group by lowest particle index
    /// (`crate::scene::Family`), so with the vertices numbered along x the split falls about the
    /// same place in every group, and few particles are touched by two threads (each passes its
    /// cache line between the cores: the bunny's lattice, 181 of 1,292 particles against 500 with
    /// the vertices numbered like the cells; BENCHMARKS.md, "Two threads on the bunny").
    pub fn box_grid(cells: [u32; 3], min: Vec3, max: Vec3) -> Self {
        let [nx, ny, nz] = cells.map(|c| c.max(1));
        let idx = |i: u32, j: u32, k: u32| k + (nz + 1) * (j + (ny + 1) * i);
        let step = (max - min) / Vec3::new(nx as f32, ny as f32, nz as f32);
        let mut positions = Vec::with_capacity(((nx + 1) * (ny + 1) * (nz + 1)) as usize);
        for i in 0..=nx {
            for j in 0..=ny {
                for k in 0..=nz {
                    positions.push(min + step * Vec3::new(i as f32, j as f32, k as f32));
                }
            }
        }
        let axes = [[1u32, 0, 0], [0, 1, 0], [0, 0, 1]];
        let perms = [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]];
        let mut tets = Vec::with_capacity((6 * nx * ny * nz) as usize);
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    for p in perms {
                        let mut c = [i, j, k];
                        let mut t = [idx(i, j, k); 4];
                        for (s, &axis) in p.iter().enumerate() {
                            for d in 0..3 {
                                c[d] += axes[axis][d];
                            }
                            t[s + 1] = idx(c[0], c[1], c[2]);
                        }
                        // Odd permutations give mirrored tetrahedra: swap two corners.
                        if matches!(p, [0, 2, 1] | [1, 0, 2] | [2, 1, 0]) {
                            t.swap(2, 3);
                        }
                        tets.push(t);
                    }
                }
            }
        }
        TetMesh { positions, tets }
    }

    /// The paper's tetrahedra for a closed surface: each triangle paired with the volume centroid
    /// of the enclosed solid (`c = Σᵢ Vᵢ (a + b + c)/4 / Σᵢ Vᵢ` over the signed volumes
    /// `Vᵢ = a·(b × c)/6` of the triangles' cones from the origin). Keeps only the vertices the
    /// triangles use (renumbered in order) and appends the centroid as the last vertex; each
    /// tetrahedron is ordered `[a, b, c, centroid]` or `[a, c, b, centroid]` for a positive volume.
    /// Fails when the surface encloses no volume or a triangle is coplanar with the centroid.
    pub fn centroid_fan(positions: &[Vec3], triangles: &[[u32; 3]]) -> Result<Self> {
        let mut remap = vec![u32::MAX; positions.len()];
        let mut kept = Vec::new();
        for t in triangles {
            for &i in t {
                let slot = remap.get_mut(i as usize).ok_or_else(|| {
                    Error::InvalidMesh(format!("triangle {t:?} names vertex {i} of {}", positions.len()))
                })?;
                if *slot == u32::MAX {
                    *slot = kept.len() as u32;
                    kept.push(positions[i as usize]);
                }
            }
        }
        let (mut volume, mut moment) = (0.0f64, DVec3::ZERO);
        for t in triangles {
            let [a, b, c] = t.map(|i| positions[i as usize].as_dvec3());
            let v = a.dot(b.cross(c)) / 6.0;
            volume += v;
            moment += v * (a + b + c) / 4.0;
        }
        let extent = kept.iter().fold(0.0f32, |m, p| m.max(p.abs().max_element())) as f64;
        if volume.is_nan() || volume.abs() <= 1e-9 * extent.powi(3).max(1e-30) {
            return Err(Error::InvalidMesh(format!(
                "the surface encloses a volume of {volume:.3e} m³: centroid tetrahedra need a closed surface"
            )));
        }
        let center = moment / volume;
        let m = kept.len() as u32;
        let mut tets = Vec::with_capacity(triangles.len());
        for (n, t) in triangles.iter().enumerate() {
            let [a, b, c] = t.map(|i| remap[i as usize]);
            let [pa, pb, pc] = t.map(|i| positions[i as usize].as_dvec3() - center);
            let v = pa.dot(pb.cross(pc)) / 6.0;
            let size = (pb - pa).length().max((pc - pa).length()).max(pa.length());
            if v.abs() <= 1e-9 * size.powi(3) {
                return Err(Error::InvalidMesh(format!(
                    "triangle {n} {t:?} is coplanar with the centroid: its tetrahedron would be flat"
                )));
            }
            // det[b − a, c − a, d − a] of [a, b, c, d] equals −6 v for d the centroid.
            tets.push(if v < 0.0 { [a, b, c, m] } else { [a, c, b, m] });
        }
        kept.push(center.as_vec3());
        Ok(TetMesh { positions: kept, tets })
    }

    /// Faces that belong to one tetrahedron only, oriented outwards.
    pub fn boundary(&self) -> Vec<[u32; 3]> {
        let mut count: HashMap<[u32; 3], (u32, [u32; 3], u32)> = HashMap::new();
        for t in &self.tets {
            for skip in 0..4 {
                let face: Vec<u32> = (0..4).filter(|&i| i != skip).map(|i| t[i]).collect();
                let mut key = [face[0], face[1], face[2]];
                key.sort_unstable();
                let e = count.entry(key).or_insert((0, [face[0], face[1], face[2]], t[skip]));
                e.0 += 1;
            }
        }
        let mut faces: Vec<[u32; 3]> = count
            .into_values()
            .filter(|(n, _, _)| *n == 1)
            .map(|(_, [a, b, c], opposite)| {
                let (pa, pb, pc, pd) = (
                    self.positions[a as usize],
                    self.positions[b as usize],
                    self.positions[c as usize],
                    self.positions[opposite as usize],
                );
                if (pb - pa).cross(pc - pa).dot(pd - pa) > 0.0 { [a, c, b] } else { [a, b, c] }
            })
            .collect();
        faces.sort_unstable();
        faces
    }

    /// Lumped vertex masses for a density (kg/m³): each tetrahedron gives a quarter of its mass
    /// to each corner.
    pub fn lumped_masses(&self, density: f32) -> Vec<f32> {
        let mut m = vec![0.0; self.positions.len()];
        for t in &self.tets {
            let [a, b, c, d] = t.map(|i| self.positions[i as usize]);
            let v = ((b - a).cross(c - a).dot(d - a) / 6.0).abs();
            for &i in t {
                m[i as usize] += density * v / 4.0;
            }
        }
        m
    }
}
