//! A model named on the command line with the parameters given for it, resolved against the
//! registry's parameter descriptions (never a hand-written list per model).

use anyhow::{bail, Result};
use brdf::{Brdf, ModelSpec, ParamSpec, Params, Value};

/// A model as the user asked for it: its registry entry and the `(name, value)` pairs given.
#[derive(Clone, Debug)]
pub struct ModelArg {
    /// The registry entry.
    pub spec: &'static ModelSpec,
    /// The parameters given, names canonicalised, values as typed.
    pub given: Vec<(String, String)>,
}

impl ModelArg {
    /// Looks the model up and checks every given parameter (name and range) now, so a typo is
    /// reported before any work starts.
    pub fn new(name: &str, given: Vec<(String, String)>) -> Result<Self> {
        let spec = brdf::find(name)?;
        let specs = (spec.params)();
        let given = given.into_iter().map(|(n, v)| (canonical_name(&specs, &n), v)).collect();
        let arg = ModelArg { spec, given };
        arg.resolved()?;
        Ok(arg)
    }

    /// Parses an overlay item: `NAME[:PARAM=VALUE]...`, e.g. `ward:alpha=0.1:ks=0.3`.
    pub fn parse_item(item: &str) -> Result<Self> {
        let mut parts = item.split(':');
        let name = parts.next().unwrap_or_default().trim();
        if name.is_empty() {
            bail!("empty model name in '{item}'; write MODEL[:PARAM=VALUE]..., e.g. ward:alpha=0.1:ks=0.3");
        }
        let mut given = Vec::new();
        for p in parts {
            let Some((k, v)) = p.split_once('=') else {
                bail!("'{p}' in '{item}' is not PARAM=VALUE; write MODEL[:PARAM=VALUE]..., e.g. ward:alpha=0.1:ks=0.3");
            };
            given.push((k.trim().to_string(), v.trim().to_string()));
        }
        ModelArg::new(name, given)
    }

    fn pairs(&self) -> Vec<(&str, &str)> {
        self.given.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect()
    }

    /// Every parameter of the model, given or defaulted.
    pub fn resolved(&self) -> Result<Params> {
        Ok(Params::resolve(self.spec.name, &(self.spec.params)(), &self.pairs())?)
    }

    /// Builds the model.
    pub fn build(&self) -> Result<Box<dyn Brdf>> {
        Ok(self.spec.build_with(&self.pairs())?)
    }

    /// The name with the parameters that were given: `ward (alpha=0.1, ks=0.3)`.
    pub fn label(&self) -> String {
        if self.given.is_empty() {
            self.spec.name.to_string()
        } else {
            format!("{} ({})", self.spec.name, self.given_text())
        }
    }

    /// The model as an overlay item: `ward:alpha=0.1:ks=0.3`.
    pub fn item(&self) -> String {
        let mut s = self.spec.name.to_string();
        for (k, v) in &self.given {
            s.push_str(&format!(":{k}={v}"));
        }
        s
    }

    /// The given parameters as `a=1, b=2`, or `defaults`.
    pub fn given_text(&self) -> String {
        if self.given.is_empty() {
            return "defaults".into();
        }
        self.given.iter().map(|(k, v)| format!("{k}={v}")).collect::<Vec<_>>().join(", ")
    }
}

/// The declared name a user meant: exact, or with `-` for `_` (`--alpha-u` for `alpha_u`).
fn canonical_name(specs: &[ParamSpec], name: &str) -> String {
    if specs.iter().any(|s| s.name == name) {
        return name.to_string();
    }
    let alt = name.replace('-', "_");
    specs.iter().find(|s| s.name == alt).map(|s| s.name.to_string()).unwrap_or_else(|| name.to_string())
}

/// Splits an `--overlay` list at commas, keeping the commas inside an RGB value:
/// `ward:ks=0.1,0.2,0.3,phong` → [`ward:ks=0.1,0.2,0.3`, `phong`]. Model names start with a
/// letter, channel values never do.
pub fn split_overlay(list: &str) -> Vec<String> {
    let mut items: Vec<String> = Vec::new();
    for piece in list.split(',') {
        let starts_number =
            piece.trim_start().starts_with(|c: char| c.is_ascii_digit() || matches!(c, '.' | '-' | '+'));
        match items.last_mut() {
            Some(last) if starts_number => {
                last.push(',');
                last.push_str(piece);
            }
            _ => items.push(piece.trim().to_string()),
        }
    }
    items.retain(|s| !s.is_empty());
    items
}

/// A parameter value as JSON: numbers, `[r, g, b]`, strings, booleans.
pub fn value_json(v: &Value) -> serde_json::Value {
    match v {
        Value::Float(x) => serde_json::json!(x),
        Value::Rgb(c) => serde_json::json!(c),
        Value::Choice(s) => serde_json::json!(s),
        Value::Bool(b) => serde_json::json!(b),
        Value::Path(p) | Value::Model(p) => serde_json::json!(p),
    }
}

/// Every resolved parameter as a JSON object.
pub fn params_json(p: &Params) -> serde_json::Value {
    serde_json::Value::Object(p.iter().map(|(k, v)| (k.to_string(), value_json(v))).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlay_lists_keep_rgb_values_whole() {
        assert_eq!(split_overlay("ward:ks=0.1,0.2,0.3,lambert"), vec!["ward:ks=0.1,0.2,0.3", "lambert"]);
        assert_eq!(split_overlay("lambert, lambert:albedo=.5"), vec!["lambert", "lambert:albedo=.5"]);
        assert_eq!(split_overlay(""), Vec::<String>::new());
    }

    #[test]
    fn items_resolve_against_the_registry() {
        let m = ModelArg::parse_item("lambert:albedo=0.5").unwrap();
        assert_eq!(m.label(), "lambert (albedo=0.5)");
        let e = ModelArg::parse_item("lambert:albedo=2").unwrap_err().to_string();
        assert!(e.contains("albedo") && e.contains("[0, 1]"), "{e}");
        let e = ModelArg::parse_item("lambert:albedo").unwrap_err().to_string();
        assert!(e.contains("PARAM=VALUE"), "{e}");
        assert!(ModelArg::parse_item("nosuch").unwrap_err().to_string().contains("lambert"));
    }
}
