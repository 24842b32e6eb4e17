//! `<transform>`: a sequence of `translate`, `rotate`, `scale`, `matrix` and `lookat`, each
//! applied after the ones before it (M ← op · M), as in Mitsuba 3. `matrix` is row-major;
//! `rotate` takes degrees about an axis; `lookat` is the camera frame of `camera::look_at`.

use super::error::XmlError;
use super::parse::{float_text, numbers, Ctx};
use crate::camera::look_at;
use glam::{Mat4, Vec3};
use roxmltree::Node;

const OPS: &str = "translate, rotate, scale, matrix, lookat";

/// Three numbers from attributes x, y, z (each defaulting to `default`) or from `value`.
fn xyz(ctx: &Ctx, node: Node, default: f32) -> Result<Vec3, XmlError> {
    if let Some(v) = ctx.attr(node, "value")? {
        return match numbers(&v).as_deref() {
            Some(&[x, y, z]) => Ok(Vec3::new(x as f32, y as f32, z as f32)),
            Some(&[s]) if default == 1.0 => Ok(Vec3::splat(s as f32)),
            _ => Err(ctx.err(node, format!("value \"{v}\" is not three numbers \"x, y, z\""))),
        };
    }
    let mut c = [default; 3];
    for (k, a) in ["x", "y", "z"].iter().enumerate() {
        if let Some(t) = ctx.attr(node, a)? {
            c[k] = float_text(ctx, node, &t)? as f32;
        }
    }
    Ok(Vec3::from(c))
}

/// A point written as "x, y, z" in attribute `name`.
fn point_attr(ctx: &Ctx, node: Node, name: &str) -> Result<Vec3, XmlError> {
    let v = ctx.req_attr(node, name)?;
    match numbers(&v).as_deref() {
        Some(&[x, y, z]) => Ok(Vec3::new(x as f32, y as f32, z as f32)),
        _ => Err(ctx.err(node, format!("attribute '{name}' = \"{v}\" is not three numbers \"x, y, z\""))),
    }
}

/// Parses the operations inside a `<transform>` element.
pub fn parse(ctx: &Ctx, node: Node) -> Result<Mat4, XmlError> {
    let mut m = Mat4::IDENTITY;
    for op in node.children().filter(Node::is_element) {
        let tag = op.tag_name().name();
        let t = match tag {
            "translate" => {
                ctx.check_attrs(op, &["x", "y", "z", "value"])?;
                Mat4::from_translation(xyz(ctx, op, 0.0)?)
            }
            "scale" => {
                ctx.check_attrs(op, &["x", "y", "z", "value"])?;
                let s = xyz(ctx, op, 1.0)?;
                if s.x * s.y * s.z == 0.0 {
                    return Err(ctx.err(op, "a scale of 0 flattens the shape; every factor must be non-zero"));
                }
                Mat4::from_scale(s)
            }
            "rotate" => {
                ctx.check_attrs(op, &["x", "y", "z", "value", "angle"])?;
                let axis = xyz(ctx, op, 0.0)?;
                let axis = axis
                    .try_normalize()
                    .ok_or_else(|| ctx.err(op, "rotation axis is zero; give x, y, z or value=\"x, y, z\""))?;
                let angle = float_text(ctx, op, &ctx.req_attr(op, "angle")?)? as f32;
                Mat4::from_axis_angle(axis, angle.to_radians())
            }
            "matrix" => {
                ctx.check_attrs(op, &["value"])?;
                let v = ctx.req_attr(op, "value")?;
                let a: Vec<f32> = numbers(&v).unwrap_or_default().into_iter().map(|x| x as f32).collect();
                let mat = match a.len() {
                    // Row-major: the transpose of glam's column-major reading.
                    16 => Mat4::from_cols_array(&a.try_into().expect("16 numbers")).transpose(),
                    9 => Mat4::from_mat3(glam::Mat3::from_cols_array(&a.try_into().expect("9 numbers")).transpose()),
                    _ => {
                        return Err(ctx.err(op, format!("value \"{v}\" is not 16 (4×4) or 9 (3×3) numbers, row-major")))
                    }
                };
                if mat.determinant().abs() < 1e-12 || !mat.is_finite() {
                    return Err(ctx.err(op, "the matrix is singular (or not finite)"));
                }
                mat
            }
            "lookat" => {
                ctx.check_attrs(op, &["origin", "target", "up"])?;
                let origin = point_attr(ctx, op, "origin")?;
                let target = point_attr(ctx, op, "target")?;
                let up = if op.attribute("up").is_some() { point_attr(ctx, op, "up")? } else { Vec3::Y };
                look_at(origin, target, up)
                    .ok_or_else(|| ctx.err(op, "origin equals target, or up is parallel to the viewing direction"))?
            }
            other => return Err(ctx.err(op, format!("unsupported transform operation <{other}>; accepted: {OPS}"))),
        };
        m = t * m;
    }
    Ok(m)
}
