//! Mitsuba 3 XML scenes (`<scene version="3.0.0">`), read with `roxmltree`.
//!
//! Supported: `<default>` and `$name` substitution (values from the caller's defines first),
//! `<integrator>` (`path`, `direct`, `phong`), `<sensor type="perspective">` with `fov`,
//! `fov_axis`, `near_clip`, `far_clip`, `to_world`, a nested `<film type="hdrfilm">` (width,
//! height, `<rfilter>` box|gaussian) and `<sampler>` (sample_count, seed); `<shape>`s (obj,
//! ply, sphere, rectangle, disk, cube — see `shape.rs`), `<bsdf>`s nested or named by `id`
//! and used through `<ref id>` (see `bsdf.rs` for the Mitsuba → gonio mapping, and gonio's own
//! models by name), `<emitter>`s (see `emitter.rs`; `area` inside a shape). Paths are relative
//! to the scene file. Anything else is an error naming the file, line:column and element and
//! listing what is accepted.

pub mod bsdf;
pub mod emitter;
pub mod error;
pub mod parse;
pub mod shape;
pub mod transform;

pub use error::{Pos, XmlError};

use crate::camera::{Camera, FovAxis};
use crate::filter::Filter;
use crate::integrator::phong::PhongCoefficients;
use crate::integrator::Integrator;
use crate::scene::{Scene, SceneBuilder};
use parse::{plugin, Ctx};
use roxmltree::Node;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The elements accepted directly inside `<scene>`.
pub const SCENE_ELEMENTS: &[&str] = &["default", "integrator", "sensor", "shape", "bsdf", "emitter"];

/// A loaded scene with the render settings the file gave.
pub struct LoadedScene {
    /// The scene, ready to render.
    pub scene: Scene,
    /// `<sampler>` `sample_count` (Mitsuba's default 4).
    pub spp: u32,
    /// `<sampler>` `seed` (default 0).
    pub seed: u64,
    /// The `<integrator>` (default `path`, unbounded depth).
    pub integrator: Integrator,
    /// Film width in pixels.
    pub width: u32,
    /// Film height in pixels.
    pub height: u32,
    /// The film's reconstruction filter (Mitsuba's default: gaussian, σ = 0.5 px).
    pub filter: Filter,
}

impl std::fmt::Debug for LoadedScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LoadedScene")
            .field("shapes", &self.scene.shapes().len())
            .field("lights", &self.scene.lights().len())
            .field("spp", &self.spp)
            .field("seed", &self.seed)
            .field("integrator", &self.integrator)
            .field("width", &self.width)
            .field("height", &self.height)
            .field("filter", &self.filter)
            .finish()
    }
}

/// Loads the scene file `path`; `defines` give `$name` values (`-D name=value`), overriding
/// the file's `<default>`s.
pub fn load_scene(path: &Path, defines: &[(String, String)]) -> Result<LoadedScene, XmlError> {
    let text = std::fs::read_to_string(path).map_err(|e| XmlError::file(path, format!("cannot read: {e}")))?;
    let base = path.parent().map(Path::to_path_buf).unwrap_or_default();
    load(text, path.to_path_buf(), base, defines)
}

/// Loads a scene from `text`; relative paths resolve against `base_dir`, and errors name
/// the file as `<string>`.
pub fn load_scene_str(text: &str, base_dir: &Path, defines: &[(String, String)]) -> Result<LoadedScene, XmlError> {
    load(text.to_string(), PathBuf::from("<string>"), base_dir.to_path_buf(), defines)
}

fn load(text: String, file: PathBuf, base: PathBuf, defines: &[(String, String)]) -> Result<LoadedScene, XmlError> {
    let doc = match roxmltree::Document::parse(&text) {
        Ok(d) => d,
        Err(e) => {
            let p = e.pos();
            return Err(XmlError {
                file,
                pos: Some(Pos { line: p.row, col: p.col }),
                element: None,
                message: format!("malformed XML: {e}"),
            });
        }
    };
    let mut ctx = Ctx { file, base, vars: HashMap::new(), text: String::new() };
    let root = doc.root_element();
    // The context keeps its own copy of the text for positions; the document borrows `text`.
    ctx.text = text.clone();
    if root.tag_name().name() != "scene" {
        return Err(ctx.err(root, "the root element must be <scene>"));
    }
    ctx.check_attrs(root, &["version"])?;
    let elements: Vec<Node> = root.children().filter(Node::is_element).collect();
    for &e in &elements {
        let tag = e.tag_name().name();
        if !SCENE_ELEMENTS.contains(&tag) {
            return Err(ctx.err(
                e,
                format!("unsupported element <{tag}> in <scene>; accepted elements: {}", SCENE_ELEMENTS.join(", ")),
            ));
        }
        if tag == "default" {
            ctx.check_attrs(e, &["name", "value"])?;
            let name = e.attribute("name").ok_or_else(|| ctx.err(e, "missing attribute 'name'"))?;
            let value = e.attribute("value").ok_or_else(|| ctx.err(e, "missing attribute 'value'"))?;
            ctx.vars.insert(name.to_string(), value.to_string());
        }
    }
    for (k, v) in defines {
        ctx.vars.insert(k.clone(), v.clone());
    }

    // Named bsdfs first, so that a <ref> may come before or after the definition.
    let mut named = bsdf::Named::new();
    for &e in elements.iter().filter(|e| e.tag_name().name() == "bsdf") {
        let id = ctx
            .attr(e, "id")?
            .ok_or_else(|| ctx.err(e, "a <bsdf> inside <scene> needs an 'id' to be referenced by"))?;
        let b = bsdf::load(&ctx, e, &named)?;
        if named.insert(id.clone(), b).is_some() {
            return Err(ctx.err(e, format!("a second <bsdf> with id '{id}'")));
        }
    }

    let mut integrator = None;
    let mut sensor = None;
    for &e in &elements {
        match e.tag_name().name() {
            "integrator" if integrator.is_some() => return Err(ctx.err(e, "a second <integrator>")),
            "integrator" => integrator = Some(load_integrator(&ctx, e)?),
            "sensor" if sensor.is_some() => return Err(ctx.err(e, "a second <sensor>; one camera per scene")),
            "sensor" => sensor = Some(load_sensor(&ctx, e)?),
            _ => {}
        }
    }
    let sensor = sensor.ok_or_else(|| ctx.err(root, "the scene has no <sensor type=\"perspective\">"))?;
    let mut builder = SceneBuilder::new(sensor.camera);
    for &e in &elements {
        match e.tag_name().name() {
            "shape" => {
                let (s, model) = shape::load(&ctx, e, &named)?;
                let i = builder.shape(s);
                if let Some(c) = PhongCoefficients::from_model(&model.model, &model.arg_refs()) {
                    builder.set_phong(i, c);
                }
            }
            "emitter" => {
                builder.light(emitter::load(&ctx, e)?);
            }
            _ => {}
        }
    }
    let scene = builder.build().map_err(|e| ctx.err(root, e.to_string()))?;
    Ok(LoadedScene {
        scene,
        spp: sensor.spp,
        seed: sensor.seed,
        integrator: integrator.unwrap_or_default(),
        width: sensor.width,
        height: sensor.height,
        filter: sensor.filter,
    })
}

/// The integrator types accepted.
pub const INTEGRATORS: &[&str] = &["path", "direct", "phong"];

fn load_integrator(ctx: &Ctx, node: Node) -> Result<Integrator, XmlError> {
    let p = plugin(ctx, node, &[])?;
    let depth = |name: &str, default: i64| -> Result<u32, XmlError> {
        match p.int(ctx, name, default)? {
            -1 => Ok(u32::MAX),
            d if (0..=u32::MAX as i64).contains(&d) => Ok(d as u32),
            d => Err(p.err_at(ctx, name, format!("{name} = {d}; expected -1 (unbounded) or a count ≥ 0"))),
        }
    };
    let no_hiding = || -> Result<(), XmlError> {
        if p.bool(ctx, "hide_emitters", false)? {
            return Err(p.err_at(ctx, "hide_emitters", "hide_emitters=true is not supported"));
        }
        Ok(())
    };
    match p.kind.as_str() {
        "path" => {
            p.allow(ctx, &["max_depth", "rr_depth", "hide_emitters"])?;
            no_hiding()?;
            Ok(Integrator::Path { max_depth: depth("max_depth", -1)?, rr_depth: depth("rr_depth", 5)? })
        }
        "direct" => {
            p.allow(ctx, &["emitter_samples", "bsdf_samples", "shading_samples", "hide_emitters"])?;
            no_hiding()?;
            for n in ["emitter_samples", "bsdf_samples", "shading_samples"] {
                if p.int(ctx, n, 1)? != 1 {
                    return Err(p.err_at(ctx, n, format!("{n}: only 1 is supported (one light and one BRDF sample)")));
                }
            }
            Ok(Integrator::Direct)
        }
        "phong" => {
            p.allow(ctx, &["shadows"])?;
            Ok(Integrator::Phong { shadows: p.bool(ctx, "shadows", true)? })
        }
        t => Err(p.err(ctx, format!("unsupported integrator type '{t}'; accepted: {}", INTEGRATORS.join(", ")))),
    }
}

struct Sensor {
    camera: Camera,
    spp: u32,
    seed: u64,
    width: u32,
    height: u32,
    filter: Filter,
}

/// Samplers accepted; all give independent uniform samples here (the same expected image
/// as Mitsuba's stratified ones, with different noise).
const SAMPLERS: &[&str] = &["independent", "stratified", "multijitter", "orthogonal", "ldsampler"];

fn load_sensor(ctx: &Ctx, node: Node) -> Result<Sensor, XmlError> {
    let p = plugin(ctx, node, &["film", "sampler"])?;
    if p.kind != "perspective" {
        return Err(p.err(ctx, format!("unsupported sensor type '{}'; accepted: perspective", p.kind)));
    }
    p.allow(ctx, &["fov", "fov_axis", "near_clip", "far_clip", "to_world"])?;
    let fov = p.get("fov").ok_or_else(|| p.err(ctx, "missing property 'fov' (degrees)"))?;
    let fov = p
        .float_in(ctx, "fov", 0.0, 1e-3, 179.9)
        .map_err(|_| ctx.err(fov.node, "property 'fov' must be a <float> in (0, 180) degrees"))?;
    let axis: FovAxis =
        p.string(ctx, "fov_axis")?.unwrap_or("x").parse().map_err(|e: String| p.err_at(ctx, "fov_axis", e))?;
    let near = p.float_in(ctx, "near_clip", 0.01, 0.0, f64::MAX)?;
    let far = p.float_in(ctx, "far_clip", 1e4, 0.0, f64::INFINITY)?;
    if far <= near {
        return Err(p.err_at(ctx, "far_clip", format!("far_clip {far} must exceed near_clip {near}")));
    }
    let to_world = p.transform(ctx, "to_world")?;
    let (mut width, mut height, mut filter) = (768, 576, Filter::gaussian(0.5).expect("σ > 0"));
    let (mut spp, mut seed) = (4, 0);
    let (mut film_seen, mut sampler_seen) = (false, false);
    for &c in &p.children {
        if c.tag_name().name() == "film" {
            if std::mem::replace(&mut film_seen, true) {
                return Err(ctx.err(c, "a second <film>"));
            }
            let f = plugin(ctx, c, &["rfilter"])?;
            if f.kind != "hdrfilm" {
                return Err(f.err(ctx, format!("unsupported film type '{}'; accepted: hdrfilm", f.kind)));
            }
            f.allow(ctx, &["width", "height", "pixel_format", "component_format", "file_format"])?;
            let size = |n: &str, d: i64| -> Result<u32, XmlError> {
                let v = f.int(ctx, n, d)?;
                if !(1..=65536).contains(&v) {
                    return Err(f.err_at(ctx, n, format!("{n} = {v}; expected 1 to 65536 pixels")));
                }
                Ok(v as u32)
            };
            width = size("width", 768)?;
            height = size("height", 576)?;
            if let Some(pf) = f.string(ctx, "pixel_format")? {
                if !["rgb", "rgba"].contains(&pf) {
                    return Err(f.err_at(ctx, "pixel_format", format!("pixel_format '{pf}'; accepted: rgb, rgba")));
                }
            }
            for &r in &f.children {
                let rf = plugin(ctx, r, &[])?;
                filter = match rf.kind.as_str() {
                    "box" => {
                        rf.allow(ctx, &[])?;
                        Filter::Box
                    }
                    "gaussian" => {
                        rf.allow(ctx, &["stddev"])?;
                        let s = rf.float_in(ctx, "stddev", 0.5, 1e-3, 100.0)?;
                        Filter::gaussian(s as f32).expect("stddev checked > 0")
                    }
                    t => return Err(rf.err(ctx, format!("unsupported rfilter type '{t}'; accepted: box, gaussian"))),
                };
            }
        } else {
            if std::mem::replace(&mut sampler_seen, true) {
                return Err(ctx.err(c, "a second <sampler>"));
            }
            let s = plugin(ctx, c, &[])?;
            if !SAMPLERS.contains(&s.kind.as_str()) {
                return Err(
                    s.err(ctx, format!("unsupported sampler type '{}'; accepted: {}", s.kind, SAMPLERS.join(", ")))
                );
            }
            s.allow(ctx, &["sample_count", "seed", "jitter"])?;
            let n = s.int(ctx, "sample_count", 4)?;
            if !(1..=u32::MAX as i64).contains(&n) {
                return Err(s.err_at(ctx, "sample_count", format!("sample_count = {n}; expected ≥ 1")));
            }
            spp = n as u32;
            let sd = s.int(ctx, "seed", 0)?;
            if sd < 0 {
                return Err(s.err_at(ctx, "seed", format!("seed = {sd}; expected ≥ 0")));
            }
            seed = sd as u64;
        }
    }
    let mut camera = Camera::new(to_world, fov as f32, axis, width, height);
    camera.filter = filter.clone();
    camera.near_clip = near as f32;
    camera.far_clip = far as f32;
    Ok(Sensor { camera, spp, seed, width, height, filter })
}

#[cfg(test)]
mod tests {
    use super::parse::pos_at;
    use super::*;

    #[test]
    fn positions_count_lines_and_characters() {
        let t = "ab\ncdé\nf";
        assert_eq!(pos_at(t, 0), Pos { line: 1, col: 1 });
        assert_eq!(pos_at(t, 3), Pos { line: 2, col: 1 });
        assert_eq!(pos_at(t, t.find('f').unwrap()), Pos { line: 3, col: 1 });
        assert_eq!(pos_at(t, t.find('é').unwrap() + 2), Pos { line: 2, col: 4 });
    }
}
