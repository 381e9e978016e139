//! A volumetric tetrahedral mesh for a closed surface: a lattice of cubes kept by the surface's
//! winding number, split into tetrahedra, with the surface embedded by barycentric weights.

use bytemuck::{Pod, Zeroable};
use glam::{DVec3, UVec3, Vec3};

use super::{TetMesh, TriMesh};
use crate::error::{Error, Result};

/// A surface vertex bound to a tetrahedron: `x = Σ w_k x[p_k]`. Keep in sync with `Binding` in
/// `shaders/render/embed.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Binding {
    /// The tetrahedron's particles.
    pub p: [u32; 4],
    /// Barycentric weights (sum 1; slightly negative when the vertex lies just outside).
    pub w: [f32; 4],
}

/// A tetrahedral mesh of a closed surface with the surface bound to it.
#[derive(Clone, Debug)]
pub struct EmbeddedTets {
    /// The tetrahedra.
    pub mesh: TetMesh,
    /// One binding per surface vertex.
    pub bindings: Vec<Binding>,
    /// Largest distance from a surface vertex to its tetrahedron (m; 0 when all lie inside).
    pub max_outside: f32,
}

/// Generalised winding number of the closed surface at `q` (1 inside, 0 outside): the sum of the
/// triangles' signed solid angles over 4π (Van Oosterom and Strackee 1983).
pub fn winding_number(surface: &TriMesh, q: DVec3) -> f64 {
    let mut sum = 0.0;
    for t in &surface.triangles {
        let [a, b, c] = t.map(|i| surface.positions[i as usize].as_dvec3() - q);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let det = a.dot(b.cross(c));
        let div = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
        sum += 2.0 * det.atan2(div);
    }
    sum / (4.0 * std::f64::consts::PI)
}

/// Distance from `p` to the triangle `(a, b, c)` (closest-point regions, Ericson 2004).
fn point_triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (p - (a + ab * (d1 / (d1 - d3)))).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (p - (a + ac * (d2 / (d2 - d6)))).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).length();
    }
    let denom = 1.0 / (va + vb + vc);
    (p - (a + ab * (vb * denom) + ac * (vc * denom))).length()
}

/// Barycentric coordinates of `p` in the tetrahedron `x`.
fn barycentric(p: DVec3, x: [DVec3; 4]) -> Option<[f64; 4]> {
    let m = glam::DMat3::from_cols(x[1] - x[0], x[2] - x[0], x[3] - x[0]);
    if m.determinant().abs() < 1e-30 {
        return None;
    }
    let w = m.inverse() * (p - x[0]);
    Some([1.0 - w.x - w.y - w.z, w.x, w.y, w.z])
}

/// Distance from `p` to the tetrahedron `x` (0 inside).
fn point_tet_distance(p: DVec3, x: [DVec3; 4], w: [f64; 4]) -> f64 {
    if w.iter().all(|&v| v >= 0.0) {
        return 0.0;
    }
    [[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]]
        .iter()
        .map(|f| point_triangle_distance(p, x[f[0]], x[f[1]], x[f[2]]))
        .fold(f64::MAX, f64::min)
}

impl EmbeddedTets {
    /// Tetrahedralizes the closed surface with `cells` cubes along its longest side: the cubes
    /// of a lattice over its bounding box whose centres have winding number ≥ ½ are kept and
    /// split into six tetrahedra each (conforming), unused lattice vertices dropped; each surface
    /// vertex is bound to the tetrahedron of a nearby kept cube in which its smallest
    /// barycentric weight is largest (inside when possible, else the least extrapolation).
    pub fn from_surface(surface: &TriMesh, cells: u32) -> Result<Self> {
        if !(2..=256).contains(&cells) {
            return Err(Error::param("--lattice", cells, "cells along the longest side must be in 2..=256"));
        }
        surface.validate()?;
        surface.validate_closed()?;
        let (lo, hi) = surface.positions.iter().fold((Vec3::MAX, Vec3::MIN), |(a, b), &p| (a.min(p), b.max(p)));
        let h = (hi - lo).max_element() / cells as f32;
        // One cell of margin on each side: cells that only the margin would keep are outside.
        let dims = ((hi - lo) / h).ceil().as_uvec3().max(UVec3::ONE) + UVec3::splat(2);
        let origin = lo - Vec3::splat(h);
        let grid = TetMesh::box_grid(dims.to_array(), origin, origin + dims.as_vec3() * h);
        let cell_index = |c: UVec3| (c.x + dims.x * (c.y + dims.y * c.z)) as usize;
        let n_cells = (dims.x * dims.y * dims.z) as usize;
        let mut kept = vec![false; n_cells];
        for z in 0..dims.z {
            for y in 0..dims.y {
                for x in 0..dims.x {
                    let centre = origin + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * h;
                    kept[cell_index(UVec3::new(x, y, z))] = winding_number(surface, centre.as_dvec3()) >= 0.5;
                }
            }
        }
        if !kept.iter().any(|&k| k) {
            return Err(Error::InvalidMesh(format!(
                "the lattice of {cells} cells has no cell inside the surface: raise --lattice"
            )));
        }
        // Keep the tetrahedra of kept cells (box_grid emits six per cell, cells in x, y, z
        // order) and renumber the vertices they use in the grid's order (x slowest, which the
        // CPU team's split follows: `TetMesh::box_grid`).
        let kept_cells = || kept.iter().enumerate().filter(|(_, k)| **k).map(|(c, _)| c);
        let mut used = vec![false; grid.positions.len()];
        for c in kept_cells() {
            for &i in grid.tets[6 * c..6 * c + 6].as_flattened() {
                used[i as usize] = true;
            }
        }
        let mut remap = vec![u32::MAX; grid.positions.len()];
        let mut mesh = TetMesh::default();
        for (i, _) in used.iter().enumerate().filter(|(_, u)| **u) {
            remap[i] = mesh.positions.len() as u32;
            mesh.positions.push(grid.positions[i]);
        }
        let mut first_tet = vec![u32::MAX; n_cells];
        for c in kept_cells() {
            first_tet[c] = mesh.tets.len() as u32;
            mesh.tets.extend(grid.tets[6 * c..6 * c + 6].iter().map(|t| t.map(|i| remap[i as usize])));
        }
        let mut bindings = Vec::with_capacity(surface.positions.len());
        let mut max_outside = 0.0f64;
        for (v, &p) in surface.positions.iter().enumerate() {
            let cell = ((p - origin) / h).floor().as_ivec3();
            let mut best: Option<(f64, usize, [f64; 4])> = None;
            for radius in 1..=3i32 {
                for dz in -radius..=radius {
                    for dy in -radius..=radius {
                        for dx in -radius..=radius {
                            let c = cell + glam::IVec3::new(dx, dy, dz);
                            if c.min_element() < 0 || c.cmpge(dims.as_ivec3()).any() {
                                continue;
                            }
                            let first = first_tet[cell_index(c.as_uvec3())];
                            if first == u32::MAX {
                                continue;
                            }
                            for t in first as usize..first as usize + 6 {
                                let x = mesh.tets[t].map(|i| mesh.positions[i as usize].as_dvec3());
                                if let Some(w) = barycentric(p.as_dvec3(), x) {
                                    let score = w.iter().copied().fold(f64::MAX, f64::min);
                                    if best.is_none_or(|(s, _, _)| score > s) {
                                        best = Some((score, t, w));
                                    }
                                }
                            }
                        }
                    }
                }
                if best.is_some() {
                    break;
                }
            }
            let Some((_, t, w)) = best else {
                return Err(Error::InvalidMesh(format!(
                    "surface vertex {v} is more than three cells from the lattice: raise --lattice"
                )));
            };
            let x = mesh.tets[t].map(|i| mesh.positions[i as usize].as_dvec3());
            max_outside = max_outside.max(point_tet_distance(p.as_dvec3(), x, w));
            bindings.push(Binding { p: mesh.tets[t], w: w.map(|v| v as f32) });
        }
        Ok(EmbeddedTets { mesh, bindings, max_outside: max_outside as f32 })
    }
}

/// Positions of the embedded vertices for particle positions `x` (m): `Σ w_k x[p_k]`.
pub fn embedded_positions(bindings: &[Binding], x: &[Vec3]) -> Vec<Vec3> {
    bindings.iter().map(|b| (0..4).fold(Vec3::ZERO, |acc, k| acc + x[b.p[k] as usize] * b.w[k])).collect()
}
