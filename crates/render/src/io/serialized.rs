//! Mitsuba's `.serialized` meshes: one or more meshes, each a little-endian header (the
//! format id 0x041C as a u16, the version 3 or 4 as a u16) followed by a zlib stream of
//!
//!   u32 flags, [version 4: the mesh's name, NUL-terminated], u64 vertices, u64 triangles,
//!   positions (3 per vertex), [normals (3) if flags & 0x1], [uvs (2) if flags & 0x2],
//!   [colours (3) if flags & 0x8, skipped], indices (3 u32 per triangle),
//!
//! as f32, or f64 when flags & 0x2000. The file ends with the byte offset of every mesh (u32
//! each in version 3, u64 in version 4) and their count (u32). `shape_index` picks a mesh.
//! Counts are checked against the data before anything is allocated for them, and the inflated
//! size is bounded, so a corrupt or hostile file is an error, never an exhausted memory.
//! Source: Mitsuba 3, `src/shapes/serialized.cpp` (the format, as its documentation states it).

use crate::error::{Error, Result};
use crate::shape::TriangleMesh;
use glam::{Vec2, Vec3};
use std::io::Read;
use std::path::Path;

const FORMAT_ID: u16 = 0x041C;
const HAS_NORMALS: u32 = 0x0001;
const HAS_UVS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const DOUBLE: u32 = 0x2000;
/// The most an inflated mesh may exceed its compressed size by (real meshes compress 2–4×).
const MAX_RATIO: u64 = 1024;

/// Loads mesh `index` of a serialized file.
pub fn load_serialized(path: &Path, index: usize) -> Result<TriangleMesh> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let (positions, normals, uvs, indices) = parse(&bytes, index).map_err(|m| Error::format(path, m))?;
    TriangleMesh::with_uvs(positions, normals, uvs, indices)
        .map_err(|e| Error::format(path, format!("mesh {index}: {e}")))
}

type Mesh = (Vec<Vec3>, Option<Vec<Vec3>>, Option<Vec<Vec2>>, Vec<[u32; 3]>);

fn u16_at(b: &[u8], at: usize) -> Option<u16> {
    Some(u16::from_le_bytes(b.get(at..at + 2)?.try_into().ok()?))
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(at..at + 4)?.try_into().ok()?))
}

fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(b.get(at..at + 8)?.try_into().ok()?))
}

/// The byte range of mesh `index`'s header and stream.
fn locate(bytes: &[u8], index: usize) -> std::result::Result<(usize, usize, u16), String> {
    let version = match (u16_at(bytes, 0), u16_at(bytes, 2)) {
        (Some(FORMAT_ID), Some(v @ (3 | 4))) => v,
        (Some(FORMAT_ID), Some(v)) => return Err(format!("format version {v} is not supported (3 and 4 are)")),
        _ => return Err("not a Mitsuba serialized mesh (no 0x041C format id at the start)".into()),
    };
    let count = u32_at(bytes, bytes.len().saturating_sub(4)).ok_or("the file ends before its mesh count")? as usize;
    let entry = if version == 4 { 8 } else { 4 };
    let table = count.checked_mul(entry).and_then(|t| t.checked_add(4)).filter(|&t| t <= bytes.len());
    let table_start = match table {
        Some(t) if count > 0 => bytes.len() - t,
        // A file written without a dictionary holds one mesh.
        _ if index == 0 => return Ok((0, bytes.len(), version)),
        _ => return Err(format!("the file's mesh table (count {count}) does not fit in its {} bytes", bytes.len())),
    };
    if index >= count {
        return Err(format!("shape_index {index} is out of range: the file holds {count} meshes (0..{})", count - 1));
    }
    let offset = |k: usize| -> Option<usize> {
        let at = table_start + k * entry;
        let o = if version == 4 { u64_at(bytes, at)? } else { u32_at(bytes, at)? as u64 };
        usize::try_from(o).ok().filter(|&o| o + 4 <= table_start)
    };
    let start = offset(index).ok_or_else(|| format!("mesh {index}'s offset points outside the file"))?;
    let end = if index + 1 < count { offset(index + 1).unwrap_or(table_start) } else { table_start };
    if end <= start + 4 {
        return Err(format!("mesh {index}'s data is empty"));
    }
    if u16_at(bytes, start) != Some(FORMAT_ID) {
        return Err(format!("mesh {index} does not start with the format id 0x041C"));
    }
    Ok((start, end, version))
}

/// Decodes mesh `index` of `bytes`.
fn parse(bytes: &[u8], index: usize) -> std::result::Result<Mesh, String> {
    let (start, end, version) = locate(bytes, index)?;
    let stream = &bytes[start + 4..end];
    let mut data = Vec::new();
    let limit = stream.len() as u64 * MAX_RATIO + (1 << 20);
    flate2::read::ZlibDecoder::new(stream)
        .take(limit)
        .read_to_end(&mut data)
        .map_err(|e| format!("mesh {index}: the compressed data is corrupt ({e})"))?;
    let mut r = Reader { data: &data, pos: 0, mesh: index };
    let flags = r.u32()?;
    if version == 4 {
        let nul = r.data[r.pos..].iter().position(|&b| b == 0).ok_or_else(|| r.err("the mesh name does not end"))?;
        r.pos += nul + 1;
    }
    let (nv, nt) = (r.u64()?, r.u64()?);
    let real: usize = if flags & DOUBLE != 0 { 8 } else { 4 };
    let per_vertex: usize = 3
        + if flags & HAS_NORMALS != 0 { 3 } else { 0 }
        + if flags & HAS_UVS != 0 { 2 } else { 0 }
        + if flags & HAS_COLORS != 0 { 3 } else { 0 };
    let need =
        nv.checked_mul((per_vertex * real) as u64).and_then(|v| nt.checked_mul(12).and_then(|t| v.checked_add(t)));
    let left = (r.data.len() - r.pos) as u64;
    if need.is_none_or(|n| n > left) || nv > u32::MAX as u64 {
        return Err(r.err(&format!("{nv} vertices and {nt} triangles need more data than the {left} bytes present")));
    }
    let (nv, nt) = (nv as usize, nt as usize);
    let vec3s = |r: &mut Reader| -> std::result::Result<Vec<Vec3>, String> {
        (0..nv).map(|_| Ok(Vec3::new(r.real(real)?, r.real(real)?, r.real(real)?))).collect()
    };
    let positions = vec3s(&mut r)?;
    let normals = if flags & HAS_NORMALS != 0 { Some(vec3s(&mut r)?) } else { None };
    let uvs = if flags & HAS_UVS != 0 {
        Some(
            (0..nv)
                .map(|_| Ok(Vec2::new(r.real(real)?, r.real(real)?)))
                .collect::<std::result::Result<Vec<_>, String>>()?,
        )
    } else {
        None
    };
    if flags & HAS_COLORS != 0 {
        r.pos += nv * 3 * real;
    }
    let indices =
        (0..nt).map(|_| Ok([r.u32()?, r.u32()?, r.u32()?])).collect::<std::result::Result<Vec<_>, String>>()?;
    Ok((positions, normals, uvs, indices))
}

/// Reads values from an inflated mesh.
struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    mesh: usize,
}

impl Reader<'_> {
    fn err(&self, m: &str) -> String {
        format!("mesh {}: {m}", self.mesh)
    }

    fn u32(&mut self) -> std::result::Result<u32, String> {
        let v = u32_at(self.data, self.pos).ok_or_else(|| self.err("the data ends early"))?;
        self.pos += 4;
        Ok(v)
    }

    fn u64(&mut self) -> std::result::Result<u64, String> {
        let v = u64_at(self.data, self.pos).ok_or_else(|| self.err("the data ends early"))?;
        self.pos += 8;
        Ok(v)
    }

    fn real(&mut self, size: usize) -> std::result::Result<f32, String> {
        if size == 8 {
            return Ok(f64::from_bits(self.u64()?) as f32);
        }
        Ok(f32::from_bits(self.u32()?))
    }
}

/// One mesh to write: positions, optional normals and uvs, triangles.
pub type MeshRef<'a> = (&'a [Vec3], Option<&'a [Vec3]>, Option<&'a [Vec2]>, &'a [[u32; 3]]);

/// Writes meshes in the version-4 format (for tests and tools): positions, normals, uvs, f32.
pub fn write(meshes: &[MeshRef]) -> Vec<u8> {
    use std::io::Write;
    let mut out = Vec::new();
    let mut offsets = Vec::new();
    for (k, (p, n, t, i)) in meshes.iter().enumerate() {
        offsets.push(out.len() as u64);
        out.extend(FORMAT_ID.to_le_bytes());
        out.extend(4u16.to_le_bytes());
        let mut raw = Vec::new();
        let flags = 0x1000 | if n.is_some() { HAS_NORMALS } else { 0 } | if t.is_some() { HAS_UVS } else { 0 };
        raw.extend(flags.to_le_bytes());
        raw.extend(format!("mesh{k}\0").bytes());
        raw.extend((p.len() as u64).to_le_bytes());
        raw.extend((i.len() as u64).to_le_bytes());
        let mut f = |v: f32| raw.extend(v.to_le_bytes());
        p.iter().for_each(|v| v.to_array().into_iter().for_each(&mut f));
        n.iter().flat_map(|n| n.iter()).for_each(|v| v.to_array().into_iter().for_each(&mut f));
        t.iter().flat_map(|t| t.iter()).for_each(|v| v.to_array().into_iter().for_each(&mut f));
        i.iter().flatten().for_each(|x| raw.extend(x.to_le_bytes()));
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        z.write_all(&raw).expect("writing to memory");
        out.extend(z.finish().expect("writing to memory"));
    }
    for o in &offsets {
        out.extend(o.to_le_bytes());
    }
    out.extend((offsets.len() as u32).to_le_bytes());
    out
}

#[cfg(test)]
#[allow(clippy::excessive_precision)] // Mitsuba's reference numbers, as it prints them
mod tests {
    use super::*;

    fn two_meshes() -> Vec<u8> {
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let n = [Vec3::Z; 3];
        let t = [Vec2::ZERO, Vec2::X, Vec2::Y];
        let q = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y];
        write(&[(&p, Some(&n), Some(&t), &[[0, 1, 2]]), (&q, None, None, &[[0, 1, 2], [0, 2, 3]])])
    }

    #[test]
    fn round_trip_and_shape_index() {
        let b = two_meshes();
        let (p, n, t, i) = parse(&b, 0).unwrap();
        assert_eq!((p.len(), i), (3, vec![[0, 1, 2]]));
        assert_eq!(n.unwrap()[0], Vec3::Z);
        assert_eq!(t.unwrap()[1], Vec2::X);
        let (p, n, t, i) = parse(&b, 1).unwrap();
        assert!(p.len() == 4 && i.len() == 2 && n.is_none() && t.is_none());
        let e = parse(&b, 2).unwrap_err();
        assert!(e.contains("out of range") && e.contains("2 meshes"), "{e}");
    }

    #[test]
    fn corrupt_files_are_errors() {
        let b = two_meshes();
        for cut in [3, 10, b.len() / 2, b.len() - 3] {
            assert!(parse(&b[..cut], 0).is_err() || parse(&b[..cut], 1).is_err(), "cut at {cut}");
        }
        let mut bad = b.clone();
        bad[20] ^= 0xFF;
        assert!(parse(&bad, 0).is_err());
        assert!(parse(b"not a mesh at all", 0).unwrap_err().contains("0x041C"));
    }

    #[test]
    fn mitsubas_matpreview_file_when_present() {
        // Mitsuba 3.9.1 reads these counts, first vertex and uv from Mitsuba's own file.
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/bench/real/matpreview.serialized");
        if !path.exists() {
            return;
        }
        let bytes = std::fs::read(&path).unwrap();
        let expect = [
            (289, 512, Vec3::new(-0.5048662424, 0.5747208595, 0.7843790054), Vec2::new(0.644658029, 0.8092356324)),
            (2078, 3936, Vec3::new(0.6670285463, 0.2762922645, 0.06282293797), Vec2::new(0.1591454148, 0.3169771433)),
            (
                29439,
                57152,
                Vec3::new(0.04749059677, -0.4495031834, -0.9026844502),
                Vec2::new(0.9039270282, 0.8643703461),
            ),
        ];
        for (k, (nv, nt, p0, t0)) in expect.into_iter().enumerate() {
            let (p, n, t, i) = parse(&bytes, k).unwrap();
            assert_eq!((p.len(), i.len()), (nv, nt), "mesh {k}");
            assert_eq!((p[0], t.unwrap()[0]), (p0, t0), "mesh {k}");
            assert!(n.is_some());
        }
    }
}
