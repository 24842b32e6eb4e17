//! `<shape>`: `obj`, `ply`, `sphere`, `rectangle`, `disk` and `cube`, each placed by an
//! optional `to_world`, with a nested or referenced `<bsdf>` (Mitsuba's default: diffuse 0.5)
//! and an optional nested `<emitter type="area">`.

use super::bsdf::{self, LoadedBsdf, Named};
use super::error::XmlError;
use super::parse::{plugin, Ctx, Plugin};
use crate::io::load_mesh;
use crate::scene::Shape;
use crate::shape::{Disk, Geometry, Rectangle, Sphere, TriangleMesh};
use glam::{Mat3, Mat4, Vec3};
use radiometry::Rgb;
use roxmltree::Node;
use std::sync::Arc;

/// The shape types this loader reads.
pub const TYPES: &[&str] = &["obj", "ply", "sphere", "rectangle", "disk", "cube"];

/// The uniform scale of `m`'s linear part, or None when it shears or scales unevenly.
fn uniform_scale(m: &Mat4) -> Option<f32> {
    let l = Mat3::from_mat4(*m);
    let s = l.x_axis.length();
    let ok = |a: Vec3, b: Vec3| a.dot(b).abs() <= 1e-5 * s * s;
    let same = |a: Vec3| (a.length() - s).abs() <= 1e-5 * s;
    (s > 0.0
        && same(l.y_axis)
        && same(l.z_axis)
        && ok(l.x_axis, l.y_axis)
        && ok(l.y_axis, l.z_axis)
        && ok(l.x_axis, l.z_axis))
    .then_some(s)
}

/// Mitsuba's `cube`: [−1, 1]³, flat faces with outward normals (by the winding), 12 triangles.
pub fn unit_cube() -> TriangleMesh {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for a in 0..3 {
        for s in [1.0f32, -1.0] {
            let n = Vec3::AXES[a] * s;
            // u × v = n for the counter-clockwise winding seen from outside.
            let (mut u, mut v) = (Vec3::AXES[(a + 1) % 3], Vec3::AXES[(a + 2) % 3]);
            if s < 0.0 {
                std::mem::swap(&mut u, &mut v);
            }
            let base = positions.len() as u32;
            positions.extend([n - u - v, n + u - v, n + u + v, n - u + v]);
            indices.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
        }
    }
    TriangleMesh::new(positions, None, indices).expect("the unit cube is a valid mesh")
}

fn geometry(ctx: &Ctx, p: &Plugin) -> Result<Geometry, XmlError> {
    let flip_ok = |p: &Plugin| -> Result<(), XmlError> {
        if p.bool(ctx, "flip_normals", false)? {
            return Err(p.err_at(ctx, "flip_normals", "flip_normals=true is not supported yet"));
        }
        Ok(())
    };
    let to_world = p.transform(ctx, "to_world")?;
    match p.kind.as_str() {
        "obj" | "ply" => {
            p.allow(ctx, &["filename", "face_normals", "flip_normals", "to_world"])?;
            flip_ok(p)?;
            let name = p.string(ctx, "filename")?.ok_or_else(|| p.err(ctx, "missing property 'filename'"))?;
            let path = ctx.path(name);
            let mut mesh = load_mesh(&path, p.bool(ctx, "face_normals", false)?)
                .map_err(|e| p.err_at(ctx, "filename", e.to_string()))?;
            mesh.transform(&to_world);
            Ok(Geometry::Mesh(mesh))
        }
        "sphere" => {
            p.allow(ctx, &["center", "radius", "flip_normals", "to_world"])?;
            flip_ok(p)?;
            let center = p.vec3(ctx, "center")?.unwrap_or(Vec3::ZERO);
            let radius = p.float(ctx, "radius", 1.0)?;
            if radius <= 0.0 {
                return Err(p.err_at(ctx, "radius", format!("radius {radius} must be > 0")));
            }
            let s = uniform_scale(&to_world).ok_or_else(|| {
                p.err_at(ctx, "to_world", "a sphere's to_world may only rotate, translate and scale uniformly")
            })?;
            Ok(Geometry::Sphere(Sphere { center: to_world.transform_point3(center), radius: radius as f32 * s }))
        }
        "rectangle" => {
            p.allow(ctx, &["flip_normals", "to_world"])?;
            flip_ok(p)?;
            Rectangle::new(&to_world)
                .map(Geometry::Rectangle)
                .ok_or_else(|| p.err_at(ctx, "to_world", "the rectangle has zero area under to_world"))
        }
        "disk" => {
            p.allow(ctx, &["flip_normals", "to_world"])?;
            flip_ok(p)?;
            Disk::new(&to_world)
                .map(Geometry::Disk)
                .ok_or_else(|| p.err_at(ctx, "to_world", "the disk has zero area under to_world"))
        }
        "cube" => {
            p.allow(ctx, &["flip_normals", "to_world"])?;
            flip_ok(p)?;
            let mut mesh = unit_cube();
            mesh.transform(&to_world);
            Ok(Geometry::Mesh(mesh))
        }
        t => Err(p.err(ctx, format!("unsupported shape type '{t}'; accepted: {}", TYPES.join(", ")))),
    }
}

/// Reads a `<shape>`; returns it with the description of its model.
pub fn load(ctx: &Ctx, node: Node, named: &Named) -> Result<(Shape, LoadedBsdf), XmlError> {
    let p = plugin(ctx, node, &["bsdf", "ref", "emitter"])?;
    let geometry = geometry(ctx, &p)?;
    let mut brdf = None;
    let mut emission = None;
    for &c in &p.children {
        if c.tag_name().name() == "emitter" {
            if emission.is_some() {
                return Err(ctx.err(c, "a shape takes at most one emitter"));
            }
            emission = Some(area_emitter(ctx, c)?);
        } else {
            if brdf.is_some() {
                return Err(ctx.err(c, "a shape takes at most one <bsdf> or <ref>"));
            }
            brdf = Some(bsdf::nested(ctx, c, named)?);
        }
    }
    let loaded = match brdf {
        Some(b) => b,
        // Mitsuba's default material.
        None => LoadedBsdf {
            brdf: Arc::from(brdf::build("lambert", &[("albedo", "0.5")]).expect("lambert 0.5 builds")),
            model: "lambert".to_string(),
            args: vec![("albedo".to_string(), "0.5".to_string())],
        },
    };
    Ok((Shape { geometry, brdf: loaded.brdf.clone(), emission }, loaded))
}

/// `<emitter type="area">` inside a shape: its radiance.
fn area_emitter(ctx: &Ctx, node: Node) -> Result<Rgb, XmlError> {
    let p = plugin(ctx, node, &[])?;
    if p.kind != "area" {
        return Err(p.err(ctx, format!("emitter type '{}' cannot sit inside a shape; accepted: area", p.kind)));
    }
    p.allow(ctx, &["radiance"])?;
    p.rgb(ctx, "radiance", Rgb::ONE)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cube_is_closed_with_outward_normals() {
        let c = unit_cube();
        assert_eq!(c.len(), 12);
        assert!((c.area() - 24.0).abs() < 1e-5);
        for i in 0..c.len() {
            let [a, b, d] = c.triangle(i);
            let centroid = (a + b + d) / 3.0;
            let (ng, _) = c.normals_at(i, 0.3, 0.3);
            assert!(ng.dot(centroid) > 0.0, "triangle {i} faces inwards");
        }
        assert_eq!(uniform_scale(&Mat4::from_scale(Vec3::splat(2.0))), Some(2.0));
        assert_eq!(uniform_scale(&Mat4::from_scale(Vec3::new(1.0, 2.0, 1.0))), None);
    }
}
