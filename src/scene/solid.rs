//! Volumetric scenes: a cantilever beam and a cube, tetrahedralized boxes of 1000 kg/m³; and the
//! scene of any tetrahedral mesh (the bunny's bodies use it too).

use glam::Vec3;

use super::{Embedding, Family, Ground, Scene, SceneOptions, TetMode};
use crate::constraints::{Tet, TetParams};
use crate::error::{Error, Result};
use crate::material::{Elastic, Model};
use crate::mesh::{TetMesh, unique_edges};

/// Which solid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// `beam`: 1 m × 0.2 m × 0.2 m cantilever, its `x = −0.5` end fixed, under gravity.
    Beam,
    /// `cube`: a 0.3 m cube dropped from 0.4 m onto the ground.
    Cube,
}

/// Density of the volumetric bodies (kg/m³).
pub const DENSITY: f32 = 1000.0;

/// The most tetrahedra a box scene may have (2²⁴, about 3 GiB of solver state on the CPU):
/// `--resolution` up to 140 for the cube, 414 for the beam.
pub const MAX_BOX_TETS: u64 = 1 << 24;

pub(super) fn build(kind: Kind, o: &SceneOptions) -> Result<Scene> {
    let (cells, corners, name) = match kind {
        Kind::Beam => {
            let n = o.resolution.unwrap_or(10);
            let across = (n / 5).max(1);
            ([n, across, across], (Vec3::new(-0.5, 0.9, -0.1), Vec3::new(0.5, 1.1, 0.1)), "beam")
        }
        Kind::Cube => {
            let n = o.resolution.unwrap_or(4);
            ([n, n, n], (Vec3::new(-0.15, 0.4, -0.15), Vec3::new(0.15, 0.7, 0.15)), "cube")
        }
    };
    // Six tetrahedra a cell.
    if 6 * cells.iter().map(|&c| c as u64).product::<u64>() > MAX_BOX_TETS {
        let reason = "more than 2^24 (16.8 million) tetrahedra: at most 140 for the cube, 414 for the beam";
        return Err(Error::param("--resolution", cells[0], reason));
    }
    let mesh = TetMesh::box_grid(cells, corners.0, corners.1);
    let mesh = match o.tets {
        TetMode::Volume => mesh,
        TetMode::Centroid => TetMesh::centroid_fan(&mesh.positions, &mesh.boundary())?,
    };
    let pinned = |p: Vec3| kind == Kind::Beam && p.x <= -0.5 + 1e-6;
    tet_scene(name, mesh, o, &pinned, None)
}

/// The scene of tetrahedral `mesh` with the options' 3D model, particles where `pinned` holds
/// fixed, a ground at y = 0, drawn by its boundary or by `embedding`.
pub(super) fn tet_scene(
    name: &str,
    mesh: TetMesh,
    o: &SceneOptions,
    pinned: &dyn Fn(Vec3) -> bool,
    embedding: Option<Embedding>,
) -> Result<Scene> {
    let model = o.solid.unwrap_or(Model::NeoHookean);
    let elastic = Elastic::new(model, o.young, o.poisson)?;
    let np = mesh.positions.len();
    let mut inv_mass: Vec<f32> = mesh.lumped_masses(DENSITY).iter().map(|m| 1.0 / m).collect();
    for (w, p) in inv_mass.iter_mut().zip(&mesh.positions) {
        if pinned(*p) {
            *w = 0.0;
        }
    }
    let tets = mesh
        .tets
        .iter()
        .map(|&t| {
            Tet::at_rest(t, &mesh.positions).ok_or_else(|| Error::InvalidMesh(format!("degenerate tetrahedron {t:?}")))
        })
        .collect::<Result<Vec<_>>>()?;
    let faces: Vec<[u32; 3]> = mesh
        .tets
        .iter()
        .flat_map(|t| [[t[0], t[1], t[2]], [t[0], t[1], t[3]], [t[0], t[2], t[3]], [t[1], t[2], t[3]]])
        .collect();
    let edges = unique_edges(&faces);
    let edge_rest =
        edges.iter().map(|&[a, b]| mesh.positions[a as usize].distance(mesh.positions[b as usize])).collect();
    Ok(Scene {
        name: name.into(),
        triangles: mesh.boundary(),
        inv_mass,
        edges,
        edge_rest,
        springs: None,
        bends: None,
        tets: Some(Family::new(TetParams { elastic, scale: o.young }, tets, np)),
        membranes: None,
        embedding,
        ground: Some(Ground { height: 0.0, friction: 0.5 }),
        spheres: Vec::new(),
        gravity: if o.gravity { Vec3::new(0.0, -9.81, 0.0) } else { Vec3::ZERO },
        contact_offset: 0.002,
        self_collision: None,
        positions: mesh.positions,
    })
}
