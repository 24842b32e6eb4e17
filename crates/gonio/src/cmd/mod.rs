//! One module per subcommand.

pub mod check;
pub mod compare;
pub mod demo;
pub mod envmap;
pub mod eval;
pub mod fit;
pub mod measure;
pub mod models;
pub mod plot;
pub mod render;

use crate::cli::parse_param_options;
use crate::modelarg::ModelArg;
use anyhow::Result;

/// The model named on the command line with its `--NAME VALUE` and `-p NAME=VALUE` parameters.
pub fn model_arg(name: &str, model_params: &[(String, String)], param_opts: &[String]) -> Result<ModelArg> {
    let mut given = model_params.to_vec();
    given.extend(parse_param_options(param_opts)?);
    ModelArg::new(name, given)
}

/// The claims as words: `reciprocal, energy-conserving, isotropic`, or `none`.
pub fn claims_text(c: brdf::Claims) -> String {
    let words: Vec<&str> =
        [(c.reciprocal, "reciprocal"), (c.energy_conserving, "energy-conserving"), (c.isotropic, "isotropic")]
            .into_iter()
            .filter_map(|(on, w)| on.then_some(w))
            .collect();
    if words.is_empty() {
        "none".into()
    } else {
        words.join(", ")
    }
}

/// The claims as a JSON object.
pub fn claims_json(c: brdf::Claims) -> serde_json::Value {
    serde_json::json!({
        "reciprocal": c.reciprocal,
        "energy_conserving": c.energy_conserving,
        "isotropic": c.isotropic,
    })
}
