//! `gonio plot`: polar or 3D lobe, albedo curve, θh × θd slice or Fresnel curves, to SVG or PNG.

use super::model_arg;
use crate::cli::{PlotArgs, PlotKind, UsageError};
use crate::modelarg::{split_overlay, ModelArg};
use crate::output::{write_atomic, Format};
use crate::plot::{albedo, fresnel, lobe3d, polar, raster, slice, Figure, Series};
use anyhow::{bail, Context, Result};
use std::path::Path;

/// Builds each model for plotting, labelled for the legend.
pub fn series(models: &[ModelArg]) -> Result<Vec<Series>> {
    models.iter().map(|m| Ok(Series { label: m.label(), brdf: m.build()? })).collect()
}

/// Writes a figure to `path` in the format its extension names.
pub fn write_figure(fig: &Figure, path: &Path, width: Option<u32>) -> Result<()> {
    let bytes = match Format::from_path(path)? {
        Format::Svg => raster::to_svg(fig)?.into_bytes(),
        Format::Png => raster::to_png(fig, width)?,
    };
    // No command reads a file yet; measured data will be listed here as inputs.
    write_atomic(path, &bytes, &[])
}

/// Pairs each model with its Fresnel term; a model without one is a usage error.
fn with_fresnel(series: Vec<Series>) -> Result<Vec<(Series, brdf::fresnel::Fresnel)>> {
    series
        .into_iter()
        .map(|s| match s.brdf.fresnel() {
            Some(f) => Ok((s, f)),
            None => Err(usage(format!(
                "{} has no Fresnel term to plot; --kind fresnel takes models with a specular interface \
                 (mirror, microfacet, ggx, beckmann, cook-torrance, plastic, roughplastic, dielectric, …)",
                s.label
            ))),
        })
        .collect()
}

fn usage(msg: String) -> anyhow::Error {
    UsageError(msg).into()
}

/// Runs `gonio plot`.
pub fn run(args: &PlotArgs, model_params: &[(String, String)]) -> Result<()> {
    let mut models = vec![model_arg(&args.model, model_params, &args.param)?];
    for list in &args.overlay {
        for item in split_overlay(list) {
            models.push(ModelArg::parse_item(&item).with_context(|| format!("--overlay item '{item}'"))?);
        }
    }
    // Check everything the user typed before any work starts.
    Format::from_path(&args.output).map_err(|e| usage(e.to_string()))?;
    if !(0.0..=90.0).contains(&args.theta_i) {
        return Err(usage(format!("--theta-i {} is out of range; expected [0, 90] degrees", args.theta_i)));
    }
    if !(-360.0..=360.0).contains(&args.phi_i) {
        return Err(usage(format!("--phi-i {} is out of range; expected [-360, 360] degrees", args.phi_i)));
    }
    if !args.phi_d.is_finite() {
        return Err(usage("--phi-d must be a finite angle in degrees".into()));
    }
    if let Some(d) = args.decades.filter(|d| !(*d > 0.0 && *d <= 12.0)) {
        return Err(usage(format!("--decades {d} is out of range; expected (0, 12]")));
    }
    if args.normalize && !matches!(args.kind, PlotKind::Polar | PlotKind::Lobe3d) {
        return Err(usage("--normalize applies to --kind polar and --kind lobe3d".into()));
    }
    if !(2..=100_000_000).contains(&args.samples) {
        return Err(usage(format!("--samples {} is out of range; expected 2 to 100000000", args.samples)));
    }
    if args.kind == PlotKind::Slice && models.len() > 1 {
        bail!(UsageError("a slice shows one model; --overlay works with --kind polar and --kind albedo".into()));
    }
    let series = series(&models)?;
    let fig = match args.kind {
        PlotKind::Polar => {
            polar::figure(&series, (args.theta_i, args.phi_i), args.quantity, args.channel, args.normalize)
        }
        PlotKind::Albedo => albedo::figure(&series, args.samples, args.seed, args.channel, args.over),
        PlotKind::Slice => slice::figure(&series, args.phi_d, args.decades, args.channel),
        PlotKind::Fresnel => fresnel::figure(&with_fresnel(series)?, args.channel),
        PlotKind::Lobe3d => {
            lobe3d::figure(&series, (args.theta_i, args.phi_i), args.quantity, args.channel, args.normalize)
        }
    };
    write_figure(&fig, &args.output, args.width)?;
    eprintln!("wrote {}", args.output.display());
    Ok(())
}
