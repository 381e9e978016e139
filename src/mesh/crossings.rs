//! Self-intersection of a triangle surface: the pairs of triangles that pass through each other,
//! the measure of a cloth's self-collision (a cloth that interpenetrates has such pairs; one
//! whose layers only touch has none).
//!
//! Two triangles that share no vertex cross when an edge of one pierces the other: segment
//! `p + t (q − p)`, `t ∈ [0, 1]`, meets the triangle's interior or boundary (Möller and Trumbore
//! 1997). Triangles that share a vertex (neighbours in the mesh, which touch by construction) are
//! not counted; coplanar overlaps (measure zero in a simulation) are not detected. The broad phase
//! sorts the triangles' bounding boxes along x and sweeps.

use glam::Vec3;

/// The pairs `(a, b)`, `a < b`, of `triangles` over `positions` that share no vertex and pass
/// through each other, in increasing order.
pub fn crossing_pairs(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let corners = |t: &[u32; 3]| t.map(|i| positions[i as usize]);
    let boxes: Vec<(Vec3, Vec3)> = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = corners(t);
            (a.min(b).min(c), a.max(b).max(c))
        })
        .collect();
    let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
    order.sort_by(|&i, &j| boxes[i as usize].0.x.total_cmp(&boxes[j as usize].0.x));
    let mut out = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let (lo, hi) = boxes[i as usize];
        for &j in &order[k + 1..] {
            let (lo_j, hi_j) = boxes[j as usize];
            if lo_j.x > hi.x {
                break;
            }
            let overlap = lo.cmple(hi_j).all() && lo_j.cmple(hi).all();
            let (ti, tj) = (&triangles[i as usize], &triangles[j as usize]);
            if overlap && !ti.iter().any(|v| tj.contains(v)) && cross(corners(ti), corners(tj)) {
                out.push((i.min(j), i.max(j)));
            }
        }
    }
    out.sort_unstable();
    out
}

/// `true` when an edge of either triangle pierces the other.
fn cross(a: [Vec3; 3], b: [Vec3; 3]) -> bool {
    let pierces = |edges: [Vec3; 3], tri: [Vec3; 3]| (0..3).any(|e| segment_hits(edges[e], edges[(e + 1) % 3], tri));
    pierces(a, b) || pierces(b, a)
}

/// `true` when the segment `p → q` meets the triangle `t` (Möller–Trumbore, `t ∈ [0, 1]`).
fn segment_hits(p: Vec3, q: Vec3, t: [Vec3; 3]) -> bool {
    let d = q - p;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let h = d.cross(e2);
    let det = e1.dot(h);
    // Parallel to the plane (or a degenerate triangle): no transversal crossing.
    if det.abs() <= 1e-12 * e1.length_squared().max(e2.length_squared()) * d.length() {
        return false;
    }
    let inv = 1.0 / det;
    let s = p - t[0];
    let u = s.dot(h) * inv;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let qv = s.cross(e1);
    let v = d.dot(qv) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let along = e2.dot(qv) * inv;
    (0.0..=1.0).contains(&along)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Diagonals, grid};

    #[test]
    fn a_flat_sheet_has_no_crossings_and_a_pierced_one_has() {
        let sheet = grid(9, 1.0, 0.5, Diagonals::Uniform);
        assert!(crossing_pairs(&sheet.positions, &sheet.triangles).is_empty());
        // A vertical triangle through the sheet, apart from it in the index space.
        let mut positions = sheet.positions.clone();
        let base = positions.len() as u32;
        positions.extend([Vec3::new(0.01, 0.2, 0.02), Vec3::new(0.03, 0.8, 0.01), Vec3::new(0.2, 0.3, 0.04)]);
        let mut triangles = sheet.triangles.clone();
        triangles.push([base, base + 1, base + 2]);
        let pairs = crossing_pairs(&positions, &triangles);
        assert!(!pairs.is_empty() && pairs.len() <= 4, "{pairs:?}");
        assert!(pairs.iter().all(|&(_, b)| b == triangles.len() as u32 - 1));
        // Lifted just above the sheet it touches nothing.
        for p in &mut positions[base as usize..] {
            p.y += 0.31;
        }
        assert!(crossing_pairs(&positions, &triangles).is_empty());
    }

    #[test]
    fn two_layers_cross_only_where_one_passes_through_the_other() {
        // Two stacked sheets 1 cm apart: none; the upper one's centre pushed through: some.
        let lower = grid(11, 1.0, 0.5, Diagonals::Uniform);
        let upper = grid(11, 1.0, 0.51, Diagonals::Alternating);
        let n = lower.positions.len() as u32;
        let mut positions = [lower.positions.clone(), upper.positions.clone()].concat();
        let triangles: Vec<[u32; 3]> =
            lower.triangles.iter().copied().chain(upper.triangles.iter().map(|t| t.map(|v| v + n))).collect();
        assert!(crossing_pairs(&positions, &triangles).is_empty());
        let centre = n as usize + 60;
        positions[centre].y -= 0.05;
        let pairs = crossing_pairs(&positions, &triangles);
        assert!(!pairs.is_empty());
        assert!(pairs.iter().all(|&(a, b)| a < lower.triangles.len() as u32 && b >= lower.triangles.len() as u32));
    }
}
