//! The numbers behind the page's 2D plots and 3D lobe, computed by the same functions as
//! `gonio plot` (so a figure on the page can be made again from the command line).

use super::http::{ApiError, Query};
use super::model::Resolved;
use crate::cli::{Channel, Quantity};
use crate::plot::{albedo, fresnel, polar, slice};
use clap::ValueEnum;
use radiometry::Vec3;
use serde_json::{json, Value};

/// Viewing-angle step of the in-plane lobe, degrees.
const POLAR_STEP: f64 = 0.5;
/// Cells per side of the θh × θd slice on the page.
pub const SLICE_CELLS: usize = 64;
/// The 3D lobe's grid: polar rows over [0°, 90°] and azimuth columns over [0°, 360°].
const LOBE_GRID: (usize, usize) = (24, 48);
/// Angles of the page's albedo curves, degrees: every 5° and near grazing (half the plot's, so a
/// slider move stays interactive).
const ALBEDO_THETAS: [f64; 20] = [
    0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0, 89.0,
    89.9,
];
/// Incidence step of the Fresnel curves, degrees.
const FRESNEL_STEP: f64 = 1.0;

/// The view parts a request may ask for.
pub const PARTS: [&str; 5] = ["polar", "lobe", "slice", "fresnel", "albedo"];

/// The incident direction and the view settings of a request.
#[derive(Clone, Copy, Debug)]
pub struct Setting {
    /// θi, degrees.
    pub theta_i: f64,
    /// φi, degrees.
    pub phi_i: f64,
    /// φd of the slice, degrees.
    pub phi_d: f64,
    /// How RGB becomes one number.
    pub channel: Channel,
    /// Monte Carlo samples per albedo point.
    pub samples: usize,
}

/// Parses a clap value enum from the query, listing its values in the error.
pub fn value_enum<T: ValueEnum>(q: &Query, key: &str, default: T) -> Result<T, ApiError> {
    let Some(text) = q.get(key) else { return Ok(default) };
    T::from_str(text, true).map_err(|_| {
        let names: Vec<String> = T::value_variants()
            .iter()
            .filter_map(|v| v.to_possible_value())
            .map(|p| p.get_name().to_string())
            .collect();
        ApiError::param(key, text, &format!("one of {}", names.join("|")))
    })
}

impl Setting {
    /// Reads `ti`, `pi`, `phid`, `channel` and `samples`.
    pub fn from_query(q: &Query) -> Result<Setting, ApiError> {
        Ok(Setting {
            theta_i: q.number("ti", 0.0, 89.9, 45.0)?,
            phi_i: q.number("pi", -360.0, 360.0, 0.0)?,
            phi_d: q.number("phid", 0.0, 180.0, 90.0)?,
            channel: value_enum(q, "channel", Channel::Luminance)?,
            samples: q.number("samples", 16.0, 65536.0, 512.0)? as usize,
        })
    }

    /// The direction towards the light.
    pub fn wi(&self) -> Vec3 {
        polar::incident_at(self.theta_i, self.phi_i)
    }
}

/// A plotted value as JSON, to 5 significant digits (a fifth of the text of full precision;
/// exact values come from `/api/eval`), null when not finite.
fn finite(v: f64) -> Value {
    if v.is_finite() {
        if v == 0.0 {
            return json!(0);
        }
        let scale = 10f64.powi(4 - v.abs().log10().floor() as i32);
        json!((v * scale).round() / scale)
    } else {
        Value::Null
    }
}

/// ρ (one number) for θo from −90° to 90° in the plane of incidence; the page multiplies by cos θo.
fn polar_part(r: &Resolved, s: &Setting) -> Value {
    let wi = s.wi();
    let n = (180.0 / POLAR_STEP).round() as usize;
    let rho: Vec<Value> = (0..=n)
        .map(|k| {
            let wo = polar::rotate_z(polar::outgoing(-90.0 + k as f64 * POLAR_STEP), s.phi_i);
            finite(polar::lobe_value(&*r.brdf, wi, wo, Quantity::Brdf, s.channel))
        })
        .collect();
    json!({ "theta0": -90.0, "step": POLAR_STEP, "rho": rho, "delta": r.brdf.has_delta() })
}

/// ρ on a (θo, φo) grid, rows from the pole, φo measured from the x axis.
fn lobe_part(r: &Resolved, s: &Setting) -> Value {
    let wi = s.wi();
    let (rows, cols) = LOBE_GRID;
    let mut rho = Vec::with_capacity((rows + 1) * cols);
    for i in 0..=rows {
        let t = (i as f64 * 90.0 / rows as f64).min(89.5).to_radians();
        for j in 0..cols {
            let p = (j as f64 * 360.0 / cols as f64).to_radians();
            let wo = Vec3::new((t.sin() * p.cos()) as f32, (t.sin() * p.sin()) as f32, t.cos() as f32);
            rho.push(finite(polar::lobe_value(&*r.brdf, wi, wo, Quantity::Brdf, s.channel)));
        }
    }
    json!({ "rows": rows, "cols": cols, "rho": rho })
}

fn slice_part(r: &Resolved, s: &Setting) -> Value {
    let g = slice::grid_of(&*r.brdf, s.phi_d, s.channel, SLICE_CELLS);
    json!({ "cells": SLICE_CELLS, "rho": g.into_iter().map(|v| v.map_or(Value::Null, finite)).collect::<Vec<_>>() })
}

fn fresnel_part(r: &Resolved, s: &Setting) -> Value {
    let Some(f) = r.brdf.fresnel() else { return Value::Null };
    let n = (90.0 / FRESNEL_STEP).round() as usize;
    let curves: Vec<Value> = fresnel::curves_of(&f)
        .iter()
        .map(|&c| {
            let v: Vec<Value> = (0..=n)
                .map(|k| finite(fresnel::value(&f, c, (k as f64 * FRESNEL_STEP).to_radians().cos() as f32, s.channel)))
                .collect();
            json!({ "name": c.label(), "values": v })
        })
        .collect();
    json!({ "step": FRESNEL_STEP, "curves": curves, "interface": format!("{f:?}") })
}

fn albedo_part(r: &Resolved, s: &Setting) -> Value {
    let curve = |over| {
        let pts = albedo::curve_at(&*r.brdf, &ALBEDO_THETAS, s.samples, 0x5EED, s.channel, over);
        json!({
            "theta": pts.iter().map(|p| p.theta).collect::<Vec<_>>(),
            "mean": pts.iter().map(|p| finite(p.mean)).collect::<Vec<_>>(),
            "se": pts.iter().map(|p| finite(p.se)).collect::<Vec<_>>(),
        })
    };
    json!({ "over_wi": curve(albedo::Over::Wi), "over_wo": curve(albedo::Over::Wo), "samples": s.samples })
}

/// The parts named in `parts=` (all when absent) for every model; the slice only for model
/// number `active` (the one the page shows it for).
pub fn views(models: &[Resolved], q: &Query) -> Result<Value, ApiError> {
    let s = Setting::from_query(q)?;
    let active = q.number("active", 0.0, (models.len().max(1) - 1) as f64, 0.0)? as usize;
    let parts: Vec<&str> = match q.get("parts") {
        None => PARTS.to_vec(),
        Some(list) => list
            .split(',')
            .map(|p| {
                PARTS
                    .iter()
                    .find(|k| **k == p)
                    .copied()
                    .ok_or_else(|| ApiError::param("parts", p, &format!("a list of {}", PARTS.join(","))))
            })
            .collect::<Result<_, _>>()?,
    };
    let out: Vec<Value> = models
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let mut o = json!({ "label": r.arg.label(), "has_delta": r.brdf.has_delta() });
            for &p in &parts {
                if p == "slice" && i != active {
                    continue;
                }
                o[p] = match p {
                    "polar" => polar_part(r, &s),
                    "lobe" => lobe_part(r, &s),
                    "slice" => slice_part(r, &s),
                    "fresnel" => fresnel_part(r, &s),
                    _ => albedo_part(r, &s),
                };
            }
            o
        })
        .collect();
    Ok(json!({ "wi": s.wi().to_array(), "models": out }))
}
