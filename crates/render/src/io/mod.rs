//! File input and output: images (EXR, PNG, Radiance HDR) and meshes (PLY, OBJ).

pub mod atomic;
pub mod exr;
pub mod hdr;
pub mod obj;
pub mod ply;
pub mod png;

use crate::error::{Error, Result};
use crate::shape::TriangleMesh;
use std::path::Path;

/// Loads a mesh by extension (`.ply` or `.obj`); `face_normals` ignores vertex normals.
pub fn load_mesh(path: impl AsRef<Path>, face_normals: bool) -> Result<TriangleMesh> {
    let path = path.as_ref();
    match path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).as_deref() {
        Some("ply") => ply::load_ply(path, face_normals),
        Some("obj") => obj::load_obj(path, face_normals),
        _ => Err(Error::format(path, "cannot read meshes of this type; expected .ply or .obj")),
    }
}
