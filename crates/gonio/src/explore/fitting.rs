//! Measured against fitted: `gonio fit` behind a button, and the log-ratio residual over the
//! θh × θd slice.

use super::http::{ApiError, Query};
use super::model::Resolved;
use super::views::{Setting, SLICE_CELLS};
use crate::plot::slice;
use brdf::fit::{self, report, FitModel};
use serde_json::{json, Value};

/// Fits `model=` (a `gonio fit` model) to the measured model `r`.
pub fn fit(r: &Resolved, q: &Query) -> Result<Value, ApiError> {
    let Some(measured) = &r.measured else {
        return Err(ApiError::new(
            400,
            format!("'{}' is not measured data; fit a merl or tabulated model", r.arg.label()),
        )
        .named("m"));
    };
    let name = q.required("model", "the model to fit")?;
    let model = FitModel::from_name(name)
        .ok_or_else(|| ApiError::param("model", name, &format!("one of {}", FitModel::names())))?;
    let n = q.number("samples", 16.0, 1e6, 4000.0)? as usize;
    let start = std::time::Instant::now();
    let data = measured.samples(n, 0x5EED);
    if data.len() < 16 {
        return Err(ApiError::new(
            400,
            format!("only {} measured points within {}° to fit", data.len(), fit::MAX_THETA_DEG),
        ));
    }
    let f = fit::fit(model, &data);
    let options = report::options(&f);
    let note = (model == FitModel::CookTorrance)
        .then_some("cook-torrance has no parameter for the fitted constant Fresnel k_s: the model added has F = 1");
    Ok(json!({
        "item": item_of(&options),
        "note": note,
        "options": options,
        "error": f.error,
        "relative_error": f.relative_error,
        "converged": f.converged,
        "samples": data.len(),
        "seconds": start.elapsed().as_secs_f64(),
    }))
}

/// `ggx --alpha 0.1 --diffuse 0.1,0.2,0.3` as the item `ggx:alpha=0.1:diffuse=0.1,0.2,0.3`.
fn item_of(options: &str) -> String {
    let mut words = options.split_whitespace();
    let mut item = words.next().unwrap_or_default().to_string();
    while let (Some(k), Some(v)) = (words.next(), words.next()) {
        item.push_str(&format!(":{}={v}", k.trim_start_matches("--")));
    }
    item
}

/// log10(measured / fitted) over the slice at `phid`, null where either is not positive.
pub fn residual(measured: &Resolved, fitted: &Resolved, q: &Query) -> Result<Value, ApiError> {
    let s = Setting::from_query(q)?;
    let a = slice::grid_of(&*measured.brdf, s.phi_d, s.channel, SLICE_CELLS);
    let b = slice::grid_of(&*fitted.brdf, s.phi_d, s.channel, SLICE_CELLS);
    let ratio: Vec<Value> = a
        .iter()
        .zip(&b)
        .map(|(x, y)| match (x, y) {
            (Some(x), Some(y)) if *x > 0.0 && *y > 0.0 => json!((x / y).log10()),
            _ => Value::Null,
        })
        .collect();
    Ok(json!({ "cells": SLICE_CELLS, "log10_ratio": ratio }))
}

#[cfg(test)]
mod tests {
    #[test]
    fn fit_options_become_items() {
        assert_eq!(super::item_of("ggx --alpha 0.1 --diffuse 0.1,0.2,0.3"), "ggx:alpha=0.1:diffuse=0.1,0.2,0.3");
    }
}
