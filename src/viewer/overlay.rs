//! Segments drawn over the scene: the surface wireframe, and every element of a family as its
//! edges in the colour of its color group (static: built once per scene).

use crate::constraints::Element;
use crate::mesh::unique_edges;
use crate::scene::{Family, Scene};

/// Colour of the wireframe (linear RGB).
pub const WIRE_COLOR: [f32; 3] = [0.02, 0.02, 0.03];

/// The colour of color group `c`: hues a golden angle apart, so neighbouring groups differ
/// clearly (linear RGB).
pub fn group_color(c: usize) -> [f32; 3] {
    let h = (c as f32 * 0.381_966).fract() * 6.0;
    let (s, v) = (0.8f32, 0.95f32);
    let f = h.fract();
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    let rgb = match h as u32 {
        0 => [v, t, p],
        1 => [q, v, p],
        2 => [p, v, t],
        3 => [p, q, v],
        4 => [t, p, v],
        _ => [v, p, q],
    };
    rgb.map(|x| x.powf(2.2))
}

/// The surface's edges.
pub fn wireframe(scene: &Scene) -> Vec<[u32; 2]> {
    unique_edges(&scene.triangles)
}

/// One constraint family as the color-group view shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct GroupView {
    /// The family's name.
    pub name: &'static str,
    /// Number of elements.
    pub elements: usize,
    /// Number of color groups.
    pub colors: usize,
    /// Segments: the elements' edges (a spring itself, a triangle's three edges, a bending
    /// element's hinge, a tetrahedron's six edges).
    pub segments: Vec<[u32; 2]>,
    /// Colour of each segment: its element's color group.
    pub segment_colors: Vec<[f32; 3]>,
}

fn view<E: Element<N>, const N: usize>(name: &'static str, f: &Family<E, N>) -> GroupView {
    let (mut segments, mut segment_colors) = (Vec::new(), Vec::new());
    for (c, range) in f.colors.iter().enumerate() {
        for e in &f.elements[range.start as usize..range.end as usize] {
            let edges = e.outline();
            segment_colors.extend(std::iter::repeat_n(group_color(c), edges.len()));
            segments.extend(edges);
        }
    }
    GroupView { name, elements: f.len(), colors: f.colors.len(), segments, segment_colors }
}

/// The color-group views of every family of `scene`, in solve order.
pub fn group_views(scene: &Scene) -> Vec<GroupView> {
    let mut out = Vec::new();
    crate::for_each_family!(scene, |i, f| out.push(view(crate::scene::FAMILY_LABELS[i], f)));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{self, SceneOptions};

    #[test]
    fn group_views_cover_every_element_with_its_group_colour() {
        let s = scene::build("cloth", &SceneOptions { resolution: Some(6), ..SceneOptions::default() }).unwrap();
        let views = group_views(&s);
        assert_eq!(views.iter().map(|v| v.name).collect::<Vec<_>>(), ["springs", "bending"]);
        let springs = &views[0];
        assert_eq!(springs.segments.len(), s.springs.as_ref().unwrap().len());
        assert_eq!(springs.segments.len(), springs.segment_colors.len());
        let distinct: std::collections::HashSet<[u32; 3]> =
            springs.segment_colors.iter().map(|c| c.map(f32::to_bits)).collect();
        assert_eq!(distinct.len(), springs.colors);
        let cube = scene::build("cube", &SceneOptions { resolution: Some(2), ..SceneOptions::default() }).unwrap();
        let tets = &group_views(&cube)[0];
        assert_eq!(tets.segments.len(), 6 * tets.elements);
        assert_eq!(wireframe(&s).len(), s.edges.len());
    }
}
