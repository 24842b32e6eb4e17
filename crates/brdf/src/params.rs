//! Model parameters described once as data: names, kinds, ranges, defaults, docs.
//! The CLI, the scene loader and the web page are generated from these descriptions.

use radiometry::Rgb;
use std::collections::BTreeMap;
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
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Value::Float(v) => write!(f, "{v}"),
            Value::Rgb([r, g, b]) if r == g && g == b => write!(f, "{r}"),
            Value::Rgb([r, g, b]) => write!(f, "{r},{g},{b}"),
            Value::Choice(s) => f.write_str(s),
            Value::Bool(b) => write!(f, "{b}"),
            Value::Path(p) => f.write_str(p),
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
}

impl ParamSpec {
    /// A real parameter in [min, max].
    pub fn float(name: &'static str, min: f64, max: f64, default: f64, doc: &'static str) -> Self {
        ParamSpec { name, kind: ParamKind::Float { min, max }, default: Value::Float(default), doc }
    }

    /// An RGB parameter with channels in [min, max].
    pub fn rgb(name: &'static str, min: f64, max: f64, default: f64, doc: &'static str) -> Self {
        ParamSpec { name, kind: ParamKind::Rgb { min, max }, default: Value::Rgb([default; 3]), doc }
    }

    /// A choice among `options`.
    pub fn choice(name: &'static str, options: &'static [&'static str], default: &str, doc: &'static str) -> Self {
        ParamSpec { name, kind: ParamKind::Choice(options), default: Value::Choice(default.to_string()), doc }
    }

    /// A flag.
    pub fn boolean(name: &'static str, default: bool, doc: &'static str) -> Self {
        ParamSpec { name, kind: ParamKind::Bool, default: Value::Bool(default), doc }
    }

    /// A file path, empty by default.
    pub fn path(name: &'static str, doc: &'static str) -> Self {
        ParamSpec { name, kind: ParamKind::Path, default: Value::Path(String::new()), doc }
    }

    /// The valid values, as a user reads them: "[0, 1]", "one of a|b", "true|false".
    pub fn range_text(&self) -> String {
        match &self.kind {
            ParamKind::Float { min, max } => format!("[{min}, {max}]"),
            ParamKind::Rgb { min, max } => format!("[{min}, {max}] (one value or r,g,b)"),
            ParamKind::Choice(opts) => format!("one of {}", opts.join("|")),
            ParamKind::Bool => "true|false".to_string(),
            ParamKind::Path => "a file path".to_string(),
        }
    }

    /// Parses and range-checks a value written as text.
    pub fn parse(&self, text: &str) -> Result<Value, ParamError> {
        let bad = || ParamError::BadValue {
            name: self.name.to_string(),
            value: text.to_string(),
            expected: self.range_text(),
        };
        let in_range = |v: f64, min: f64, max: f64| v.is_finite() && v >= min && v <= max;
        match &self.kind {
            ParamKind::Float { min, max } => {
                let v: f64 = text.trim().parse().map_err(|_| bad())?;
                in_range(v, *min, *max).then_some(Value::Float(v)).ok_or_else(bad)
            }
            ParamKind::Rgb { min, max } => {
                let parts: Vec<f64> =
                    text.split(',').map(|s| s.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad())?;
                let c = match parts.as_slice() {
                    [v] => [*v; 3],
                    [r, g, b] => [*r, *g, *b],
                    _ => return Err(bad()),
                };
                c.iter().all(|&v| in_range(v, *min, *max)).then_some(Value::Rgb(c)).ok_or_else(bad)
            }
            ParamKind::Choice(opts) => opts
                .iter()
                .find(|o| o.eq_ignore_ascii_case(text.trim()))
                .map(|o| Value::Choice(o.to_string()))
                .ok_or_else(bad),
            ParamKind::Bool => match text.trim() {
                "true" | "1" | "yes" => Ok(Value::Bool(true)),
                "false" | "0" | "no" => Ok(Value::Bool(false)),
                _ => Err(bad()),
            },
            // The file is read when the model is built, which names it in any error.
            ParamKind::Path => Ok(Value::Path(text.trim().to_string())),
        }
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

/// Resolved parameter values: every parameter of a model, given or defaulted, range-checked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Params {
    values: BTreeMap<&'static str, Value>,
}

impl Params {
    /// Resolves `(name, text)` pairs against `specs`, filling in defaults.
    pub fn resolve(model: &str, specs: &[ParamSpec], given: &[(&str, &str)]) -> Result<Params, ParamError> {
        let mut values: BTreeMap<&'static str, Value> = specs.iter().map(|s| (s.name, s.default.clone())).collect();
        for (name, text) in given {
            let spec = specs.iter().find(|s| s.name == *name).ok_or_else(|| ParamError::UnknownParam {
                model: model.to_string(),
                name: name.to_string(),
                valid: if specs.is_empty() {
                    "(none)".to_string()
                } else {
                    specs.iter().map(|s| s.name).collect::<Vec<_>>().join(", ")
                },
            })?;
            values.insert(spec.name, spec.parse(text)?);
        }
        Ok(Params { values })
    }

    /// The resolved values in name order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, &Value)> {
        self.values.iter().map(|(k, v)| (*k, v))
    }

    fn get(&self, name: &str) -> &Value {
        self.values.get(name).unwrap_or_else(|| panic!("model asked for undeclared parameter '{name}'"))
    }

    /// A real parameter (panics only on a programming error: a name the model did not declare).
    pub fn float(&self, name: &str) -> f32 {
        match self.get(name) {
            Value::Float(v) => *v as f32,
            other => panic!("parameter '{name}' is {other:?}, not a float"),
        }
    }

    /// An RGB parameter.
    pub fn rgb(&self, name: &str) -> Rgb {
        match self.get(name) {
            Value::Rgb([r, g, b]) => Rgb::new(*r as f32, *g as f32, *b as f32),
            other => panic!("parameter '{name}' is {other:?}, not RGB"),
        }
    }

    /// A choice parameter.
    pub fn choice(&self, name: &str) -> &str {
        match self.get(name) {
            Value::Choice(s) => s,
            other => panic!("parameter '{name}' is {other:?}, not a choice"),
        }
    }

    /// A file path ("" when none was given).
    pub fn path(&self, name: &str) -> &str {
        match self.get(name) {
            Value::Path(p) => p,
            other => panic!("parameter '{name}' is {other:?}, not a path"),
        }
    }

    /// A flag.
    pub fn flag(&self, name: &str) -> bool {
        match self.get(name) {
            Value::Bool(b) => *b,
            other => panic!("parameter '{name}' is {other:?}, not a flag"),
        }
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
}
