//! The generic layer of the loader: every object of the tree by `id` (and `<alias>`), `<ref>`s
//! resolved, and the property tags (`float`, `integer`, `boolean`, `string`, `rgb`,
//! `spectrum`, `point`, `vector`, `transform`) of an element collected with its nested
//! objects into a [`Plugin`] that each element kind then reads.

use super::error::{Pos, XmlError};
use super::transform;
use super::tree::Elem;
use glam::{Mat4, Vec3};
use radiometry::cie::{self, SpectrumUse};
use std::collections::HashMap;

/// The tags that give a plugin a property.
pub const PROPERTY_TAGS: &[&str] =
    &["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform"];

/// The tags of objects (plugins with a `type`).
pub const OBJECT_TAGS: &[&str] = &[
    "bsdf",
    "texture",
    "emitter",
    "shape",
    "medium",
    "phase",
    "volume",
    "sensor",
    "film",
    "rfilter",
    "sampler",
    "integrator",
];

/// Line and column (1-based, columns in characters) of byte offset `offset` in `text`.
pub fn pos_at(text: &str, offset: usize) -> Pos {
    let before = &text[..offset.min(text.len())];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    Pos { line: before.matches('\n').count() as u32 + 1, col: before[line_start..].chars().count() as u32 + 1 }
}

/// True for an element that is an object: a plugin tag, or a `<spectrum>` with a `type`.
pub fn is_object(e: &Elem) -> bool {
    OBJECT_TAGS.contains(&e.tag.as_str()) || (e.tag == "spectrum" && e.attr("type").is_some())
}

/// Every object with an `id`, and the names `<alias>` gives them.
pub struct Ids<'t> {
    map: HashMap<&'t str, &'t Elem>,
}

impl<'t> Ids<'t> {
    /// Indexes the tree under `root`; two objects with one id are an error.
    pub fn new(root: &'t Elem) -> Result<Self, XmlError> {
        let mut ids = Ids { map: HashMap::new() };
        ids.add(root)?;
        Ok(ids)
    }

    fn add(&mut self, e: &'t Elem) -> Result<(), XmlError> {
        for c in &e.children {
            if c.tag == "alias" {
                c.check_attrs(&["id", "as"])?;
                let (from, to) = (c.req("id")?, c.req("as")?);
                let target = *self
                    .map
                    .get(from)
                    .ok_or_else(|| c.err(format!("alias source id \"{from}\" is not defined before the alias")))?;
                if self.map.insert(to, target).is_some() {
                    return Err(c.err(format!("alias destination id \"{to}\" is already taken")));
                }
                continue;
            }
            if c.tag != "ref" {
                if let Some(id) = c.attr("id") {
                    if let Some(first) = self.map.insert(id, c) {
                        return Err(c.err(format!(
                            "a second object with id \"{id}\" (the first is at {}:{})",
                            first.src.file.display(),
                            first.src.pos.line
                        )));
                    }
                }
            }
            self.add(c)?;
        }
        Ok(())
    }

    /// The object `e` stands for: itself, or the one a `<ref id>` names.
    pub fn deref(&self, e: &'t Elem) -> Result<&'t Elem, XmlError> {
        if e.tag != "ref" {
            return Ok(e);
        }
        e.check_attrs(&["id", "name"])?;
        let id = e.req("id")?;
        self.map.get(id).copied().ok_or_else(|| {
            let mut known: Vec<&str> = self.map.keys().copied().collect();
            known.sort_unstable();
            let list = if known.is_empty() { "(none)".to_string() } else { known.join(", ") };
            e.err(format!("no object with id '{id}'; the ids are: {list}"))
        })
    }

    /// The object with id `id`, if any.
    pub fn get(&self, id: &str) -> Option<&'t Elem> {
        self.map.get(id).copied()
    }
}

/// A spectrum given as a property.
#[derive(Clone, Debug, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Uniform(f64),
    /// Samples (nm, value), wavelengths strictly increasing, linearly interpolated.
    Sampled {
        /// Wavelengths in nm.
        lambda: Vec<f64>,
        /// Values at them.
        values: Vec<f64>,
    },
}

impl Spectrum {
    /// The RGB value it reduces to for `usage` (Mitsuba's RGB variants).
    pub fn rgb(&self, usage: SpectrumUse) -> [f64; 3] {
        match self {
            Spectrum::Uniform(v) => cie::uniform_to_srgb(*v, usage),
            Spectrum::Sampled { lambda, values } => cie::spectrum_to_srgb(lambda, values, usage),
        }
    }
}

/// A property value.
#[derive(Clone, Debug)]
pub enum Val<'t> {
    /// `<float>`.
    Float(f64),
    /// `<integer>`.
    Int(i64),
    /// `<boolean>`.
    Bool(bool),
    /// `<string>`.
    Str(String),
    /// `<rgb>`.
    Rgb([f64; 3]),
    /// `<spectrum>` without a type.
    Spectrum(Spectrum),
    /// `<point>` or `<vector>`.
    Vec(Vec3),
    /// `<transform>`.
    Transform(Mat4),
    /// A named nested object or `<ref name>`: a texture, a BSDF, ...
    Object(&'t Elem),
}

/// One property of a plugin.
#[derive(Clone, Debug)]
pub struct Prop<'t> {
    /// Its `name` attribute.
    pub name: String,
    /// Its value.
    pub val: Val<'t>,
    /// The element that gave it (for error positions).
    pub elem: &'t Elem,
}

/// An element with a `type` (a plugin): its properties and its unnamed nested objects.
pub struct Plugin<'t> {
    /// The element.
    pub elem: &'t Elem,
    /// Its `type` attribute.
    pub kind: String,
    /// Its properties in file order (named objects included).
    pub props: Vec<Prop<'t>>,
    /// Nested objects without a name (references resolved), in file order.
    pub objects: Vec<&'t Elem>,
}

/// A number as a reader wants it: large ones in exponent form.
fn short(x: f64) -> String {
    if x.abs() >= 1e7 {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// Numbers separated by commas and/or whitespace.
pub fn numbers(text: &str) -> Option<Vec<f64>> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect()
}

/// A finite number, or an error naming the text.
pub fn float_text(e: &Elem, text: &str) -> Result<f64, XmlError> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| e.err(format!("value \"{text}\" is not a finite number")))
}

/// Reads a plugin element: `type`, `id` and `name` attributes, property children, and nested
/// objects whose tags are in `nested`.
pub fn plugin<'t>(ids: &Ids<'t>, e: &'t Elem, nested: &[&str]) -> Result<Plugin<'t>, XmlError> {
    e.check_attrs(&["type", "id", "name", "version"])?;
    let kind = e.req("type")?.to_string();
    let mut props: Vec<Prop> = Vec::new();
    let mut objects = Vec::new();
    for child in &e.children {
        let tag = child.tag.as_str();
        let (name, target) = if tag == "ref" {
            (child.attr("name"), ids.deref(child)?)
        } else if is_object(child) {
            (child.attr("name"), child)
        } else if PROPERTY_TAGS.contains(&tag) {
            let prop = property(child)?;
            if props.iter().any(|p| p.name == prop.name) {
                return Err(child.err(format!("property '{}' is given twice", prop.name)));
            }
            props.push(prop);
            continue;
        } else {
            let accepted: Vec<&str> = PROPERTY_TAGS.iter().chain(nested).chain(&["ref"]).copied().collect();
            return Err(child.err(format!(
                "unsupported element <{tag}> inside {}; accepted elements: {}",
                e.describe(),
                accepted.join(", ")
            )));
        };
        let takes = nested.contains(&target.tag.as_str()) || (target.tag == "spectrum" && nested.contains(&"texture"));
        if !takes {
            let list = if nested.is_empty() { "(none)".to_string() } else { nested.join(", ") };
            return Err(child.err(format!(
                "{} cannot hold a <{}>; the objects it takes: {list}",
                e.describe(),
                target.tag
            )));
        }
        match name {
            Some(n) => {
                if props.iter().any(|p| p.name == n) {
                    return Err(child.err(format!("property '{n}' is given twice")));
                }
                props.push(Prop { name: n.to_string(), val: Val::Object(target), elem: child });
            }
            None => objects.push(target),
        }
    }
    Ok(Plugin { elem: e, kind, props, objects })
}

/// A `<spectrum>` property's value: one number, `λ:value` pairs, or an `.spd` file.
fn spectrum(e: &Elem) -> Result<Spectrum, XmlError> {
    e.check_attrs(&["name", "value", "filename"])?;
    let (lambda, values) = match (e.attr("value"), e.attr("filename")) {
        (Some(v), None) => {
            let tokens: Vec<&str> =
                v.split(|c: char| c == ',' || c.is_whitespace()).filter(|t| !t.is_empty()).collect();
            if let [one] = tokens.as_slice() {
                if !one.contains(':') {
                    return Ok(Spectrum::Uniform(float_text(e, one)?));
                }
            }
            let mut l = Vec::new();
            let mut s = Vec::new();
            for t in tokens {
                let bad = || e.err(format!("\"{t}\" in value \"{v}\" is not a wavelength:value pair such as 400:0.5"));
                let (a, b) = t.split_once(':').ok_or_else(bad)?;
                let (a, b) = (a.parse::<f64>().map_err(|_| bad())?, b.parse::<f64>().map_err(|_| bad())?);
                if !(a.is_finite() && b.is_finite()) {
                    return Err(bad());
                }
                l.push(a);
                s.push(b);
            }
            (l, s)
        }
        (None, Some(f)) => {
            let path = e.path(f);
            let text = std::fs::read_to_string(&path)
                .map_err(|err| e.err(format!("cannot read the spectrum file \"{}\": {err}", path.display())))?;
            spd(&text).map_err(|m| e.err(format!("{}: {m}", path.display())))?
        }
        _ => return Err(e.err("a <spectrum> takes either 'value' or 'filename' (one of them)")),
    };
    if lambda.len() < 2 {
        return Err(e.err("a sampled spectrum needs at least two wavelength:value pairs"));
    }
    if let Some(k) = lambda.windows(2).position(|w| w[1] <= w[0]) {
        return Err(e.err(format!("wavelengths must increase: {} nm follows {} nm", lambda[k + 1], lambda[k])));
    }
    Ok(Spectrum::Sampled { lambda, values })
}

/// An `.spd` file: a wavelength and a value per line (more numbers or text after them are
/// ignored, as by Mitsuba); lines starting with `#` are comments.
fn spd(text: &str) -> Result<(Vec<f64>, Vec<f64>), String> {
    let (mut l, mut v) = (Vec::new(), Vec::new());
    for (n, line) in text.lines().enumerate() {
        if line.starts_with('#') || line.trim().is_empty() {
            continue;
        }
        let mut it = line.split_whitespace();
        let mut num = |what: &str| {
            it.next()
                .and_then(|t| t.parse::<f64>().ok())
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("line {}: cannot read a {what} in \"{line}\"", n + 1))
        };
        l.push(num("wavelength")?);
        v.push(num("value")?);
    }
    Ok((l, v))
}

/// Reads one property element.
pub fn property(e: &Elem) -> Result<Prop<'_>, XmlError> {
    let tag = e.tag.as_str();
    let name = e.req("name")?.to_string();
    if !e.children.is_empty() && tag != "transform" {
        return Err(e.children[0].err(format!("a <{tag}> property holds no elements")));
    }
    let val = match tag {
        "transform" => {
            e.check_attrs(&["name"])?;
            Val::Transform(transform::parse(e)?)
        }
        "point" | "vector" => {
            e.check_attrs(&["name", "x", "y", "z", "value"])?;
            if let Some(v) = e.attr("value") {
                if e.attr("x").is_some() || e.attr("y").is_some() || e.attr("z").is_some() {
                    return Err(e.err("give either 'value' or 'x', 'y', 'z', not both"));
                }
                match numbers(v).as_deref() {
                    Some(&[x, y, z]) => Val::Vec(Vec3::new(x as f32, y as f32, z as f32)),
                    Some(&[s]) => Val::Vec(Vec3::splat(s as f32)),
                    _ => return Err(e.err(format!("value \"{v}\" is not three numbers \"x, y, z\""))),
                }
            } else {
                let mut c = [0.0f32; 3];
                for (k, a) in ["x", "y", "z"].iter().enumerate() {
                    if let Some(t) = e.attr(a) {
                        c[k] = float_text(e, t)? as f32;
                    }
                }
                Val::Vec(Vec3::from(c))
            }
        }
        "spectrum" => Val::Spectrum(spectrum(e)?),
        _ => {
            e.check_attrs(&["name", "value"])?;
            let v = e.req("value")?;
            match tag {
                "float" => Val::Float(float_text(e, v)?),
                "integer" => Val::Int(v.trim().parse().map_err(|_| e.err(format!("value \"{v}\" is not an integer")))?),
                "boolean" => Val::Bool(match v.to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => return Err(e.err(format!("value \"{v}\" is not a boolean; expected true|false"))),
                }),
                "string" => Val::Str(v.to_string()),
                "rgb" => match numbers(v).as_deref() {
                    Some(&[x]) => Val::Rgb([x; 3]),
                    Some(&[r, g, b]) => Val::Rgb([r, g, b]),
                    _ => return Err(e.err(format!("value \"{v}\" is not an RGB triple \"r, g, b\""))),
                },
                _ => unreachable!("PROPERTY_TAGS lists every tag handled here"),
            }
        }
    };
    Ok(Prop { name, val, elem: e })
}

impl<'t> Plugin<'t> {
    /// Every nested object, unnamed ones first, then named ones (Mitsuba reads a named one as
    /// its type's, whatever the name).
    pub fn all_objects(&self) -> Vec<&'t Elem> {
        let named = self.props.iter().filter_map(|q| match q.val {
            Val::Object(o) => Some(o),
            _ => None,
        });
        self.objects.iter().copied().chain(named).collect()
    }

    /// Fails on a property not in `accepted`, listing the accepted names.
    pub fn allow(&self, accepted: &[&str]) -> Result<(), XmlError> {
        for p in &self.props {
            if !accepted.contains(&p.name.as_str()) {
                let list = if accepted.is_empty() { "(none)".to_string() } else { accepted.join(", ") };
                return Err(p.elem.err(format!(
                    "{} has no property '{}'; its properties are: {list}",
                    self.elem.describe(),
                    p.name
                )));
            }
        }
        Ok(())
    }

    /// Fails when there are nested objects without a name.
    pub fn no_objects(&self) -> Result<(), XmlError> {
        match self.objects.first() {
            Some(o) => Err(o.err(format!("{} takes no nested object here", self.elem.describe()))),
            None => Ok(()),
        }
    }

    /// The property called `name`.
    pub fn get(&self, name: &str) -> Option<&Prop<'t>> {
        self.props.iter().find(|p| p.name == name)
    }

    fn wrong(p: &Prop, expected: &str) -> XmlError {
        p.elem.err(format!("property '{}' must be given as {expected}", p.name))
    }

    /// A real property (`<float>` or `<integer>`), or `default`.
    pub fn float(&self, name: &str, default: f64) -> Result<f64, XmlError> {
        match self.get(name) {
            None => Ok(default),
            Some(Prop { val: Val::Float(v), .. }) => Ok(*v),
            Some(Prop { val: Val::Int(v), .. }) => Ok(*v as f64),
            Some(p) => Err(Self::wrong(p, "<float>")),
        }
    }

    /// A real property in [min, max].
    pub fn float_in(&self, name: &str, default: f64, min: f64, max: f64) -> Result<f64, XmlError> {
        let v = self.float(name, default)?;
        if !(v >= min && v <= max) {
            let (v, min, max) = (short(v), short(min), short(max));
            return Err(self.err_at(name, format!("property '{name}' = {v} is outside [{min}, {max}]")));
        }
        Ok(v)
    }

    /// An `<integer>` property, or `default`.
    pub fn int(&self, name: &str, default: i64) -> Result<i64, XmlError> {
        match self.get(name) {
            None => Ok(default),
            Some(Prop { val: Val::Int(v), .. }) => Ok(*v),
            Some(p) => Err(Self::wrong(p, "<integer>")),
        }
    }

    /// A `<boolean>` property, or `default`.
    pub fn bool(&self, name: &str, default: bool) -> Result<bool, XmlError> {
        match self.get(name) {
            None => Ok(default),
            Some(Prop { val: Val::Bool(v), .. }) => Ok(*v),
            Some(p) => Err(Self::wrong(p, "<boolean>")),
        }
    }

    /// A `<string>` property.
    pub fn string(&self, name: &str) -> Result<Option<&str>, XmlError> {
        match self.get(name) {
            None => Ok(None),
            Some(Prop { val: Val::Str(s), .. }) => Ok(Some(s)),
            Some(p) => Err(Self::wrong(p, "<string>")),
        }
    }

    /// A `<string>` property that must be one of `choices` (case-insensitive), or `default`.
    pub fn choice(
        &self,
        name: &str,
        choices: &[&'static str],
        default: &'static str,
    ) -> Result<&'static str, XmlError> {
        match self.string(name)? {
            None => Ok(default),
            Some(s) => choices
                .iter()
                .find(|c| c.eq_ignore_ascii_case(s))
                .copied()
                .ok_or_else(|| self.err_at(name, format!("{name} \"{s}\" is not one of {}", choices.join("|")))),
        }
    }

    /// A `<point>` or `<vector>` property.
    pub fn vec3(&self, name: &str) -> Result<Option<Vec3>, XmlError> {
        match self.get(name) {
            None => Ok(None),
            Some(Prop { val: Val::Vec(v), .. }) => Ok(Some(*v)),
            Some(p) => Err(Self::wrong(p, "<point> or <vector>")),
        }
    }

    /// A `<transform>` property, identity when absent.
    pub fn transform(&self, name: &str) -> Result<Mat4, XmlError> {
        match self.get(name) {
            None => Ok(Mat4::IDENTITY),
            Some(Prop { val: Val::Transform(m), .. }) => Ok(*m),
            Some(p) => Err(Self::wrong(p, "<transform>")),
        }
    }

    /// A named nested object (or `<ref name>`).
    pub fn object(&self, name: &str) -> Option<&'t Elem> {
        match self.get(name) {
            Some(Prop { val: Val::Object(e), .. }) => Some(e),
            _ => None,
        }
    }

    /// An error at this element.
    pub fn err(&self, message: impl Into<String>) -> XmlError {
        self.elem.err(message)
    }

    /// An error at property `name` (at the element when it is absent).
    pub fn err_at(&self, name: &str, message: impl Into<String>) -> XmlError {
        self.get(name).map_or(self.elem, |p| p.elem).err(message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spd_files_and_positions() {
        let (l, v) = spd("# comment\n400 0.2\n500\t0.4 extra words\n\n700 0.6 # tail\n").unwrap();
        assert_eq!((l, v), (vec![400.0, 500.0, 700.0], vec![0.2, 0.4, 0.6]));
        let e = spd("400, 0.2\n").unwrap_err();
        assert!(e.contains("line 1"), "{e}");
        let t = "ab\ncdé\nf";
        assert_eq!(pos_at(t, 0), Pos { line: 1, col: 1 });
        assert_eq!(pos_at(t, 3), Pos { line: 2, col: 1 });
        assert_eq!(pos_at(t, t.find('é').unwrap() + 2), Pos { line: 2, col: 4 });
    }
}
