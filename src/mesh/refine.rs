//! Longest-edge bisection of a triangle mesh, to reach a face count.

use std::collections::{BinaryHeap, HashMap};

use super::TriMesh;

/// An edge in the queue, ordered by length (longest first), ties by the smaller indices.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Queued {
    length2: f32,
    edge: [u32; 2],
}

impl Eq for Queued {}

impl PartialOrd for Queued {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Queued {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.length2.total_cmp(&other.length2).then_with(|| other.edge.cmp(&self.edge))
    }
}

impl TriMesh {
    /// Splits the longest edge at its midpoint, over and over, until the mesh has at least
    /// `faces` triangles. On a closed mesh each split adds one vertex, three edges and two faces
    /// (a boundary edge adds one face), so a closed genus-0 surface of `F` faces reaches exactly
    /// `V = F/2 + 2` and `E = 3F/2`. Orientation is kept.
    pub fn refine_to_faces(&self, faces: usize) -> TriMesh {
        let mut mesh = self.clone();
        // Directed edge → the triangle holding it.
        let mut owner: HashMap<(u32, u32), usize> = HashMap::with_capacity(faces * 3);
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                owner.insert((tri[k], tri[(k + 1) % 3]), t);
            }
        }
        let length2 = |m: &TriMesh, [a, b]: [u32; 2]| m.positions[a as usize].distance_squared(m.positions[b as usize]);
        let mut heap: BinaryHeap<Queued> = owner
            .keys()
            .filter(|(a, b)| a < b || !owner.contains_key(&(*b, *a)))
            .map(|&(a, b)| {
                let edge = [a.min(b), a.max(b)];
                Queued { length2: length2(&mesh, edge), edge }
            })
            .collect();
        while mesh.triangles.len() < faces {
            let Some(q) = heap.pop() else { break };
            let [a, b] = q.edge;
            let sides: Vec<(u32, u32, usize)> =
                [(a, b), (b, a)].into_iter().filter_map(|(u, v)| owner.get(&(u, v)).map(|&t| (u, v, t))).collect();
            if sides.is_empty() {
                continue; // split already
            }
            let m = mesh.positions.len() as u32;
            mesh.positions.push((mesh.positions[a as usize] + mesh.positions[b as usize]) * 0.5);
            for (u, v, t) in sides {
                let tri = mesh.triangles[t];
                let k = (0..3).find(|&k| tri[k] == u && tri[(k + 1) % 3] == v).unwrap_or(0);
                let w = tri[(k + 2) % 3];
                // (u, v, w) → (u, m, w) in place and (m, v, w) appended.
                mesh.triangles[t] = [u, m, w];
                let new = mesh.triangles.len();
                mesh.triangles.push([m, v, w]);
                owner.remove(&(u, v));
                owner.insert((u, m), t);
                owner.insert((m, w), t);
                owner.insert((w, u), t);
                owner.insert((m, v), new);
                owner.insert((v, w), new);
                owner.insert((w, m), new);
                // The halves of (a, b) are queued by both sides; a stale or repeated entry is
                // skipped when popped, since its directed edges no longer exist.
                for e in [[u, m], [m, v], [m, w]] {
                    let edge = [e[0].min(e[1]), e[0].max(e[1])];
                    heap.push(Queued { length2: length2(&mesh, edge), edge });
                }
            }
        }
        mesh
    }
}
