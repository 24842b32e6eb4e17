//! "Copy as command": the `gonio eval`, `gonio plot` and render lines that make again what the
//! page shows, and the Mitsuba 3 `<bsdf>` of the model.

use super::http::{ApiError, Query};
use super::model::Resolved;
use super::views::{value_enum, Setting};
use crate::cli::Quantity;
use clap::ValueEnum;
use serde_json::{json, Value};

/// A word as a shell reads it back: quoted when it holds anything but safe characters.
fn sh(word: &str) -> String {
    if !word.is_empty() && word.chars().all(|c| c.is_ascii_alphanumeric() || "-_.,/:=+@%".contains(c)) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', r"'\''"))
    }
}

fn name_of<T: ValueEnum>(v: T) -> String {
    v.to_possible_value().map(|p| p.get_name().to_string()).unwrap_or_default()
}

/// The model and its given parameters as command-line words.
fn model_words(r: &Resolved) -> String {
    let mut s = r.arg.spec.name.to_string();
    for (k, v) in &r.arg.given {
        s.push_str(&format!(" --{k} {}", sh(v)));
    }
    s
}

/// The lines for the first model at the page's settings (`wo=` the read-out direction).
pub fn commands(r: &Resolved, q: &Query) -> Result<Value, ApiError> {
    let s = Setting::from_query(q)?;
    let quantity = value_enum(q, "quantity", Quantity::Intensity)?;
    let wi = s.wi();
    let wi_text = q.get("wi").map(str::to_string).unwrap_or_else(|| format!("{},{},{}", wi.x, wi.y, wi.z));
    let wo_text = q.get("wo").map(str::to_string).unwrap_or_else(|| format!("{},{},{}", -wi.x, -wi.y, wi.z));
    let m = model_words(r);
    let ch = name_of(s.channel);
    let angles = format!("--theta-i {} --phi-i {}", s.theta_i, s.phi_i);
    let plot = |kind: &str, extra: &str| format!("gonio plot {m} --kind {kind}{extra} --channel {ch} -o {kind}.svg");
    let q_name = name_of(quantity);
    // The lit view: the object alone in front of the probe, the model as it is, a fixed spp.
    let object = q.get("object").unwrap_or("sphere");
    let mut render =
        format!("gonio compare {} --mesh {} --backdrop none --base none --noise 0", sh(&r.arg.item()), sh(object));
    for (flag, key) in [
        ("--env", "probe"),
        ("--env-scale", "env"),
        ("--light", "light"),
        ("--light-irradiance", "irradiance"),
        ("--size", "size"),
        ("--spp", "spp"),
    ] {
        match (key, q.get(key)) {
            ("probe", Some("studio")) | (_, None) => {}
            (_, Some(v)) => render.push_str(&format!(" {flag} {}", sh(v))),
        }
    }
    render.push_str(" -o lit.png");
    let mitsuba = match r.arg.resolved() {
        Ok(p) => render::xml::export::bsdf_xml(r.arg.spec.name, &p).unwrap_or_else(|why| format!("<!-- {why} -->")),
        Err(e) => format!("<!-- {e} -->"),
    };
    Ok(json!({
        "eval": format!("gonio eval {m} --wi {} --wo {}", sh(&wi_text), sh(&wo_text)),
        "plot": {
            "polar": plot("polar", &format!(" {angles} --quantity {q_name}")),
            "lobe3d": plot("lobe3d", &format!(" {angles} --quantity {q_name}")),
            "albedo": plot("albedo", &format!(" --samples {}", s.samples)),
            "slice": plot("slice", &format!(" --phi-d {}", s.phi_d)),
            "fresnel": plot("fresnel", ""),
        },
        "render": render,
        "mitsuba": mitsuba,
    }))
}
