//! PLY triangle meshes (Turk, "The PLY polygon file format", 1994): ASCII and binary (both
//! byte orders), vertices `x y z` with optional `nx ny nz` and uvs (`u v`, else `texture_u
//! texture_v`, else `s t`, as Mitsuba reads them), faces as a `vertex_indices` (or
//! `vertex_index`) list, polygons fanned into triangles. Other elements and properties are
//! read past. Errors name the header line or the element and record that is wrong.

use crate::error::{Error, Result};
use crate::shape::TriangleMesh;
use glam::{Vec2, Vec3};
use std::path::Path;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
}

#[derive(Clone, Debug)]
enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    props: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Format {
    Ascii,
    Little,
    Big,
}

/// Reads values one at a time from the body, in any of the three encodings.
struct Body<'a> {
    bytes: &'a [u8],
    pos: usize,
    format: Format,
}

impl Body<'_> {
    fn next_token(&mut self) -> Option<&str> {
        while self.pos < self.bytes.len() && self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        let start = self.pos;
        while self.pos < self.bytes.len() && !self.bytes[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        (self.pos > start).then(|| std::str::from_utf8(&self.bytes[start..self.pos]).unwrap_or("?"))
    }

    /// The next value as f64; Err names what went wrong.
    fn read(&mut self, t: Scalar) -> std::result::Result<f64, String> {
        if self.format == Format::Ascii {
            let tok = self.next_token().ok_or("the file ends early")?;
            return tok.parse::<f64>().map_err(|_| format!("'{tok}' is not a number"));
        }
        let n = t.size();
        let b = self.bytes.get(self.pos..self.pos + n).ok_or("the file ends early")?;
        self.pos += n;
        let mut a = [0u8; 8];
        a[..n].copy_from_slice(b);
        if self.format == Format::Big {
            a[..n].reverse();
        }
        Ok(match t {
            Scalar::I8 => a[0] as i8 as f64,
            Scalar::U8 => a[0] as f64,
            Scalar::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(a),
        })
    }
}

/// Loads a PLY file as a triangle mesh; `face_normals` drops any vertex normals, `flip_v`
/// stores 1 − v.
pub fn load_ply(path: &Path, face_normals: bool, flip_v: bool) -> Result<TriangleMesh> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    let m = parse_ply(&bytes).map_err(|m| Error::format(path, m))?;
    let normals = if face_normals { None } else { m.normals };
    let uvs = m.uvs.map(|t| if flip_v { t.into_iter().map(|t| Vec2::new(t.x, 1.0 - t.y)).collect() } else { t });
    TriangleMesh::with_uvs(m.positions, normals, uvs, m.indices).map_err(|e| Error::format(path, e.to_string()))
}

/// A mesh as read from a file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshData {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Vertex normals, when the file has them.
    pub normals: Option<Vec<Vec3>>,
    /// Vertex uvs, when the file has them.
    pub uvs: Option<Vec<Vec2>>,
    /// Triangles.
    pub indices: Vec<[u32; 3]>,
}

/// Parses PLY bytes into positions, optional normals and uvs, and triangles.
pub fn parse_ply(bytes: &[u8]) -> std::result::Result<MeshData, String> {
    let (elements, format, body_start) = parse_header(bytes)?;
    let mut body = Body { bytes, pos: body_start, format };
    let mut positions = Vec::new();
    let mut normals: Option<Vec<Vec3>> = None;
    let mut uvs: Option<Vec<Vec2>> = None;
    let mut indices = Vec::new();
    // A record takes at least one byte (a binary scalar) or two (an ASCII number and a space):
    // more records than bytes cannot be there, so the header cannot size an allocation past the file.
    let room = |count: usize| count.min(bytes.len());
    let mut vertex_count = None;
    for el in &elements {
        let find = |n: &str| el.props.iter().position(|p| matches!(p, Property::Scalar(name, _) if name == n));
        let is_vertex = el.name == "vertex";
        let xyz = [find("x"), find("y"), find("z")];
        let nxyz = [find("nx"), find("ny"), find("nz")];
        let uv = [["u", "v"], ["texture_u", "texture_v"], ["s", "t"]]
            .iter()
            .map(|[a, b]| [find(a), find(b)])
            .find(|p| p.iter().all(Option::is_some));
        if is_vertex {
            if xyz.iter().any(Option::is_none) {
                return Err("element 'vertex' lacks one of the properties x, y, z".into());
            }
            positions.reserve(room(el.count));
            if nxyz.iter().all(Option::is_some) {
                normals = Some(Vec::with_capacity(room(el.count)));
            }
            if uv.is_some() {
                uvs = Some(Vec::with_capacity(room(el.count)));
            }
            vertex_count = Some(el.count);
        }
        let face_list = el.props.iter().position(
            |p| matches!(p, Property::List(name, _, _) if name == "vertex_indices" || name == "vertex_index"),
        );
        let is_face = el.name == "face";
        if is_face && face_list.is_none() {
            return Err("element 'face' has no 'vertex_indices' list".into());
        }
        let mut values = vec![0.0f64; el.props.len()];
        let mut poly: Vec<u32> = Vec::new();
        for rec in 0..el.count {
            let at = |m: String| format!("element '{}' record {rec} of {}: {m}", el.name, el.count);
            for (pi, prop) in el.props.iter().enumerate() {
                match prop {
                    Property::Scalar(_, t) => values[pi] = body.read(*t).map_err(at)?,
                    Property::List(name, ct, it) => {
                        let n = body.read(*ct).map_err(at)?;
                        if !(0.0..=1e6).contains(&n) || n.fract() != 0.0 {
                            return Err(at(format!("list '{name}' has length {n}")));
                        }
                        let keep = is_face && Some(pi) == face_list;
                        poly.clear();
                        for _ in 0..n as usize {
                            let v = body.read(*it).map_err(at)?;
                            if keep {
                                let nv = vertex_count.ok_or_else(|| at("faces come before the vertices".into()))?;
                                if !(v >= 0.0 && v < nv as f64 && v.fract() == 0.0) {
                                    return Err(at(format!("vertex index {v} is not in 0..{nv}")));
                                }
                                poly.push(v as u32);
                            }
                        }
                        if keep {
                            if poly.len() < 3 {
                                return Err(at(format!("a face has {} vertices", poly.len())));
                            }
                            for k in 1..poly.len() - 1 {
                                indices.push([poly[0], poly[k], poly[k + 1]]);
                            }
                        }
                    }
                }
            }
            if is_vertex {
                let get = |i: [Option<usize>; 3]| {
                    Vec3::new(values[i[0].unwrap()] as f32, values[i[1].unwrap()] as f32, values[i[2].unwrap()] as f32)
                };
                positions.push(get(xyz));
                if let Some(ns) = &mut normals {
                    ns.push(get(nxyz));
                }
                if let (Some(ts), Some([u, v])) = (&mut uvs, uv) {
                    ts.push(Vec2::new(values[u.unwrap()] as f32, values[v.unwrap()] as f32));
                }
            }
        }
    }
    if positions.is_empty() || indices.is_empty() {
        return Err(format!("no triangles ({} vertices, {} triangles)", positions.len(), indices.len()));
    }
    Ok(MeshData { positions, normals, uvs, indices })
}

fn parse_header(bytes: &[u8]) -> std::result::Result<(Vec<Element>, Format, usize), String> {
    let mut pos = 0;
    let mut elements: Vec<Element> = Vec::new();
    let mut format = None;
    for line_no in 1.. {
        let end = bytes[pos..].iter().position(|&b| b == b'\n').ok_or("the header has no 'end_header' line")? + pos;
        let line = String::from_utf8_lossy(&bytes[pos..end]).trim_end_matches('\r').trim().to_string();
        pos = end + 1;
        let err = |m: &str| format!("header line {line_no}: {m}: '{line}'");
        let words: Vec<&str> = line.split_whitespace().collect();
        if line_no == 1 {
            if line != "ply" {
                return Err("not a PLY file: the first line is not 'ply'".into());
            }
            continue;
        }
        match words.as_slice() {
            ["format", f, _version] => {
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Little,
                    "binary_big_endian" => Format::Big,
                    _ => return Err(err("unknown format")),
                })
            }
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => {
                let count = count.parse().map_err(|_| err("the element count is not a number"))?;
                elements.push(Element { name: name.to_string(), count, props: Vec::new() });
            }
            ["property", "list", ct, it, name] => {
                let el = elements.last_mut().ok_or_else(|| err("a property before any element"))?;
                let (Some(ct), Some(it)) = (Scalar::parse(ct), Scalar::parse(it)) else {
                    return Err(err("unknown list type"));
                };
                el.props.push(Property::List(name.to_string(), ct, it));
            }
            ["property", t, name] => {
                let el = elements.last_mut().ok_or_else(|| err("a property before any element"))?;
                let t = Scalar::parse(t).ok_or_else(|| err("unknown property type"))?;
                el.props.push(Property::Scalar(name.to_string(), t));
            }
            ["end_header"] => break,
            _ => return Err(err("not a PLY header line")),
        }
    }
    Ok((elements, format.ok_or("the header has no 'format' line")?, pos))
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment a unit square\nelement vertex 4\nproperty float x\n\
        property float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
        element face 1\nproperty list uchar int vertex_indices\nend_header\n\
        0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n4 0 1 2 3\n";

    fn binary(big: bool) -> Vec<u8> {
        let order = if big { "binary_big_endian" } else { "binary_little_endian" };
        let mut b = format!(
            "ply\nformat {order} 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n\
             property uchar red\nelement face 1\nproperty list uchar uint vertex_indices\nproperty short flags\nend_header\n"
        )
        .into_bytes();
        for (i, p) in [[0.0f64, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]].iter().enumerate() {
            for c in p {
                b.extend(if big { c.to_be_bytes() } else { c.to_le_bytes() });
            }
            b.push(i as u8);
        }
        b.push(3);
        for i in [0u32, 1, 2] {
            b.extend(if big { i.to_be_bytes() } else { i.to_le_bytes() });
        }
        b.extend(if big { 7i16.to_be_bytes() } else { 7i16.to_le_bytes() });
        b
    }

    #[test]
    fn ascii_quad_is_fanned_and_keeps_normals() {
        let m = parse_ply(ASCII.as_bytes()).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.normals.unwrap()[2], Vec3::Z);
        assert!(m.uvs.is_none());
        let with_uv = ASCII
            .replace("property float nz\n", "property float nz\nproperty float u\nproperty float v\n")
            .replace(" 0 0 1\n", " 0 0 1 0.25 0.75\n");
        let m = parse_ply(with_uv.as_bytes()).unwrap();
        assert_eq!(m.uvs.unwrap()[1], Vec2::new(0.25, 0.75));
        // A header that promises more vertices than the file could hold is caught, not allocated.
        let e = parse_ply(ASCII.replace("element vertex 4", "element vertex 4000000000000").as_bytes()).unwrap_err();
        assert!(e.contains("ends early") || e.contains("record"), "{e}");
    }

    #[test]
    fn binary_both_byte_orders_skip_unused_properties() {
        for big in [false, true] {
            let m = parse_ply(&binary(big)).unwrap();
            assert_eq!(m.positions, vec![Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0)]);
            assert!(m.normals.is_none());
            assert_eq!(m.indices, vec![[0, 1, 2]]);
        }
    }

    #[test]
    fn malformed_files_say_where() {
        let e = parse_ply(b"PLY\n").unwrap_err();
        assert!(e.contains("first line"), "{e}");
        let e = parse_ply(ASCII.replace("property float y", "property flt y").as_bytes()).unwrap_err();
        assert!(e.contains("header line 6") && e.contains("unknown property type"), "{e}");
        let e = parse_ply(ASCII.replace("4 0 1 2 3", "4 0 1 2 9").as_bytes()).unwrap_err();
        assert!(e.contains("element 'face' record 0") && e.contains("vertex index 9"), "{e}");
        let e = parse_ply(ASCII.replace("1 1 0 0 0 1\n", "1 1 0 x 0 1\n").as_bytes()).unwrap_err();
        assert!(e.contains("element 'vertex' record 2") && e.contains("'x'"), "{e}");
        let b = binary(false);
        let e = parse_ply(&b[..b.len() - 3]).unwrap_err();
        assert!(e.contains("ends early"), "{e}");
        let e = parse_ply(ASCII.replace("end_header\n", "").as_bytes()).unwrap_err();
        assert!(e.contains("end_header") || e.contains("header line"), "{e}");
        let e = load_ply(Path::new("/nonexistent/x.ply"), false, false).unwrap_err().to_string();
        assert!(e.contains("/nonexistent/x.ply"), "{e}");
    }

    #[test]
    fn benchmark_torus_loads_when_present() {
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/bench/data/torus.ply");
        if p.exists() {
            let m = load_ply(&p, false, false).unwrap();
            assert_eq!((m.positions.len(), m.len()), (50_000, 100_000));
            assert!(m.normals.is_some());
        }
    }
}
