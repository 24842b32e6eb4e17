//! Command-line definitions. Each model's own parameters (`--ks 0.5`, `--ks=0.5`) are not known
//! to clap statically: a pre-pass takes every `--NAME` that is not one of the command's own
//! options out of the argument list, and the model's `ParamSpec`s judge them afterwards.

use clap::{Args, CommandFactory, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;

const AFTER_HELP: &str = "\
Model parameters: write them after the model as --NAME VALUE or --NAME=VALUE (RGB values as
one number or r,g,b), or as -p NAME=VALUE; `gonio models` lists every model's parameters,
ranges and defaults.

Exit status: 0 success; 1 a property a model claims failed (check, demo); 2 an error (bad
usage, unknown model or parameter, value out of range, unreadable or unwritable file).";

/// Reflection models and radiometry: evaluate, check and plot BRDFs.
#[derive(Debug, Parser)]
#[command(name = "gonio", version, about, after_help = AFTER_HELP)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// List every model with its parameters, ranges, defaults and claimed properties.
    Models(ModelsArgs),
    /// Evaluate a model's BRDF value (1/sr) and sampling pdf for one pair of directions.
    #[command(after_help = AFTER_HELP)]
    Eval(EvalArgs),
    /// Measure reciprocity, energy conservation, isotropy and sampling of a model (or --all).
    #[command(after_help = AFTER_HELP)]
    Check(CheckArgs),
    /// Plot a model: in-plane polar lobe, directional albedo, or θh × θd slice image.
    #[command(after_help = PLOT_AFTER_HELP)]
    Plot(PlotArgs),
    /// Write gonio-lobes.svg and gonio-albedo.svg and print the `check --all` report.
    Demo(DemoArgs),
    /// Virtual gonio-reflectometer: tabulate a model into a MERL .binary or a tabulated .csv file.
    #[command(after_help = MEASURE_AFTER_HELP)]
    Measure(MeasureArgs),
    /// Convert a light probe (mirror ball, equirect, cube map) and print its upward irradiance.
    Envmap(crate::cmd::envmap::EnvmapArgs),
    /// Render a scene (without one, the built-in demo) to PNG or EXR.
    Render(crate::cmd::render::RenderArgs),
    /// Render the same object in several models side by side, labelled, in one image.
    Compare(crate::cmd::compare::CompareArgs),
    /// Fit analytic models (plus a Lambert term) to a MERL or tabulated file by Levenberg–Marquardt.
    Fit(crate::cmd::fit::FitArgs),
    /// Serve a local web page to turn a model's knobs and watch its lobe, checks and a lit object.
    Explore(crate::explore::ExploreArgs),
}

const PLOT_AFTER_HELP: &str = "\
Model parameters: --NAME VALUE, --NAME=VALUE or -p NAME=VALUE (see `gonio models`).

Overlays: --overlay takes a comma-separated list of models, each optionally followed by its
parameters as :NAME=VALUE, e.g. --overlay ward:alpha=0.1:ks=0.3,lambert:albedo=0.5
(RGB values keep their commas: ward:ks=0.1,0.2,0.3). The option may be repeated.

The output format follows the extension: .svg (written directly) or .png (rasterised).

Exit status: 0 success; 2 an error.";

/// `gonio models`.
#[derive(Debug, Args)]
pub struct ModelsArgs {
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// `gonio eval`.
#[derive(Debug, Args)]
pub struct EvalArgs {
    /// Model name (see `gonio models`).
    pub model: String,
    /// Direction towards the light, local frame (z = normal); normalised for you.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub wi: String,
    /// Direction towards the viewer, local frame (z = normal); normalised for you.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub wo: String,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// A model parameter, NAME=VALUE (the same as --NAME VALUE).
    #[arg(short = 'p', long = "param", value_name = "NAME=VALUE")]
    pub param: Vec<String>,
}

/// `gonio check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Model name (see `gonio models`); omit with --all.
    #[arg(required_unless_present = "all", conflicts_with = "all")]
    pub model: Option<String>,
    /// Check every model at its defaults and at each of its showcase parameter sets.
    #[arg(long)]
    pub all: bool,
    /// Print JSON instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Seed of every random stream (the same seed gives the same report).
    #[arg(long, default_value_t = 0x5EED)]
    pub seed: u64,
    /// Family-wise significance level of the χ² tests (Šidák-corrected over all cases).
    #[arg(long, default_value_t = 0.01, value_name = "ALPHA")]
    pub significance: f64,
    /// Worker threads (default: the machine's cores).
    #[arg(long, short = 'j')]
    pub jobs: Option<usize>,
    /// A model parameter, NAME=VALUE (the same as --NAME VALUE).
    #[arg(short = 'p', long = "param", value_name = "NAME=VALUE")]
    pub param: Vec<String>,
}

/// What a plot shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PlotKind {
    /// In-plane polar lobe for a fixed incident direction.
    Polar,
    /// Directional albedo against the viewing angle θo.
    Albedo,
    /// θh × θd image (Disney BRDF Explorer's image slice).
    Slice,
    /// Fresnel reflectance (Rs, Rp, unpolarised, Schlick) of the model's interface against θi.
    Fresnel,
    /// The lobe over the whole hemisphere of viewing directions, in 3D, for a fixed incident direction.
    Lobe3d,
}

/// The radial quantity of a polar plot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Quantity {
    /// ρ·cosθo: reflected intensity per unit area per unit incident irradiance (1/sr).
    Intensity,
    /// ρ itself: reflected radiance per unit incident irradiance (1/sr).
    #[value(alias = "radiance")]
    Brdf,
}

/// How an RGB value becomes the one number a plot draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Channel {
    /// Rec.709 luminance 0.2126 R + 0.7152 G + 0.0722 B.
    Luminance,
    /// The largest channel (the one energy conservation bounds first).
    Max,
    /// Red.
    R,
    /// Green.
    G,
    /// Blue.
    B,
}

impl Channel {
    /// The scalar for an RGB triple.
    pub fn of(self, c: radiometry::Rgb) -> f64 {
        f64::from(match self {
            Channel::Luminance => c.luminance(),
            Channel::Max => c.max_channel(),
            Channel::R => c.0[0],
            Channel::G => c.0[1],
            Channel::B => c.0[2],
        })
    }

    /// Its name in axis labels.
    pub fn label(self) -> &'static str {
        match self {
            Channel::Luminance => "luminance",
            Channel::Max => "max channel",
            Channel::R => "red",
            Channel::G => "green",
            Channel::B => "blue",
        }
    }
}

/// `gonio plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// Model name (see `gonio models`).
    pub model: String,
    /// Which plot.
    #[arg(long, value_enum, default_value_t = PlotKind::Polar)]
    pub kind: PlotKind,
    /// Incident polar angle θi in degrees (polar plot).
    #[arg(long, default_value_t = 45.0, value_name = "DEG", allow_hyphen_values = true)]
    pub theta_i: f64,
    /// Azimuth φi of the plane of incidence in degrees, turned about the normal from the xz-plane
    /// (polar and lobe3d plots; matters for anisotropic models).
    #[arg(long, default_value_t = 0.0, value_name = "DEG", allow_hyphen_values = true)]
    pub phi_i: f64,
    /// Difference azimuth φd in degrees (slice plot).
    #[arg(long, default_value_t = 90.0, value_name = "DEG", allow_hyphen_values = true)]
    pub phi_d: f64,
    /// Radial quantity of the polar plot.
    #[arg(long, value_enum, default_value_t = Quantity::Intensity)]
    pub quantity: Quantity,
    /// How RGB becomes the plotted number.
    #[arg(long, value_enum, default_value_t = Channel::Luminance)]
    pub channel: Channel,
    /// Output file, .svg or .png.
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: PathBuf,
    /// More models on the same axes: MODEL[:NAME=VALUE]...,... (see below).
    #[arg(long, value_name = "LIST")]
    pub overlay: Vec<String>,
    /// Monte Carlo samples per albedo point.
    #[arg(long, default_value_t = 1 << 15)]
    pub samples: usize,
    /// Decades of dynamic range of the slice image's log colour scale (default: down to the
    /// 5th percentile of the values, 1 to 8 decades).
    #[arg(long)]
    pub decades: Option<f64>,
    /// What the albedo integrates over: wi (a(wo), against θo; what `check` bounds) or wo
    /// (the reflected fraction of light from wi, against θi).
    #[arg(long, value_enum, default_value_t = crate::plot::albedo::Over::Wi)]
    pub over: crate::plot::albedo::Over,
    /// Scale each polar lobe to its own peak, to compare shapes rather than magnitudes.
    #[arg(long)]
    pub normalize: bool,
    /// PNG width in pixels (default: the plot's own size).
    #[arg(long)]
    pub width: Option<u32>,
    /// Seed of the albedo estimates.
    #[arg(long, default_value_t = 0x5EED)]
    pub seed: u64,
    /// A model parameter, NAME=VALUE (the same as --NAME VALUE).
    #[arg(short = 'p', long = "param", value_name = "NAME=VALUE")]
    pub param: Vec<String>,
}

const MEASURE_AFTER_HELP: &str = "\
Model parameters: --NAME VALUE, --NAME=VALUE or -p NAME=VALUE (see `gonio models`).

The output format follows the extension: .binary writes the full MERL table (90 θh × 90 θd ×
180 φd, 34,992,012 bytes; the step options do not apply); .csv or .txt writes the tabulated
text format (theta_i,phi_i,theta_o,phi_o,r,g,b in degrees and 1/sr) on the grid θ = j·90°/steps,
φ = j·360°/steps. Entries with a direction below the horizon are written as not measured (-1)
in MERL files. The output is written atomically and never over one of the inputs.

--microsurface measures a periodic Gaussian height field of RMS slope --rms-slope whose facets
reflect by MODEL (default: a mirror), by tracing --rays rays per incident direction: ρ = the
fraction of the beam's flux reaching a detector cell / the cell's projected solid angle. Each
θo, φo value is the centre of a cell reaching halfway to its neighbours. Only .csv/.txt output.
  gonio measure --microsurface --rms-slope 0.3 -o rough.csv
  gonio measure lambert --albedo 0.8 --microsurface --rms-slope 0.5 --rays 1000000 -o l.csv

Exit status: 0 success; 2 an error.";

/// `gonio measure`.
#[derive(Debug, Args)]
pub struct MeasureArgs {
    /// Model name (see `gonio models`), analytic or measured (`merl --filename F`); with
    /// --microsurface, the facets' model (default: an ideal mirror).
    #[arg(required_unless_present = "microsurface")]
    pub model: Option<String>,
    /// Measure an explicit micro-surface (a Gaussian random height field) by ray tracing, with
    /// multiple bounces between facets, instead of tabulating a model.
    #[arg(long)]
    pub microsurface: bool,
    /// --microsurface: RMS slope of the height field (Beckmann's m = Ward's α).
    #[arg(long, default_value_t = 0.3, value_name = "S", requires = "microsurface")]
    pub rms_slope: f64,
    /// --microsurface: rays traced per incident direction.
    #[arg(long, default_value_t = 200_000, value_name = "N", requires = "microsurface")]
    pub rays: usize,
    /// --microsurface: seed of the height field and of the rays.
    #[arg(long, default_value_t = 1, value_name = "S", requires = "microsurface")]
    pub seed: u64,
    /// --microsurface: facet hits after which a ray is given up.
    #[arg(long, default_value_t = 100, value_name = "K", requires = "microsurface")]
    pub bounces: u32,
    /// --microsurface: height-field cells per side (the surface is periodic).
    #[arg(long, default_value_t = 256, value_name = "N", requires = "microsurface")]
    pub grid: usize,
    /// --microsurface: collimated beams, or light filling each incident grid cell (reciprocal bins).
    #[arg(long, default_value = "collimated", value_parser = ["collimated", "cell"], requires = "microsurface")]
    pub beam: String,
    /// Output file: .binary (MERL) or .csv/.txt (tabulated).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: PathBuf,
    /// Incident polar angles θi of the tabulated grid (0° up to 90° exclusive).
    #[arg(long, default_value_t = 18, value_name = "M")]
    pub theta_i_steps: usize,
    /// Incident azimuths φi of the tabulated grid (1: one plane of incidence, for isotropic models).
    #[arg(long, default_value_t = 1, value_name = "K")]
    pub phi_i_steps: usize,
    /// Outgoing polar angles θo of the tabulated grid (0° up to 90° exclusive).
    #[arg(long, default_value_t = 18, value_name = "N")]
    pub theta_o_steps: usize,
    /// Outgoing azimuths φo of the tabulated grid (0° up to 360° exclusive).
    #[arg(long, default_value_t = 72, value_name = "K")]
    pub phi_o_steps: usize,
    /// A model parameter, NAME=VALUE (the same as --NAME VALUE).
    #[arg(short = 'p', long = "param", value_name = "NAME=VALUE")]
    pub param: Vec<String>,
}

/// `gonio demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Folder the plots are written to.
    #[arg(long, default_value = ".", value_name = "DIR")]
    pub out_dir: PathBuf,
    /// Worker threads for the checks (default: the machine's cores).
    #[arg(long, short = 'j')]
    pub jobs: Option<usize>,
}

/// A usage error of ours (clap reports its own): exit status 2.
#[derive(Debug)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// An option name and whether it takes a value.
type Known<T> = Vec<(T, bool)>;

/// `--NAME VALUE` pairs given for the model.
pub type ModelParams = Vec<(String, String)>;

/// The options of subcommand `sub` that clap knows: (long names, short names), each with
/// whether it takes a value.
fn known_options(sub: &str) -> Option<(Known<String>, Known<char>)> {
    let cmd = Cli::command();
    let sc = cmd.find_subcommand(sub)?;
    let mut longs = vec![("help".to_string(), false)];
    let mut shorts = vec![('h', false)];
    for a in sc.get_arguments() {
        let takes = a.get_action().takes_values();
        if let Some(l) = a.get_long() {
            longs.push((l.to_string(), takes));
        }
        for l in a.get_all_aliases().unwrap_or_default() {
            longs.push((l.to_string(), takes));
        }
        if let Some(s) = a.get_short() {
            shorts.push((s, takes));
        }
    }
    Some((longs, shorts))
}

/// Splits `argv` into what clap parses and the model parameters (`--NAME VALUE`, `--NAME=VALUE`).
pub fn split_args(argv: Vec<String>) -> Result<(Vec<String>, ModelParams), UsageError> {
    let Some(sub) = argv.get(1).cloned() else { return Ok((argv, Vec::new())) };
    if !matches!(sub.as_str(), "eval" | "check" | "plot" | "measure") {
        return Ok((argv, Vec::new()));
    }
    let (longs, shorts) = known_options(&sub).expect("the subcommand exists");
    let mut out: Vec<String> = argv[..2].to_vec();
    let mut params = Vec::new();
    let mut rest = argv[2..].iter();
    while let Some(arg) = rest.next() {
        if arg == "--" {
            out.push(arg.clone());
            out.extend(rest.by_ref().cloned());
            break;
        }
        if let Some(body) = arg.strip_prefix("--") {
            let (name, inline) = match body.split_once('=') {
                Some((n, v)) => (n, Some(v.to_string())),
                None => (body, None),
            };
            if let Some((_, takes)) = longs.iter().find(|(l, _)| l == name) {
                out.push(arg.clone());
                if *takes && inline.is_none() {
                    out.extend(rest.next().cloned());
                }
                continue;
            }
            let value = match inline {
                Some(v) => v,
                None => rest
                    .next()
                    .cloned()
                    .ok_or_else(|| UsageError(format!("model parameter --{name} needs a value: --{name} VALUE")))?,
            };
            params.push((name.to_string(), value));
            continue;
        }
        out.push(arg.clone());
        // A short option that takes a separate value (`-o FILE`, `-p NAME=VALUE`).
        let mut chars = arg.chars();
        if let (Some('-'), Some(c), None) = (chars.next(), chars.next(), chars.next()) {
            if shorts.iter().any(|&(s, takes)| s == c && takes) {
                out.extend(rest.next().cloned());
            }
        }
    }
    Ok((out, params))
}

/// Parses `-p NAME=VALUE` options.
pub fn parse_param_options(opts: &[String]) -> Result<Vec<(String, String)>, UsageError> {
    opts.iter()
        .map(|o| {
            o.split_once('=')
                .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
                .ok_or_else(|| UsageError(format!("-p '{o}' is not NAME=VALUE")))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(v: &[&str]) -> Vec<String> {
        v.iter().map(|x| x.to_string()).collect()
    }

    #[test]
    fn model_params_are_taken_out_and_options_kept() {
        let (a, p) =
            split_args(s(&["gonio", "eval", "phong", "--ks", "0.1,0.2,0.3", "--wi", "-1,0,1", "--ke=20", "--json"]))
                .unwrap();
        assert_eq!(a, s(&["gonio", "eval", "phong", "--wi", "-1,0,1", "--json"]));
        assert_eq!(p, vec![("ks".into(), "0.1,0.2,0.3".into()), ("ke".into(), "20".into())]);
        let (a, p) =
            split_args(s(&["gonio", "plot", "ward", "-o", "x.svg", "--alpha", "0.1", "--kind=slice"])).unwrap();
        assert_eq!(a, s(&["gonio", "plot", "ward", "-o", "x.svg", "--kind=slice"]));
        assert_eq!(p, vec![("alpha".into(), "0.1".into())]);
        assert!(split_args(s(&["gonio", "eval", "phong", "--ks"])).is_err());
        let (a, p) = split_args(s(&["gonio", "models", "--json"])).unwrap();
        assert_eq!((a.len(), p.len()), (3, 0));
    }

    #[test]
    fn the_cli_definition_is_consistent() {
        Cli::command().debug_assert();
    }
}
