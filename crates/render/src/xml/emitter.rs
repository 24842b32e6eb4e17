//! Top-level `<emitter>`s: `point`, `spot`, `directional`, `constant`, `envmap`. `area`
//! emitters sit inside a `<shape>` (see `shape.rs`).

use super::error::XmlError;
use super::parse::{plugin, Ctx, Plugin};
use crate::image::Image;
use crate::light::{ConstantEnv, DirectionalLight, EnvMap, Light, PointLight, SpotLight};
use glam::{Mat3, Vec3};
use radiometry::Rgb;
use roxmltree::Node;

/// The emitter types accepted at the top level.
pub const TYPES: &[&str] = &["point", "spot", "directional", "constant", "envmap"];

/// The position of a light given by `position` or by `to_world`'s translation, not both.
fn position(ctx: &Ctx, p: &Plugin) -> Result<Vec3, XmlError> {
    match (p.vec3(ctx, "position")?, p.get("to_world")) {
        (Some(_), Some(_)) => Err(p.err_at(ctx, "position", "give either 'position' or 'to_world', not both")),
        (Some(v), None) => Ok(v),
        (None, _) => Ok(p.transform(ctx, "to_world")?.transform_point3(Vec3::ZERO)),
    }
}

/// Reads a top-level `<emitter>`.
pub fn load(ctx: &Ctx, node: Node) -> Result<Light, XmlError> {
    let p = plugin(ctx, node, &[])?;
    match p.kind.as_str() {
        "point" => {
            p.allow(ctx, &["position", "to_world", "intensity"])?;
            Ok(Light::Point(PointLight { position: position(ctx, &p)?, intensity: p.rgb(ctx, "intensity", Rgb::ONE)? }))
        }
        "spot" => {
            p.allow(ctx, &["to_world", "intensity", "cutoff_angle", "beam_width"])?;
            let m = p.transform(ctx, "to_world")?;
            let axis = m
                .transform_vector3(Vec3::Z)
                .try_normalize()
                .ok_or_else(|| p.err_at(ctx, "to_world", "to_world maps the spot's axis to zero"))?;
            let cutoff = p.float_in(ctx, "cutoff_angle", 20.0, 1e-3, 180.0)?;
            let beam = p.float_in(ctx, "beam_width", cutoff * 0.75, 0.0, cutoff)?;
            Ok(Light::Spot(SpotLight {
                position: m.transform_point3(Vec3::ZERO),
                axis,
                intensity: p.rgb(ctx, "intensity", Rgb::ONE)?,
                cutoff: (cutoff as f32).to_radians(),
                beam_width: (beam as f32).to_radians(),
            }))
        }
        "directional" => {
            p.allow(ctx, &["direction", "to_world", "irradiance"])?;
            let d = match (p.vec3(ctx, "direction")?, p.get("to_world")) {
                (Some(_), Some(_)) => {
                    return Err(p.err_at(ctx, "direction", "give either 'direction' or 'to_world', not both"))
                }
                (Some(d), None) => d,
                (None, _) => p.transform(ctx, "to_world")?.transform_vector3(Vec3::Z),
            };
            let direction =
                d.try_normalize().ok_or_else(|| p.err_at(ctx, "direction", "the direction is the zero vector"))?;
            Ok(Light::Directional(DirectionalLight { direction, irradiance: p.rgb(ctx, "irradiance", Rgb::ONE)? }))
        }
        "constant" => {
            p.allow(ctx, &["radiance"])?;
            Ok(Light::Constant(ConstantEnv { radiance: p.rgb(ctx, "radiance", Rgb::ONE)? }))
        }
        "envmap" => {
            p.allow(ctx, &["filename", "scale", "to_world"])?;
            let name = p.string(ctx, "filename")?.ok_or_else(|| p.err(ctx, "missing property 'filename'"))?;
            let image = Image::load(ctx.path(name)).map_err(|e| p.err_at(ctx, "filename", e.to_string()))?;
            let scale = p.float_in(ctx, "scale", 1.0, 0.0, f32::MAX as f64)?;
            let env = EnvMap::new(&image, scale as f32).map_err(|e| p.err_at(ctx, "filename", e.to_string()))?;
            let to_world = Mat3::from_mat4(p.transform(ctx, "to_world")?);
            let env = env
                .with_rotation(to_world)
                .ok_or_else(|| p.err_at(ctx, "to_world", "an envmap's to_world must be a rotation"))?;
            Ok(Light::EnvMap(Box::new(env)))
        }
        "area" => Err(p.err(ctx, "an area emitter goes inside the <shape> that emits")),
        t => Err(
            p.err(ctx, format!("unsupported emitter type '{t}'; accepted: {} (area inside a shape)", TYPES.join(", ")))
        ),
    }
}
