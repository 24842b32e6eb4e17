//! `gonio demo`: the lecture's models side by side (lobes and albedo) and the full check report.

use super::check;
use super::plot::{series, write_figure};
use crate::cli::{Channel, DemoArgs, Quantity};
use crate::modelarg::ModelArg;
use crate::plot::{albedo, polar};
use anyhow::{Context, Result};

/// The lecture's models, in the order it introduces them.
pub const LECTURE_MODELS: [&str; 7] =
    ["lambert", "phong", "modified-phong", "blinn-phong", "modified-blinn-phong", "ward", "cook-torrance"];

/// Runs `gonio demo`; `Ok(false)` when a claimed property failed.
pub fn run(args: &DemoArgs) -> Result<bool> {
    let models: Vec<ModelArg> = LECTURE_MODELS.iter().map(|n| ModelArg::new(n, Vec::new())).collect::<Result<_>>()?;
    std::fs::create_dir_all(&args.out_dir).with_context(|| format!("cannot create '{}'", args.out_dir.display()))?;
    let s = series(&models)?;
    let out =
        |name: &str| if args.out_dir == std::path::Path::new(".") { name.into() } else { args.out_dir.join(name) };
    let lobes = out("gonio-lobes.svg");
    write_figure(&polar::figure(&s, (45.0, 0.0), Quantity::Intensity, Channel::Luminance, false), &lobes, None)?;
    outln!("wrote {} (in-plane lobes at θi = 45°)", lobes.display());
    let alb = out("gonio-albedo.svg");
    write_figure(&albedo::figure(&s, 1 << 14, 0x5EED, Channel::Luminance, albedo::Over::Wi), &alb, None)?;
    outln!("wrote {} (directional albedo against θo)", alb.display());
    outln!();
    let start = std::time::Instant::now();
    let outcomes = check::run_cases(check::all_cases()?, 0x5EED, 0.01, args.jobs)?;
    check::print_report(&outcomes, start.elapsed().as_secs_f64());
    Ok(outcomes.iter().all(|o| o.report.ok()))
}
