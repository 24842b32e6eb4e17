//! `gonio render`: render a scene (the built-in demo when none is given) to PNG or EXR, with a
//! progress bar; Ctrl-C stops the render and saves the samples taken so far.

use crate::converge::{self, Converged, Target};
use crate::label;
use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use render::{Image, Integrator, RenderOptions};
use std::path::{Path, PathBuf};

/// Which estimator renders the image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum IntegratorArg {
    /// Path tracing (the demo's default: 3 bounces).
    Path,
    /// Direct lighting only.
    Direct,
    /// The lecture's Phong illumination model (point lights and a constant ambient only;
    /// the demo then swaps its probe for two point lights).
    Phong,
}

/// `gonio render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// A Mitsuba 3 XML scene; without it, the built-in demo scene.
    pub scene: Option<PathBuf>,
    /// Output image: .png (sRGB, with --exposure) or .exr (linear float RGB).
    #[arg(short, long, default_value = "gonio.png")]
    pub output: PathBuf,
    /// Samples per pixel, or with --noise the most to take (default: the scene file's; for
    /// the demo, up to 256).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Render until the estimated noise of the PNG's values (0..1, at --exposure) is at most
    /// this, or --spp is reached (default: off for a scene file, 0.015 for the demo; 0: off).
    #[arg(long)]
    pub noise: Option<f32>,
    /// Text drawn in the image's top-left corner; a second line after a `|`.
    #[arg(long)]
    pub label: Option<String>,
    /// Seed of every random stream: the same seed gives the same image whatever --threads
    /// (default: the scene file's, 0 for the demo).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Worker threads (0: every core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Exposure in stops for PNG output (the image is scaled by 2^E before sRGB encoding).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub exposure: f32,
    /// Scene parameter for the XML file's $name references, NAME=VALUE (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
    /// Image width of the demo scene.
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    /// Image height of the demo scene.
    #[arg(long, default_value_t = 360)]
    pub height: u32,
    /// The estimator (default: the scene's own, the path tracer for the demo).
    #[arg(long)]
    pub integrator: Option<IntegratorArg>,
    /// Instruction set of the ray queries: auto (the widest this CPU runs, or $GONIO_SIMD),
    /// scalar (one ray at a time), sse2, avx2 or avx512 (sixteen rays at once). The image is the
    /// same with every choice.
    #[arg(long, default_value = "auto", value_parser = render::simd::Simd::parse_arg)]
    pub simd: render::simd::Simd,
}

/// The demo's sample budget and noise target (`--spp`, `--noise`).
const DEMO_SPP: u32 = 256;
const DEMO_NOISE: f32 = 0.015;

/// `--noise` as a stopping rule: None for 0, an error unless finite and in [0, 1).
pub fn noise_target(noise: Option<f32>) -> Result<Option<f32>> {
    match noise {
        Some(n) if !(0.0..1.0).contains(&n) => bail!("--noise must be in [0, 1) (0: off), not {n}"),
        Some(n) if n > 0.0 => Ok(Some(n)),
        _ => Ok(None),
    }
}

/// `-D NAME=VALUE` arguments as pairs.
pub fn parse_defines(defines: &[String]) -> Result<Vec<(String, String)>> {
    defines
        .iter()
        .map(|d| d.split_once('=').map(|(k, v)| (k.to_string(), v.to_string())))
        .collect::<Option<Vec<_>>>()
        .context("-D takes NAME=VALUE")
}

/// Saves `img` by extension, atomically, refusing to overwrite any of `inputs`.
pub fn save_image(img: &Image, path: &Path, exposure: f32, inputs: &[PathBuf]) -> Result<()> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    if ext != "png" && ext != "exr" {
        bail!("cannot tell the format of '{}': the output must end in .png or .exr", path.display());
    }
    if path.is_dir() {
        bail!("'{}' is a folder, not a file", path.display());
    }
    if let Ok(out) = std::fs::canonicalize(path) {
        if inputs.iter().any(|i| std::fs::canonicalize(i).is_ok_and(|i| i == out)) {
            bail!("refusing to overwrite the input '{}' with output", path.display());
        }
    }
    let r = if ext == "png" { img.save_png(path, exposure) } else { img.save(path) };
    r.with_context(|| format!("writing '{}'", path.display()))
}

/// Runs the command.
pub fn run(a: &RenderArgs) -> Result<()> {
    if !a.exposure.is_finite() {
        bail!("--exposure must be a finite number of stops");
    }
    let (mut scene, integrator, inputs, spp, seed) = match &a.scene {
        None => {
            if a.width == 0 || a.height == 0 || a.width > 16384 || a.height > 16384 {
                bail!("--width and --height must be in 1..=16384");
            }
            let phong = a.integrator == Some(IntegratorArg::Phong);
            let scene =
                crate::demo_scene::demo_scene_lit(a.width, a.height, phong).context("building the demo scene")?;
            (scene, crate::demo_scene::demo_integrator(), Vec::new(), DEMO_SPP, 0)
        }
        Some(path) => {
            let loaded = render::xml::load_scene(path, &parse_defines(&a.define)?)?;
            (loaded.scene, loaded.integrator, vec![path.clone()], loaded.spp, loaded.seed)
        }
    };
    let integrator = match a.integrator {
        None => integrator,
        Some(IntegratorArg::Path) => Integrator::default(),
        Some(IntegratorArg::Direct) => Integrator::DIRECT,
        Some(IntegratorArg::Phong) => Integrator::Phong { shadows: true },
    };
    let spp = a.spp.unwrap_or(spp);
    if spp == 0 {
        bail!("--spp must be at least 1");
    }
    let noise = noise_target(a.noise.or(a.scene.is_none().then_some(DEMO_NOISE)))?;
    let opts =
        RenderOptions { spp, seed: a.seed.unwrap_or(seed), threads: a.threads, integrator, ..Default::default() };
    scene.set_simd(a.simd);
    let start = std::time::Instant::now();
    let target = Target { max_spp: spp, noise, exposure: a.exposure };
    let Converged { mut image, spp: taken, noise, cancelled } = converge::render(&scene, &opts, target, "rendering");
    if let Some(text) = &a.label {
        let lines: Vec<String> = text.split('|').map(|l| l.trim().to_string()).collect();
        let (w, h) = (image.width, image.height);
        let size = label::size_for(h.min(w));
        label::draw(&mut image, &lines, (size / 2.0) as u32, (size / 2.0) as u32, w, size, a.exposure)?;
    }
    save_image(&image, &a.output, a.exposure, &inputs)?;
    let secs = start.elapsed().as_secs_f64();
    let (w, h) = (image.width, image.height);
    let noise = noise.map(|n| format!(", noise {n:.4}")).unwrap_or_default();
    if cancelled {
        outln!(
            "wrote {} ({w}x{h}, interrupted before {spp} spp: the samples taken so far, {secs:.1} s)",
            a.output.display()
        );
    } else {
        outln!("wrote {} ({w}x{h}, {taken} spp{noise}, {secs:.1} s)", a.output.display());
    }
    Ok(())
}
