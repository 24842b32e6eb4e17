//! `gonio fit FILE --model M | --all`: fits analytic models (plus a Lambert term) to a MERL
//! `.binary` file or a tabulated text file with Levenberg–Marquardt, prints the parameters and
//! Ngan et al.'s cosine-weighted error (or, with `--all`, every model ranked), and with `-o`
//! plots data against fit in the plane of incidence for a few θi.

use crate::output::{write_atomic, Format};
use crate::plot::svg::{fmt_tick, nice_ticks, series_style, Anchor, Svg};
use crate::plot::{raster, Figure};
use anyhow::{anyhow, bail, Context, Result};
use brdf::fit::{self, report, Fit, FitModel, Sample};
use brdf::measured::{MerlTable, Tabulated};
use clap::Args;
use radiometry::{Rgb, Vec3};
use std::path::{Path, PathBuf};

/// `gonio fit`.
#[derive(Debug, Args)]
pub struct FitArgs {
    /// Measured data: a MERL .binary file, or a tabulated .csv/.txt file (`gonio measure` writes both).
    pub file: PathBuf,
    /// Model to fit: ward, cook-torrance, blinn-phong (the normalised modified-blinn-phong), ggx, beckmann.
    #[arg(long, required_unless_present = "all", conflicts_with = "all")]
    pub model: Option<String>,
    /// Fit every model and print them ranked by error.
    #[arg(long)]
    pub all: bool,
    /// Entries drawn from a MERL table (tabulated files use every point).
    #[arg(long, default_value_t = 4000, value_name = "N")]
    pub samples: usize,
    /// Seed of the MERL subsampling.
    #[arg(long, default_value_t = 0x5EED)]
    pub seed: u64,
    /// Plot data vs fit (the best fit with --all) in the plane of incidence: .svg or .png.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// The data read from the file.
enum Source {
    Merl(MerlTable),
    Tabulated(Tabulated),
}

impl Source {
    fn read(path: &Path) -> Result<Source> {
        let is_merl = path.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("binary"));
        Ok(if is_merl { Source::Merl(MerlTable::read(path)?) } else { Source::Tabulated(Tabulated::read(path)?) })
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        match self {
            Source::Merl(t) => t.lookup(wi, wo),
            Source::Tabulated(t) => t.lookup(wi, wo),
        }
    }

    fn samples(&self, n: usize, seed: u64) -> Vec<Sample> {
        match self {
            Source::Merl(t) => fit::merl_samples(t, n, seed),
            Source::Tabulated(t) => fit::tabulated_samples(t),
        }
    }
}

fn fit_json(f: &Fit) -> serde_json::Value {
    serde_json::json!({
        "model": f.model.name(),
        "shape_name": f.model.shape_name(),
        "shape": f.shape,
        "ks": f.ks,
        "diffuse": f.diffuse,
        "std_err": { "shape": f.std_err[0], "diffuse": &f.std_err[1..4], "ks": &f.std_err[4..7] },
        "error": f.error,
        "relative_error": f.relative_error,
        "iterations": f.iterations,
        "converged": f.converged,
        "options": report::options(f),
    })
}

/// Runs the command.
pub fn run(args: &FitArgs) -> Result<()> {
    let models: Vec<FitModel> = match (&args.model, args.all) {
        (_, true) => FitModel::ALL.to_vec(),
        (Some(name), false) => vec![FitModel::from_name(name)
            .ok_or_else(|| anyhow!("cannot fit model '{name}'; the fit models are: {}", FitModel::names()))?],
        (None, false) => bail!("give --model NAME or --all"),
    };
    if let Some(out) = &args.output {
        Format::from_path(out)?;
    }
    let source =
        Source::read(&args.file).with_context(|| format!("cannot read the data in '{}'", args.file.display()))?;
    let data = source.samples(args.samples.max(1), args.seed);
    if data.len() < 16 {
        bail!(
            "'{}' has only {} measured points within {}° to fit",
            args.file.display(),
            data.len(),
            fit::MAX_THETA_DEG
        );
    }
    let start = std::time::Instant::now();
    let mut fits: Vec<Fit> = models.iter().map(|&m| fit::fit(m, &data)).collect();
    fits.sort_by(|a, b| a.error.total_cmp(&b.error));
    let seconds = start.elapsed().as_secs_f64();
    if args.json {
        outln!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({
                "file": args.file.display().to_string(),
                "samples": data.len(),
                "seconds": seconds,
                "fits": fits.iter().map(fit_json).collect::<Vec<_>>(),
            }))?
        );
    } else {
        outln!("data         {} ({} samples, θ ≤ {}°)", args.file.display(), data.len(), fit::MAX_THETA_DEG);
        if fits.len() == 1 {
            outln!("{}", report::describe(&fits[0]).trim_end());
        } else {
            outln!("{}", report::table(&fits).trim_end());
            outln!("best: {}", report::options(&fits[0]));
        }
        outln!("time         {seconds:.3} s");
    }
    if let Some(out) = &args.output {
        let fig = plot(&source, &fits[0]);
        let bytes = match Format::from_path(out)? {
            Format::Svg => raster::to_svg(&fig)?.into_bytes(),
            Format::Png => raster::to_png(&fig, None)?,
        };
        write_atomic(out, &bytes, std::slice::from_ref(&args.file))?;
    }
    Ok(())
}

/// Incident angles of the plotted curves (degrees).
const PLOT_THETA_I: [f64; 4] = [0.0, 20.0, 40.0, 60.0];

/// Rec.709 luminance of ρ·cos θi.
fn lum(c: [f64; 3], cos_i: f64) -> f64 {
    (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]) * cos_i
}

/// Data (solid) against fit (dashed), luminance of ρ·cos θi against the signed θo in the plane
/// of incidence (θo > 0 on the mirror side), one colour per θi.
fn plot(source: &Source, f: &Fit) -> Figure {
    let (w, h) = (760.0, 480.0);
    let (x0, x1, y0, y1) = (70.0, w - 20.0, 40.0, h - 50.0);
    let thetas: Vec<f64> = (-80..=80).map(f64::from).collect();
    let mut curves = Vec::new();
    let mut vmax: f64 = 0.0;
    for &ti in &PLOT_THETA_I {
        let t = ti.to_radians();
        let wi = Vec3::new(-t.sin() as f32, 0.0, t.cos() as f32);
        let (mut data, mut model) = (Vec::new(), Vec::new());
        for &to in &thetas {
            let r = to.to_radians();
            let wo = Vec3::new(r.sin() as f32, 0.0, r.cos() as f32);
            let d = lum(source.eval(wi, wo).0.map(f64::from), t.cos());
            let m = lum(f.eval(wi, wo), t.cos());
            vmax = vmax.max(d).max(m);
            data.push((to, d));
            model.push((to, m));
        }
        curves.push((ti, data, model));
    }
    let vmax = if vmax > 0.0 && vmax.is_finite() { vmax } else { 1.0 };
    let px = |x: f64| x0 + (x + 90.0) / 180.0 * (x1 - x0);
    let py = |y: f64| y1 - (y / vmax).clamp(0.0, 1.05) / 1.05 * (y1 - y0);
    let mut svg = Svg::new(w, h);
    svg.rect(0.0, 0.0, w, h, r##"fill="#ffffff""##);
    svg.line((x0, y1), (x1, y1), "#000000", 1.0, None);
    svg.line((x0, y0), (x0, y1), "#000000", 1.0, None);
    for t in [-90.0, -60.0, -30.0, 0.0, 30.0, 60.0, 90.0] {
        svg.line((px(t), y1), (px(t), y1 + 5.0), "#000000", 1.0, None);
        svg.text(px(t), y1 + 18.0, &format!("{t}°"), 11.0, Anchor::Middle);
    }
    for v in nice_ticks(0.0, vmax * 1.05, 6) {
        svg.line((x0 - 5.0, py(v)), (x0, py(v)), "#000000", 1.0, None);
        svg.text(x0 - 8.0, py(v) + 4.0, &fmt_tick(v), 11.0, Anchor::End);
    }
    svg.text((x0 + x1) / 2.0, h - 12.0, "θo in the plane of incidence (mirror side > 0)", 12.0, Anchor::Middle);
    svg.text(
        (x0 + x1) / 2.0,
        22.0,
        &format!("data (solid) vs {} fit (dashed): ρ·cosθi, luminance, 1/sr", f.model.name()),
        13.0,
        Anchor::Middle,
    );
    let mut legend = Vec::new();
    for (i, (ti, data, model)) in curves.iter().enumerate() {
        let (colour, _) = series_style(i);
        let to_px = |pts: &[(f64, f64)]| pts.iter().map(|&(x, y)| (px(x), py(y))).collect::<Vec<_>>();
        svg.polyline(&to_px(data), colour, 2.0, None);
        svg.polyline(&to_px(model), colour, 2.0, Some("6 4"));
        legend.push((format!("θi = {ti}°"), colour, None));
    }
    svg.legend(x1 - 130.0, y0 + 4.0, &legend);
    Figure { svg: svg.finish(), image: None }
}
