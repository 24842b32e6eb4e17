//! Wavefront OBJ meshes through the `tobj` crate: every object in the file merged into one
//! triangle mesh (polygons fanned from their first corner), one vertex per distinct
//! (position, uv, normal) triple as Mitsuba 3 welds them, with vertex normals and uvs when every
//! vertex has one; uvs are stored as (u, 1 − v) unless told otherwise (Mitsuba's
//! `flip_tex_coords`, on by default for OBJ).

use crate::error::{Error, Result};
use crate::shape::TriangleMesh;
use glam::{Vec2, Vec3};
use std::path::Path;

/// Loads an OBJ file as one triangle mesh; `face_normals` drops any vertex normals, `flip_v`
/// stores 1 − v.
pub fn load_obj(path: &Path, face_normals: bool, flip_v: bool) -> Result<TriangleMesh> {
    let opts = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, _materials) = tobj::load_obj(path, &opts).map_err(|e| match e {
        tobj::LoadError::OpenFileFailed => {
            Error::io(path, std::fs::File::open(path).err().unwrap_or_else(|| std::io::Error::other("cannot open")))
        }
        other => Error::format(path, format!("not a valid OBJ file: {other}")),
    })?;
    mesh(&models, face_normals, flip_v).map_err(|m| Error::format(path, m))
}

/// Parses OBJ text (an embedded asset) as one triangle mesh.
pub fn parse_obj(text: &[u8], face_normals: bool, flip_v: bool) -> std::result::Result<TriangleMesh, String> {
    let opts = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, _) =
        tobj::load_obj_buf(&mut std::io::Cursor::new(text), &opts, |_| Err(tobj::LoadError::OpenFileFailed))
            .map_err(|e| format!("not a valid OBJ file: {e}"))?;
    mesh(&models, face_normals, flip_v)
}

fn mesh(models: &[tobj::Model], face_normals: bool, flip_v: bool) -> std::result::Result<TriangleMesh, String> {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    let mut indices = Vec::new();
    let (mut all_normals, mut all_uvs) = (true, true);
    for m in models {
        let mesh = &m.mesh;
        let base = positions.len() as u32;
        let nv = mesh.positions.len() / 3;
        positions.extend(mesh.positions.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        if mesh.normals.len() == mesh.positions.len() {
            normals.extend(mesh.normals.chunks_exact(3).map(|c| Vec3::new(c[0], c[1], c[2])));
        } else {
            all_normals = false;
        }
        if mesh.texcoords.len() == 2 * nv {
            uvs.extend(mesh.texcoords.chunks_exact(2).map(|c| Vec2::new(c[0], if flip_v { 1.0 - c[1] } else { c[1] })));
        } else {
            all_uvs = false;
        }
        for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
            if tri.iter().any(|&i| i as usize >= nv) {
                return Err(format!("object '{}' face {t} refers to a missing vertex", m.name));
            }
            indices.push([base + tri[0], base + tri[1], base + tri[2]]);
        }
    }
    if indices.is_empty() {
        return Err("no faces".into());
    }
    let normals = (all_normals && !face_normals).then_some(normals);
    let uvs = all_uvs.then_some(uvs);
    TriangleMesh::with_uvs(positions, normals, uvs, indices).map_err(|e| e.to_string())
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
        let m = load_obj(&p, false, true).unwrap();
        assert_eq!(m.len(), 2);
        assert!((m.area() - 1.0).abs() < 1e-6);
        assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::Z);
        assert!(load_obj(&p, true, true).unwrap().normals.is_none());
        let bad = dir.join("bad.obj");
        std::fs::write(&bad, "v 0 0 zero\nf 1 1 1\n").unwrap();
        let e = load_obj(&bad, false, true).unwrap_err().to_string();
        assert!(e.contains("bad.obj"), "{e}");
        let e = load_obj(&dir.join("missing.obj"), false, true).unwrap_err().to_string();
        assert!(e.contains("missing.obj"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
        // The shared Suzanne, when present: 968 triangles.
        let s = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/meshes/suzanne.obj");
        if s.exists() {
            assert_eq!(load_obj(&s, false, true).unwrap().len(), 968);
        }
    }
}
