//! `gonio render`: render a scene (the built-in demo when none is given) to PNG or EXR, with a
//! progress bar; Ctrl-C stops the render and saves the samples taken so far.

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use render::{Image, Integrator, RenderOptions, Scene};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

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
    /// Samples per pixel (default: the scene file's, 32 for the demo).
    #[arg(long)]
    pub spp: Option<u32>,
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

/// The process-wide cancel flag, set by Ctrl-C (the handler can be installed only once).
pub fn cancel_flag() -> Arc<AtomicBool> {
    static FLAG: OnceLock<Arc<AtomicBool>> = OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        // Without a handler (e.g. none can be installed) Ctrl-C simply ends the process.
        let _ = ctrlc::set_handler(move || f.store(true, Ordering::Relaxed));
        flag
    })
    .clone()
}

/// Renders with a progress bar on stderr (hidden when stderr is not a terminal); returns the
/// image and whether Ctrl-C cut it short.
pub fn render_with_progress(scene: &Scene, opts: &RenderOptions, label: &str) -> (Image, bool) {
    let cancel = cancel_flag();
    let opts = RenderOptions { cancel: Some(cancel.clone()), ..opts.clone() };
    let total = scene.camera.width as u64 * scene.camera.height as u64 * opts.spp as u64;
    let bar = if std::io::stderr().is_terminal() {
        indicatif::ProgressBar::new(total)
    } else {
        indicatif::ProgressBar::hidden()
    };
    bar.set_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {percent:>3}% {elapsed_precise} ETA {eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(label.to_string());
    let img = render::render(scene, &opts, |p| bar.set_position(p.done));
    bar.finish_and_clear();
    (img, cancel.load(Ordering::Relaxed))
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
            (scene, crate::demo_scene::demo_integrator(), Vec::new(), 32, 0)
        }
        Some(path) => {
            let defines = a
                .define
                .iter()
                .map(|d| d.split_once('=').map(|(k, v)| (k.to_string(), v.to_string())))
                .collect::<Option<Vec<_>>>()
                .context("-D takes NAME=VALUE")?;
            let loaded = render::xml::load_scene(path, &defines)?;
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
    let opts = RenderOptions { spp, seed: a.seed.unwrap_or(seed), threads: a.threads, integrator, cancel: None };
    scene.set_simd(a.simd);
    let start = std::time::Instant::now();
    let (img, cancelled) = render_with_progress(&scene, &opts, "rendering");
    save_image(&img, &a.output, a.exposure, &inputs)?;
    let secs = start.elapsed().as_secs_f64();
    let (w, h) = (img.width, img.height);
    if cancelled {
        outln!(
            "wrote {} ({w}x{h}, interrupted before {spp} spp: the samples taken so far, {secs:.1} s)",
            a.output.display()
        );
    } else {
        outln!("wrote {} ({w}x{h}, {spp} spp, {secs:.1} s)", a.output.display());
    }
    Ok(())
}
