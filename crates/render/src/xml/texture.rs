//! `<texture>` (`bitmap`, `checkerboard`), the spectrum plugins (`<spectrum type="d65">`,
//! `blackbody`, `uniform`, `srgb`, `regular`, `irregular`), and colour properties that may be
//! a constant or a texture, reduced to RGB for what they describe (`SpectrumUse`).
//!
//! `blackbody` cannot be evaluated by Mitsuba's RGB variants at all; gonio gives it the colour
//! its spectral variants converge to: Planck's radiance B(λ, T) (W·m⁻²·sr⁻¹·nm⁻¹, CODATA 2014
//! constants, zero outside 360–830 nm) reduced like any sampled emission spectrum.

use super::error::XmlError;
use super::parse::{plugin, Plugin, Spectrum, Val};
use super::tree::Elem;
use super::Loader;
use crate::texture::{Bitmap, BitmapOptions, Checkerboard, Decoded, FilterType, Texture, UvTransform, WrapMode};
use radiometry::cie::SpectrumUse;
use radiometry::Rgb;
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// The texture types accepted.
pub const TYPES: &[&str] = &["bitmap", "checkerboard"];
/// The spectrum types accepted.
pub const SPECTRUM_TYPES: &[&str] = &["d65", "blackbody", "uniform", "srgb", "regular", "irregular"];

/// An RGB triple as a constant texture.
pub fn constant(c: [f64; 3]) -> Texture {
    Texture::Constant(Rgb::new(c[0] as f32, c[1] as f32, c[2] as f32))
}

/// Planck's spectral radiance at `lambda_nm` for temperature `t` K, per nm.
fn planck(lambda_nm: f64, t: f64) -> f64 {
    const C: f64 = 2.99792458e8;
    const H: f64 = 6.62607004e-34;
    const K: f64 = 1.38064852e-23;
    let l = lambda_nm * 1e-9;
    1e-9 * 2.0 * H * C * C / (l.powi(5) * ((H * C / (l * K * t)).exp() - 1.0))
}

/// The object `e` (a `<texture>` or typed `<spectrum>`) as a texture describing `usage`.
pub fn object(ld: &Loader, e: &Elem, usage: SpectrumUse) -> Result<Texture, XmlError> {
    let key = (e as *const Elem, usage);
    if let Some(t) = ld.textures.borrow().get(&key) {
        return Ok(t.clone());
    }
    let t = build(ld, e, usage)?;
    ld.textures.borrow_mut().insert(key, t.clone());
    Ok(t)
}

fn build(ld: &Loader, e: &Elem, usage: SpectrumUse) -> Result<Texture, XmlError> {
    if e.tag == "spectrum" {
        return spectrum_plugin(ld, e, usage);
    }
    if e.tag != "texture" {
        return Err(e.err(format!("a <{}> cannot stand where a texture or colour is expected", e.tag)));
    }
    let p = plugin(&ld.ids, e, &["texture"])?;
    p.no_objects()?;
    match p.kind.as_str() {
        "bitmap" => {
            p.allow(&["filename", "filter_type", "wrap_mode", "raw", "to_uv", "format", "accel"])?;
            let name = p.string("filename")?.ok_or_else(|| p.err("missing property 'filename'"))?;
            let filter = match p.choice("filter_type", &["bilinear", "nearest"], "bilinear")? {
                "nearest" => FilterType::Nearest,
                _ => FilterType::Bilinear,
            };
            let wrap = match p.choice("wrap_mode", &["repeat", "mirror", "clamp"], "repeat")? {
                "mirror" => WrapMode::Mirror,
                "clamp" => WrapMode::Clamp,
                _ => WrapMode::Repeat,
            };
            // Storage formats change precision only.
            p.choice("format", &["auto", "variant", "float16", "uint8"], "auto")?;
            p.bool("accel", true)?;
            let options = BitmapOptions { filter, wrap, raw: p.bool("raw", false)?, to_uv: to_uv(&p)? };
            let path = e.path(name);
            let decoded = ld.decoded.borrow_mut().remove(&path);
            let bitmap = match decoded {
                Some(d) => Bitmap::from_decoded(&path, d, options),
                None => Bitmap::load(&path, options),
            }
            .map_err(|err| p.err_at("filename", err.to_string()))?;
            Ok(Texture::Bitmap(Arc::new(bitmap)))
        }
        "checkerboard" => {
            p.allow(&["color0", "color1", "to_uv"])?;
            Ok(Texture::Checkerboard(Arc::new(Checkerboard {
                color0: color(ld, &p, "color0", Rgb::splat(0.4), usage)?,
                color1: color(ld, &p, "color1", Rgb::splat(0.2), usage)?,
                to_uv: to_uv(&p)?,
            })))
        }
        t => Err(p.err(format!("unsupported texture type '{t}'; accepted: {}", TYPES.join(", ")))),
    }
}

/// Decodes every bitmap file the tree below `root` names, several at once; a file that
/// fails is left out, to be read again where it is used so that its error names that place.
pub fn prefetch(root: &Elem) -> HashMap<PathBuf, Decoded> {
    fn collect(e: &Elem, out: &mut Vec<PathBuf>) {
        if e.tag == "texture" && e.attr("type") == Some("bitmap") {
            let name = e.children.iter().find(|c| c.tag == "string" && c.attr("name") == Some("filename"));
            if let Some(value) = name.and_then(|c| c.attr("value")) {
                out.push(e.path(value));
            }
        }
        e.children.iter().for_each(|c| collect(c, out));
    }
    let mut paths = Vec::new();
    collect(root, &mut paths);
    paths.sort();
    paths.dedup();
    paths.into_par_iter().filter_map(|p| crate::texture::decode(&p).ok().map(|d| (p, d))).collect()
}

fn to_uv(p: &Plugin) -> Result<UvTransform, XmlError> {
    Ok(UvTransform::from_mat4(&p.transform("to_uv")?))
}

/// `<spectrum type="...">`.
fn spectrum_plugin(ld: &Loader, e: &Elem, usage: SpectrumUse) -> Result<Texture, XmlError> {
    let p = plugin(&ld.ids, e, &[])?;
    p.no_objects()?;
    match p.kind.as_str() {
        "d65" => {
            p.allow(&["color", "scale"])?;
            let scale = p.float("scale", 1.0)?;
            let c = match p.get("color") {
                None => [1.0; 3],
                Some(_) => rgb_value(&p, "color", usage)?.unwrap_or([1.0; 3]),
            };
            Ok(constant(c.map(|v| v * scale)))
        }
        "uniform" => {
            p.allow(&["value"])?;
            Ok(constant([p.float("value", 1.0)?; 3]))
        }
        "srgb" => {
            p.allow(&["color"])?;
            Ok(constant(rgb_value(&p, "color", usage)?.unwrap_or([0.5; 3])))
        }
        "blackbody" => {
            p.allow(&["temperature"])?;
            let t = p.get("temperature").ok_or_else(|| p.err("missing property 'temperature' (kelvin)"))?;
            let t = p
                .float_in("temperature", 0.0, 1.0, 1e6)
                .map_err(|_| t.elem.err("temperature must be in (0, 1e6] K"))?;
            if usage == SpectrumUse::Reflectance {
                return Err(p.err("a blackbody is an emission spectrum; it cannot be a reflectance"));
            }
            let lambda: Vec<f64> = (360..=830).map(f64::from).collect();
            let values: Vec<f64> = lambda.iter().map(|&l| planck(l, t)).collect();
            Ok(constant(Spectrum::Sampled { lambda, values }.rgb(usage)))
        }
        "regular" => {
            p.allow(&["wavelength_min", "wavelength_max", "values"])?;
            let (lo, hi) = (p.float("wavelength_min", 360.0)?, p.float("wavelength_max", 830.0)?);
            let values = number_list(&p, "values")?;
            if values.len() < 2 || hi.is_nan() || hi <= lo {
                return Err(p.err("a regular spectrum needs wavelength_min < wavelength_max and two or more values"));
            }
            let n = values.len() - 1;
            let lambda = (0..=n).map(|i| lo + (hi - lo) * i as f64 / n as f64).collect();
            Ok(constant(Spectrum::Sampled { lambda, values }.rgb(usage)))
        }
        "irregular" => {
            p.allow(&["wavelengths", "values"])?;
            let (lambda, values) = (number_list(&p, "wavelengths")?, number_list(&p, "values")?);
            if lambda.len() != values.len() || lambda.len() < 2 || lambda.windows(2).any(|w| w[1] <= w[0]) {
                return Err(p.err("an irregular spectrum needs as many values as increasing wavelengths, two or more"));
            }
            Ok(constant(Spectrum::Sampled { lambda, values }.rgb(usage)))
        }
        t => Err(p.err(format!("unsupported spectrum type '{t}'; accepted: {}", SPECTRUM_TYPES.join(", ")))),
    }
}

/// A `<string>` list of numbers.
fn number_list(p: &Plugin, name: &str) -> Result<Vec<f64>, XmlError> {
    let s = p.string(name)?.ok_or_else(|| p.err(format!("missing property '{name}'")))?;
    super::parse::numbers(s).ok_or_else(|| p.err_at(name, format!("'{name}' = \"{s}\" is not a list of numbers")))
}

/// A colour property given as a value (not a texture), reduced for `usage`; None when absent.
/// A reflectance `<rgb>` must lie in [0, 1], as Mitsuba requires.
pub fn rgb_value(p: &Plugin, name: &str, usage: SpectrumUse) -> Result<Option<[f64; 3]>, XmlError> {
    let Some(prop) = p.get(name) else { return Ok(None) };
    let c = match &prop.val {
        Val::Float(v) => [*v; 3],
        Val::Int(v) => [*v as f64; 3],
        Val::Rgb(c) => {
            if usage == SpectrumUse::Reflectance && c.iter().any(|v| !(0.0..=1.0).contains(v)) {
                return Err(prop.elem.err(format!("a reflectance's <rgb> must lie in [0, 1], not {c:?}")));
            }
            *c
        }
        Val::Spectrum(s) => s.rgb(usage),
        _ => return Err(prop.elem.err(format!("property '{name}' must be given as <rgb>, <spectrum> or <float>"))),
    };
    if c.iter().any(|v| !v.is_finite() || *v < 0.0) {
        return Err(prop.elem.err(format!("property '{name}' must have finite channels ≥ 0")));
    }
    Ok(Some(c))
}

/// A colour property that may be a texture: a constant (`default` when absent) or the texture.
pub fn color(ld: &Loader, p: &Plugin, name: &str, default: Rgb, usage: SpectrumUse) -> Result<Texture, XmlError> {
    if let Some(e) = p.object(name) {
        return object(ld, e, usage);
    }
    Ok(rgb_value(p, name, usage)?.map_or(Texture::Constant(default), constant))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn planck_matches_mitsubas_spectral_values() {
        // Mitsuba 3.9.1 scalar_spectral blackbody values.
        for (l, t, want) in [(400.0, 3000.0, 72.1974), (555.0, 3000.0, 399.6393), (500.0, 6500.0, 46097.14)] {
            let got = planck(l, t);
            assert!((got - want).abs() < 1e-5 * want, "{l} nm {t} K: {got}");
        }
    }
}
