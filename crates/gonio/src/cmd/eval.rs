//! `gonio eval`: one BRDF value and pdf.

use super::model_arg;
use crate::cli::{EvalArgs, UsageError};
use crate::modelarg::params_json;
use anyhow::Result;
use radiometry::Vec3;

/// Parses `x,y,z` into a unit vector; the zero vector and non-numbers are usage errors.
pub fn parse_direction(flag: &str, text: &str) -> Result<Vec3, UsageError> {
    let bad =
        |why: &str| UsageError(format!("--{flag} '{text}': {why}; write three numbers x,y,z, e.g. --{flag} 0,0,1"));
    let parts: Vec<f64> =
        text.split(',').map(|s| s.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| bad("not numbers"))?;
    let [x, y, z] = parts[..] else { return Err(bad("not three components")) };
    if ![x, y, z].iter().all(|v| v.is_finite()) {
        return Err(bad("not finite"));
    }
    let len = (x * x + y * y + z * z).sqrt();
    if !(len > 1e-12 && len.is_finite()) {
        return Err(bad("a direction cannot be the zero vector"));
    }
    Ok(Vec3::new((x / len) as f32, (y / len) as f32, (z / len) as f32))
}

fn deg(w: Vec3) -> f64 {
    f64::from(w.z.clamp(-1.0, 1.0)).acos().to_degrees()
}

/// Runs `gonio eval`.
pub fn run(args: &EvalArgs, model_params: &[(String, String)]) -> Result<()> {
    let m = model_arg(&args.model, model_params, &args.param)?;
    let wi = parse_direction("wi", &args.wi)?;
    let wo = parse_direction("wo", &args.wo)?;
    let brdf = m.build()?;
    let rho = brdf.eval(wi, wo);
    let pdf = brdf.pdf(wi, wo);
    if args.json {
        let out = serde_json::json!({
            "model": m.spec.name,
            "params": params_json(&m.resolved()?),
            "wi": wi.to_array(),
            "wo": wo.to_array(),
            "brdf": rho.0,
            "pdf": pdf,
            "has_delta": brdf.has_delta(),
        });
        outln!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    let params: Vec<String> = m.resolved()?.iter().map(|(k, v)| format!("{k}={v}")).collect();
    outln!("model  {}  ({})", m.spec.name, if params.is_empty() { "no parameters".into() } else { params.join(", ") });
    outln!("wi     ({:.6}, {:.6}, {:.6})  θi = {:.3}°", wi.x, wi.y, wi.z, deg(wi));
    outln!("wo     ({:.6}, {:.6}, {:.6})  θo = {:.3}°", wo.x, wo.y, wo.z, deg(wo));
    outln!("ρ      {:.6} {:.6} {:.6}  1/sr (r g b)", rho.0[0], rho.0[1], rho.0[2]);
    outln!("pdf    {pdf:.6}  1/sr (solid angle density of sampling wi given wo)");
    if wi.z <= 0.0 || wo.z <= 0.0 {
        outln!("note   a direction is at or below the surface (z ≤ 0): ρ and pdf are zero there");
    }
    if brdf.has_delta() {
        outln!("note   the model has a delta lobe, which ρ and pdf exclude");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directions_are_normalised_and_checked() {
        assert_eq!(parse_direction("wi", "0,0,2").unwrap(), Vec3::Z);
        let w = parse_direction("wi", " 3, 0 ,4").unwrap();
        assert!((w - Vec3::new(0.6, 0.0, 0.8)).length() < 1e-7);
        for bad in ["0,0,0", "1,2", "a,b,c", "1,2,3,4", "nan,0,1", "inf,0,1"] {
            assert!(parse_direction("wi", bad).is_err(), "{bad}");
        }
    }
}
