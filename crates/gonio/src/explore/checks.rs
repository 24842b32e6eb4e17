//! The check panel: `gonio check`'s verdicts for the current parameters, and what the χ² test
//! saw at the current incident direction (observed against expected counts, and a cloud of
//! drawn directions over the pdf).

use super::http::{ApiError, Query};
use super::model::Resolved;
use super::views::Setting;
use crate::cmd::check::finding_json;
use brdf::check::{self, chi2_test, Config};
use radiometry::Vec2;
use serde_json::{json, Value};

/// Histogram raster of the χ² view: cos θ rows × φ columns.
const RASTER: (usize, usize) = (16, 32);
/// Directions drawn for the page's χ² test (a tenth of `check`'s, to answer within a second).
const CHI2_DRAWS: usize = 20_000;
/// Directions shown in the sample cloud.
const CLOUD: usize = 600;

/// The check report and the χ² view of the first model.
pub fn checks(r: &Resolved, q: &Query) -> Result<Value, ApiError> {
    let s = Setting::from_query(q)?;
    let cfg = Config::default();
    let start = std::time::Instant::now();
    let report = check::check(&*r.brdf, &cfg);
    let w = s.wi();
    let chi = chi2_test(&*r.brdf, w, CHI2_DRAWS, cfg.seed, 0x9A6E);
    let (obs, exp) = chi.raster(RASTER.0, RASTER.1);
    // A low-discrepancy (R₃) sequence: the cloud is the same every time and evenly spread.
    let frac = |k: usize, a: f64| (0.5 + k as f64 * a).fract() as f32;
    let cloud: Vec<[f32; 3]> = (0..CLOUD)
        .filter_map(|k| {
            let u =
                [frac(k, 0.819_172_513_396_164_4), frac(k, 0.671_043_606_703_789_2), frac(k, 0.549_700_477_901_970_4)];
            r.brdf.sample(w, u[0], Vec2::new(u[1], u[2]))
        })
        .filter(|smp| !smp.delta && smp.wi.z > 0.0 && smp.wi.is_finite())
        .map(|smp| smp.wi.to_array())
        .collect();
    Ok(json!({
        "label": r.arg.label(),
        "claims": crate::cmd::claims_json(r.brdf.claims()),
        "ok": report.ok(),
        "findings": report.findings.iter().map(finding_json).collect::<Vec<_>>(),
        "chi2": {
            "w": w.to_array(),
            "samples": chi.samples,
            "p_value": chi.p_value,
            "statistic": chi.chi2,
            "dof": chi.dof,
            "delta_only": chi.delta_only,
            "note": chi.note,
            "rows": RASTER.0, "cols": RASTER.1,
            "observed": obs, "expected": exp,
        },
        "cloud": cloud,
        "seconds": start.elapsed().as_secs_f64(),
    }))
}
