//! Wavefront OBJ export.

use std::io::Write;
use std::path::Path;

use glam::Vec3;

use crate::error::{Error, Result};

/// Writes positions (m) and triangles as a Wavefront OBJ file (1-based indices).
pub fn write_obj(path: &Path, positions: &[Vec3], triangles: &[[u32; 3]]) -> Result<()> {
    let io = |source| Error::Io { path: path.to_path_buf(), source };
    let file = std::fs::File::create(path).map_err(io)?;
    let mut w = std::io::BufWriter::new(file);
    writeln!(w, "# eapbd export: {} vertices, {} triangles, metres", positions.len(), triangles.len()).map_err(io)?;
    for p in positions {
        writeln!(w, "v {} {} {}", p.x, p.y, p.z).map_err(io)?;
    }
    for t in triangles {
        writeln!(w, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).map_err(io)?;
    }
    w.flush().map_err(io)
}
