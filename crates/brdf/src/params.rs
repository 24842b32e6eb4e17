//! Model parameters described once as data: names, kinds, ranges, defaults, docs, and
//! whether a scene may vary them over a surface (a texture). The CLI, the scene loader and
//! the web page are generated from these descriptions.
//!
//! A model is built from a [`ParamSource`]: the resolved [`Params`] of a constant material, or
//! [`Varied`], the same `Params` with some values replaced by a texture's at one surface point.

use radiometry::Rgb;
use std::cell::{Cell, RefCell};
use std::fmt;

/// What values a parameter takes.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamKind {
    /// A real number in [min, max].
    Float { min: f64, max: f64 },
    /// An RGB triple (or one number for all channels), each channel in [min, max].
    Rgb { min: f64, max: f64 },
    /// One of a fixed list of names.
    Choice(&'static [&'static str]),
    /// true or false.
    Bool,
    /// A file path; the empty default means "none given" (the model says whether it needs one).
    Path,
    /// A nested model, written `NAME[:PARAM=VALUE]...` (wrappers such as `mask` hold one).
    Model,
}

/// A parameter value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A real number.
    Float(f64),
    /// An RGB triple.
    Rgb([f64; 3]),
    /// A name from a choice list.
    Choice(String),
    /// A flag.
    Bool(bool),
    /// A file path, as written.
    Path(String),
    /// A nested model, as written: `NAME[:PARAM=VALUE]...`.
    Model(String),
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Float(v) => write!(f, "{v}"),
            Value::Rgb([r, g, b]) if r == g && g == b => write!(f, "{r}"),
            Value::Rgb([r, g, b]) => write!(f, "{r},{g},{b}"),
            Value::Choice(s) => f.write_str(s),
            Value::Bool(b) => write!(f, "{b}"),
            Value::Path(p) | Value::Model(p) => f.write_str(p),
        }
    }
}

/// The description of one parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSpec {
    /// Its name, the same on the command line, in scene files and in the web page.
    pub name: &'static str,
    /// What values it takes.
    pub kind: ParamKind,
    /// Its default value.
    pub default: Value,
    /// One line saying what it is.
    pub doc: &'static str,
    /// True when a scene may give it a texture: the model is then rebuilt at each surface
    /// point from the texture's value there (real and RGB parameters, unless marked `fixed`).
    pub varies: bool,
    /// Names a real parameter also accepts for a value (Mitsuba's `bk7`, `water`, … for an IOR).
    pub names: &'static [(&'static str, f64)],
}

impl ParamSpec {
    /// A real parameter in [min, max].
    pub fn float(name: &'static str, min: f64, max: f64, default: f64, doc: &'static str) -> Self {
        ParamSpec {
            name,
            kind: ParamKind::Float { min, max },
            default: Value::Float(default),
            doc,
            varies: true,
            names: &[],
        }
    }

    /// An RGB parameter with channels in [min, max].
    pub fn rgb(name: &'static str, min: f64, max: f64, default: f64, doc: &'static str) -> Self {
        ParamSpec {
            name,
            kind: ParamKind::Rgb { min, max },
            default: Value::Rgb([default; 3]),
            doc,
            varies: true,
            names: &[],
        }
    }

    /// A choice among `options`.
    pub fn choice(name: &'static str, options: &'static [&'static str], default: &str, doc: &'static str) -> Self {
        ParamSpec {
            name,
            kind: ParamKind::Choice(options),
            default: Value::Choice(default.to_string()),
            doc,
            varies: false,
            names: &[],
        }
    }

    /// A flag.
    pub fn boolean(name: &'static str, default: bool, doc: &'static str) -> Self {
        ParamSpec { name, kind: ParamKind::Bool, default: Value::Bool(default), doc, varies: false, names: &[] }
    }

    /// A file path, empty by default.
    pub fn path(name: &'static str, doc: &'static str) -> Self {
        ParamSpec { name, kind: ParamKind::Path, default: Value::Path(String::new()), doc, varies: false, names: &[] }
    }

    /// A nested model, `default` as written (`NAME[:PARAM=VALUE]...`).
    pub fn model(name: &'static str, default: &str, doc: &'static str) -> Self {
        ParamSpec {
            name,
            kind: ParamKind::Model,
            default: Value::Model(default.to_string()),
            doc,
            varies: false,
            names: &[],
        }
    }

    /// The same parameter, constant over a surface: the model precomputes from it (a table,
    /// a normalisation), so a texture may not give it.
    pub fn fixed(self) -> Self {
        ParamSpec { varies: false, ..self }
    }

    /// The same parameter with named values, e.g. Mitsuba's indices of refraction.
    pub fn with_names(self, names: &'static [(&'static str, f64)]) -> Self {
        ParamSpec { names, ..self }
    }

    /// The same parameter with another default (a model that shares a description but not its default).
    pub fn with_default(self, default: Value) -> Self {
        ParamSpec { default, ..self }
    }

    /// The valid values, as a user reads them: "[0, 1]", "one of a|b", "true|false".
    pub fn range_text(&self) -> String {
        match &self.kind {
            ParamKind::Float { min, max } if self.names.is_empty() => format!("[{min}, {max}]"),
            ParamKind::Float { min, max } => format!(
                "a number in [{min}, {max}] or one of {}",
                self.names.iter().map(|n| n.0).collect::<Vec<_>>().join("|")
            ),
            ParamKind::Rgb { min, max } => format!("[{min}, {max}] (one value or r,g,b)"),
            ParamKind::Choice(opts) => format!("one of {}", opts.join("|")),
            ParamKind::Bool => "true|false".to_string(),
            ParamKind::Path => "a file path".to_string(),
            ParamKind::Model => "a model, NAME[:PARAM=VALUE]...".to_string(),
        }
    }

    fn bad(&self, value: impl fmt::Display) -> ParamError {
        ParamError::BadValue { name: self.name.to_string(), value: value.to_string(), expected: self.range_text() }
    }

    /// Parses and range-checks a value written as text.
    pub fn parse(&self, text: &str) -> Result<Value, ParamError> {
        let t = text.trim();
        let v = match &self.kind {
            ParamKind::Float { .. } => match self.names.iter().find(|(n, _)| n.eq_ignore_ascii_case(t)) {
                Some((_, v)) => Value::Float(*v),
                None => Value::Float(t.parse().map_err(|_| self.bad(text))?),
            },
            ParamKind::Rgb { .. } => {
                let parts: Vec<f64> = t
                    .split(',')
                    .map(|s| s.trim().parse::<f64>())
                    .collect::<Result<_, _>>()
                    .map_err(|_| self.bad(text))?;
                match parts.as_slice() {
                    [v] => Value::Rgb([*v; 3]),
                    [r, g, b] => Value::Rgb([*r, *g, *b]),
                    _ => return Err(self.bad(text)),
                }
            }
            ParamKind::Choice(_) => Value::Choice(t.to_string()),
            ParamKind::Bool => match t {
                "true" | "1" | "yes" => Value::Bool(true),
                "false" | "0" | "no" => Value::Bool(false),
                _ => return Err(self.bad(text)),
            },
            // The file is read when the model is built, which names it in any error.
            ParamKind::Path => Value::Path(t.to_string()),
            ParamKind::Model => Value::Model(t.to_string()),
        };
        self.check(v)
    }

    /// Range-checks a typed value: a number for an RGB parameter is the grey of that value;
    /// a choice is matched without regard to case.
    pub fn check(&self, value: Value) -> Result<Value, ParamError> {
        let in_range = |v: f64, min: f64, max: f64| v.is_finite() && v >= min && v <= max;
        match (&self.kind, value) {
            (ParamKind::Float { min, max }, Value::Float(v)) if in_range(v, *min, *max) => Ok(Value::Float(v)),
            (ParamKind::Rgb { min, max }, Value::Float(v)) if in_range(v, *min, *max) => Ok(Value::Rgb([v; 3])),
            (ParamKind::Rgb { min, max }, Value::Rgb(c)) if c.iter().all(|&v| in_range(v, *min, *max)) => {
                Ok(Value::Rgb(c))
            }
            (ParamKind::Choice(opts), Value::Choice(s)) => opts
                .iter()
                .find(|o| o.eq_ignore_ascii_case(s.trim()))
                .map(|o| Value::Choice(o.to_string()))
                .ok_or_else(|| self.bad(s)),
            (ParamKind::Bool, v @ Value::Bool(_))
            | (ParamKind::Path, v @ Value::Path(_))
            | (ParamKind::Model, v @ Value::Model(_)) => Ok(v),
            (_, v) => Err(self.bad(v)),
        }
    }

    /// `value` moved into this parameter's range (a texture's value at a surface point; a
    /// non-finite channel becomes the range's minimum).
    #[inline]
    pub fn clamp(&self, value: [f32; 3]) -> Value {
        // max then min rather than `clamp`, which checks min ≤ max at every hit.
        let c = |v: f32, min: f64, max: f64| if v.is_finite() { (v as f64).max(min).min(max) } else { min };
        match self.kind {
            ParamKind::Float { min, max } => Value::Float(c(value[0], min, max)),
            ParamKind::Rgb { min, max } => Value::Rgb(value.map(|v| c(v, min, max))),
            _ => self.default_value(),
        }
    }

    /// The default, out of line: a value of a kind that does not vary.
    #[cold]
    #[inline(never)]
    fn default_value(&self) -> Value {
        self.default.clone()
    }
}

/// A wrong model name, parameter name or value; the message lists what would be right.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// No model of that name.
    #[error("unknown model '{name}'; the models are: {valid}")]
    UnknownModel { name: String, valid: String },
    /// The model has no parameter of that name.
    #[error("model '{model}' has no parameter '{name}'; its parameters are: {valid}")]
    UnknownParam { model: String, name: String, valid: String },
    /// The value is malformed or out of range.
    #[error("parameter '{name}': '{value}' is not valid; expected {expected}")]
    BadValue { name: String, value: String, expected: String },
    /// Parameters that are valid alone but not together.
    #[error("{0}")]
    Inconsistent(String),
}

/// Where a model's build reads its parameters: every parameter has a value (given or
/// defaulted, range-checked). Asking for an undeclared name is a programming error and panics.
/// Names are `'static` (a model's own constants), so that a recorded question can be known
/// again by its name's address alone ([`AskOrder`]).
pub trait ParamSource {
    /// The value of parameter `name`.
    fn value(&self, name: &'static str) -> &Value;

    /// True when `name` was given rather than defaulted.
    fn was_given(&self, name: &'static str) -> bool;

    /// A real parameter.
    fn float(&self, name: &'static str) -> f32 {
        float_of(name, self.value(name))
    }

    /// An RGB parameter.
    fn rgb(&self, name: &'static str) -> Rgb {
        rgb_of(name, self.value(name))
    }

    /// A choice parameter.
    fn choice(&self, name: &'static str) -> &str {
        match self.value(name) {
            Value::Choice(s) => s,
            other => panic!("parameter '{name}' is {other:?}, not a choice"),
        }
    }

    /// A file path ("" when none was given).
    fn path(&self, name: &'static str) -> &str {
        match self.value(name) {
            Value::Path(p) => p,
            other => panic!("parameter '{name}' is {other:?}, not a path"),
        }
    }

    /// A flag.
    fn flag(&self, name: &'static str) -> bool {
        flag_of(name, self.value(name))
    }

    /// A nested model, as written.
    fn model(&self, name: &'static str) -> &str {
        match self.value(name) {
            Value::Model(m) => m,
            other => panic!("parameter '{name}' is {other:?}, not a model"),
        }
    }
}

/// Parameter `name`'s value `v` as a real number.
fn float_of(name: &str, v: &Value) -> f32 {
    match v {
        Value::Float(v) => *v as f32,
        other => panic!("parameter '{name}' is {other:?}, not a float"),
    }
}

/// Parameter `name`'s value `v` as RGB.
fn rgb_of(name: &str, v: &Value) -> Rgb {
    match v {
        Value::Rgb([r, g, b]) => Rgb::new(*r as f32, *g as f32, *b as f32),
        other => panic!("parameter '{name}' is {other:?}, not RGB"),
    }
}

/// Parameter `name`'s value `v` as a flag.
fn flag_of(name: &str, v: &Value) -> bool {
    match v {
        Value::Bool(b) => *b,
        other => panic!("parameter '{name}' is {other:?}, not a flag"),
    }
}

/// Resolved parameter values: every parameter of a model, given or defaulted, range-checked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Params {
    /// Every parameter's name, value and whether it was given, in name order.
    values: Vec<(&'static str, Value, bool)>,
}

impl Params {
    /// Resolves `(name, text)` pairs against `specs`, filling in defaults.
    pub fn resolve(model: &str, specs: &[ParamSpec], given: &[(&str, &str)]) -> Result<Params, ParamError> {
        Self::resolve_with(model, specs, given.iter().map(|(n, t)| (*n, *t)), |s, t: &str| s.parse(t))
    }

    /// Resolves typed `(name, value)` pairs against `specs`, filling in defaults.
    pub fn from_values(model: &str, specs: &[ParamSpec], given: &[(&str, Value)]) -> Result<Params, ParamError> {
        Self::resolve_with(model, specs, given.iter().map(|(n, v)| (*n, v)), |s, v: &Value| s.check(v.clone()))
    }

    fn resolve_with<'g, T: 'g>(
        model: &str,
        specs: &[ParamSpec],
        given: impl Iterator<Item = (&'g str, T)>,
        read: impl Fn(&ParamSpec, T) -> Result<Value, ParamError>,
    ) -> Result<Params, ParamError> {
        let mut values: Vec<_> = specs.iter().map(|s| (s.name, s.default.clone(), false)).collect();
        values.sort_by_key(|e| e.0);
        values.dedup_by_key(|e| e.0);
        let mut p = Params { values };
        for (name, v) in given {
            let spec = find_spec(model, specs, name)?;
            let i = p.index(spec.name).expect("every spec has an entry");
            p.values[i] = (spec.name, read(spec, v)?, true);
        }
        Ok(p)
    }

    /// The entry of parameter `name`. Models ask with the names their specs hold (the same
    /// string constants), so the address usually finds it before any string is compared: a
    /// textured material asks at every hit.
    #[inline]
    fn index(&self, name: &str) -> Option<usize> {
        self.values
            .iter()
            .position(|e| std::ptr::eq(e.0, name))
            .or_else(|| self.values.binary_search_by(|e| e.0.cmp(name)).ok())
    }

    /// The resolved values in name order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, &Value)> {
        self.values.iter().map(|(k, v, _)| (*k, v))
    }

    /// The (name, value) pairs that were given, in name order.
    pub fn given(&self) -> impl Iterator<Item = (&'static str, &Value)> {
        self.values.iter().filter(|e| e.2).map(|(k, v, _)| (*k, v))
    }
}

/// The description of `name` among `specs`, or an error listing them.
pub fn find_spec<'s>(model: &str, specs: &'s [ParamSpec], name: &str) -> Result<&'s ParamSpec, ParamError> {
    specs.iter().find(|s| s.name == name).ok_or_else(|| ParamError::UnknownParam {
        model: model.to_string(),
        name: name.to_string(),
        valid: if specs.is_empty() {
            "(none)".to_string()
        } else {
            specs.iter().map(|s| s.name).collect::<Vec<_>>().join(", ")
        },
    })
}

impl ParamSource for Params {
    fn value(&self, name: &'static str) -> &Value {
        match self.index(name) {
            Some(i) => &self.values[i].1,
            None => panic!("model asked for undeclared parameter '{name}'"),
        }
    }

    fn was_given(&self, name: &'static str) -> bool {
        self.index(name).is_some_and(|i| self.values[i].2)
    }
}

/// `Params` with some values replaced: a textured material's parameters at one surface point.
/// Borrowed, so that a renderer builds it on the stack at every hit.
#[derive(Clone, Debug)]
pub struct Varied<'a> {
    base: &'a Params,
    values: &'a [(&'static str, Value)],
    /// The questions a build of the same model asked before, answered from their places.
    order: Option<&'a AskOrder>,
    /// The next question of `order`.
    next: Cell<usize>,
}

impl<'a> Varied<'a> {
    /// `base` with `values` (already in range: see [`ParamSpec::clamp`]) in place of its own.
    pub fn new(base: &'a Params, values: &'a [(&'static str, Value)]) -> Self {
        Varied { base, values, order: None, next: Cell::new(0) }
    }

    /// The same, answering the questions of `order` (recorded with values of the same names in
    /// the same places) from where they were answered then, without searching by name; a
    /// question asked otherwise is searched for.
    pub fn with_order(mut self, order: &'a AskOrder) -> Self {
        self.order = Some(order);
        self
    }

    /// The recorded answer to `name` (a `was_given` question when `given`), if it is the
    /// question the order expects next.
    #[inline]
    fn replay(&self, name: &'static str, given: bool) -> Option<&'a Ask> {
        let k = self.next.get();
        let ask = self.order?.0.get(k)?;
        (ask.given == given && std::ptr::eq(ask.name, name)).then(|| {
            self.next.set(k + 1);
            ask
        })
    }

    /// The value of `name` found by its name.
    #[cold]
    #[inline(never)]
    fn search(&self, name: &'static str) -> &Value {
        self.values.iter().find(|(n, _)| same_name(n, name)).map_or_else(|| self.base.value(name), |(_, v)| v)
    }

    /// The value answering `name`: replayed from the order, else searched for.
    #[inline]
    fn answer(&self, ask: Option<&Ask>, name: &'static str) -> &Value {
        match ask.and_then(|a| self.at(a.at)) {
            Some(v) => v,
            None => self.search(name),
        }
    }

    /// Where `name` is answered: a varied value, else the base entry.
    fn slot(&self, name: &str) -> Option<Slot> {
        match self.values.iter().position(|(n, _)| same_name(n, name)) {
            Some(k) => Some(Slot::Varied(k)),
            None => self.base.index(name).map(Slot::Base),
        }
    }

    /// The value at `slot`.
    #[inline]
    fn at(&self, slot: Slot) -> Option<&Value> {
        match slot {
            Slot::Varied(k) => self.values.get(k).map(|v| &v.1),
            Slot::Base(i) => self.base.values.get(i).map(|v| &v.1),
        }
    }
}

/// The questions one build of a model asked of its parameters, in order, with where each was
/// answered: the builds of a textured material at every hit ask the same questions, which
/// [`Varied::with_order`] then answers without searching by name (the build of a textured
/// microfacet model asks about fifteen).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AskOrder(Vec<Ask>);

#[derive(Clone, Copy, Debug, PartialEq)]
struct Ask {
    /// Known again by its address and length alone, which identify its text: names are
    /// `'static`, never freed and replaced by another.
    name: &'static str,
    /// A `was_given` question rather than a `value` one.
    given: bool,
    at: Slot,
    /// The answer, read once, where it cannot vary: the per-hit build then neither matches
    /// the value's kind nor converts it again.
    fixed: Fixed,
}

/// An answer that does not vary, in the type it is asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Fixed {
    /// None kept: read the value at the slot.
    No,
    /// A real number.
    Float(f32),
    /// An RGB triple.
    Rgb(Rgb),
    /// A flag, or the answer to a `was_given` question.
    Flag(bool),
}

/// Where an answer lies.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Slot {
    /// The varied value of this index.
    Varied(usize),
    /// The base entry of this index.
    Base(usize),
}

/// A [`Varied`] that writes down the questions asked of it ([`AskOrder`]).
pub struct Recorder<'a> {
    varied: Varied<'a>,
    asks: RefCell<Vec<Ask>>,
}

impl<'a> Recorder<'a> {
    /// Records the questions asked of `Varied::new(base, values)`.
    pub fn new(base: &'a Params, values: &'a [(&'static str, Value)]) -> Self {
        Recorder { varied: Varied::new(base, values), asks: RefCell::new(Vec::new()) }
    }

    /// The questions asked so far.
    pub fn order(self) -> AskOrder {
        AskOrder(self.asks.into_inner())
    }

    fn note(&self, name: &'static str, given: bool) {
        let Some(at) = self.varied.slot(name) else { return };
        let fixed = match (at, given) {
            (Slot::Varied(_), true) => Fixed::Flag(true),
            (Slot::Varied(_), false) => Fixed::No,
            (Slot::Base(i), true) => Fixed::Flag(self.varied.base.values[i].2),
            (Slot::Base(i), false) => match &self.varied.base.values[i].1 {
                v @ Value::Float(_) => Fixed::Float(float_of(name, v)),
                v @ Value::Rgb(_) => Fixed::Rgb(rgb_of(name, v)),
                Value::Bool(b) => Fixed::Flag(*b),
                _ => Fixed::No,
            },
        };
        self.asks.borrow_mut().push(Ask { name, given, at, fixed });
    }
}

impl ParamSource for Recorder<'_> {
    fn value(&self, name: &'static str) -> &Value {
        self.note(name, false);
        self.varied.value(name)
    }

    fn was_given(&self, name: &'static str) -> bool {
        self.note(name, true);
        self.varied.was_given(name)
    }
}

/// Equal names, tested first by address: models ask with their `ParamSpec`'s own `&'static str`,
/// so at every hit of a textured material the comparison is usually one pointer test.
#[inline]
fn same_name(a: &str, b: &str) -> bool {
    std::ptr::eq(a, b) || a == b
}

impl ParamSource for Varied<'_> {
    fn value(&self, name: &'static str) -> &Value {
        self.answer(self.replay(name, false), name)
    }

    fn was_given(&self, name: &'static str) -> bool {
        match self.replay(name, true) {
            Some(&Ask { fixed: Fixed::Flag(b), .. }) => b,
            _ => self.given_slow(name),
        }
    }

    // The typed questions answer a fixed value at once; the rest (a varied value, or a
    // question asked out of the recorded order) go the slow way, kept out of line so that
    // the fast one needs no stack frame.
    fn float(&self, name: &'static str) -> f32 {
        match self.replay(name, false) {
            Some(&Ask { fixed: Fixed::Float(v), .. }) => v,
            ask => match self.varied(ask) {
                Some(&Value::Float(v)) => v as f32,
                _ => self.slow(ask, name, float_of),
            },
        }
    }

    fn rgb(&self, name: &'static str) -> Rgb {
        match self.replay(name, false) {
            Some(&Ask { fixed: Fixed::Rgb(v), .. }) => v,
            ask => match self.varied(ask) {
                Some(&Value::Rgb([r, g, b])) => Rgb::new(r as f32, g as f32, b as f32),
                _ => self.slow(ask, name, rgb_of),
            },
        }
    }

    fn flag(&self, name: &'static str) -> bool {
        match self.replay(name, false) {
            Some(&Ask { fixed: Fixed::Flag(b), .. }) => b,
            ask => self.slow(ask, name, flag_of),
        }
    }
}

impl Varied<'_> {
    /// The varied value a replayed question reads.
    #[inline]
    fn varied(&self, ask: Option<&Ask>) -> Option<&Value> {
        match ask {
            Some(&Ask { at: Slot::Varied(k), .. }) => self.values.get(k).map(|v| &v.1),
            _ => None,
        }
    }

    /// `was_given` by name.
    #[cold]
    #[inline(never)]
    fn given_slow(&self, name: &'static str) -> bool {
        self.values.iter().any(|(n, _)| same_name(n, name)) || self.base.was_given(name)
    }

    /// The answer to `name` read from its value with `read`.
    #[inline(never)]
    fn slow<T>(&self, ask: Option<&Ask>, name: &'static str, read: fn(&str, &Value) -> T) -> T {
        read(name, self.answer(ask, name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn specs() -> Vec<ParamSpec> {
        vec![
            ParamSpec::float("ke", 0.0, 1000.0, 20.0, "exponent"),
            ParamSpec::rgb("ks", 0.0, 1.0, 0.5, "specular"),
            ParamSpec::choice("fresnel", &["none", "schlick"], "none", "fresnel"),
            ParamSpec::boolean("anisotropic", false, "flag"),
        ]
    }

    #[test]
    fn defaults_and_overrides() {
        let p = Params::resolve("m", &specs(), &[("ks", "0.1,0.2,0.3"), ("fresnel", "Schlick")]).unwrap();
        assert_eq!(p.float("ke"), 20.0);
        assert_eq!(p.rgb("ks"), Rgb::new(0.1, 0.2, 0.3));
        assert_eq!(p.choice("fresnel"), "schlick");
        assert!(!p.flag("anisotropic"));
    }

    #[test]
    fn errors_name_the_valid_values() {
        let e = Params::resolve("m", &specs(), &[("kx", "1")]).unwrap_err().to_string();
        assert!(e.contains("'kx'") && e.contains("ke, ks, fresnel, anisotropic"), "{e}");
        let e = Params::resolve("m", &specs(), &[("ke", "2000")]).unwrap_err().to_string();
        assert!(e.contains("[0, 1000]"), "{e}");
        let e = Params::resolve("m", &specs(), &[("ks", "0.1,0.2")]).unwrap_err().to_string();
        assert!(e.contains("r,g,b"), "{e}");
        let e = Params::resolve("m", &specs(), &[("fresnel", "exact")]).unwrap_err().to_string();
        assert!(e.contains("none|schlick"), "{e}");
        assert!(Params::resolve("m", &specs(), &[("ke", "nan")]).is_err());
    }

    #[test]
    fn typed_values_named_values_and_varied_overlays() {
        const IORS: &[(&str, f64)] = &[("water", 1.333)];
        let mut s = specs();
        s.push(ParamSpec::float("ior", 1.0, 3.0, 1.5, "index").with_names(IORS).fixed());
        let p = Params::from_values("m", &s, &[("ks", Value::Float(0.25)), ("ke", Value::Float(5.0))]).unwrap();
        assert_eq!(p.rgb("ks"), Rgb::splat(0.25));
        assert!(p.was_given("ke") && !p.was_given("ior"));
        assert!(Params::from_values("m", &s, &[("ke", Value::Rgb([1.0; 3]))]).is_err(), "RGB for a float");
        assert!(Params::from_values("m", &s, &[("ke", Value::Float(-1.0))]).is_err());
        assert_eq!(Params::resolve("m", &s, &[("ior", "Water")]).unwrap().float("ior"), 1.333);
        let e = Params::resolve("m", &s, &[("ior", "milk")]).unwrap_err().to_string();
        assert!(e.contains("water"), "{e}");
        assert!(s[0].varies && s[1].varies && !s[2].varies && !s[4].varies);
        // A texture's value, clamped into range, replaces the base value at one point only.
        let v = [("ks", s[1].clamp([0.5, 2.0, f32::NAN]))];
        let here = Varied::new(&p, &v);
        assert_eq!(here.rgb("ks"), Rgb::new(0.5, 1.0, 0.0));
        assert_eq!(here.float("ke"), 5.0);
        assert!(here.was_given("ks"));
    }

    /// The questions of one build, asked again in the same order or in another, get the
    /// answers a search by name gives.
    #[test]
    fn recorded_questions_are_answered_as_by_name() {
        let s = specs();
        let p = Params::from_values("m", &s, &[("ke", Value::Float(5.0))]).unwrap();
        // Each name by its value, by its typed accessor (the answer kept typed, or read from
        // a varied value) and by whether it was given.
        let typed = |q: &dyn ParamSource, n: &'static str| match n {
            "ke" => q.float(n).to_string(),
            "ks" => format!("{:?}", q.rgb(n)),
            "fresnel" => q.choice(n).to_string(),
            _ => q.flag(n).to_string(),
        };
        let ask = |q: &dyn ParamSource, order: &[&'static str]| -> Vec<String> {
            order.iter().map(|&n| format!("{:?} {} {}", q.value(n), typed(q, n), q.was_given(n))).collect()
        };
        let first = [("ks", Value::Rgb([0.1, 0.2, 0.3]))];
        let recorder = Recorder::new(&p, &first);
        let names = ["ke", "ks", "fresnel", "anisotropic"];
        ask(&recorder, &names);
        let order = recorder.order();
        assert_eq!(order.0.len(), 3 * names.len());
        let here = [("ks", Value::Rgb([0.7, 0.8, 0.9]))];
        // A name equal in text but at another address is found by the search.
        let copied: &'static str = Box::leak(String::from("ks").into_boxed_str());
        for asked in [&names[..], &["fresnel", "ke", "ks", "ke"], &["ke", copied, "anisotropic"]] {
            let by_name = ask(&Varied::new(&p, &here), asked);
            assert_eq!(ask(&Varied::new(&p, &here).with_order(&order), asked), by_name, "{asked:?}");
        }
        let replayed = ask(&Varied::new(&p, &here).with_order(&order), &names);
        assert_eq!(replayed[0], "Float(5.0) 5 true");
        assert!(
            replayed[1].starts_with("Rgb([0.7, 0.8, 0.9]) Rgb([0.7") && replayed[1].ends_with("true"),
            "{}",
            replayed[1]
        );
    }
}
