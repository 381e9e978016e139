//! Edges and dihedral pairs of a triangle mesh.

use std::collections::HashMap;

/// Undirected edges, each once, in order of first appearance (triangle order, then corner
/// order), with the smaller index first.
pub fn unique_edges(triangles: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let mut seen = HashMap::with_capacity(triangles.len() * 2);
    let mut edges = Vec::with_capacity(triangles.len() * 3 / 2 + 1);
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let e = [a.min(b), a.max(b)];
            seen.entry(e).or_insert_with(|| {
                edges.push(e);
            });
        }
    }
    edges
}

/// Interior edges of a consistently oriented mesh as bending stencils `[x₀, x₁, x₂, x₃]`: the
/// shared edge `x₀ → x₁` as it runs in the first triangle, that triangle's third corner `x₂`, and
/// the third corner `x₃` of the triangle holding `x₁ → x₀`. Edges with a third triangle or with
/// inconsistent orientation are left out.
pub fn dihedral_pairs(triangles: &[[u32; 3]]) -> Vec<[u32; 4]> {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(triangles.len() * 3);
    for t in triangles {
        for k in 0..3 {
            directed.insert((t[k], t[(k + 1) % 3]), t[(k + 2) % 3]);
        }
    }
    let mut pairs = Vec::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b, wing) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
            if a < b
                && let Some(&other) = directed.get(&(b, a))
            {
                pairs.push([a, b, wing, other]);
            }
        }
    }
    pairs
}

/// Why `triangles` is not a closed, consistently oriented 2-manifold, or `None` when it is: the
/// first edge used by one triangle only (a hole), by more than two, or twice in the same
/// direction (inconsistent orientation).
pub fn closed_surface_problem(triangles: &[[u32; 3]]) -> Option<String> {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(triangles.len() * 3);
    for t in triangles {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
        }
    }
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let forward = directed[&(a, b)];
            let back = directed.get(&(b, a)).copied().unwrap_or(0);
            if forward + back == 1 {
                return Some(format!("edge ({a}, {b}) borders one triangle only (a hole)"));
            }
            if forward > 1 {
                return Some(format!(
                    "edge ({a}, {b}) runs the same way in {forward} triangles (non-manifold or flipped)"
                ));
            }
            if forward + back > 2 {
                return Some(format!("edge ({a}, {b}) is shared by {} triangles (non-manifold)", forward + back));
            }
        }
    }
    None
}
