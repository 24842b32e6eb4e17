//! `<bsdf>`: Mitsuba 3's reflection plugins mapped onto gonio's models, and gonio's own
//! models by their `gonio models` names with their own parameter names.
//!
//! | Mitsuba | gonio |
//! |---|---|
//! | `diffuse` (reflectance) | `lambert` (albedo) |
//! | `conductor` (material, eta, k, specular_reflectance) | `mirror` with a conductor Fresnel term (`material="none"`: no Fresnel, R = 1) |
//! | `roughconductor` (distribution, alpha, alpha_u/v, material, eta, k) | `microfacet`, Smith separable shadowing (Mitsuba's G1·G1) |
//! | `roughplastic` (distribution, alpha, int_ior, ext_ior, diffuse/specular_reflectance, nonlinear) | `roughplastic`, the same model and names |
//! | `plastic` (int_ior, ext_ior, diffuse/specular_reflectance, nonlinear) | `plastic`, the same model and names |
//! | `dielectric` (int_ior, ext_ior, specular_reflectance/transmittance) | `dielectric`, the same model and names |
//! | `roughdielectric` (distribution, alpha, alpha_u/v, int_ior, ext_ior, specular_reflectance/transmittance) | `roughdielectric`, the same model and names |
//! | `twosided` (one or two nested bsdfs) | `brdf::two_sided::TwoSided` around them (see below) |
//!
//! `roughplastic`, `plastic`, `dielectric` and `roughdielectric` are Mitsuba's models
//! reproduced in `brdf`; named indices of refraction (`<string name="int_ior" value="bk7"/>`)
//! become their numbers here. `sample_visible` is accepted and ignored: gonio always samples
//! visible normals, which changes the noise, not the expected image.
//!
//! gonio's surfaces, like Mitsuba's, reflect from their front side only; a back face is
//! black. `twosided` makes the nested model act on both sides, mirrored on the back (or the
//! second nested model on the back when two are given), as in Mitsuba. A transmitting model
//! already has two sides, and `twosided` refuses one, as Mitsuba does.

use super::error::XmlError;
use super::parse::{plugin, Ctx, Plugin, Val};
use brdf::{Brdf, ParamError, ParamKind};
use roxmltree::Node;
use std::collections::HashMap;
use std::sync::Arc;

/// The Mitsuba BSDF types this loader maps.
pub const MITSUBA_TYPES: &[&str] =
    &["diffuse", "conductor", "roughconductor", "plastic", "roughplastic", "dielectric", "roughdielectric", "twosided"];

/// Mitsuba types gonio does not have yet.
const UNSUPPORTED: &[&str] = &["thindielectric", "blendbsdf", "mask", "bumpmap", "normalmap", "polarizer"];

/// Named indices of refraction Mitsuba accepts for `int_ior`/`ext_ior` (its `ior.h` table).
const IORS: &[(&str, f64)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.333),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.47),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.575),
    ("diamond", 2.419),
];

/// A loaded `<bsdf>`: the model, and the gonio name and parameters it was built from (the
/// Phong integrator reads its coefficients from these).
#[derive(Clone, Debug)]
pub struct LoadedBsdf {
    /// The model.
    pub brdf: Arc<dyn Brdf>,
    /// Its `gonio models` name.
    pub model: String,
    /// The (parameter, value) pairs it was built with.
    pub args: Vec<(String, String)>,
}

impl LoadedBsdf {
    /// The pairs as `&str`s, as `brdf::build` takes them.
    pub fn arg_refs(&self) -> Vec<(&str, &str)> {
        self.args.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect()
    }
}

/// Named `<bsdf id=...>`s defined at the top level.
pub type Named = HashMap<String, LoadedBsdf>;

/// One gonio parameter to pass: its name, its value as text, and the Mitsuba property it came
/// from (so that an error from `ParamSpec` points at that line).
struct Arg {
    ours: &'static str,
    text: String,
    from: Option<String>,
}

fn arg(ours: &'static str, text: impl Into<String>, from: Option<&str>) -> Arg {
    Arg { ours, text: text.into(), from: from.map(str::to_string) }
}

/// Builds gonio model `model` from `args`, turning a `ParamError` into an error at the
/// property that gave the bad value.
fn build(ctx: &Ctx, p: &Plugin, model: &str, args: &[Arg]) -> Result<LoadedBsdf, XmlError> {
    let pairs: Vec<(&str, &str)> = args.iter().map(|a| (a.ours, a.text.as_str())).collect();
    let loaded = |b: Box<dyn Brdf>| LoadedBsdf {
        brdf: Arc::from(b),
        model: model.to_string(),
        args: args.iter().map(|a| (a.ours.to_string(), a.text.clone())).collect(),
    };
    brdf::build(model, &pairs).map(loaded).map_err(|e| {
        let name = match &e {
            ParamError::BadValue { name, .. } | ParamError::UnknownParam { name, .. } => Some(name.as_str()),
            _ => None,
        };
        let from = name.and_then(|n| args.iter().find(|a| a.ours == n)).and_then(|a| a.from.as_deref());
        match from {
            Some(prop) => p.err_at(ctx, prop, format!("{e} (gonio model '{model}')")),
            None => p.err(ctx, format!("{e} (gonio model '{model}')")),
        }
    })
}

/// A colour property as `ParamSpec` text ("r,g,b"), or `default` when absent.
fn rgb_text(ctx: &Ctx, p: &Plugin, name: &str, default: &str) -> Result<String, XmlError> {
    Ok(match p.get(name) {
        None => default.to_string(),
        Some(prop) => match &prop.val {
            Val::Rgb(_) | Val::Float(_) | Val::Int(_) => prop.text(),
            _ => {
                return Err(p.err_at(
                    ctx,
                    name,
                    format!("property '{name}' must be given as <rgb>, <spectrum> or <float>"),
                ))
            }
        },
    })
}

/// An index of refraction: a number or one of Mitsuba's names.
fn ior(ctx: &Ctx, p: &Plugin, name: &str, default: f64) -> Result<f64, XmlError> {
    match p.get(name).map(|x| &x.val) {
        None => Ok(default),
        Some(Val::Float(v)) if *v > 0.0 => Ok(*v),
        Some(Val::Str(s)) => IORS.iter().find(|(n, _)| n.eq_ignore_ascii_case(s)).map(|x| x.1).ok_or_else(|| {
            let names: Vec<&str> = IORS.iter().map(|x| x.0).collect();
            p.err_at(
                ctx,
                name,
                format!("unknown material '{s}' for '{name}'; give a number > 0 or one of: {}", names.join(", ")),
            )
        }),
        Some(_) => {
            Err(p.err_at(ctx, name, format!("property '{name}' must be a <float> > 0 or a <string> material name")))
        }
    }
}

/// Fails unless property `name` is absent or equal to `expected` (a value gonio has no
/// counterpart for).
fn only_default(ctx: &Ctx, p: &Plugin, name: &str, ok: impl Fn(&Val) -> bool, why: &str) -> Result<(), XmlError> {
    match p.get(name) {
        Some(prop) if !ok(&prop.val) => Err(p.err_at(ctx, name, format!("property '{name}': {why}"))),
        _ => Ok(()),
    }
}

fn is_one(v: &Val) -> bool {
    match v {
        Val::Float(x) => *x == 1.0,
        Val::Int(x) => *x == 1,
        Val::Rgb(c) => c.iter().all(|x| *x == 1.0),
        _ => false,
    }
}

/// The `material`, `eta`, `k` of a conductor as gonio `fresnel`/`material`/`eta`/`k` args.
fn conductor_args(ctx: &Ctx, p: &Plugin) -> Result<Vec<Arg>, XmlError> {
    let material = p.string(ctx, "material")?;
    let has_eta_k = p.get("eta").is_some() || p.get("k").is_some();
    match material {
        Some(m) if has_eta_k => {
            Err(p.err_at(ctx, "material", format!("material '{m}' sets eta and k; give either material or eta and k")))
        }
        Some(m) if m != "none" => {
            let ours = brdf::fresnel::MATERIALS.iter().filter(|n| **n != "custom").copied().collect::<Vec<_>>();
            let name = ours.iter().find(|n| n.eq_ignore_ascii_case(m)).ok_or_else(|| {
                p.err_at(ctx, "material", format!("unknown material '{m}'; accepted: none, {}", ours.join(", ")))
            })?;
            Ok(vec![arg("fresnel", "conductor", None), arg("material", *name, Some("material"))])
        }
        _ if has_eta_k => {
            if p.get("eta").is_none() || p.get("k").is_none() {
                return Err(p.err(ctx, "give both 'eta' and 'k' for a custom conductor (or a 'material')"));
            }
            Ok(vec![
                arg("fresnel", "conductor", None),
                arg("eta", rgb_text(ctx, p, "eta", "")?, Some("eta")),
                arg("k", rgb_text(ctx, p, "k", "")?, Some("k")),
            ])
        }
        // Mitsuba's default material "none" is a perfect reflector.
        _ => Ok(vec![arg("fresnel", "none", None)]),
    }
}

/// The `distribution`, `alpha`, `alpha_u`, `alpha_v` of a rough Mitsuba BSDF.
fn roughness_args(ctx: &Ctx, p: &Plugin) -> Result<Vec<Arg>, XmlError> {
    let dist = p.string(ctx, "distribution")?.unwrap_or("beckmann");
    if !["beckmann", "ggx"].contains(&dist) {
        return Err(p.err_at(ctx, "distribution", format!("distribution '{dist}' is not one of beckmann|ggx")));
    }
    let mut v = vec![arg("distribution", dist, Some("distribution")), arg("shadowing", "smith-separable", None)];
    match (p.get("alpha_u"), p.get("alpha_v")) {
        (None, None) => v.push(arg("alpha", p.float(ctx, "alpha", 0.1)?.to_string(), Some("alpha"))),
        (Some(_), Some(_)) => {
            if p.get("alpha").is_some() {
                return Err(p.err_at(ctx, "alpha", "give either 'alpha' or 'alpha_u' and 'alpha_v'"));
            }
            v.push(arg("alpha_u", p.float(ctx, "alpha_u", 0.1)?.to_string(), Some("alpha_u")));
            v.push(arg("alpha_v", p.float(ctx, "alpha_v", 0.1)?.to_string(), Some("alpha_v")));
        }
        _ => return Err(p.err(ctx, "give both 'alpha_u' and 'alpha_v' for an anisotropic surface")),
    }
    Ok(v)
}

/// Builds the model of a `<bsdf>` element.
pub fn load(ctx: &Ctx, node: Node, named: &Named) -> Result<LoadedBsdf, XmlError> {
    let p = plugin(ctx, node, &["bsdf", "ref"])?;
    let kind = p.kind.as_str();
    if kind != "twosided" {
        p.allow_children(ctx, &[])?;
    }
    match kind {
        "twosided" => {
            p.allow(ctx, &[])?;
            let (front, back) = match p.children.as_slice() {
                [one] => {
                    let b = nested(ctx, *one, named)?;
                    (b.clone(), b)
                }
                [front, back] => (nested(ctx, *front, named)?, nested(ctx, *back, named)?),
                _ => return Err(p.err(ctx, "twosided takes one nested <bsdf> or <ref> (or two: front, back)")),
            };
            let two = brdf::two_sided::TwoSided::new(front.brdf.clone(), back.brdf.clone())
                .map_err(|e| p.err(ctx, format!("{e}; nested: {} / {}", front.model, back.model)))?;
            // The front's name and parameters stay: the Phong integrator reads its coefficients.
            Ok(LoadedBsdf { brdf: Arc::new(two), ..front })
        }
        "dielectric" | "roughdielectric" => {
            let rough = kind == "roughdielectric";
            let mut names = vec!["int_ior", "ext_ior", "specular_reflectance", "specular_transmittance"];
            if rough {
                names.extend(["distribution", "alpha", "alpha_u", "alpha_v", "sample_visible"]);
            }
            p.allow(ctx, &names)?;
            let mut args = vec![
                arg(
                    "int_ior",
                    ior(ctx, &p, "int_ior", brdf::dielectric::DEFAULT_INT_IOR)?.to_string(),
                    Some("int_ior"),
                ),
                arg(
                    "ext_ior",
                    ior(ctx, &p, "ext_ior", brdf::dielectric::DEFAULT_EXT_IOR)?.to_string(),
                    Some("ext_ior"),
                ),
                arg(
                    "specular_reflectance",
                    rgb_text(ctx, &p, "specular_reflectance", "1")?,
                    Some("specular_reflectance"),
                ),
                arg(
                    "specular_transmittance",
                    rgb_text(ctx, &p, "specular_transmittance", "1")?,
                    Some("specular_transmittance"),
                ),
            ];
            if rough {
                p.bool(ctx, "sample_visible", true)?;
                args.extend(roughness_args(ctx, &p)?.into_iter().filter(|a| a.ours != "shadowing"));
            }
            build(ctx, &p, kind, &args)
        }
        "diffuse" => {
            p.allow(ctx, &["reflectance"])?;
            build(ctx, &p, "lambert", &[arg("albedo", rgb_text(ctx, &p, "reflectance", "0.5")?, Some("reflectance"))])
        }
        "conductor" => {
            p.allow(ctx, &["material", "eta", "k", "specular_reflectance"])?;
            let mut args = conductor_args(ctx, &p)?;
            args.push(arg(
                "reflectance",
                rgb_text(ctx, &p, "specular_reflectance", "1")?,
                Some("specular_reflectance"),
            ));
            build(ctx, &p, "mirror", &args)
        }
        "roughconductor" => {
            p.allow(
                ctx,
                &[
                    "distribution",
                    "alpha",
                    "alpha_u",
                    "alpha_v",
                    "material",
                    "eta",
                    "k",
                    "specular_reflectance",
                    "sample_visible",
                ],
            )?;
            only_default(
                ctx,
                &p,
                "specular_reflectance",
                is_one,
                "only 1 is supported (gonio's microfacet has no tint)",
            )?;
            p.bool(ctx, "sample_visible", true)?;
            let mut args = roughness_args(ctx, &p)?;
            args.extend(conductor_args(ctx, &p)?);
            build(ctx, &p, "microfacet", &args)
        }
        "plastic" | "roughplastic" => {
            let rough = kind == "roughplastic";
            let mut names = vec!["int_ior", "ext_ior", "diffuse_reflectance", "specular_reflectance", "nonlinear"];
            if rough {
                names.extend(["distribution", "alpha", "sample_visible"]);
            }
            p.allow(ctx, &names)?;
            p.bool(ctx, "sample_visible", true)?;
            let mut args = vec![
                arg("int_ior", ior(ctx, &p, "int_ior", 1.49)?.to_string(), Some("int_ior")),
                arg("ext_ior", ior(ctx, &p, "ext_ior", 1.000277)?.to_string(), Some("ext_ior")),
                arg(
                    "diffuse_reflectance",
                    rgb_text(ctx, &p, "diffuse_reflectance", "0.5")?,
                    Some("diffuse_reflectance"),
                ),
                arg(
                    "specular_reflectance",
                    rgb_text(ctx, &p, "specular_reflectance", "1")?,
                    Some("specular_reflectance"),
                ),
                arg("nonlinear", p.bool(ctx, "nonlinear", false)?.to_string(), Some("nonlinear")),
            ];
            if rough {
                let dist = p.string(ctx, "distribution")?.unwrap_or("beckmann");
                args.push(arg("distribution", dist, Some("distribution")));
                args.push(arg("alpha", p.float(ctx, "alpha", 0.1)?.to_string(), Some("alpha")));
            }
            build(ctx, &p, kind, &args)
        }
        t if UNSUPPORTED.contains(&t) => Err(p.err(
            ctx,
            format!(
                "bsdf type '{t}' (blending, masks, textures or thin sheets) is not supported yet; accepted: {}",
                accepted()
            ),
        )),
        t => match brdf::find(t) {
            Ok(spec) => gonio_model(ctx, &p, spec),
            Err(_) => Err(p.err(ctx, format!("unknown bsdf type '{t}'; accepted: {}", accepted()))),
        },
    }
}

/// Every accepted `type`, Mitsuba's then gonio's.
fn accepted() -> String {
    let ours: Vec<&str> = brdf::models().iter().map(|m| m.name).collect();
    format!("{} (Mitsuba), {} (gonio models)", MITSUBA_TYPES.join(", "), ours.join(", "))
}

/// A gonio model with its own parameter names; paths resolve against the scene file.
fn gonio_model(ctx: &Ctx, p: &Plugin, spec: &brdf::ModelSpec) -> Result<LoadedBsdf, XmlError> {
    let specs = (spec.params)();
    let names: Vec<&str> = specs.iter().map(|s| s.name).collect();
    p.allow(ctx, &names)?;
    let mut args = Vec::new();
    for prop in &p.props {
        let s = specs.iter().find(|s| s.name == prop.name).expect("allow() checked the name");
        let text = match (&s.kind, &prop.val) {
            (ParamKind::Path, Val::Str(path)) => ctx.path(path).to_string_lossy().into_owned(),
            (_, Val::Transform(_)) | (_, Val::Vec(_)) => {
                return Err(ctx.err(prop.node, format!("parameter '{}' takes {}", s.name, s.range_text())))
            }
            _ => prop.text(),
        };
        args.push(arg(s.name, text, Some(s.name)));
    }
    build(ctx, p, spec.name, &args)
}

/// A `<bsdf>` or a `<ref id="...">` to a named one.
pub fn nested(ctx: &Ctx, node: Node, named: &Named) -> Result<LoadedBsdf, XmlError> {
    if node.tag_name().name() == "ref" {
        ctx.check_attrs(node, &["id", "name"])?;
        let id = ctx.req_attr(node, "id")?;
        return named.get(&id).cloned().ok_or_else(|| {
            let mut ids: Vec<&str> = named.keys().map(String::as_str).collect();
            ids.sort_unstable();
            let list = if ids.is_empty() { "(none)".to_string() } else { ids.join(", ") };
            ctx.err(node, format!("no <bsdf> with id '{id}'; the named bsdfs are: {list}"))
        });
    }
    load(ctx, node, named)
}
