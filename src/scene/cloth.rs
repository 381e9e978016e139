//! The cloth scenes: a 1 m, 1 kg square grid, horizontal at the start.

use glam::{Vec2, Vec3};

use super::{Family, Ground, Scene, SceneOptions, SelfCollision, Sphere};
use crate::constraints::{Bend, BendParams, Membrane, MembraneParams, Orthotropic, Spring, SpringParams};
use crate::error::{Error, Result};
use crate::mesh::{TriMesh, dihedral_pairs, grid, unique_edges};

/// Which cloth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// `cloth`: two corners of one edge pinned, bending on by default.
    Hanging,
    /// `cloth-paper`: the paper's 41×41 cloth with springs only (4880 edges).
    Paper,
    /// `cloth-sphere`: a free cloth dropped onto a sphere resting on the ground.
    Sphere,
    /// `cloth-free`: no pins, no gravity, no ground, stretched by 10% in its plane at the start
    /// (rest lengths are those of the unstretched grid): the clean energy-conservation test.
    Free,
    /// `cloth-drape`: a free cloth held upright (its rest shape flat), its lower edge 5 cm above
    /// the ground and a gentle wave across it, dropped: it piles onto itself in folds.
    Drape,
}

/// `cloth-drape`: height of the lower edge (m) and amplitude of the wave (m) along the cloth's
/// normal, one period over the cloth's height, that decides which way the folds go.
const DRAPE_BASE: f32 = 0.05;
const DRAPE_WAVE: f32 = 0.02;
/// Friction coefficient between the cloth's own layers.
const SELF_FRICTION: f32 = 0.3;
/// The self-collision's default thickness as a multiple of the grid's spacing `s`. At least
/// `1/√2` stops a particle passing between the four of a square; 1.2 also keeps a free edge
/// folding in a Z at the scale of one square and a layer landing at a few thicknesses per
/// substep from crossing (docs/algorithm.md §3.1), where `s` itself leaves a few crossing pairs.
/// Mesh neighbours (rest distance `s`) stay left out; diagonals (`√2 s`) are clear at rest.
const THICKNESS_PER_SPACING: f32 = 1.2;
/// The largest thickness `--thickness` takes, as a multiple of the spacing: within the
/// candidates' reach `1.75 t` a particle of a pile of three layers `t` apart then has about
/// `π (2.6)² − 5 ≈ 17` others in its own layer and `π (2.15)² ≈ 15` in each next one, well
/// within [`crate::solver::self_collision::CAPACITY`] (64).
const MAX_THICKNESS_PER_SPACING: f32 = 1.5;

/// In-plane stretch of `cloth-free` at the start.
const FREE_STRETCH: f32 = 1.1;

const SIZE: f32 = 1.0;
const MASS: f32 = 1.0;
const DEFAULT_RESOLUTION: u32 = 41;
const DEFAULT_BENDING: f32 = 1.0e-3;

pub(super) fn build(kind: Kind, o: &SceneOptions) -> Result<Scene> {
    let n = o.resolution.unwrap_or(DEFAULT_RESOLUTION);
    if let Some(t) = o.thickness
        && t > MAX_THICKNESS_PER_SPACING * SIZE / (n - 1) as f32
    {
        return Err(Error::param(
            "--thickness",
            t,
            "must be at most 1.5 times the grid's spacing, 1 m / (resolution − 1): in a pile of a \
             thicker cloth a particle has more candidates within reach than self-collision keeps",
        ));
    }
    let height = match kind {
        Kind::Sphere => 0.9,
        _ => 1.2,
    };
    let mesh = grid(n, SIZE, height, o.diagonals);
    mesh.validate()?;
    let mut inv_mass: Vec<f32> = mesh.lumped_masses(MASS).iter().map(|m| 1.0 / m).collect();
    if matches!(kind, Kind::Hanging | Kind::Paper) {
        inv_mass[0] = 0.0;
        inv_mass[n as usize - 1] = 0.0;
    }
    let kb = match kind {
        Kind::Paper => o.bending_stiffness.unwrap_or(0.0),
        _ => o.bending_stiffness.unwrap_or(DEFAULT_BENDING),
    };
    let np = mesh.positions.len();
    let edges = unique_edges(&mesh.triangles);
    let edge_rest: Vec<f32> =
        edges.iter().map(|&[a, b]| mesh.positions[a as usize].distance(mesh.positions[b as usize])).collect();
    let (springs, membranes) = match o.membrane {
        Some(moduli) => (None, Some(membranes(&mesh, moduli)?)),
        None => {
            let springs = edges
                .iter()
                .zip(&edge_rest)
                .map(|(&[a, b], &rest)| Spring::new(a, b, rest, o.stiffness, o.material))
                .collect();
            (Some(Family::new(SpringParams { material: o.material }, springs, np)), None)
        }
    };
    let bends = (kb > 0.0).then(|| bending(&mesh, kb));
    let spheres = match kind {
        Kind::Sphere => vec![Sphere { center: Vec3::new(0.1, 0.3, 0.06), radius: 0.3, friction: 0.4 }],
        _ => Vec::new(),
    };
    let name = match kind {
        Kind::Hanging => "cloth",
        Kind::Paper => "cloth-paper",
        Kind::Sphere => "cloth-sphere",
        Kind::Free => "cloth-free",
        Kind::Drape => "cloth-drape",
    };
    let positions = match kind {
        Kind::Free => mesh.positions.iter().map(|p| Vec3::new(p.x * FREE_STRETCH, p.y, p.z * FREE_STRETCH)).collect(),
        // The grid's z (−½..½) becomes the height above the lower edge.
        Kind::Drape => mesh
            .positions
            .iter()
            .map(|p| {
                let up = p.z + SIZE / 2.0;
                Vec3::new(p.x, DRAPE_BASE + up, DRAPE_WAVE * (std::f32::consts::TAU * up / SIZE).sin())
            })
            .collect(),
        _ => mesh.positions.clone(),
    };
    let free = kind == Kind::Free;
    let self_collision = o.self_collision.unwrap_or(super::self_collides_by_default(name)).then(|| SelfCollision {
        thickness: o.thickness.unwrap_or(THICKNESS_PER_SPACING * SIZE / (n - 1) as f32),
        friction: SELF_FRICTION,
        rest: mesh.positions.clone(),
    });
    Ok(Scene {
        name: name.into(),
        positions,
        inv_mass,
        triangles: mesh.triangles,
        edges,
        edge_rest,
        springs,
        bends,
        tets: None,
        membranes,
        embedding: None,
        ground: (!free).then_some(Ground { height: 0.0, friction: 0.5 }),
        spheres,
        gravity: if o.gravity && !free { Vec3::new(0.0, -9.81, 0.0) } else { Vec3::ZERO },
        contact_offset: 0.005,
        self_collision,
    })
}

/// Membrane triangles with the warp along x and the weft along z of the flat rest grid.
fn membranes(mesh: &TriMesh, moduli: Orthotropic) -> Result<Family<Membrane, 3>> {
    let uv: Vec<Vec2> = mesh.positions.iter().map(|p| Vec2::new(p.x, p.z)).collect();
    let elements = mesh
        .triangles
        .iter()
        .map(|&t| Membrane::at_rest(t, &uv).ok_or_else(|| Error::InvalidMesh(format!("degenerate triangle {t:?}"))))
        .collect::<Result<Vec<_>>>()?;
    Ok(Family::new(MembraneParams::new(moduli), elements, mesh.positions.len()))
}

fn bending(mesh: &TriMesh, kb: f32) -> Family<Bend, 4> {
    let bends = dihedral_pairs(&mesh.triangles).into_iter().map(|p| Bend::at_rest(p, &mesh.positions, kb)).collect();
    Family::new(BendParams, bends, mesh.positions.len())
}
