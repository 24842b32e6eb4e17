//! `<shape>`: `obj`, `ply`, `serialized`, `sphere`, `rectangle`, `disk`, `cube`, and
//! `shapegroup` + `instance`, each placed by an optional `to_world`, with a nested or
//! referenced `<bsdf>` and an optional `<emitter type="area">` (nested, or a top-level one
//! referenced by id: it then belongs to this shape alone).
//!
//! As in Mitsuba 3: a shape without a BSDF is diffuse 0.5, or black when it emits; meshes
//! without normals get smooth angle-weighted ones unless `face_normals`; OBJ uvs are stored as
//! (u, 1 − v) unless `flip_tex_coords` is false (PLY's default is not to flip; `serialized`
//! stores them as they are); `flip_normals` turns both normals (and the side an area light
//! emits to). An instance is its group's shapes placed by the instance's `to_world` after
//! their own (gonio copies them into the scene).

use super::bsdf;
use super::error::XmlError;
use super::parse::{plugin, Plugin, Val};
use super::texture;
use super::tree::Elem;
use super::Loader;
use crate::io::{obj, ply, serialized};
use crate::material::Material;
use crate::scene::Shape;
use crate::shape::{Disk, Geometry, Rectangle, Sphere, TriangleMesh};
use crate::texture::Texture;
use glam::{Mat3, Mat4, Vec2, Vec3};
use radiometry::cie::SpectrumUse;
use radiometry::Rgb;

/// The shape types this loader reads.
pub const TYPES: &[&str] =
    &["obj", "ply", "serialized", "sphere", "rectangle", "disk", "cube", "shapegroup", "instance"];

/// The uniform scale of `m`'s linear part, or None when it shears or scales unevenly.
fn uniform_scale(m: &Mat3) -> Option<f32> {
    let s = m.x_axis.length();
    let ok = |a: Vec3, b: Vec3| a.dot(b).abs() <= 1e-4 * s * s;
    let same = |a: Vec3| (a.length() - s).abs() <= 1e-4 * s;
    (s > 0.0
        && same(m.y_axis)
        && same(m.z_axis)
        && ok(m.x_axis, m.y_axis)
        && ok(m.y_axis, m.z_axis)
        && ok(m.x_axis, m.z_axis))
    .then_some(s)
}

/// Mitsuba's `cube`: [−1, 1]³, 24 vertices with per-face normals and uvs, 12 triangles.
pub fn unit_cube() -> TriangleMesh {
    // Per face: its normal and the corners in Mitsuba's order, whose uvs are (0,1), (1,1), (1,0), (0,0).
    #[rustfmt::skip]
    let faces: [([f32; 3], [[f32; 3]; 4]); 6] = [
        ([0., -1., 0.], [[1., -1., -1.], [1., -1., 1.], [-1., -1., 1.], [-1., -1., -1.]]),
        ([0., 1., 0.], [[1., 1., -1.], [-1., 1., -1.], [-1., 1., 1.], [1., 1., 1.]]),
        ([1., 0., 0.], [[1., -1., -1.], [1., 1., -1.], [1., 1., 1.], [1., -1., 1.]]),
        ([0., 0., 1.], [[1., -1., 1.], [1., 1., 1.], [-1., 1., 1.], [-1., -1., 1.]]),
        ([-1., 0., 0.], [[-1., -1., 1.], [-1., 1., 1.], [-1., 1., -1.], [-1., -1., -1.]]),
        ([0., 0., -1.], [[1., 1., -1.], [1., -1., -1.], [-1., -1., -1.], [-1., 1., -1.]]),
    ];
    let corner_uv = [Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0), Vec2::ZERO];
    let (mut positions, mut normals, mut uvs, mut indices) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (n, corners) in faces {
        let base = positions.len() as u32;
        positions.extend(corners.map(Vec3::from));
        normals.extend([Vec3::from(n); 4]);
        uvs.extend(corner_uv);
        indices.extend([[base, base + 1, base + 2], [base + 3, base, base + 2]]);
    }
    TriangleMesh::with_uvs(positions, Some(normals), Some(uvs), indices).expect("the unit cube is a valid mesh")
}

/// The geometry of a shape placed by `parent` (an instance's transform) after its own.
fn geometry(p: &Plugin, parent: &Mat4) -> Result<Geometry, XmlError> {
    let to_world = *parent * p.transform("to_world")?;
    let flip = p.bool("flip_normals", false)?;
    let mesh = |mut m: TriangleMesh, face_normals: bool| {
        m.transform(&to_world);
        if face_normals {
            m.normals = None;
        } else if m.normals.is_none() {
            m.compute_vertex_normals();
        }
        m.flip = flip;
        Geometry::Mesh(m)
    };
    let file = |p: &Plugin| -> Result<std::path::PathBuf, XmlError> {
        let name = p.string("filename")?.ok_or_else(|| p.err("missing property 'filename'"))?;
        Ok(p.elem.path(name))
    };
    match p.kind.as_str() {
        "obj" | "ply" => {
            p.allow(&["filename", "face_normals", "flip_normals", "flip_tex_coords", "to_world"])?;
            let face_normals = p.bool("face_normals", false)?;
            let flip_v = p.bool("flip_tex_coords", p.kind == "obj")?;
            let path = file(p)?;
            let m = if p.kind == "obj" {
                obj::load_obj(&path, face_normals, flip_v)
            } else {
                ply::load_ply(&path, face_normals, flip_v)
            }
            .map_err(|e| p.err_at("filename", e.to_string()))?;
            Ok(mesh(m, face_normals))
        }
        "serialized" => {
            p.allow(&["filename", "shape_index", "face_normals", "flip_normals", "to_world"])?;
            let index = p.int("shape_index", 0)?;
            if index < 0 {
                return Err(p.err_at("shape_index", format!("shape_index {index} must be ≥ 0")));
            }
            let face_normals = p.bool("face_normals", false)?;
            let m = serialized::load_serialized(&file(p)?, index as usize)
                .map_err(|e| p.err_at("filename", e.to_string()))?;
            Ok(mesh(m, face_normals))
        }
        "sphere" => {
            p.allow(&["center", "radius", "flip_normals", "to_world"])?;
            let radius = p.float("radius", 1.0)? as f32;
            if radius.is_nan() || radius <= 0.0 {
                return Err(p.err_at("radius", format!("radius {radius} must be > 0")));
            }
            let center = p.vec3("center")?.unwrap_or(Vec3::ZERO);
            let m = to_world * Mat4::from_translation(center) * Mat4::from_scale(Vec3::splat(radius));
            let lin = Mat3::from_mat4(m);
            let r = uniform_scale(&lin).ok_or_else(|| {
                p.err_at("to_world", "a sphere's to_world may only rotate, mirror, translate and scale uniformly")
            })?;
            // A mirroring placement turns the sphere inside out, as Mitsuba's does.
            let mirrored = lin.determinant() < 0.0;
            Ok(Geometry::Sphere(Sphere {
                center: m.transform_point3(Vec3::ZERO),
                radius: r,
                rotation: lin * (1.0 / r),
                flip: flip ^ mirrored,
            }))
        }
        "rectangle" | "disk" => {
            p.allow(&["flip_normals", "to_world"])?;
            let mut rect = Rectangle::new(&to_world)
                .ok_or_else(|| p.err_at("to_world", format!("the {} has zero area under to_world", p.kind)))?;
            rect.flip = flip;
            Ok(if p.kind == "disk" { Geometry::Disk(Disk { frame: rect }) } else { Geometry::Rectangle(rect) })
        }
        "cube" => {
            p.allow(&["flip_normals", "to_world"])?;
            Ok(mesh(unit_cube(), false))
        }
        t => Err(p.err(format!("unsupported shape type '{t}'; accepted: {}", TYPES.join(", ")))),
    }
}

/// The shapes a `<shape>` element stands for (an instance stands for its group's), placed by
/// `parent` after their own transforms; `in_group` when inside a shapegroup.
pub fn load(ld: &Loader, e: &Elem, parent: &Mat4, in_group: bool) -> Result<Vec<Shape>, XmlError> {
    let p = plugin(&ld.ids, e, &["bsdf", "emitter", "shape", "medium", "texture"])?;
    match p.kind.as_str() {
        "shapegroup" => return Err(p.err("a shapegroup is placed by an <instance>, not rendered itself")),
        "instance" => return instance(ld, &p, parent, in_group),
        _ => {}
    }
    let mut material = None;
    let mut emission = None;
    let objects = p.all_objects();
    let rest = p.props.iter().filter(|q| !matches!(q.val, Val::Object(_))).cloned().collect::<Vec<_>>();
    for o in objects {
        match o.tag.as_str() {
            "bsdf" => {
                if material.is_some() {
                    return Err(o.err("a shape takes at most one <bsdf>"));
                }
                material = Some(bsdf::material(ld, o)?);
            }
            "emitter" => {
                if in_group {
                    return Err(o.err("an emitter inside a shapegroup cannot be instanced (Mitsuba refuses it too)"));
                }
                if emission.is_some() {
                    return Err(o.err("a shape takes at most one emitter"));
                }
                emission = Some(area_emitter(ld, o)?);
            }
            "medium" => {
                return Err(o.err("participating media (<medium>) are not supported yet; accepted: bsdf, emitter"))
            }
            "shape" => return Err(o.err("only a shapegroup holds shapes")),
            t => return Err(o.err(format!("a shape cannot hold a <{t}>"))),
        }
    }
    let shape = Plugin { elem: p.elem, kind: p.kind.clone(), props: rest, objects: Vec::new() };
    let geometry = geometry(&shape, parent)?;
    let material = material.unwrap_or_else(|| {
        let albedo = if emission.is_some() { "0" } else { "0.5" };
        Material::from(brdf::build("lambert", &[("albedo", albedo)]).expect("lambert builds"))
    });
    Ok(vec![Shape { geometry, material, emission }])
}

/// An `<instance>`: the shapes of the group it references, placed by its `to_world`.
fn instance(ld: &Loader, p: &Plugin, parent: &Mat4, in_group: bool) -> Result<Vec<Shape>, XmlError> {
    if in_group {
        return Err(p.err("an instance inside a shapegroup: nested instancing is not supported (nor by Mitsuba)"));
    }
    let groups = p.all_objects();
    let accepted: Vec<&str> = p
        .props
        .iter()
        .filter(|q| matches!(q.val, Val::Object(_)))
        .map(|q| q.name.as_str())
        .chain(["to_world"])
        .collect();
    p.allow(&accepted)?;
    let [group] = groups.as_slice() else {
        return Err(p.err("an instance takes exactly one <ref> to a shapegroup"));
    };
    if group.tag != "shape" || group.attr("type") != Some("shapegroup") {
        return Err(p.err(format!("an instance places a shapegroup, not {}", group.describe())));
    }
    let g = plugin(&ld.ids, group, &["shape"])?;
    g.allow(&[])?;
    let place = *parent * p.transform("to_world")?;
    let mut shapes = Vec::new();
    for s in &g.objects {
        if s.attr("type") == Some("shapegroup") {
            return Err(s.err("a shapegroup inside a shapegroup is not supported (nor by Mitsuba)"));
        }
        shapes.extend(load(ld, s, &place, true)?);
    }
    Ok(shapes)
}

/// `<emitter type="area">` of a shape: its radiance. A top-level one referenced by id may
/// belong to one shape only.
fn area_emitter(ld: &Loader, e: &Elem) -> Result<Texture, XmlError> {
    if e.attr("id").is_some() {
        let key = e as *const Elem;
        let mut used = ld.area_used.borrow_mut();
        if !used.insert(key) {
            return Err(
                e.err("this area emitter is already attached to another shape; an emitter belongs to one shape")
            );
        }
    }
    let p = plugin(&ld.ids, e, &["texture"])?;
    p.no_objects()?;
    if p.kind != "area" {
        return Err(p.err(format!("emitter type '{}' cannot be attached to a shape; accepted: area", p.kind)));
    }
    p.allow(&["radiance"])?;
    texture::color(ld, &p, "radiance", Rgb::ONE, SpectrumUse::Emission)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_uvs_and_frames_match_mitsuba() {
        let c = unit_cube();
        assert_eq!((c.len(), c.positions.len()), (12, 24));
        assert!((c.area() - 24.0).abs() < 1e-5);
        // Mitsuba 3.9.1 hits: (triangle, barycentrics) → uv, ∂p/∂u, ∂p/∂v, normal.
        let find = |p: Vec3| {
            (0..c.len())
                .find_map(|i| {
                    let [a, b, d] = c.triangle(i);
                    let (e1, e2) = (b - a, d - a);
                    let n = e1.cross(e2);
                    let q = p - a;
                    let (u, v) = (q.cross(e2).dot(n) / n.dot(n), e1.cross(q).dot(n) / n.dot(n));
                    (u >= -1e-6 && v >= -1e-6 && u + v <= 1.0 + 1e-6 && q.dot(n).abs() < 1e-5)
                        .then(|| c.surface(i, u, v))
                })
                .unwrap()
        };
        let s = find(Vec3::new(0.2, 0.3, 1.0));
        assert!((s.uv - Vec2::new(0.65, 0.6)).length() < 1e-5 && s.dp_du.abs_diff_eq(Vec3::new(0.0, 2.0, 0.0), 1e-5));
        assert!(s.dp_dv.abs_diff_eq(Vec3::new(2.0, 0.0, 0.0), 1e-5) && s.ng.abs_diff_eq(Vec3::Z, 1e-6));
        let f = s.frame();
        assert!(f.s.abs_diff_eq(Vec3::Y, 1e-6) && f.t.abs_diff_eq(-Vec3::X, 1e-6));
        let s = find(Vec3::new(1.0, 0.2, -0.4));
        assert!((s.uv - Vec2::new(0.6, 0.7)).length() < 1e-5 && s.dp_dv.abs_diff_eq(Vec3::new(0.0, 0.0, -2.0), 1e-5));
        let s = find(Vec3::new(0.25, 1.0, -0.5));
        assert!((s.uv - Vec2::new(0.375, 0.75)).length() < 1e-5 && s.ng.abs_diff_eq(Vec3::Y, 1e-6));
        assert_eq!(uniform_scale(&Mat3::from_diagonal(Vec3::splat(2.0))), Some(2.0));
        assert_eq!(uniform_scale(&Mat3::from_diagonal(Vec3::new(1.0, 2.0, 1.0))), None);
    }
}
