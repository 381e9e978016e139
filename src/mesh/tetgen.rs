//! Reading tetrahedral meshes in TetGen's `.node` / `.ele` form.

use std::path::{Path, PathBuf};

use glam::Vec3;

use super::TetMesh;
use crate::error::{Error, Result};

/// Reads `base.node` and `base.ele` for `path` = `base.node`, `base.ele` or `base`. Points may be
/// numbered from 0 or 1 (as the first point says); attributes, boundary markers and the extra
/// nodes of 10-node tetrahedra are ignored. Fails with the file, line and problem on malformed
/// input, indices out of range and non-finite coordinates.
pub fn load_tetgen(path: &Path) -> Result<TetMesh> {
    let base: PathBuf = match path.extension().and_then(|e| e.to_str()) {
        Some("node" | "ele") => path.with_extension(""),
        _ => path.to_path_buf(),
    };
    let read = |ext: &str| {
        let p = base.with_extension(ext);
        std::fs::read_to_string(&p).map(|t| (p.clone(), t)).map_err(|source| Error::Io { path: p, source })
    };
    let (node_path, nodes) = read("node")?;
    let (ele_path, eles) = read("ele")?;
    parse_tetgen(&nodes, &eles).map_err(|e| match e {
        Error::InvalidMesh(m) => Error::InvalidMesh(format!("{} / {}: {m}", node_path.display(), ele_path.display())),
        other => other,
    })
}

/// Lines of `text` without comments and blank lines, with their 1-based line numbers.
fn records(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(n, l)| {
        let l = l.split('#').next().unwrap_or("");
        let fields: Vec<&str> = l.split_whitespace().collect();
        (!fields.is_empty()).then_some((n + 1, fields))
    })
}

fn number<T: std::str::FromStr>(what: &str, line: usize, s: &str) -> Result<T> {
    s.parse().map_err(|_| Error::InvalidMesh(format!("{what} line {line}: '{s}' is not a number")))
}

/// Parses the text of a `.node` and an `.ele` file (see [`load_tetgen`]).
pub fn parse_tetgen(node: &str, ele: &str) -> Result<TetMesh> {
    let mut lines = records(node);
    let Some((line, header)) = lines.next() else { return Err(Error::InvalidMesh(".node: empty".into())) };
    let count: usize = number(".node", line, header[0])?;
    if header.get(1).is_some_and(|d| *d != "3") {
        return Err(Error::InvalidMesh(format!(".node line {line}: dimension {} (3 needed)", header[1])));
    }
    let mut positions = Vec::with_capacity(count.min(1 << 24));
    let mut first = None;
    for (line, f) in lines.take(count) {
        if f.len() < 4 {
            return Err(Error::InvalidMesh(format!(".node line {line}: a point needs an index and x y z")));
        }
        let index: usize = number(".node", line, f[0])?;
        first.get_or_insert(index);
        let p = Vec3::new(number(".node", line, f[1])?, number(".node", line, f[2])?, number(".node", line, f[3])?);
        if !p.is_finite() {
            return Err(Error::InvalidMesh(format!(".node line {line}: coordinates are not finite")));
        }
        positions.push(p);
    }
    if positions.len() != count {
        return Err(Error::InvalidMesh(format!(".node: {count} points announced, {} found", positions.len())));
    }
    let offset = first.unwrap_or(0);
    if offset > 1 {
        return Err(Error::InvalidMesh(format!(".node: points numbered from {offset} (0 or 1 expected)")));
    }
    let mut lines = records(ele);
    let Some((line, header)) = lines.next() else { return Err(Error::InvalidMesh(".ele: empty".into())) };
    let count: usize = number(".ele", line, header[0])?;
    let mut tets = Vec::with_capacity(count.min(1 << 24));
    for (line, f) in lines.take(count) {
        if f.len() < 5 {
            return Err(Error::InvalidMesh(format!(".ele line {line}: a tetrahedron needs an index and 4 nodes")));
        }
        let mut t = [0u32; 4];
        for k in 0..4 {
            let i: usize = number(".ele", line, f[k + 1])?;
            if i < offset || i - offset >= positions.len() {
                return Err(Error::InvalidMesh(format!(".ele line {line}: node {i} is not a point")));
            }
            t[k] = (i - offset) as u32;
        }
        tets.push(t);
    }
    if tets.len() != count || count == 0 {
        return Err(Error::InvalidMesh(format!(".ele: {count} tetrahedra announced, {} found", tets.len())));
    }
    Ok(TetMesh { positions, tets })
}
