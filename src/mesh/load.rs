//! Reading triangle meshes from Wavefront OBJ (through tobj), with the checks a simulation needs.

use std::path::Path;

use glam::Vec3;

use super::TriMesh;
use crate::error::{Error, Result};

/// Reads the OBJ file at `path`: every object merged into one mesh, polygons split into triangle
/// fans, points, lines, normals, texture coordinates and materials ignored. Fails with a message
/// naming the file and the problem: unreadable, malformed, no faces, an index out of range, a
/// coordinate that is not finite, or a zero-area triangle.
pub fn load_obj(path: &Path) -> Result<TriMesh> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    parse_obj(&bytes).map_err(|e| match e {
        Error::InvalidMesh(m) => Error::InvalidMesh(format!("{}: {m}", path.display())),
        other => other,
    })
}

/// Parses OBJ text (see [`load_obj`]).
pub fn parse_obj(bytes: &[u8]) -> Result<TriMesh> {
    let options = tobj::LoadOptions { triangulate: true, single_index: false, ignore_points: true, ignore_lines: true };
    let mut reader = std::io::BufReader::new(bytes);
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| Err(tobj::LoadError::GenericFailure))
        .map_err(|e| Error::InvalidMesh(format!("not a readable OBJ file: {e}")))?;
    let mut mesh = TriMesh::default();
    for m in &models {
        let base = mesh.positions.len() as u32;
        let p = &m.mesh.positions;
        if p.len() % 3 != 0 {
            return Err(Error::InvalidMesh(format!("object '{}' has a truncated vertex", m.name)));
        }
        let count = (p.len() / 3) as u32;
        mesh.positions.extend(p.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        if m.mesh.indices.len() % 3 != 0 {
            return Err(Error::InvalidMesh(format!("object '{}' has a face that is not a triangle", m.name)));
        }
        for t in m.mesh.indices.chunks_exact(3) {
            if let Some(&i) = t.iter().find(|&&i| i >= count) {
                return Err(Error::InvalidMesh(format!(
                    "object '{}' has a face using vertex {} of {count}",
                    m.name,
                    i + 1
                )));
            }
            mesh.triangles.push([base + t[0], base + t[1], base + t[2]]);
        }
    }
    if mesh.triangles.is_empty() {
        return Err(Error::InvalidMesh("no faces (an OBJ surface needs 'f' lines)".into()));
    }
    mesh.validate()?;
    Ok(mesh)
}
