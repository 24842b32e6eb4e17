//! `gonio check`: every property measured for one model or for every model's cases, as a table.

use super::{claims_json, claims_text, model_arg};
use crate::cli::{CheckArgs, UsageError};
use crate::modelarg::{params_json, ModelArg};
use anyhow::{anyhow, bail, Result};
use brdf::check::{Config, Finding, Report};
use brdf::Claims;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// The measured outcome of one case.
pub struct Outcome {
    /// The model and parameters checked.
    pub case: ModelArg,
    /// What the model claims with those parameters.
    pub claims: Claims,
    /// The measurements.
    pub report: Report,
    /// Wall time of the check, seconds.
    pub seconds: f64,
}

/// Every model at its defaults and at each of its showcase parameter sets.
pub fn all_cases() -> Result<Vec<ModelArg>> {
    let mut cases = Vec::new();
    // A model read from a file has no default to check (`gonio check merl --filename F` does).
    for m in brdf::models().iter().filter(|m| !m.requires_file()) {
        cases.push(ModelArg::new(m.name, Vec::new())?);
        for set in m.showcase {
            let given = set.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect();
            cases.push(ModelArg::new(m.name, given)?);
        }
    }
    Ok(cases)
}

/// Checks `cases` on `jobs` threads; the χ² tests are Šidák-corrected over all of them.
pub fn run_cases(cases: Vec<ModelArg>, seed: u64, alpha: f64, jobs: Option<usize>) -> Result<Vec<Outcome>> {
    let cfg = Config { seed, alpha, chi2_tests: cases.len().max(1) };
    let threads = jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, cases.len().max(1));
    let next = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Result<Outcome>>>> = Mutex::new((0..cases.len()).map(|_| None).collect());
    let progress = std::io::stderr().is_terminal() && cases.len() > 1;
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                let Some(case) = cases.get(k) else { break };
                let r = check_one(case, &cfg);
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if progress {
                    eprint!("\rchecked {n}/{} cases ", cases.len());
                }
                results.lock().unwrap_or_else(|e| e.into_inner())[k] = Some(r);
            });
        }
    });
    if progress {
        eprintln!();
    }
    results.into_inner().unwrap_or_else(|e| e.into_inner()).into_iter().map(|r| r.expect("every case ran")).collect()
}

fn check_one(case: &ModelArg, cfg: &Config) -> Result<Outcome> {
    let brdf = case.build()?;
    let start = Instant::now();
    let report = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| brdf::check::check(brdf.as_ref(), cfg)))
        .map_err(|p| {
            let msg = p.downcast_ref::<&str>().map(|s| s.to_string()).or_else(|| p.downcast_ref::<String>().cloned());
            anyhow!("the property checks crashed on {}: {}", case.label(), msg.unwrap_or_else(|| "panic".into()))
        })?;
    Ok(Outcome { case: case.clone(), claims: brdf.claims(), report, seconds: start.elapsed().as_secs_f64() })
}

/// The result column: what was measured against what was claimed.
pub fn verdict(f: &Finding) -> &'static str {
    match (f.claimed, f.passed) {
        (true, true) => "pass",
        (true, false) => "FAIL",
        (false, false) => "fails, not claimed",
        (false, true) => "holds, not claimed",
    }
}

/// Width the measured column wraps at.
const MEASURED_WIDTH: usize = 72;

/// The measured figure as lines: one per `; `-separated clause, wrapped at word boundaries.
fn measured(f: &Finding) -> Vec<String> {
    if f.detail.is_empty() {
        return vec![format!("{:.4e}", f.value)];
    }
    let mut lines = Vec::new();
    for clause in f.detail.split("; ") {
        let mut line = String::new();
        for word in clause.split(' ') {
            if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > MEASURED_WIDTH {
                lines.push(std::mem::take(&mut line));
                line.push_str("  ");
            } else if !line.is_empty() && line != "  " {
                line.push(' ');
            }
            line.push_str(word);
        }
        lines.push(line);
    }
    lines
}

/// Prints the outcomes as tables and a summary line.
pub fn print_report(outcomes: &[Outcome], wall_seconds: f64) {
    let prop_w = outcomes
        .iter()
        .flat_map(|o| &o.report.findings)
        .map(|f| f.property.name().chars().count())
        .max()
        .unwrap_or(8)
        .max(8);
    for (i, o) in outcomes.iter().enumerate() {
        if i > 0 {
            outln!();
        }
        outln!("{} ({}), claims: {}", o.case.spec.name, o.case.given_text(), claims_text(o.claims));
        outln!("  {:<prop_w$}  {:<7}  {:<18}  measured", "property", "claimed", "result");
        for f in &o.report.findings {
            let lines = measured(f);
            let claimed = if f.claimed { "yes" } else { "no" };
            outln!("  {:<prop_w$}  {claimed:<7}  {:<18}  {}", f.property.name(), verdict(f), lines[0]);
            for l in &lines[1..] {
                outln!("  {:<prop_w$}  {:<7}  {:<18}  {l}", "", "", "");
            }
        }
    }
    let list = |claimed: bool| -> Vec<String> {
        outcomes
            .iter()
            .filter_map(|o| {
                let props: Vec<&str> = o
                    .report
                    .findings
                    .iter()
                    .filter(|f| f.claimed == claimed && !f.passed)
                    .map(|f| f.property.name())
                    .collect();
                (!props.is_empty()).then(|| format!("{}: {}", o.case.label(), props.join(", ")))
            })
            .collect()
    };
    let (failures, unclaimed) = (list(true), list(false));
    let n = outcomes.len();
    outln!();
    outln!("{n} case{} checked in {wall_seconds:.1} s", if n == 1 { "" } else { "s" });
    if !unclaimed.is_empty() {
        outln!("measured failing, not claimed by the model (as expected):");
        unclaimed.iter().for_each(|l| outln!("  {l}"));
    }
    if failures.is_empty() {
        outln!("every claimed property holds");
    } else {
        outln!("CLAIMED PROPERTIES FAILED:");
        failures.iter().for_each(|l| outln!("  {l}"));
    }
}

/// One finding as JSON.
pub fn finding_json(f: &brdf::check::Finding) -> serde_json::Value {
    serde_json::json!({
        "property": f.property.name(),
        "claimed": f.claimed,
        "passed": f.passed,
        "value": if f.value.is_finite() { serde_json::json!(f.value) } else { serde_json::Value::Null },
        "detail": f.detail,
    })
}

/// The outcomes as JSON.
pub fn report_json(outcomes: &[Outcome], seed: u64, alpha: f64) -> Result<serde_json::Value> {
    let cases = outcomes
        .iter()
        .map(|o| {
            Ok(serde_json::json!({
                "model": o.case.spec.name,
                "given": serde_json::Value::Object(o.case.given.iter().map(|(k, v)| (k.clone(), serde_json::json!(v))).collect()),
                "params": params_json(&o.case.resolved()?),
                "claims": claims_json(o.claims),
                "ok": o.report.ok(),
                "seconds": o.seconds,
                "findings": o.report.findings.iter().map(finding_json).collect::<Vec<_>>(),
            }))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(serde_json::json!({
        "seed": seed,
        "significance": alpha,
        "ok": outcomes.iter().all(|o| o.report.ok()),
        "cases": cases,
    }))
}

/// Runs `gonio check`; `Ok(false)` when a claimed property failed.
pub fn run(args: &CheckArgs, model_params: &[(String, String)]) -> Result<bool> {
    if !(args.significance > 0.0 && args.significance < 1.0) {
        bail!(UsageError(format!("--significance {} must lie strictly between 0 and 1", args.significance)));
    }
    let cases = if args.all {
        if !model_params.is_empty() || !args.param.is_empty() {
            bail!(UsageError(
                "--all checks every model at its own parameter sets; give no model parameters with it".into()
            ));
        }
        all_cases()?
    } else {
        let name = args.model.as_deref().ok_or_else(|| UsageError("give a MODEL or --all".into()))?;
        vec![model_arg(name, model_params, &args.param)?]
    };
    let start = Instant::now();
    let outcomes = run_cases(cases, args.seed, args.significance, args.jobs)?;
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&report_json(&outcomes, args.seed, args.significance)?)?);
    } else {
        print_report(&outcomes, start.elapsed().as_secs_f64());
    }
    Ok(outcomes.iter().all(|o| o.report.ok()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use brdf::check::Property;

    fn finding(claimed: bool, passed: bool, detail: &str) -> Finding {
        Finding { property: Property::Energy, claimed, passed, value: 1.5, detail: detail.into() }
    }

    #[test]
    fn verdicts_separate_claimed_from_measured() {
        assert_eq!(verdict(&finding(true, true, "")), "pass");
        assert_eq!(verdict(&finding(true, false, "")), "FAIL");
        assert_eq!(verdict(&finding(false, false, "")), "fails, not claimed");
        assert_eq!(verdict(&finding(false, true, "")), "holds, not claimed");
        let r = Report { findings: vec![finding(false, false, ""), finding(true, false, "")] };
        assert!(!r.ok() && r.claimed_failures().len() == 1);
    }

    #[test]
    fn measured_figures_wrap_by_clause_and_word() {
        assert_eq!(measured(&finding(true, true, "")), vec!["1.5000e0"]);
        let long = format!("max albedo 1.73 at θo = 85°; {}", "word ".repeat(30).trim_end());
        let lines = measured(&finding(true, true, &long));
        assert_eq!(lines[0], "max albedo 1.73 at θo = 85°");
        assert!(lines.len() == 4 && lines.iter().all(|l| l.chars().count() <= MEASURED_WIDTH + 2), "{lines:?}");
        assert_eq!(lines[1..].join(" ").split_whitespace().count(), 30, "no word lost");
    }
}
