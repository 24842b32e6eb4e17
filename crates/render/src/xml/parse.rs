//! The generic layer of the loader: `$name` substitution, attribute checks, and the
//! property tags (`float`, `integer`, `boolean`, `string`, `rgb`, `spectrum`, `point`,
//! `vector`, `transform`) collected into a [`Plugin`] that each element kind then reads.

use super::error::{Pos, XmlError};
use super::transform;
use glam::{Mat4, Vec3};
use radiometry::Rgb;
use roxmltree::Node;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The tags that give a plugin a property.
pub const PROPERTY_TAGS: &[&str] =
    &["float", "integer", "boolean", "string", "rgb", "spectrum", "point", "vector", "transform"];

/// What the loader knows while reading one file.
pub struct Ctx {
    /// The file named in errors.
    pub file: PathBuf,
    /// The directory relative paths start from.
    pub base: PathBuf,
    /// `$name` values: `<default>`s, overridden by the caller's defines.
    pub vars: HashMap<String, String>,
    /// The file's text (for offset → line:column).
    pub text: String,
}

impl Ctx {
    /// Line and column of `node`.
    pub fn pos(&self, node: Node) -> Pos {
        pos_at(&self.text, node.range().start)
    }

    /// The element as a reader finds it in the file: `<shape type="ply" id="torus">`.
    pub fn describe(&self, node: Node) -> String {
        let mut s = format!("<{}", node.tag_name().name());
        for a in ["type", "name", "id"] {
            if let Some(v) = node.attribute(a) {
                s.push_str(&format!(" {a}=\"{v}\""));
            }
        }
        s.push('>');
        s
    }

    /// An error located at `node`.
    pub fn err(&self, node: Node, message: impl Into<String>) -> XmlError {
        XmlError::at(&self.file, self.pos(node), self.describe(node), message)
    }

    /// Attribute `name` of `node` with `$name` references replaced.
    pub fn attr(&self, node: Node, name: &str) -> Result<Option<String>, XmlError> {
        match node.attribute(name) {
            None => Ok(None),
            Some(raw) => self.substitute(node, raw).map(Some),
        }
    }

    /// A required attribute.
    pub fn req_attr(&self, node: Node, name: &str) -> Result<String, XmlError> {
        self.attr(node, name)?.ok_or_else(|| self.err(node, format!("missing attribute '{name}'")))
    }

    /// Fails on any attribute not in `allowed`, listing the allowed ones.
    pub fn check_attrs(&self, node: Node, allowed: &[&str]) -> Result<(), XmlError> {
        for a in node.attributes() {
            if !allowed.contains(&a.name()) {
                let list = if allowed.is_empty() { "(none)".to_string() } else { allowed.join(", ") };
                return Err(self.err(node, format!("unknown attribute '{}'; accepted attributes: {list}", a.name())));
            }
        }
        Ok(())
    }

    /// Replaces `$name` (letters, digits, `_`) by its value; an undefined name is an error.
    fn substitute(&self, node: Node, raw: &str) -> Result<String, XmlError> {
        if !raw.contains('$') {
            return Ok(raw.to_string());
        }
        let mut out = String::new();
        let mut rest = raw;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let len = after.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_')).unwrap_or(after.len());
            let name = &after[..len];
            if name.is_empty() {
                return Err(self.err(node, format!("'$' not followed by a parameter name in \"{raw}\"")));
            }
            let value = self.vars.get(name).ok_or_else(|| {
                self.err(
                    node,
                    format!(
                        "parameter '${name}' has no value: give it on the command line (-D {name}=...) \
                         or declare <default name=\"{name}\" value=\"...\"/> in the scene"
                    ),
                )
            })?;
            out.push_str(value);
            rest = &after[len..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// A path as written in the file, resolved against the file's directory.
    pub fn path(&self, written: &str) -> PathBuf {
        let p = Path::new(written);
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.base.join(p)
        }
    }
}

/// Line and column (1-based, columns in characters) of byte offset `offset` in `text`.
pub fn pos_at(text: &str, offset: usize) -> Pos {
    let before = &text[..offset.min(text.len())];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    Pos { line: before.matches('\n').count() as u32 + 1, col: before[line_start..].chars().count() as u32 + 1 }
}

/// A property value.
#[derive(Clone, Debug, PartialEq)]
pub enum Val {
    /// `<float>`.
    Float(f64),
    /// `<integer>`.
    Int(i64),
    /// `<boolean>`.
    Bool(bool),
    /// `<string>`.
    Str(String),
    /// `<rgb>` or a one-value `<spectrum>`.
    Rgb([f64; 3]),
    /// `<point>` or `<vector>`.
    Vec(Vec3),
    /// `<transform>`.
    Transform(Mat4),
}

/// One property of a plugin.
pub struct Prop<'a, 'i> {
    /// Its `name` attribute.
    pub name: String,
    /// Its value.
    pub val: Val,
    /// The element that gave it (for error positions).
    pub node: Node<'a, 'i>,
}

impl Prop<'_, '_> {
    /// The value as text in the syntax of `brdf::ParamSpec::parse`.
    pub fn text(&self) -> String {
        match &self.val {
            Val::Float(v) => v.to_string(),
            Val::Int(v) => v.to_string(),
            Val::Bool(b) => b.to_string(),
            Val::Str(s) => s.clone(),
            Val::Rgb([r, g, b]) => format!("{r},{g},{b}"),
            Val::Vec(v) => format!("{},{},{}", v.x, v.y, v.z),
            Val::Transform(_) => "(a transform)".to_string(),
        }
    }
}

/// An element with a `type` (a plugin): its properties and its nested plugin elements.
pub struct Plugin<'a, 'i> {
    /// The element.
    pub node: Node<'a, 'i>,
    /// Its `type` attribute.
    pub kind: String,
    /// Its properties in file order.
    pub props: Vec<Prop<'a, 'i>>,
    /// Nested elements that are not properties (bsdf, emitter, film, ...), in file order.
    pub children: Vec<Node<'a, 'i>>,
}

/// Numbers separated by commas and/or whitespace.
pub fn numbers(text: &str) -> Option<Vec<f64>> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<f64>().ok().filter(|v| v.is_finite()))
        .collect()
}

/// Reads a plugin element: `type` and `id` attributes (plus `name` where `named` allows it),
/// property children, and nested elements whose tags are in `nested`.
pub fn plugin<'a, 'i>(ctx: &Ctx, node: Node<'a, 'i>, nested: &[&str]) -> Result<Plugin<'a, 'i>, XmlError> {
    ctx.check_attrs(node, &["type", "id", "name"])?;
    let kind = ctx.req_attr(node, "type")?;
    let mut props: Vec<Prop> = Vec::new();
    let mut children = Vec::new();
    for child in node.children().filter(Node::is_element) {
        let tag = child.tag_name().name();
        if PROPERTY_TAGS.contains(&tag) {
            let prop = property(ctx, child)?;
            if props.iter().any(|p| p.name == prop.name) {
                return Err(ctx.err(child, format!("property '{}' is given twice", prop.name)));
            }
            props.push(prop);
        } else if nested.contains(&tag) {
            children.push(child);
        } else {
            let accepted: Vec<&str> = PROPERTY_TAGS.iter().chain(nested).copied().collect();
            return Err(ctx.err(
                child,
                format!(
                    "unsupported element <{tag}> inside {}; accepted elements: {}",
                    ctx.describe(node),
                    accepted.join(", ")
                ),
            ));
        }
    }
    Ok(Plugin { node, kind, props, children })
}

/// Reads one property element.
pub fn property<'a, 'i>(ctx: &Ctx, node: Node<'a, 'i>) -> Result<Prop<'a, 'i>, XmlError> {
    let tag = node.tag_name().name();
    let name = ctx.req_attr(node, "name")?;
    let val = match tag {
        "transform" => {
            ctx.check_attrs(node, &["name"])?;
            Val::Transform(transform::parse(ctx, node)?)
        }
        "point" | "vector" => {
            ctx.check_attrs(node, &["name", "x", "y", "z", "value"])?;
            if let Some(v) = ctx.attr(node, "value")? {
                match numbers(&v).as_deref() {
                    Some(&[x, y, z]) => Val::Vec(Vec3::new(x as f32, y as f32, z as f32)),
                    _ => return Err(ctx.err(node, format!("value \"{v}\" is not three numbers \"x, y, z\""))),
                }
            } else {
                let mut c = [0.0f32; 3];
                for (k, a) in ["x", "y", "z"].iter().enumerate() {
                    if let Some(t) = ctx.attr(node, a)? {
                        c[k] = float_text(ctx, node, &t)? as f32;
                    }
                }
                Val::Vec(Vec3::from(c))
            }
        }
        _ => {
            ctx.check_attrs(node, &["name", "value"])?;
            let v = ctx.req_attr(node, "value")?;
            match tag {
                "float" => Val::Float(float_text(ctx, node, &v)?),
                "integer" => {
                    Val::Int(v.trim().parse().map_err(|_| ctx.err(node, format!("value \"{v}\" is not an integer")))?)
                }
                "boolean" => Val::Bool(match v.trim() {
                    "true" => true,
                    "false" => false,
                    _ => return Err(ctx.err(node, format!("value \"{v}\" is not a boolean; expected true|false"))),
                }),
                "string" => Val::Str(v),
                "rgb" => match numbers(&v).as_deref() {
                    Some(&[x]) => Val::Rgb([x; 3]),
                    Some(&[r, g, b]) => Val::Rgb([r, g, b]),
                    _ => return Err(ctx.err(node, format!("value \"{v}\" is not an RGB triple \"r, g, b\""))),
                },
                "spectrum" => match numbers(&v).as_deref() {
                    Some(&[x]) => Val::Rgb([x; 3]),
                    _ => {
                        return Err(ctx.err(
                            node,
                            format!(
                                "value \"{v}\": only a single-value <spectrum> is supported \
                                 (use <rgb> for colours)"
                            ),
                        ))
                    }
                },
                _ => unreachable!("PROPERTY_TAGS lists every tag handled here"),
            }
        }
    };
    Ok(Prop { name, val, node })
}

/// A finite number, or an error naming the text.
pub fn float_text(ctx: &Ctx, node: Node, text: &str) -> Result<f64, XmlError> {
    text.trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| ctx.err(node, format!("value \"{text}\" is not a finite number")))
}

impl<'a, 'i> Plugin<'a, 'i> {
    /// Fails on a property not in `accepted`, listing the accepted names.
    pub fn allow(&self, ctx: &Ctx, accepted: &[&str]) -> Result<(), XmlError> {
        for p in &self.props {
            if !accepted.contains(&p.name.as_str()) {
                let list = if accepted.is_empty() { "(none)".to_string() } else { accepted.join(", ") };
                return Err(ctx.err(
                    p.node,
                    format!("{} has no property '{}'; its properties are: {list}", ctx.describe(self.node), p.name),
                ));
            }
        }
        Ok(())
    }

    /// Fails on nested elements other than those in `accepted`.
    pub fn allow_children(&self, ctx: &Ctx, accepted: &[&str]) -> Result<(), XmlError> {
        for c in &self.children {
            let tag = c.tag_name().name();
            if !accepted.contains(&tag) {
                let list = PROPERTY_TAGS.iter().chain(accepted).copied().collect::<Vec<_>>().join(", ");
                return Err(ctx.err(
                    *c,
                    format!(
                        "unsupported element <{tag}> inside {}; accepted elements: {list}",
                        ctx.describe(self.node)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The property called `name`.
    pub fn get(&self, name: &str) -> Option<&Prop<'a, 'i>> {
        self.props.iter().find(|p| p.name == name)
    }

    fn wrong(ctx: &Ctx, p: &Prop, expected: &str) -> XmlError {
        ctx.err(p.node, format!("property '{}' must be given as {expected}", p.name))
    }

    /// A real property (`<float>` or `<integer>`), or `default`.
    pub fn float(&self, ctx: &Ctx, name: &str, default: f64) -> Result<f64, XmlError> {
        match self.get(name) {
            None => Ok(default),
            Some(Prop { val: Val::Float(v), .. }) => Ok(*v),
            Some(Prop { val: Val::Int(v), .. }) => Ok(*v as f64),
            Some(p) => Err(Self::wrong(ctx, p, "<float>")),
        }
    }

    /// A real property in [min, max].
    pub fn float_in(&self, ctx: &Ctx, name: &str, default: f64, min: f64, max: f64) -> Result<f64, XmlError> {
        let v = self.float(ctx, name, default)?;
        if v < min || v > max {
            let node = self.get(name).map_or(self.node, |p| p.node);
            return Err(ctx.err(node, format!("property '{name}' = {v} is outside [{min}, {max}]")));
        }
        Ok(v)
    }

    /// An `<integer>` property, or `default`.
    pub fn int(&self, ctx: &Ctx, name: &str, default: i64) -> Result<i64, XmlError> {
        match self.get(name) {
            None => Ok(default),
            Some(Prop { val: Val::Int(v), .. }) => Ok(*v),
            Some(p) => Err(Self::wrong(ctx, p, "<integer>")),
        }
    }

    /// A `<boolean>` property, or `default`.
    pub fn bool(&self, ctx: &Ctx, name: &str, default: bool) -> Result<bool, XmlError> {
        match self.get(name) {
            None => Ok(default),
            Some(Prop { val: Val::Bool(v), .. }) => Ok(*v),
            Some(p) => Err(Self::wrong(ctx, p, "<boolean>")),
        }
    }

    /// A `<string>` property.
    pub fn string(&self, ctx: &Ctx, name: &str) -> Result<Option<&str>, XmlError> {
        match self.get(name) {
            None => Ok(None),
            Some(Prop { val: Val::Str(s), .. }) => Ok(Some(s)),
            Some(p) => Err(Self::wrong(ctx, p, "<string>")),
        }
    }

    /// A colour (`<rgb>`, one-value `<spectrum>` or `<float>`), or `default`; channels must
    /// be finite and ≥ 0.
    pub fn rgb(&self, ctx: &Ctx, name: &str, default: Rgb) -> Result<Rgb, XmlError> {
        let c = match self.get(name) {
            None => return Ok(default),
            Some(Prop { val: Val::Rgb(c), .. }) => *c,
            Some(Prop { val: Val::Float(v), .. }) => [*v; 3],
            Some(p) => return Err(Self::wrong(ctx, p, "<rgb>, <spectrum> or <float>")),
        };
        if c.iter().any(|v| !v.is_finite() || *v < 0.0) {
            let p = self.get(name).expect("matched above");
            return Err(ctx.err(p.node, format!("property '{name}' must have finite channels ≥ 0")));
        }
        Ok(Rgb::new(c[0] as f32, c[1] as f32, c[2] as f32))
    }

    /// A `<point>` or `<vector>` property.
    pub fn vec3(&self, ctx: &Ctx, name: &str) -> Result<Option<Vec3>, XmlError> {
        match self.get(name) {
            None => Ok(None),
            Some(Prop { val: Val::Vec(v), .. }) => Ok(Some(*v)),
            Some(p) => Err(Self::wrong(ctx, p, "<point> or <vector>")),
        }
    }

    /// A `<transform>` property, identity when absent.
    pub fn transform(&self, ctx: &Ctx, name: &str) -> Result<Mat4, XmlError> {
        match self.get(name) {
            None => Ok(Mat4::IDENTITY),
            Some(Prop { val: Val::Transform(m), .. }) => Ok(*m),
            Some(p) => Err(Self::wrong(ctx, p, "<transform>")),
        }
    }

    /// An error at this element.
    pub fn err(&self, ctx: &Ctx, message: impl Into<String>) -> XmlError {
        ctx.err(self.node, message)
    }

    /// An error at property `name` (at the element when it is absent).
    pub fn err_at(&self, ctx: &Ctx, name: &str, message: impl Into<String>) -> XmlError {
        ctx.err(self.get(name).map_or(self.node, |p| p.node), message)
    }
}
