//! The bunny scenes, and any closed surface turned into a body: a spring network on its edges,
//! the paper's centroid tetrahedra, or a volumetric lattice with the surface embedded.

use glam::Vec3;

use super::solid::tet_scene;
use super::{Embedding, Family, Ground, Scene, SceneOptions};
use crate::constraints::{Bend, BendParams, Spring, SpringParams};
use crate::error::{Error, Result};
use crate::mesh::{EmbeddedTets, TetMesh, TriMesh, dihedral_pairs, parse_obj, unique_edges};

/// How a closed surface becomes a simulated body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Body {
    /// Springs on the surface edges (with dihedral bending unless `--bending-stiffness 0`);
    /// open surfaces are allowed.
    Springs,
    /// The paper's tetrahedra: each surface triangle with the centroid.
    CentroidTets,
    /// A volumetric lattice of tetrahedra with the surface embedded in it.
    Volume,
}

crate::error::command_names!(Body, "body", {
    Springs => "springs",
    CentroidTets => "centroid-tets",
    Volume => "volume",
});

/// Which bunny.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// `bunny`: a volumetric Neo-Hookean bunny dropped onto the ground.
    Drop,
    /// `bunny-paper`: the paper's setting, the surface refined to 8192 faces, a spring network by
    /// default, hanging by its ears.
    Paper,
}

/// The Stanford bunny of `assets/bunny.obj` (public domain; see `assets/README.md`).
const BUNNY_OBJ: &[u8] = include_bytes!("../../assets/bunny.obj");

/// Height the surface is scaled to (m).
pub const HEIGHT: f32 = 0.3;

/// Faces of the paper's bunny (4098 vertices, 12288 edges).
pub const PAPER_FACES: usize = 8192;

/// Lattice cells along the longest side by default.
pub const DEFAULT_LATTICE: u32 = 16;

/// Area density of the spring body's shell (kg/m², as the cloth's).
pub const SHELL_DENSITY: f32 = 1.0;

/// Default dihedral bending of the spring body (N·m/rad).
const DEFAULT_BENDING: f32 = 1.0e-3;

/// The bunny, scaled to [`HEIGHT`], its base centred at the origin on y = 0.
pub fn bunny_surface() -> Result<TriMesh> {
    normalized(parse_obj(BUNNY_OBJ)?)
}

/// The widest a mesh may be for its height (`--mesh`): scaled to [`HEIGHT`] tall, a wider one
/// would span hundreds of metres, far beyond the precision its particles keep.
pub const MAX_ASPECT: f32 = 1000.0;

/// `surface` scaled uniformly to [`HEIGHT`] tall and moved so its base is centred on the origin;
/// an error when it has next to no height for its width ([`MAX_ASPECT`]) or a triangle of zero
/// area at that scale.
fn normalized(mut surface: TriMesh) -> Result<TriMesh> {
    let (lo, hi) = surface.positions.iter().fold((Vec3::MAX, Vec3::MIN), |(a, b), &p| (a.min(p), b.max(p)));
    let (height, widest) = (hi.y - lo.y, (hi - lo).max_element());
    if !(height * MAX_ASPECT >= widest && height > 0.0) {
        return Err(Error::InvalidMesh(format!(
            "the mesh is {height:e} tall and {widest:e} wide: scaled to {HEIGHT} m tall, it needs a height of at \
             least 1/{MAX_ASPECT} of its width"
        )));
    }
    let scale = HEIGHT / height;
    let base = Vec3::new(0.5 * (lo.x + hi.x), lo.y, 0.5 * (lo.z + hi.z));
    for p in &mut surface.positions {
        *p = (*p - base) * scale;
    }
    surface.validate()?;
    Ok(surface)
}

/// Builds a bunny scene from the bunny or from `surface` (a user's mesh).
pub(super) fn build(kind: Kind, o: &SceneOptions, surface: Option<TriMesh>) -> Result<Scene> {
    let surface = match surface {
        Some(s) => {
            s.validate()?;
            normalized(s)?
        }
        None => bunny_surface()?,
    };
    let (name, body, lift) = match kind {
        Kind::Drop => ("bunny", o.body.unwrap_or(Body::Volume), 0.15),
        Kind::Paper => ("bunny-paper", o.body.unwrap_or(Body::Springs), 0.25),
    };
    let mut surface = match kind {
        Kind::Paper => {
            // Refinement appends its vertices at the end; renumber them all in space.
            let mut s = surface.refine_to_faces(PAPER_FACES);
            s.reorder_spatially();
            s
        }
        Kind::Drop => surface,
    };
    for p in &mut surface.positions {
        p.y += lift;
    }
    // The paper's bunny hangs by the tips of its ears (the top 4% of its height).
    let top = surface.positions.iter().map(|p| p.y).fold(f32::MIN, f32::max);
    let hanging = kind == Kind::Paper;
    let pinned = move |p: Vec3| hanging && p.y >= top - 0.04 * HEIGHT;
    if body != Body::Springs {
        surface.validate_closed()?;
    }
    match body {
        Body::Springs => springs(name, &surface, o, &pinned),
        Body::CentroidTets => {
            tet_scene(name, TetMesh::centroid_fan(&surface.positions, &surface.triangles)?, o, &pinned, None)
        }
        Body::Volume => {
            let e = EmbeddedTets::from_surface(&surface, o.lattice.unwrap_or(DEFAULT_LATTICE))?;
            // Contacts act on the particles: keep them as far from the ground as the surface
            // hangs below its tetrahedra's lowest particle, so the drawn surface touches it.
            let below = e
                .bindings
                .iter()
                .zip(&surface.positions)
                .map(|(b, p)| b.p.iter().map(|&i| e.mesh.positions[i as usize].y).fold(f32::MAX, f32::min) - p.y)
                .fold(0.0f32, f32::max);
            let embedding = Embedding { bindings: e.bindings, triangles: surface.triangles };
            let mut scene = tet_scene(name, e.mesh, o, &pinned, Some(embedding))?;
            scene.contact_offset = scene.contact_offset.max(below);
            Ok(scene)
        }
    }
}

/// Builds a bunny scene from a tetrahedral mesh, scaled and placed as a surface would be.
pub(super) fn build_tets(kind: Kind, o: &SceneOptions, mut tets: TetMesh) -> Result<Scene> {
    if let Some(i) = tets.positions.iter().position(|p| !p.is_finite()) {
        return Err(Error::InvalidMesh(format!("vertex {i} is not finite")));
    }
    let placed = normalized(TriMesh { positions: tets.positions, triangles: Vec::new() })?;
    tets.positions = placed.positions;
    let lift = if kind == Kind::Paper { 0.25 } else { 0.15 };
    for p in &mut tets.positions {
        p.y += lift;
    }
    let top = tets.positions.iter().map(|p| p.y).fold(f32::MIN, f32::max);
    let hanging = kind == Kind::Paper;
    let pinned = move |p: Vec3| hanging && p.y >= top - 0.04 * HEIGHT;
    let name = if kind == Kind::Paper { "bunny-paper" } else { "bunny" };
    tet_scene(name, tets, o, &pinned, None)
}

/// A spring network on the surface's edges (stiffness `--stiffness`, the spring material of the
/// options) and dihedral bending on its interior edges: a hollow shell of [`SHELL_DENSITY`], its
/// mass lumped by area.
fn springs(name: &str, surface: &TriMesh, o: &SceneOptions, pinned: &dyn Fn(Vec3) -> bool) -> Result<Scene> {
    let np = surface.positions.len();
    let area: f32 = (0..surface.triangles.len()).map(|t| surface.area(t)).sum();
    let mass = SHELL_DENSITY * area;
    let mut inv_mass: Vec<f32> = surface.lumped_masses(mass).iter().map(|m| 1.0 / m).collect();
    for (w, p) in inv_mass.iter_mut().zip(&surface.positions) {
        if pinned(*p) {
            *w = 0.0;
        }
    }
    let edges = unique_edges(&surface.triangles);
    let edge_rest: Vec<f32> =
        edges.iter().map(|&[a, b]| surface.positions[a as usize].distance(surface.positions[b as usize])).collect();
    let springs =
        edges.iter().zip(&edge_rest).map(|(&[a, b], &l)| Spring::new(a, b, l, o.stiffness, o.material)).collect();
    let kb = o.bending_stiffness.unwrap_or(DEFAULT_BENDING);
    let bends = (kb > 0.0).then(|| {
        let b =
            dihedral_pairs(&surface.triangles).into_iter().map(|p| Bend::at_rest(p, &surface.positions, kb)).collect();
        Family::new(BendParams, b, np)
    });
    Ok(Scene {
        name: name.into(),
        positions: surface.positions.clone(),
        inv_mass,
        triangles: surface.triangles.clone(),
        edges,
        edge_rest,
        springs: Some(Family::new(SpringParams { material: o.material }, springs, np)),
        bends,
        tets: None,
        membranes: None,
        embedding: None,
        ground: Some(Ground { height: 0.0, friction: 0.5 }),
        spheres: Vec::new(),
        gravity: if o.gravity { Vec3::new(0.0, -9.81, 0.0) } else { Vec3::ZERO },
        contact_offset: 0.002,
        self_collision: None,
    })
}
