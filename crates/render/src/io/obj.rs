//! Wavefront OBJ meshes through the `tobj` crate: every object in the file merged into one
//! triangle mesh (polygons triangulated), with vertex normals when every vertex has one.

use crate::error::{Error, Result};
use crate::shape::TriangleMesh;
use glam::Vec3;
use std::path::Path;

/// Loads an OBJ file as one triangle mesh; `face_normals` drops any vertex normals.
pub fn load_obj(path: &Path, face_normals: bool) -> Result<TriangleMesh> {
    let opts = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, _materials) = tobj::load_obj(path, &opts).map_err(|e| match e {
        tobj::LoadError::OpenFileFailed => {
            Error::io(path, std::fs::File::open(path).err().unwrap_or_else(|| std::io::Error::other("cannot open")))
        }
        other => Error::format(path, format!("not a valid OBJ file: {other}")),
    })?;
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut indices = Vec::new();
    let mut all_normals = true;
    for m in &models {
        let mesh = &m.mesh;
        let base = positions.len() as u32;
        let nv = mesh.positions.len() / 3;
        positions.extend(mesh.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        if mesh.normals.len() == mesh.positions.len() {
            normals.extend(mesh.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        } else {
            all_normals = false;
        }
        for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
            if tri.iter().any(|&i| i as usize >= nv) {
                return Err(Error::format(path, format!("object '{}' face {t} refers to a missing vertex", m.name)));
            }
            indices.push([base + tri[0], base + tri[1], base + tri[2]]);
        }
    }
    if indices.is_empty() {
        return Err(Error::format(path, "no faces"));
    }
    let normals = (all_normals && !face_normals).then_some(normals);
    TriangleMesh::new(positions, normals, indices).map_err(|e| Error::format(path, e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_with_normals_and_errors() {
        let dir = std::env::temp_dir().join(format!("gonio-render-obj-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("quad.obj");
        std::fs::write(&p, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 4//1\n").unwrap();
        let m = load_obj(&p, false).unwrap();
        assert_eq!(m.len(), 2);
        assert!((m.area() - 1.0).abs() < 1e-6);
        assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::Z);
        assert!(load_obj(&p, true).unwrap().normals.is_none());
        let bad = dir.join("bad.obj");
        std::fs::write(&bad, "v 0 0 zero\nf 1 1 1\n").unwrap();
        let e = load_obj(&bad, false).unwrap_err().to_string();
        assert!(e.contains("bad.obj"), "{e}");
        let e = load_obj(&dir.join("missing.obj"), false).unwrap_err().to_string();
        assert!(e.contains("missing.obj"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
        // The shared Suzanne, when present: 968 triangles.
        let s = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes/suzanne.obj");
        if s.exists() {
            assert_eq!(load_obj(&s, false).unwrap().len(), 968);
        }
    }
}
