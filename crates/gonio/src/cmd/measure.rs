//! `gonio measure`: a virtual gonio-reflectometer. Tabulates any model, analytic or measured,
//! into a MERL .binary file (the full 90 × 90 × 180 table) or the tabulated text format on a
//! θi × φi × θo × φo grid.

use super::model_arg;
use crate::cli::{MeasureArgs, UsageError};
use crate::output::write_atomic;
use anyhow::{bail, Result};
use brdf::measured::merl::{MerlTable, FILE_BYTES};
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
    let m = model_arg(&args.model, model_params, &args.param)?;
    // Files the model reads are inputs: the output must never replace one.
    let inputs: Vec<PathBuf> = m
        .resolved()?
        .iter()
        .filter_map(|(_, v)| match v {
            Value::Path(p) if !p.is_empty() => Some(PathBuf::from(p)),
            _ => None,
        })
        .collect();
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
