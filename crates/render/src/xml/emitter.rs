//! Top-level `<emitter>`s: `point`, `spot`, `directional`, `constant`, `envmap`. `area`
//! emitters belong to a `<shape>` (nested, or declared here with an id and referenced from it;
//! one no shape references emits nothing, as in Mitsuba). Emitted colours are reduced as
//! emission (`<rgb>` and `<float>` as given; a spectrum by the CIE rule without an illuminant).

use super::error::XmlError;
use super::parse::{plugin, Plugin};
use super::texture;
use super::tree::Elem;
use super::Loader;
use crate::image::Image;
use crate::light::{ConstantEnv, DirectionalLight, EnvMap, Light, PointLight, SpotLight};
use glam::{Mat3, Vec3};
use radiometry::cie::SpectrumUse;
use radiometry::Rgb;

/// The emitter types accepted at the top level.
pub const TYPES: &[&str] = &["point", "spot", "directional", "constant", "envmap", "area"];

/// Mitsuba emitters gonio does not have.
pub const UNSUPPORTED: &[&str] = &["projector", "directionalarea", "sunsky"];

/// The position of a light given by `position` or by `to_world`'s translation, not both.
fn position(p: &Plugin) -> Result<Vec3, XmlError> {
    match (p.vec3("position")?, p.get("to_world")) {
        (Some(_), Some(_)) => Err(p.err_at("position", "give either 'position' or 'to_world', not both")),
        (Some(v), None) => Ok(v),
        (None, _) => Ok(p.transform("to_world")?.transform_point3(Vec3::ZERO)),
    }
}

/// An emitted colour that must be a constant, `default` when absent.
fn emitted(p: &Plugin, name: &str, default: Rgb) -> Result<Rgb, XmlError> {
    if p.object(name).is_some() {
        return Err(p.err_at(name, format!("'{name}' of a {} emitter must be a colour, not a texture", p.kind)));
    }
    Ok(texture::rgb_value(p, name, SpectrumUse::Emission)?
        .map_or(default, |c| Rgb::new(c[0] as f32, c[1] as f32, c[2] as f32)))
}

/// Reads a top-level `<emitter>`; None for an area emitter (a shape takes it).
pub fn load(ld: &Loader, e: &Elem) -> Result<Option<Light>, XmlError> {
    let p = plugin(&ld.ids, e, &["texture"])?;
    if p.kind != "spot" {
        p.no_objects()?;
    }
    Ok(Some(match p.kind.as_str() {
        "point" => {
            p.allow(&["position", "to_world", "intensity"])?;
            Light::Point(PointLight { position: position(&p)?, intensity: emitted(&p, "intensity", Rgb::ONE)? })
        }
        "spot" => {
            p.allow(&["to_world", "intensity", "cutoff_angle", "beam_width", "texture"])?;
            let m = p.transform("to_world")?;
            let axis = m
                .transform_vector3(Vec3::Z)
                .try_normalize()
                .ok_or_else(|| p.err_at("to_world", "to_world maps the spot's axis to zero"))?;
            let cutoff = p.float_in("cutoff_angle", 20.0, 1e-3, 180.0)?;
            let beam = p.float_in("beam_width", cutoff * 0.75, 0.0, 180.0)?.min(cutoff);
            let tex = match p.object("texture") {
                Some(t) => {
                    let frame = Mat3::from_mat4(m).inverse();
                    Some((texture::object(ld, t, SpectrumUse::Emission)?, frame))
                }
                None => None,
            };
            Light::Spot(SpotLight {
                position: m.transform_point3(Vec3::ZERO),
                axis,
                intensity: emitted(&p, "intensity", Rgb::ONE)?,
                cutoff: (cutoff as f32).to_radians(),
                beam_width: (beam as f32).to_radians(),
                texture: tex,
            })
        }
        "directional" => {
            p.allow(&["direction", "to_world", "irradiance"])?;
            let d = match (p.vec3("direction")?, p.get("to_world")) {
                (Some(_), Some(_)) => {
                    return Err(p.err_at("direction", "give either 'direction' or 'to_world', not both"))
                }
                (Some(d), None) => d,
                (None, _) => p.transform("to_world")?.transform_vector3(Vec3::Z),
            };
            let direction =
                d.try_normalize().ok_or_else(|| p.err_at("direction", "the direction is the zero vector"))?;
            Light::Directional(DirectionalLight { direction, irradiance: emitted(&p, "irradiance", Rgb::ONE)? })
        }
        "constant" => {
            p.allow(&["radiance", "to_world"])?;
            Light::Constant(ConstantEnv { radiance: emitted(&p, "radiance", Rgb::ONE)? })
        }
        "envmap" => {
            p.allow(&["filename", "scale", "to_world", "mis_compensation"])?;
            p.bool("mis_compensation", false)?;
            let name = p.string("filename")?.ok_or_else(|| p.err("missing property 'filename'"))?;
            let path = e.path(name);
            let image = load_map(&path).map_err(|err| p.err_at("filename", err))?;
            let scale = p.float_in("scale", 1.0, 0.0, f32::MAX as f64)?;
            let env = EnvMap::new(&image, scale as f32).map_err(|err| p.err_at("filename", err.to_string()))?;
            let to_world = Mat3::from_mat4(p.transform("to_world")?);
            let env = env.with_rotation(to_world).ok_or_else(|| {
                p.err_at("to_world", "an envmap's to_world may only rotate or mirror (its translation is ignored); a scale would distort the map")
            })?;
            Light::EnvMap(Box::new(env))
        }
        // Attached to the shape that references it.
        "area" => {
            p.allow(&["radiance"])?;
            return Ok(None);
        }
        t if UNSUPPORTED.contains(&t) => {
            return Err(p.err(format!("Mitsuba's '{t}' emitter is not supported; accepted: {}", TYPES.join(", "))))
        }
        t => return Err(p.err(format!("unsupported emitter type '{t}'; accepted: {}", TYPES.join(", ")))),
    }))
}

/// An environment map's image: EXR or HDR as they are, an 8-bit image decoded from sRGB.
fn load_map(path: &std::path::Path) -> Result<Image, String> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
    if ["exr", "hdr", "rgbe", "pic"].contains(&ext.as_str()) {
        return Image::load(path).map_err(|e| e.to_string());
    }
    let b = crate::texture::Bitmap::load(path, Default::default()).map_err(|e| e.to_string())?;
    let (w, h) = b.size();
    let mut img = Image::new(w as u32, h as u32);
    for y in 0..h {
        for x in 0..w {
            let uv = glam::Vec2::new((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            img.set(x as u32, y as u32, b.eval(uv));
        }
    }
    Ok(img)
}
