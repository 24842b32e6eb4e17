//! File input and output: images (EXR, PNG, Radiance HDR) and meshes (PLY, OBJ, Mitsuba's
//! serialized format).

pub mod atomic;
pub mod exr;
pub mod hdr;
pub mod obj;
pub mod ply;
pub mod png;
pub mod serialized;

use crate::error::{Error, Result};
use crate::shape::TriangleMesh;
use std::path::Path;

/// Loads a mesh by extension (`.obj`, `.ply`, or the first mesh of a `.serialized` file) as
/// Mitsuba would with its defaults: OBJ uvs flipped, smooth normals where the file has none.
pub fn load_mesh(path: impl AsRef<Path>) -> Result<TriangleMesh> {
    let mut m = read_mesh(path)?;
    if m.normals.is_none() {
        m.compute_vertex_normals();
    }
    Ok(m)
}

/// Reads a mesh as [`load_mesh`] does, with the normals of the file only (None if it has none).
pub fn read_mesh(path: impl AsRef<Path>) -> Result<TriangleMesh> {
    let path = path.as_ref();
    Ok(match path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).as_deref() {
        Some("ply") => ply::load_ply(path, false, false)?,
        Some("obj") => obj::load_obj(path, false, true)?,
        Some("serialized") => serialized::load_serialized(path, 0)?,
        _ => return Err(Error::format(path, "cannot read meshes of this type; expected .obj, .ply or .serialized")),
    })
}

/// Parses an `.obj` or `.ply` mesh held in memory (`name` gives the type), with load_mesh's defaults.
pub fn parse_mesh(bytes: &[u8], name: &str) -> std::result::Result<TriangleMesh, String> {
    let ext = Path::new(name).extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    let mut m = match ext.as_deref() {
        Some("obj") => obj::parse_obj(bytes, false, true)?,
        Some("ply") => {
            let d = ply::parse_ply(bytes)?;
            TriangleMesh::with_uvs(d.positions, d.normals, d.uvs, d.indices).map_err(|e| e.to_string())?
        }
        _ => return Err(format!("'{name}': cannot read meshes of this type; expected .obj or .ply")),
    };
    if m.normals.is_none() {
        m.compute_vertex_normals();
    }
    Ok(m)
}
