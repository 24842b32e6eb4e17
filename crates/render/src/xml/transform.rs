//! `<transform>`: a sequence of `translate`, `rotate`, `scale`, `matrix` and `lookat`, each
//! applied after the ones before it (M ← op · M), as in Mitsuba 3. `matrix` is row-major (16
//! numbers, its last row taken as 0 0 0 1, or a 3×3); `rotate` takes degrees about an axis
//! that is used as written — Rodrigues' R = cos θ I + (1 − cos θ) a aᵀ + sin θ [a]×, which is a
//! rotation only for a unit axis, exactly as Mitsuba builds it (its example scenes rotate about
//! (0, 1, 1)); `lookat` is the camera frame of `camera::look_at`, with Mitsuba's `up` when none
//! is given.

use super::error::XmlError;
use super::parse::{float_text, numbers};
use super::tree::Elem;
use crate::camera::look_at;
use glam::{Mat3, Mat4, Vec3};
use radiometry::Frame;

const OPS: &str = "translate, rotate, scale, matrix, lookat";

/// Three numbers from attributes x, y, z (each defaulting to `default`) or from `value`
/// (three numbers, or one for all three).
fn xyz(e: &Elem, default: f32) -> Result<Vec3, XmlError> {
    if let Some(v) = e.attr("value") {
        return match numbers(v).as_deref() {
            Some(&[x, y, z]) => Ok(Vec3::new(x as f32, y as f32, z as f32)),
            Some(&[s]) => Ok(Vec3::splat(s as f32)),
            _ => Err(e.err(format!("value \"{v}\" is not three numbers \"x, y, z\" (or one)"))),
        };
    }
    let mut c = [default; 3];
    for (k, a) in ["x", "y", "z"].iter().enumerate() {
        if let Some(t) = e.attr(a) {
            c[k] = float_text(e, t)? as f32;
        }
    }
    Ok(Vec3::from(c))
}

/// A point written as "x, y, z" in attribute `name`.
fn point_attr(e: &Elem, name: &str) -> Result<Vec3, XmlError> {
    let v = e.req(name)?;
    match numbers(v).as_deref() {
        Some(&[x, y, z]) => Ok(Vec3::new(x as f32, y as f32, z as f32)),
        _ => Err(e.err(format!("attribute '{name}' = \"{v}\" is not three numbers \"x, y, z\""))),
    }
}

/// Mitsuba's rotation about `a` (not normalised) by `degrees`.
fn rotation(a: Vec3, degrees: f32) -> Mat4 {
    let (s, c) = degrees.to_radians().sin_cos();
    let outer = Mat3::from_cols(a * a.x, a * a.y, a * a.z);
    let cross = Mat3::from_cols(Vec3::new(0.0, a.z, -a.y), Vec3::new(-a.z, 0.0, a.x), Vec3::new(a.y, -a.x, 0.0));
    Mat4::from_mat3(Mat3::IDENTITY * c + outer * (1.0 - c) + cross * s)
}

/// Parses the operations inside a `<transform>` element.
pub fn parse(t: &Elem) -> Result<Mat4, XmlError> {
    let mut m = Mat4::IDENTITY;
    for op in &t.children {
        let m_op = match op.tag.as_str() {
            "translate" => {
                op.check_attrs(&["x", "y", "z", "value"])?;
                Mat4::from_translation(xyz(op, 0.0)?)
            }
            "scale" => {
                op.check_attrs(&["x", "y", "z", "value"])?;
                let s = xyz(op, 1.0)?;
                if s.x * s.y * s.z == 0.0 {
                    return Err(op.err("a scale of 0 flattens the shape; every factor must be non-zero"));
                }
                Mat4::from_scale(s)
            }
            "rotate" => {
                op.check_attrs(&["x", "y", "z", "value", "angle"])?;
                let axis = xyz(op, 0.0)?;
                if axis == Vec3::ZERO {
                    return Err(op.err("rotation axis is zero; give x, y, z or value=\"x, y, z\""));
                }
                rotation(axis, float_text(op, op.req("angle")?)? as f32)
            }
            "matrix" => {
                op.check_attrs(&["value"])?;
                let v = op.req("value")?;
                let a: Vec<f32> = numbers(v).unwrap_or_default().into_iter().map(|x| x as f32).collect();
                let mut mat = match a.len() {
                    // Row-major: the transpose of glam's column-major reading.
                    16 => Mat4::from_cols_array(&a.try_into().expect("16 numbers")).transpose(),
                    9 => Mat4::from_mat3(Mat3::from_cols_array(&a.try_into().expect("9 numbers")).transpose()),
                    n => {
                        return Err(op
                            .err(format!("value \"{v}\" has {n} numbers; a matrix is 16 (4×4) or 9 (3×3), row-major")))
                    }
                };
                mat.x_axis.w = 0.0;
                mat.y_axis.w = 0.0;
                mat.z_axis.w = 0.0;
                mat.w_axis.w = 1.0;
                if mat.determinant().abs() < 1e-12 || !mat.is_finite() {
                    return Err(op.err("the matrix is singular (or not finite)"));
                }
                mat
            }
            "lookat" => {
                op.check_attrs(&["origin", "target", "up"])?;
                let origin = point_attr(op, "origin")?;
                let target = point_attr(op, "target")?;
                let mut up = if op.attr("up").is_some() { point_attr(op, "up")? } else { Vec3::ZERO };
                if up == Vec3::ZERO {
                    let dir = (target - origin).normalize_or_zero();
                    up = Frame::from_normal(dir).s;
                }
                look_at(origin, target, up)
                    .ok_or_else(|| op.err("origin equals target, or up is parallel to the viewing direction"))?
            }
            other => return Err(op.err(format!("unsupported transform operation <{other}>; accepted: {OPS}"))),
        };
        m = m_op * m;
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_use_the_axis_as_written() {
        // Mitsuba 3.9.1: <rotate z="2" angle="30"/> and <rotate x="1" y="1" angle="90"/>.
        let m = rotation(Vec3::new(0.0, 0.0, 2.0), 30.0);
        let want = Mat3::from_cols(
            Vec3::new(0.8660254, 1.0, 0.0),
            Vec3::new(-1.0, 0.8660254, 0.0),
            Vec3::new(0.0, 0.0, 1.4019238),
        );
        assert!(Mat3::from_mat4(m).abs_diff_eq(want, 1e-6), "{m}");
        let m = rotation(Vec3::new(1.0, 1.0, 0.0), 90.0);
        let want = Mat3::from_cols(Vec3::new(1.0, 1.0, -1.0), Vec3::new(1.0, 1.0, 1.0), Vec3::new(1.0, -1.0, 0.0));
        assert!(Mat3::from_mat4(m).abs_diff_eq(want, 1e-6), "{m}");
        // A unit axis is the usual right-handed rotation: 90° about x takes y to z.
        assert!(rotation(Vec3::X, 90.0).transform_vector3(Vec3::Y).abs_diff_eq(Vec3::Z, 1e-6));
    }
}
