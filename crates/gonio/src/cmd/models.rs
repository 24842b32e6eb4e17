//! `gonio models`: every registered model with its parameters and claimed properties.

use super::{claims_json, claims_text};
use crate::cli::ModelsArgs;
use crate::modelarg::value_json;
use anyhow::Result;
use brdf::{ModelSpec, ParamKind, ParamSpec, Value};

fn kind_name(p: &ParamSpec) -> &'static str {
    match p.kind {
        ParamKind::Float { .. } => "float",
        ParamKind::Rgb { .. } => "rgb",
        ParamKind::Choice(_) => "choice",
        ParamKind::Bool => "bool",
        ParamKind::Path => "path",
        ParamKind::Model => "model",
    }
}

fn param_json(p: &ParamSpec) -> serde_json::Value {
    let mut o = serde_json::json!({
        "name": p.name,
        "kind": kind_name(p),
        "default": value_json(&p.default),
        "range": p.range_text(),
        "doc": p.doc,
    });
    match &p.kind {
        ParamKind::Float { min, max } | ParamKind::Rgb { min, max } => {
            o["min"] = serde_json::json!(min);
            o["max"] = serde_json::json!(max);
            if !p.names.is_empty() {
                o["names"] = serde_json::Value::Object(
                    p.names.iter().map(|(n, v)| (n.to_string(), serde_json::json!(v))).collect(),
                );
            }
        }
        ParamKind::Choice(opts) => o["options"] = serde_json::json!(opts),
        ParamKind::Bool | ParamKind::Path | ParamKind::Model => {}
    }
    o
}

/// A value for reading: floats to six significant digits (JSON keeps them exact).
fn short(v: &Value) -> String {
    let f = |x: f64| {
        let s = format!("{x:.6}");
        let t = s.trim_end_matches('0').trim_end_matches('.');
        if x != 0.0 && x.abs() < 1e-3 {
            format!("{x:.3e}")
        } else {
            t.to_string()
        }
    };
    match v {
        Value::Float(x) => f(*x),
        Value::Rgb([r, g, b]) if r == g && g == b => f(*r),
        Value::Rgb(c) => c.map(f).join(","),
        other => other.to_string(),
    }
}

fn showcase_text(set: &[(&str, &str)]) -> String {
    set.iter().map(|(k, v)| format!("--{k} {v}")).collect::<Vec<_>>().join(" ")
}

/// The valid values for the table: a long choice list shortened (`--json` and the errors
/// give it whole).
fn range_column(p: &ParamSpec) -> String {
    const SHOWN: usize = 8;
    match &p.kind {
        ParamKind::Choice(opts) if opts.len() > SHOWN => {
            format!("one of {}|… ({} names)", opts[..SHOWN].join("|"), opts.len())
        }
        ParamKind::Float { min, max } if !p.names.is_empty() => {
            format!("[{min}, {max}] or a name ({} names)", p.names.len())
        }
        _ => p.range_text(),
    }
}

/// The claims at the defaults, or why the model would not build.
fn default_claims(m: &ModelSpec) -> Result<brdf::Claims, String> {
    m.build_with(&[]).map(|b| b.claims()).map_err(|e| e.to_string())
}

/// Every model with its parameters (names, kinds, ranges, defaults), claims and showcases:
/// what `gonio models --json` prints and the explorer's model panel is generated from.
pub fn models_json() -> serde_json::Value {
    let list: Vec<serde_json::Value> = brdf::models()
        .iter()
        .map(|m| {
            serde_json::json!({
                "name": m.name,
                "summary": m.summary,
                "reference": m.reference,
                "params": (m.params)().iter().map(param_json).collect::<Vec<_>>(),
                "claims": match default_claims(m) {
                    Ok(c) => claims_json(c),
                    Err(e) => serde_json::json!({ "error": e }),
                },
                "showcase": m.showcase.iter().map(|set| {
                    serde_json::Value::Object(set.iter().map(|(k, v)| (k.to_string(), serde_json::json!(v))).collect())
                }).collect::<Vec<_>>(),
            })
        })
        .collect();
    serde_json::Value::Array(list)
}

/// Runs `gonio models`.
pub fn run(args: &ModelsArgs) -> Result<()> {
    let models = brdf::models();
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&models_json())?);
        return Ok(());
    }
    for (i, m) in models.iter().enumerate() {
        if i > 0 {
            outln!();
        }
        outln!("{}  {}", m.name, m.summary);
        outln!("  source:   {}", m.reference);
        match default_claims(m) {
            Ok(c) => outln!("  claims:   {} (at the defaults)", claims_text(c)),
            Err(e) => outln!("  claims:   unknown: the defaults do not build ({e})"),
        }
        let params = (m.params)();
        if params.is_empty() {
            outln!("  parameters: none");
        }
        let name_w = params.iter().map(|p| p.name.len()).max().unwrap_or(0) + 2;
        let range_w = params.iter().map(|p| range_column(p).chars().count()).max().unwrap_or(0);
        let def_w = params.iter().map(|p| short(&p.default).chars().count()).max().unwrap_or(0);
        for p in &params {
            outln!(
                "  {:<name_w$}  {:<6}  {:<range_w$}  default {:<def_w$}  {}",
                format!("--{}", p.name),
                kind_name(p),
                range_column(p),
                short(&p.default),
                p.doc
            );
        }
        for set in m.showcase {
            outln!("  showcase: {}", showcase_text(set));
        }
    }
    Ok(())
}
