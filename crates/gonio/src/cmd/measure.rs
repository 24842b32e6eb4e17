//! `gonio measure`: a virtual gonio-reflectometer. Tabulates any model, analytic or measured,
//! into a MERL .binary file (the full 90 × 90 × 180 table) or the tabulated text format on a
//! θi × φi × θo × φo grid.

use super::model_arg;
use crate::cli::{MeasureArgs, UsageError};
use crate::modelarg::ModelArg;
use crate::output::write_atomic;
use anyhow::{bail, Result};
use brdf::measured::merl::{MerlTable, FILE_BYTES};
use brdf::measured::microsurface::{Beam, Facet, MeasureOptions, Microsurface};
use brdf::measured::tabulated::{uniform_phi, uniform_theta, Tabulated};
use brdf::Value;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Grid steps above this are a typo, not a measurement (10⁸ rows would be gigabytes of text).
const MAX_STEPS: usize = 3600;
/// Rows of a text table above this are refused for the same reason.
const MAX_ROWS: usize = 50_000_000;

/// What the output extension asks for.
enum Kind {
    Merl,
    Tabulated,
}

fn kind(path: &Path) -> Result<Kind> {
    match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
        Some("binary") => Ok(Kind::Merl),
        Some("csv" | "txt") => Ok(Kind::Tabulated),
        _ => bail!(
            "cannot tell the format of '{}': the output must end in .binary (MERL) or .csv/.txt (tabulated)",
            path.display()
        ),
    }
}

/// Runs `gonio measure`.
pub fn run(args: &MeasureArgs, model_params: &[(String, String)]) -> Result<()> {
    let kind = kind(&args.output)?;
    if args.microsurface {
        return run_microsurface(args, model_params, kind);
    }
    let name = args.model.as_deref().ok_or_else(|| UsageError("give a MODEL or --microsurface".into()))?;
    let m = model_arg(name, model_params, &args.param)?;
    // Files the model reads are inputs: the output must never replace one.
    let inputs = input_files(&m)?;
    let brdf = m.build()?;
    let start = Instant::now();
    match kind {
        Kind::Merl => {
            let table = MerlTable::from_brdf(brdf.as_ref());
            let unmeasured = table.entries().iter().filter(|e| e.iter().any(|&v| v < 0.0)).count();
            write_atomic(&args.output, &table.to_bytes(), &inputs)?;
            outln!(
                "wrote {} (MERL, 90 θh × 90 θd × 180 φd, {FILE_BYTES} bytes) from {} in {:.2} s; {unmeasured} entries \
                 with a direction below the horizon written as not measured",
                args.output.display(),
                m.label(),
                start.elapsed().as_secs_f64()
            );
        }
        Kind::Tabulated => {
            let rows = checked_rows(args)?;
            let t = Tabulated::from_brdf(
                brdf.as_ref(),
                uniform_theta(args.theta_i_steps),
                uniform_phi(args.phi_i_steps),
                uniform_theta(args.theta_o_steps),
                uniform_phi(args.phi_o_steps),
            );
            write_atomic(&args.output, t.to_text().as_bytes(), &inputs)?;
            outln!(
                "wrote {} (tabulated, {} θi × {} φi × {} θo × {} φo = {rows} rows) from {} in {:.2} s",
                args.output.display(),
                args.theta_i_steps,
                args.phi_i_steps,
                args.theta_o_steps,
                args.phi_o_steps,
                m.label(),
                start.elapsed().as_secs_f64()
            );
        }
    }
    Ok(())
}

/// The number of grid points the step options ask for, after checking each is sensible.
fn checked_rows(args: &MeasureArgs) -> Result<usize> {
    let steps = [
        ("theta-i-steps", args.theta_i_steps),
        ("phi-i-steps", args.phi_i_steps),
        ("theta-o-steps", args.theta_o_steps),
        ("phi-o-steps", args.phi_o_steps),
    ];
    for (name, n) in steps {
        if !(1..=MAX_STEPS).contains(&n) {
            return Err(UsageError(format!("--{name} {n}: expected 1 to {MAX_STEPS}")).into());
        }
    }
    let rows = steps.iter().map(|s| s.1).product::<usize>();
    if rows > MAX_ROWS {
        return Err(UsageError(format!("{rows} grid points is more than {MAX_ROWS}; use fewer steps")).into());
    }
    Ok(rows)
}

/// Rays above this per incident direction would run for hours.
const MAX_RAYS: usize = 1_000_000_000;

/// `gonio measure --microsurface`: ray-trace a Gaussian height field into a tabulated file.
fn run_microsurface(args: &MeasureArgs, model_params: &[(String, String)], kind: Kind) -> Result<()> {
    if matches!(kind, Kind::Merl) {
        return Err(UsageError(
            "--microsurface writes the tabulated format: give an output ending in .csv or .txt".into(),
        )
        .into());
    }
    if !(args.rms_slope.is_finite() && (0.001..=10.0).contains(&args.rms_slope)) {
        return Err(UsageError(format!("--rms-slope {}: expected 0.001 to 10", args.rms_slope)).into());
    }
    if !(1..=MAX_RAYS).contains(&args.rays) {
        return Err(UsageError(format!("--rays {}: expected 1 to {MAX_RAYS}", args.rays)).into());
    }
    if !(8..=4096).contains(&args.grid) {
        return Err(UsageError(format!("--grid {}: expected 8 to 4096", args.grid)).into());
    }
    let rows = checked_rows(args)?;
    let (facet, label, inputs) = match args.model.as_deref() {
        None => {
            if let Some((name, _)) = model_params.first() {
                return Err(UsageError(format!(
                    "--{name}: the default mirror facets take no parameters; name a MODEL"
                ))
                .into());
            }
            (Facet::Mirror, "mirror facets".to_string(), Vec::new())
        }
        Some(name) => {
            let m = model_arg(name, model_params, &args.param)?;
            let inputs = input_files(&m)?;
            (Facet::Model(m.build()?), format!("{} facets", m.label()), inputs)
        }
    };
    let start = Instant::now();
    // Correlation kernel of 4 cells: slopes vary smoothly over a few triangles, and a 256² grid
    // still holds ~1000 independent correlation areas.
    let mut surface = Microsurface::gaussian(args.rms_slope, args.grid, 4.0, args.seed, facet);
    surface.max_bounces = args.bounces;
    let beam = if args.beam == "cell" { Beam::Bin } else { Beam::Collimated };
    let opts = MeasureOptions { rays: args.rays, seed: args.seed, beam, threads: 0 };
    let m = surface.measure(
        uniform_theta(args.theta_i_steps),
        uniform_phi(args.phi_i_steps),
        uniform_theta(args.theta_o_steps),
        uniform_phi(args.phi_o_steps),
        &opts,
    );
    write_atomic(&args.output, m.table.to_text().as_bytes(), &inputs)?;
    let n = m.balance.len() as f64;
    let mean = |f: &dyn Fn(&brdf::measured::microsurface::FluxBalance) -> f64| m.balance.iter().map(f).sum::<f64>() / n;
    outln!(
        "wrote {} (tabulated, {rows} rows) from a {g}×{g} Gaussian height field of RMS slope {} with {label}, {} rays \
         per incident direction, in {:.2} s",
        args.output.display(),
        args.rms_slope,
        args.rays,
        start.elapsed().as_secs_f64(),
        g = args.grid
    );
    outln!(
        "flux, mean over incident directions: {:.4} escaped ({:.4} beyond the last θo cell), {:.2e} stopped at {} \
         bounces, {:.2e} lost; {:.3} facet hits per escaping ray",
        mean(&|b| b.escaped[1]),
        mean(&|b| b.unbinned[1]),
        mean(&|b| b.truncated[1]),
        args.bounces,
        mean(&|b| b.lost[1]),
        mean(&|b| b.mean_bounces)
    );
    Ok(())
}

/// The files a model reads (its non-empty path parameters): inputs the output must never replace.
fn input_files(m: &ModelArg) -> Result<Vec<PathBuf>> {
    Ok(m.resolved()?
        .iter()
        .filter_map(|(_, v)| match v {
            Value::Path(p) if !p.is_empty() => Some(PathBuf::from(p)),
            _ => None,
        })
        .collect())
}
