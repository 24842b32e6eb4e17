//! `<bsdf>`: Mitsuba 3's plugins as gonio models, and gonio's own models by their
//! `gonio models` names with their own parameter names.
//!
//! A Mitsuba plugin whose names or defaults differ from its gonio model's is a row of
//! [`ROWS`]: the model, the renamed parameters, Mitsuba's defaults where they differ, the values
//! Mitsuba fixes, the properties read and ignored. Every other plugin ([`SAME_NAME`]) has a
//! model of its own name and parameters. Values stay typed: a `<float>`
//! is a number, an `<rgb>` a colour, a `<spectrum>` its RGB reduction for what the parameter
//! describes (a reflectance, or an unbounded constant such as η), a `<texture>` or `<ref>` a
//! texture; every range is the model's `ParamSpec`, and a texture is accepted only where the
//! `ParamSpec` says the parameter may vary.
//!
//! The wrappers are materials around materials: `twosided` (one model on both sides, or two),
//! `mask` (opacity), `blendbsdf` (weight, two models), `normalmap` and `bumpmap`.

use super::error::XmlError;
use super::parse::{plugin, Plugin, Val};
use super::texture;
use super::tree::Elem;
use super::Loader;
use crate::material::{Material, Textured};
use crate::scene::SurfaceInteraction;
use crate::texture::Texture;
use brdf::{ModelSpec, ParamError, ParamKind, ParamSpec, Params, Value};
use glam::{Vec2, Vec3};
use radiometry::cie::SpectrumUse;
use radiometry::{Frame, Rgb};
use std::sync::Arc;

/// A Mitsuba plugin over a gonio model whose names or defaults differ.
pub struct Row {
    /// Mitsuba's plugin name.
    pub mitsuba: &'static str,
    /// The gonio model.
    pub model: &'static str,
    /// (Mitsuba's name, gonio's name) of renamed parameters.
    pub renamed: &'static [(&'static str, &'static str)],
    /// Mitsuba's defaults where they differ from gonio's (gonio names, as text).
    pub defaults: &'static [(&'static str, &'static str)],
    /// Values Mitsuba fixes (gonio names): the file cannot give them.
    pub fixed: &'static [(&'static str, &'static str)],
    /// Mitsuba properties read and ignored: they change the noise, not the image.
    pub ignored: &'static [&'static str],
}

/// The plugins whose model differs in names or defaults.
pub const ROWS: &[Row] = &[
    Row {
        mitsuba: "diffuse",
        model: "lambert",
        renamed: &[("reflectance", "albedo")],
        defaults: &[("albedo", "0.5")],
        fixed: &[],
        ignored: &[],
    },
    Row {
        mitsuba: "conductor",
        model: "mirror",
        renamed: &[("specular_reflectance", "reflectance")],
        defaults: &[("material", "none")],
        fixed: &[("fresnel", "conductor")],
        ignored: &[],
    },
    Row {
        mitsuba: "roughconductor",
        model: "microfacet",
        renamed: &[("specular_reflectance", "reflectance")],
        defaults: &[("distribution", "beckmann"), ("alpha", "0.1"), ("material", "none")],
        // Mitsuba's rough conductors take G1(wi) G1(wo).
        fixed: &[("fresnel", "conductor"), ("shadowing", "smith-separable"), ("diffuse", "0")],
        ignored: &["sample_visible"],
    },
    Row {
        mitsuba: "roughplastic",
        model: "roughplastic",
        renamed: &[],
        defaults: &[],
        fixed: &[],
        ignored: &["sample_visible"],
    },
    Row {
        mitsuba: "roughdielectric",
        model: "roughdielectric",
        renamed: &[],
        defaults: &[],
        fixed: &[],
        ignored: &["sample_visible"],
    },
];

/// Mitsuba plugins whose gonio model has their name and parameters.
pub const SAME_NAME: &[&str] = &[
    "plastic",
    "roughplastic",
    "dielectric",
    "roughdielectric",
    "thindielectric",
    "principled",
    "principledthin",
    "null",
];

/// Mitsuba's wrappers, built here around nested materials.
pub const WRAPPERS: &[&str] = &["twosided", "mask", "blendbsdf", "normalmap", "bumpmap"];

/// Mitsuba BSDFs gonio does not have.
pub const UNSUPPORTED: &[&str] =
    &["hair", "measured", "pplastic", "polarizer", "retarder", "circular", "measured_polarized"];

/// The material of a `<bsdf>` element (or the object a `<ref>` names), built once per element.
pub fn material(ld: &Loader, e: &Elem) -> Result<Material, XmlError> {
    let e = ld.ids.deref(e)?;
    let key = e as *const Elem;
    if let Some(m) = ld.materials.borrow().get(&key) {
        return Ok(m.clone());
    }
    if e.tag != "bsdf" {
        return Err(e.err(format!("a <{}> stands where a <bsdf> is expected", e.tag)));
    }
    let m = build(ld, e)?;
    ld.materials.borrow_mut().insert(key, m.clone());
    Ok(m)
}

fn build(ld: &Loader, e: &Elem) -> Result<Material, XmlError> {
    let p = plugin(&ld.ids, e, &["bsdf", "texture"])?;
    let kind = p.kind.as_str();
    if WRAPPERS.contains(&kind) {
        return wrapper(ld, &p);
    }
    p.no_objects()?;
    if let Some(row) = ROWS.iter().find(|r| r.mitsuba == kind) {
        let spec = brdf::find(row.model).expect("every row names a registered model");
        return model(ld, &p, spec, Some(row));
    }
    if UNSUPPORTED.contains(&kind) {
        return Err(p.err(format!("Mitsuba's '{kind}' BSDF is not supported; {}", accepted())));
    }
    match brdf::find(kind) {
        Ok(spec) if !is_wrapper_model(spec) => model(ld, &p, spec, None),
        _ => Err(p.err(format!("unknown BSDF type '{kind}'; {}", accepted()))),
    }
}

/// The registry's own wrapper models take their nested models as text (for `gonio check`); in a
/// scene file the Mitsuba wrapper of that name is meant.
fn is_wrapper_model(spec: &ModelSpec) -> bool {
    (spec.params)().iter().any(|p| p.kind == ParamKind::Model)
}

/// The accepted types, for errors.
fn accepted() -> String {
    let rows = ROWS.iter().map(|r| r.mitsuba).filter(|n| !SAME_NAME.contains(n));
    let mitsuba: Vec<&str> = rows.chain(SAME_NAME.iter().copied()).chain(WRAPPERS.iter().copied()).collect();
    let ours: Vec<&str> = brdf::models().iter().filter(|m| !is_wrapper_model(m)).map(|m| m.name).collect();
    format!("accepted: Mitsuba's {}, and gonio's models {}", mitsuba.join(", "), ours.join(", "))
}

/// What a colour parameter describes, for a `<spectrum>`'s reduction.
fn usage(s: &ParamSpec) -> SpectrumUse {
    match s.kind {
        ParamKind::Rgb { max, .. } if max <= 1.0 => SpectrumUse::Reflectance,
        _ => SpectrumUse::Unbounded,
    }
}

/// A property's value as parameter `s` takes it.
fn value(s: &ParamSpec, prop: &super::parse::Prop, e: &Elem) -> Result<Value, XmlError> {
    let wrong = |what: &str| prop.elem.err(format!("property '{}' must be given as {what}", prop.name));
    Ok(match (&s.kind, &prop.val) {
        (ParamKind::Float { .. }, Val::Float(v)) => Value::Float(*v),
        (ParamKind::Float { .. }, Val::Int(v)) => Value::Float(*v as f64),
        (ParamKind::Float { .. }, Val::Spectrum(super::parse::Spectrum::Uniform(v))) => Value::Float(*v),
        (ParamKind::Float { .. }, Val::Str(t)) if !s.names.is_empty() => {
            s.parse(t).map_err(|err| prop.elem.err(err.to_string()))?
        }
        (ParamKind::Float { .. }, _) => {
            return Err(wrong(if s.names.is_empty() { "<float>" } else { "a <float> or a <string> name" }))
        }
        (ParamKind::Rgb { .. }, Val::Float(v)) => Value::Float(*v),
        (ParamKind::Rgb { .. }, Val::Int(v)) => Value::Float(*v as f64),
        (ParamKind::Rgb { .. }, Val::Rgb(c)) => Value::Rgb(*c),
        (ParamKind::Rgb { .. }, Val::Spectrum(sp)) => Value::Rgb(sp.rgb(usage(s))),
        (ParamKind::Rgb { .. }, _) => return Err(wrong("<rgb>, <spectrum>, <float> or a texture")),
        (ParamKind::Choice(_), Val::Str(t)) => Value::Choice(t.clone()),
        (ParamKind::Choice(opts), _) => return Err(wrong(&format!("a <string>, one of {}", opts.join("|")))),
        (ParamKind::Bool, Val::Bool(b)) => Value::Bool(*b),
        (ParamKind::Bool, _) => return Err(wrong("<boolean>")),
        (ParamKind::Path, Val::Str(t)) => Value::Path(e.path(t).to_string_lossy().into_owned()),
        (ParamKind::Path, _) => return Err(wrong("a <string> file name")),
        (ParamKind::Model, _) => return Err(wrong("a nested <bsdf> of a wrapper")),
    })
}

/// A model from a plugin element, `row` giving Mitsuba's names and defaults.
fn model(ld: &Loader, p: &Plugin, spec: &'static ModelSpec, row: Option<&Row>) -> Result<Material, XmlError> {
    let empty = Row { mitsuba: "", model: "", renamed: &[], defaults: &[], fixed: &[], ignored: &[] };
    let row = row.unwrap_or(&empty);
    let ours = |written: &str| -> String {
        row.renamed.iter().find(|(m, _)| *m == written).map_or(written, |(_, o)| *o).to_string()
    };
    let theirs = |ours: &'static str| row.renamed.iter().find(|(_, o)| *o == ours).map_or(ours, |(m, _)| *m);
    let specs: Vec<ParamSpec> = (spec.params)()
        .into_iter()
        .map(|s| match row.defaults.iter().find(|(n, _)| *n == s.name) {
            Some((_, text)) => {
                let d = s.parse(text).expect("a row's default is valid for its model");
                s.with_default(d)
            }
            None => s,
        })
        .collect();
    let mut accepted: Vec<&str> =
        specs.iter().filter(|s| !row.fixed.iter().any(|(n, _)| *n == s.name)).map(|s| theirs(s.name)).collect();
    accepted.extend(row.ignored);
    p.allow(&accepted)?;
    let mut values: Vec<(&str, Value)> = Vec::new();
    let mut textures = Vec::new();
    for prop in &p.props {
        if row.ignored.contains(&prop.name.as_str()) {
            continue;
        }
        let name = ours(&prop.name);
        let s = specs.iter().find(|s| s.name == name).expect("allow() checked the name");
        match prop.val {
            Val::Object(obj) => {
                if !s.varies {
                    return Err(prop.elem.err(format!(
                        "parameter '{}' of '{}' cannot be a texture: it is constant over a surface",
                        prop.name, spec.name
                    )));
                }
                textures.push((s.clone(), texture::object(ld, obj, usage(s))?));
            }
            _ => values.push((s.name, value(s, prop, p.elem)?)),
        }
    }
    for (n, text) in row.fixed {
        let s = specs.iter().find(|s| s.name == *n).expect("a row fixes a parameter of its model");
        values.push((s.name, s.parse(text).expect("a row's fixed value is valid")));
    }
    let at = |e: ParamError| {
        let name = match &e {
            ParamError::BadValue { name, .. } | ParamError::UnknownParam { name, .. } => Some(theirs_of(row, name)),
            _ => None,
        };
        let where_ = name.and_then(|n| p.get(&n)).map_or(p.elem, |prop| prop.elem);
        where_.err(format!("{e} (gonio model '{}')", spec.name))
    };
    let params = Params::from_values(spec.name, &specs, &values).map_err(at)?;
    if textures.is_empty() {
        return Ok(Material::Fixed(Arc::from(spec.build_from(&params).map_err(at)?)));
    }
    let t = Textured::new(spec, params, textures).map_err(|m| p.err(format!("{m} (gonio model '{}')", spec.name)))?;
    Ok(Material::Textured(Arc::new(t)))
}

/// The Mitsuba name of gonio parameter `ours` under `row`.
fn theirs_of(row: &Row, ours: &str) -> String {
    row.renamed.iter().find(|(_, o)| *o == ours).map_or(ours, |(m, _)| *m).to_string()
}

/// The nested `<bsdf>`s of a wrapper, in file order.
fn nested<'t>(p: &Plugin<'t>) -> Vec<&'t Elem> {
    let named = p.props.iter().filter_map(|q| match q.val {
        Val::Object(e) if e.tag == "bsdf" => Some((q.elem.src.pos, e)),
        _ => None,
    });
    let mut all: Vec<_> = p.objects.iter().filter(|e| e.tag == "bsdf").map(|e| (e.src.pos, *e)).chain(named).collect();
    all.sort_by_key(|(pos, _)| (pos.line, pos.col));
    all.into_iter().map(|(_, e)| e).collect()
}

/// One nested `<bsdf>`, exactly.
fn one_nested(ld: &Loader, p: &Plugin) -> Result<Box<Material>, XmlError> {
    match nested(p).as_slice() {
        [one] => Ok(Box::new(material(ld, one)?)),
        other => Err(p.err(format!("{} takes exactly one nested <bsdf>, not {}", p.kind, other.len()))),
    }
}

/// A one-number texture property (`opacity`, `weight`), with `default` when absent.
fn scalar(ld: &Loader, p: &Plugin, name: &str, default: Option<f32>) -> Result<Texture, XmlError> {
    if p.get(name).is_none() {
        return default
            .map(|d| Texture::Constant(Rgb::splat(d)))
            .ok_or_else(|| p.err(format!("missing property '{name}' (a <float> or a texture)")));
    }
    texture::color(ld, p, name, Rgb::ZERO, SpectrumUse::Reflectance)
}

/// A surface point for load-time checks of a material's model.
fn probe() -> SurfaceInteraction {
    SurfaceInteraction {
        t: 1.0,
        p: Vec3::ZERO,
        ng: Vec3::Z,
        frame: Frame::IDENTITY,
        uv: Vec2::splat(0.5),
        dp_du: Vec3::X,
        dp_dv: Vec3::Y,
        shape: 0,
    }
}

fn wrapper(ld: &Loader, p: &Plugin) -> Result<Material, XmlError> {
    let flags = |p: &Plugin| -> Result<(bool, bool), XmlError> {
        Ok((p.bool("flip_invalid_normals", true)?, p.bool("use_shadowing_function", true)?))
    };
    match p.kind.as_str() {
        "twosided" => {
            p.allow(&[])?;
            let bsdfs = nested(p);
            let (front, back) = match bsdfs.as_slice() {
                [one] => {
                    let m = material(ld, one)?;
                    (m.clone(), m)
                }
                [front, back] => (material(ld, front)?, material(ld, back)?),
                _ => return Err(p.err("twosided takes one nested <bsdf> or <ref> (or two: front, back)")),
            };
            for (m, e) in [(&front, bsdfs[0]), (&back, *bsdfs.last().expect("one or two"))] {
                if m.with(&probe(), |b| b.transmits()) {
                    return Err(e.err(
                        "twosided takes only models without transmission (Mitsuba's rule; glass, masks and \
                         null surfaces already have two sides: put twosided inside the mask)",
                    ));
                }
            }
            Ok(Material::TwoSided(Box::new(front), Box::new(back)))
        }
        "mask" => {
            p.allow(&["opacity"])?;
            Ok(Material::Mask { opacity: scalar(ld, p, "opacity", Some(0.5))?, nested: one_nested(ld, p)? })
        }
        "blendbsdf" => {
            p.allow(&["weight"])?;
            let bsdfs = nested(p);
            let [first, second] = bsdfs.as_slice() else {
                return Err(p.err(format!("blendbsdf takes exactly two nested <bsdf>s, not {}", bsdfs.len())));
            };
            Ok(Material::Blend {
                weight: scalar(ld, p, "weight", None)?,
                first: Box::new(material(ld, first)?),
                second: Box::new(material(ld, second)?),
            })
        }
        "normalmap" => {
            p.allow(&["normalmap", "flip_invalid_normals", "use_shadowing_function"])?;
            let map = p.object("normalmap").ok_or_else(|| p.err("missing the texture 'normalmap'"))?;
            let (flip_invalid, shadowing) = flags(p)?;
            Ok(Material::NormalMap {
                map: texture::object(ld, map, SpectrumUse::Unbounded)?,
                flip_invalid,
                shadowing,
                nested: one_nested(ld, p)?,
            })
        }
        "bumpmap" => {
            let textures: Vec<&Elem> = p
                .objects
                .iter()
                .copied()
                .chain(p.props.iter().filter_map(|q| match q.val {
                    Val::Object(e) if e.tag == "texture" => Some(e),
                    _ => None,
                }))
                .filter(|e| e.tag == "texture")
                .collect();
            let names: Vec<&str> = p
                .props
                .iter()
                .filter(|q| matches!(q.val, Val::Object(e) if e.tag == "texture"))
                .map(|q| q.name.as_str())
                .chain(["scale", "flip_invalid_normals", "use_shadowing_function"])
                .collect();
            p.allow(&names)?;
            let [height] = textures.as_slice() else {
                return Err(p.err(format!("bumpmap takes exactly one nested <texture>, not {}", textures.len())));
            };
            let (flip_invalid, shadowing) = flags(p)?;
            Ok(Material::BumpMap {
                height: texture::object(ld, height, SpectrumUse::Unbounded)?,
                scale: p.float("scale", 1.0)? as f32,
                flip_invalid,
                shadowing,
                nested: one_nested(ld, p)?,
            })
        }
        _ => unreachable!("WRAPPERS lists the kinds handled here"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_plugin_named_here_has_its_model_and_none_is_also_refused() {
        for r in ROWS {
            assert!(brdf::find(r.model).is_ok(), "{}", r.model);
        }
        for n in SAME_NAME {
            assert!(brdf::find(n).is_ok_and(|m| !is_wrapper_model(m)), "{n}");
        }
        for n in UNSUPPORTED {
            assert!(!SAME_NAME.contains(n) && !WRAPPERS.contains(n) && ROWS.iter().all(|r| r.mitsuba != *n), "{n}");
        }
    }
}
