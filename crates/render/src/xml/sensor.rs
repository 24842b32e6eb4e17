//! `<sensor>` (`perspective`, `thinlens`, `orthographic`) with its `<film type="hdrfilm">`
//! (size, crop window, `<rfilter>`) and `<sampler>`, and `<integrator>` (`path`, `direct`,
//! `phong`), with Mitsuba 3's parameters and defaults.
//!
//! The field of view: `fov` degrees along `fov_axis` (x, y, diagonal, smaller, larger), or a
//! `focal_length` of 35 mm film ("50mm" by default), fov = 2 atan(43.27 mm / 2f) along the
//! diagonal. A perspective camera's `to_world` may not scale (Mitsuba refuses it); an
//! orthographic one's scale sets the view's extent.

use super::error::XmlError;
use super::parse::{plugin, Plugin};
use super::tree::Elem;
use super::Loader;
use crate::camera::{Camera, FovAxis, Projection};
use crate::filter::Filter;
use crate::integrator::direct::DirectSamples;
use crate::integrator::Integrator;
use glam::{Mat3, Vec2};

/// The sensor types accepted.
pub const TYPES: &[&str] = &["perspective", "thinlens", "orthographic"];
/// The integrator types accepted.
pub const INTEGRATORS: &[&str] = &["path", "direct", "phong"];
/// Mitsuba's integrators gonio does not have.
const UNSUPPORTED_INTEGRATORS: &[&str] = &[
    "volpath",
    "volpathmis",
    "prb",
    "prb_basic",
    "prbvolpath",
    "direct_projective",
    "aov",
    "moment",
    "stokes",
    "depth",
    "ptracer",
    "prb_projective",
];
/// The reconstruction filters accepted.
const FILTERS: &[&str] = &["box", "gaussian", "tent", "mitchell", "catmullrom", "lanczos"];
/// Samplers accepted; all give independent uniform samples here (the same expected image
/// as Mitsuba's stratified ones, with different noise).
const SAMPLERS: &[&str] = &["independent", "stratified", "multijitter", "orthogonal", "ldsampler"];

/// What a `<sensor>` gives.
pub struct Sensor {
    /// The camera.
    pub camera: Camera,
    /// `<sampler>` `sample_count`.
    pub spp: u32,
    /// `<sampler>` `seed`.
    pub seed: u64,
    /// The film's reconstruction filter.
    pub filter: Filter,
}

/// A size property in 1..=65536 pixels.
fn size(f: &Plugin, name: &str, default: i64) -> Result<u32, XmlError> {
    let v = f.int(name, default)?;
    if !(1..=65536).contains(&v) {
        return Err(f.err_at(name, format!("{name} = {v}; expected 1 to 65536 pixels")));
    }
    Ok(v as u32)
}

/// The film: (width, height, crop offset, crop size, filter).
type Film = (u32, u32, (u32, u32), (u32, u32), Filter);

fn film(ld: &Loader, e: &Elem) -> Result<Film, XmlError> {
    let f = plugin(&ld.ids, e, &["rfilter"])?;
    if f.kind != "hdrfilm" {
        return Err(f.err(format!("unsupported film type '{}'; accepted: hdrfilm", f.kind)));
    }
    f.allow(&[
        "width",
        "height",
        "crop_offset_x",
        "crop_offset_y",
        "crop_width",
        "crop_height",
        "pixel_format",
        "component_format",
        "file_format",
        "sample_border",
        "banner",
    ])?;
    let (w, h) = (size(&f, "width", 768)?, size(&f, "height", 576)?);
    f.choice("pixel_format", &["rgb", "rgba", "luminance", "luminance_alpha", "xyz", "xyza"], "rgb")?;
    f.choice("component_format", &["float16", "float32", "uint32"], "float16")?;
    f.choice("file_format", &["openexr", "exr", "rgbe", "pfm"], "openexr")?;
    f.bool("banner", true)?;
    if f.bool("sample_border", false)? {
        return Err(f.err_at("sample_border", "sample_border=true is not supported"));
    }
    let off = (f.int("crop_offset_x", 0)?, f.int("crop_offset_y", 0)?);
    if off.0 < 0 || off.1 < 0 {
        return Err(f.err("crop_offset_x and crop_offset_y must be ≥ 0"));
    }
    let crop = (size(&f, "crop_width", w as i64)?, size(&f, "crop_height", h as i64)?);
    let mut filter = Filter::gaussian(0.5).expect("σ > 0");
    match f.objects.as_slice() {
        [] => {}
        [r] => filter = rfilter(ld, r)?,
        [_, second, ..] => return Err(second.err("a film takes one reconstruction filter")),
    }
    Ok((w, h, (off.0 as u32, off.1 as u32), crop, filter))
}

fn rfilter(ld: &Loader, e: &Elem) -> Result<Filter, XmlError> {
    let r = plugin(&ld.ids, e, &[])?;
    r.no_objects()?;
    Ok(match r.kind.as_str() {
        "box" => {
            r.allow(&[])?;
            Filter::Box
        }
        "gaussian" => {
            r.allow(&["stddev"])?;
            Filter::gaussian(r.float_in("stddev", 0.5, 1e-3, 100.0)? as f32).expect("stddev checked > 0")
        }
        "tent" => {
            r.allow(&["radius"])?;
            Filter::Tent { radius: r.float_in("radius", 1.0, 1e-3, 100.0)? as f32 }
        }
        "mitchell" => {
            r.allow(&["B", "C"])?;
            Filter::Mitchell { b: r.float("B", 1.0 / 3.0)? as f32, c: r.float("C", 1.0 / 3.0)? as f32 }
        }
        "catmullrom" => {
            r.allow(&[])?;
            Filter::Mitchell { b: 0.0, c: 0.5 }
        }
        "lanczos" => {
            r.allow(&["lobes"])?;
            let lobes = r.int("lobes", 3)?;
            if !(1..=32).contains(&lobes) {
                return Err(r.err_at("lobes", format!("lobes = {lobes}; expected 1 to 32")));
            }
            Filter::Lanczos { lobes: lobes as u32 }
        }
        t => return Err(r.err(format!("unsupported rfilter type '{t}'; accepted: {}", FILTERS.join(", ")))),
    })
}

fn sampler(ld: &Loader, e: &Elem) -> Result<(u32, u64), XmlError> {
    let s = plugin(&ld.ids, e, &[])?;
    s.no_objects()?;
    if !SAMPLERS.contains(&s.kind.as_str()) {
        return Err(s.err(format!("unsupported sampler type '{}'; accepted: {}", s.kind, SAMPLERS.join(", "))));
    }
    s.allow(&["sample_count", "seed", "jitter", "scramble_seed"])?;
    let n = s.int("sample_count", 4)?;
    if !(1..=u32::MAX as i64).contains(&n) {
        return Err(s.err_at("sample_count", format!("sample_count = {n}; expected ≥ 1")));
    }
    let seed = s.int("seed", 0)?;
    if seed < 0 {
        return Err(s.err_at("seed", format!("seed = {seed}; expected ≥ 0")));
    }
    Ok((n as u32, seed as u64))
}

/// The field of view in degrees along its axis, from `fov` or `focal_length`.
fn fov(p: &Plugin) -> Result<(f32, FovAxis), XmlError> {
    if p.get("fov").is_some() {
        if p.get("focal_length").is_some() {
            return Err(p.err_at("focal_length", "give either 'fov' or 'focal_length', not both"));
        }
        let fov = p.float("fov", 0.0)?;
        if !(fov > 0.0 && fov < 180.0) {
            return Err(p.err_at("fov", format!("fov = {fov}; expected degrees in (0, 180)")));
        }
        let axis = p.string("fov_axis")?.unwrap_or("x").to_ascii_lowercase();
        let axis: FovAxis = axis.parse().map_err(|m: String| p.err_at("fov_axis", m))?;
        return Ok((fov as f32, axis));
    }
    let text = p.string("focal_length")?.unwrap_or("50mm");
    let f: f64 = text
        .trim()
        .trim_end_matches("mm")
        .parse()
        .ok()
        .filter(|f: &f64| *f > 0.0 && f.is_finite())
        .ok_or_else(|| p.err_at("focal_length", format!("focal_length \"{text}\" is not a length such as 50mm")))?;
    let diagonal = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
    Ok(((2.0 * (diagonal / (2.0 * f)).atan()).to_degrees() as f32, FovAxis::Diagonal))
}

/// Reads the `<sensor>`.
pub fn load(ld: &Loader, e: &Elem) -> Result<Sensor, XmlError> {
    let p = plugin(&ld.ids, e, &["film", "sampler"])?;
    let kind = p.kind.as_str();
    if !TYPES.contains(&kind) {
        return Err(p.err(format!("unsupported sensor type '{kind}'; accepted: {}", TYPES.join(", "))));
    }
    let mut names = vec!["near_clip", "far_clip", "to_world", "shutter_open", "shutter_close", "focus_distance"];
    match kind {
        "perspective" => {
            names.extend(["fov", "fov_axis", "focal_length", "principal_point_offset_x", "principal_point_offset_y"])
        }
        "thinlens" => names.extend(["fov", "fov_axis", "focal_length", "aperture_radius", "focus_distance"]),
        _ => {}
    }
    p.allow(&names)?;
    let near = p.float("near_clip", 0.01)?;
    let far = p.float("far_clip", 1e4)?;
    if near.is_nan() || near <= 0.0 {
        return Err(p.err_at("near_clip", format!("near_clip = {near}; it must be > 0")));
    }
    if far.is_nan() || far <= near {
        return Err(p.err_at("far_clip", format!("far_clip {far} must exceed near_clip {near}")));
    }
    p.float("shutter_open", 0.0)?;
    p.float("shutter_close", 0.0)?;
    let to_world = p.transform("to_world")?;
    let (mut w, mut h, mut off, mut crop, mut filter) =
        (768, 576, (0, 0), (768, 576), Filter::gaussian(0.5).expect("σ > 0"));
    let (mut spp, mut seed) = (4, 0);
    let (mut film_seen, mut sampler_seen) = (false, false);
    for &c in &p.objects {
        if c.tag == "film" {
            if std::mem::replace(&mut film_seen, true) {
                return Err(c.err("a second <film>"));
            }
            (w, h, off, crop, filter) = film(ld, c)?;
        } else {
            if std::mem::replace(&mut sampler_seen, true) {
                return Err(c.err("a second <sampler>"));
            }
            (spp, seed) = sampler(ld, c)?;
        }
    }
    if kind != "orthographic" {
        let m = Mat3::from_mat4(to_world);
        let g = m.transpose() * m;
        if (g - Mat3::IDENTITY).to_cols_array().iter().any(|v| v.abs() > 1e-3) {
            return Err(p.err_at("to_world", "a camera's to_world may not scale (rotate, mirror and translate only)"));
        }
    }
    let (fov_deg, axis) = if kind == "orthographic" { (90.0, FovAxis::X) } else { fov(&p)? };
    let mut camera = Camera::new(to_world, fov_deg, axis, w, h);
    camera.near_clip = near as f32;
    camera.far_clip = far as f32;
    camera.filter = filter.clone();
    camera.projection = match kind {
        "thinlens" => {
            let r = p.get("aperture_radius").ok_or_else(|| p.err("missing property 'aperture_radius'"))?;
            let radius = p.float("aperture_radius", 0.0)?;
            if !(radius >= 0.0 && radius.is_finite()) {
                return Err(r.elem.err(format!("aperture_radius = {radius}; expected ≥ 0")));
            }
            let focus = p.float("focus_distance", far)?;
            if focus.is_nan() || focus <= 0.0 {
                return Err(p.err_at("focus_distance", format!("focus_distance = {focus}; expected > 0")));
            }
            Projection::ThinLens {
                aperture_radius: radius.max(f32::EPSILON as f64 / 2.0) as f32,
                focus_distance: focus as f32,
            }
        }
        "orthographic" => Projection::Orthographic,
        _ => Projection::Perspective,
    };
    camera.principal_point =
        Vec2::new(p.float("principal_point_offset_x", 0.0)? as f32, p.float("principal_point_offset_y", 0.0)? as f32);
    let camera = camera.cropped(off, crop.0, crop.1).ok_or_else(|| {
        p.err(format!(
            "the crop window ({}, {}) + {}×{} does not fit in the {w}×{h} film",
            off.0, off.1, crop.0, crop.1
        ))
    })?;
    Ok(Sensor { camera, spp, seed, filter })
}

/// Reads the `<integrator>`.
pub fn integrator(ld: &Loader, e: &Elem) -> Result<Integrator, XmlError> {
    let p = plugin(&ld.ids, e, &[])?;
    p.no_objects()?;
    let depth = |name: &str, default: i64| -> Result<u32, XmlError> {
        match p.int(name, default)? {
            -1 => Ok(u32::MAX),
            d if (0..=u32::MAX as i64).contains(&d) => Ok(d as u32),
            d => Err(p.err_at(name, format!("{name} = {d}; expected -1 (unbounded) or a count ≥ 0"))),
        }
    };
    let hide = p.bool("hide_emitters", false)?;
    match p.kind.as_str() {
        "path" => {
            p.allow(&["max_depth", "rr_depth", "hide_emitters", "timeout", "samples_per_pass", "block_size"])?;
            let rr_depth = depth("rr_depth", 5)?;
            if rr_depth == 0 {
                return Err(p.err_at("rr_depth", "rr_depth must be > 0"));
            }
            Ok(Integrator::Path { max_depth: depth("max_depth", -1)?, rr_depth, hide_emitters: hide })
        }
        "direct" => {
            p.allow(&[
                "emitter_samples",
                "bsdf_samples",
                "shading_samples",
                "hide_emitters",
                "timeout",
                "samples_per_pass",
                "block_size",
            ])?;
            let count = |name: &str, default: i64| -> Result<u32, XmlError> {
                match p.int(name, default)? {
                    n if (0..=1 << 16).contains(&n) => Ok(n as u32),
                    n => Err(p.err_at(name, format!("{name} = {n}; expected 0 to 65536"))),
                }
            };
            if p.get("shading_samples").is_some()
                && (p.get("emitter_samples").is_some() || p.get("bsdf_samples").is_some())
            {
                return Err(p.err_at("shading_samples", "give either shading_samples or emitter_samples/bsdf_samples"));
            }
            let shading = count("shading_samples", 1)?;
            let samples = DirectSamples {
                emitter: count("emitter_samples", shading as i64)?,
                bsdf: count("bsdf_samples", shading as i64)?,
            };
            if samples.emitter + samples.bsdf == 0 {
                return Err(p.err("a direct integrator needs at least one emitter or BSDF sample"));
            }
            Ok(Integrator::Direct { samples, hide_emitters: hide })
        }
        "phong" => {
            p.allow(&["shadows"])?;
            Ok(Integrator::Phong { shadows: p.bool("shadows", true)? })
        }
        t if UNSUPPORTED_INTEGRATORS.contains(&t) => {
            Err(p.err(format!("Mitsuba's '{t}' integrator is not supported; accepted: {}", INTEGRATORS.join(", "))))
        }
        t => Err(p.err(format!("unsupported integrator type '{t}'; accepted: {}", INTEGRATORS.join(", ")))),
    }
}
