//! The panels of a comparison: each model with its parameters, the shared diffuse base filled
//! in where the model has a diffuse colour the user left unset, and the sweep's value.

use anyhow::{bail, Context, Result};
use brdf::{ModelSpec, Params};
use std::sync::Arc;

/// The parameters that are a model's diffuse colour, under the names its `ParamSpec`s give.
const DIFFUSE_ROLE: &[&str] = &["diffuse", "diffuse_reflectance", "albedo", "base_color"];

/// One panel: a model and the parameters it is built with.
#[derive(Clone, Debug)]
pub struct Panel {
    /// The model.
    pub spec: &'static ModelSpec,
    /// (name, value) as written, the sweep's value last.
    pub given: Vec<(String, String)>,
    /// The diffuse base's parameter and value, when the base was filled in.
    pub base: Option<(String, String)>,
}

impl Panel {
    /// Every parameter the model is built with: the given ones and the base.
    pub fn pairs(&self) -> Vec<(&str, &str)> {
        self.given.iter().chain(&self.base).map(|(k, v)| (k.as_str(), v.as_str())).collect()
    }

    /// The resolved parameters (defaults filled in, ranges checked).
    pub fn params(&self) -> Result<Params> {
        Params::resolve(self.spec.name, &(self.spec.params)(), &self.pairs()).map_err(|e| anyhow::anyhow!("{e}"))
    }

    /// The model, built.
    pub fn build(&self) -> Result<Arc<dyn brdf::Brdf>> {
        Ok(Arc::from(self.spec.build_with(&self.pairs()).with_context(|| format!("model '{}'", self.title()))?))
    }

    /// The model's name.
    pub fn title(&self) -> &'static str {
        self.spec.name
    }

    /// The parameters the user gave, as `name value` pairs ("defaults" for none).
    pub fn subtitle(&self) -> String {
        if self.given.is_empty() {
            return "defaults".into();
        }
        self.given.iter().map(|(k, v)| format!("{k} {v}")).collect::<Vec<_>>().join(", ")
    }
}

/// True for a metal (a model with a conductor's Fresnel term), which has no diffuse colour to
/// give even where its parameters allow one.
fn metal(spec: &ModelSpec, given: &[(String, String)]) -> Result<bool> {
    let pairs: Vec<(&str, &str)> = given.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
    let p = Params::resolve(spec.name, &(spec.params)(), &pairs).map_err(|e| anyhow::anyhow!("{e}"))?;
    let conductor = p.iter().any(|(n, v)| n == "fresnel" && *v == brdf::Value::Choice("conductor".into()));
    Ok(conductor)
}

/// `--sweep NAME=V1,V2,…` split into the name and its values.
pub fn parse_sweep(text: &str) -> Result<(String, Vec<String>)> {
    let Some((name, values)) = text.split_once('=') else {
        bail!("--sweep takes NAME=V1,V2,… (e.g. ke=5,20,100), not '{text}'");
    };
    let values: Vec<String> = values.split(',').map(|v| v.trim().to_string()).filter(|v| !v.is_empty()).collect();
    if name.trim().is_empty() || values.is_empty() {
        bail!("--sweep takes NAME=V1,V2,… (e.g. ke=5,20,100), not '{text}'");
    }
    Ok((name.trim().to_string(), values))
}

/// The panels, row by row: each model once, or once per sweep value. `base` is the diffuse
/// colour filled into every model that has one and was not given it (None: none).
pub fn panels(models: &[String], sweep: Option<&(String, Vec<String>)>, base: Option<&str>) -> Result<Vec<Panel>> {
    let mut out = Vec::new();
    for item in models {
        let (spec, given) = brdf::parse_item(item).map_err(|e| anyhow::anyhow!("{e}"))?;
        let names: Vec<&str> = (spec.params)().iter().map(|p| p.name).collect();
        let values: Vec<Option<&String>> = match sweep {
            None => vec![None],
            Some((name, values)) => {
                if !names.contains(&name.as_str()) {
                    bail!(
                        "--sweep {name}: model '{}' has no parameter '{name}' (it has: {})",
                        spec.name,
                        names.join(", ")
                    );
                }
                values.iter().map(Some).collect()
            }
        };
        for v in values {
            let mut given: Vec<(String, String)> = given.clone();
            if let (Some((name, _)), Some(v)) = (sweep, v) {
                given.retain(|(k, _)| k != name);
                given.push((name.clone(), v.clone()));
            }
            let role = names.iter().find(|n| DIFFUSE_ROLE.contains(n));
            let base = match (role, base) {
                (Some(r), Some(b)) if !given.iter().any(|(k, _)| k == r) && !metal(spec, &given)? => {
                    Some((r.to_string(), b.to_string()))
                }
                _ => None,
            };
            let panel = Panel { spec, given, base };
            panel.params().with_context(|| format!("model '{item}'"))?;
            out.push(panel);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn base_fills_unset_diffuse_colours_and_sweeps_replace_values() {
        let models =
            ["phong:ke=10".to_string(), "lambert".into(), "mirror".into(), "phong:diffuse=0".into(), "ggx".into()];
        let p = panels(&models, None, Some("0.5,0.1,0.1")).unwrap();
        assert_eq!(p[0].base, Some(("diffuse".into(), "0.5,0.1,0.1".into())));
        assert_eq!(p[1].base, Some(("albedo".into(), "0.5,0.1,0.1".into())));
        assert_eq!(p[2].base, None, "a mirror has no diffuse colour");
        assert_eq!(p[3].base, None, "the model's own parameter wins");
        assert_eq!(p[4].base, None, "a metal has no diffuse colour");
        let dielectric = panels(&["ggx:fresnel=dielectric".into()], None, Some("0.5")).unwrap();
        assert_eq!(dielectric[0].base, Some(("diffuse".into(), "0.5".into())));
        assert_eq!(p[0].subtitle(), "ke 10");
        assert_eq!(p[1].subtitle(), "defaults");
        let sweep = parse_sweep("ke=5, 20,100").unwrap();
        let p = panels(&models[..1], Some(&sweep), None).unwrap();
        let ke: Vec<_> = p.iter().map(|p| p.given.clone()).collect();
        assert_eq!(
            ke,
            [[("ke".to_string(), "5".to_string())], [("ke".into(), "20".into())], [("ke".into(), "100".into())]]
        );
        let e = panels(&["ward".into()], Some(&sweep), None).unwrap_err().to_string();
        assert!(e.contains("no parameter 'ke'") && e.contains("alpha"), "{e}");
        assert!(panels(&["phong:ke=-3".into()], None, None).is_err());
        assert!(parse_sweep("ke").is_err() && parse_sweep("ke=").is_err());
    }
}
