//! `gonio envmap`: convert a light probe between mirror ball, equirectangular map and cube map
//! (six faces or a cross), and print its irradiance on an upward surface, H = ∫ L cos θ dω.

use anyhow::{bail, Context, Result};
use clap::{Args, ValueEnum};
use render::envmap_convert::{faces_to_cross, write_hdr, Probe, FACE_NAMES};
use render::Image;
use std::path::{Path, PathBuf};

/// A probe layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Layout {
    /// Latitude-longitude map, 2:1.
    Equirect,
    /// Photograph of a chrome ball, square.
    Ball,
    /// Cube map as a horizontal cross, 4:3.
    Cross,
    /// Cube map as six files: the path holds `{face}`, replaced by px nx py ny pz nz.
    Cube,
}

/// `gonio envmap`.
#[derive(Debug, Args)]
pub struct EnvmapArgs {
    /// The probe (.hdr or .exr); for `--from cube`, a path with `{face}` in it.
    pub input: String,
    /// Output file (.hdr, .exr or .png); for `--to cube`, a path with `{face}` in it.
    #[arg(short, long)]
    pub output: Option<String>,
    /// The input's layout (default: from its shape, 2:1 equirect, 1:1 ball, 4:3 cross).
    #[arg(long)]
    pub from: Option<Layout>,
    /// The output's layout (default: equirect).
    #[arg(long, default_value = "equirect")]
    pub to: Layout,
    /// Output size: the equirect height (width twice it), the ball's side, or a cube face's side.
    #[arg(long, default_value_t = 512)]
    pub size: u32,
    /// Exposure in stops for .png output.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub exposure: f32,
}

fn load(path: &Path) -> Result<Image> {
    Image::load(path).with_context(|| format!("reading the probe '{}'", path.display()))
}

fn face_path(pattern: &str, face: &str) -> Result<PathBuf> {
    if !pattern.contains("{face}") {
        bail!("a cube map's path must hold '{{face}}' (replaced by px, nx, py, ny, pz, nz): '{pattern}'");
    }
    Ok(PathBuf::from(pattern.replace("{face}", face)))
}

/// Saves by extension (.hdr through the RGBE writer), refusing to overwrite an input.
fn save(img: &Image, path: &Path, exposure: f32, inputs: &[PathBuf]) -> Result<()> {
    if let Ok(out) = std::fs::canonicalize(path) {
        if inputs.iter().any(|i| std::fs::canonicalize(i).is_ok_and(|i| i == out)) {
            bail!("refusing to overwrite the input '{}' with output", path.display());
        }
    }
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
    let r = match ext.as_str() {
        "hdr" => write_hdr(img, path),
        "png" => img.save_png(path, exposure),
        _ => img.save(path),
    };
    r.with_context(|| format!("writing '{}'", path.display()))
}

/// Runs the command.
pub fn run(a: &EnvmapArgs) -> Result<()> {
    if a.size == 0 || a.size > 16384 {
        bail!("--size {} is out of range 1..=16384", a.size);
    }
    let (probe, inputs) = if a.from == Some(Layout::Cube) {
        let paths: Vec<PathBuf> = FACE_NAMES.iter().map(|f| face_path(&a.input, f)).collect::<Result<_>>()?;
        let faces = paths.iter().map(|p| load(p)).collect::<Result<Vec<_>>>()?;
        (Probe::cube(faces)?, paths)
    } else {
        let path = PathBuf::from(&a.input);
        let img = load(&path)?;
        let layout = a.from.unwrap_or(match (img.width, img.height) {
            (w, h) if w == h => Layout::Ball,
            (w, h) if 3 * w == 4 * h => Layout::Cross,
            _ => Layout::Equirect,
        });
        let probe = match layout {
            Layout::Equirect => Probe::equirect(&img),
            Layout::Ball => Probe::mirror_ball(img),
            Layout::Cross => Probe::cross(&img),
            Layout::Cube => unreachable!("handled above"),
        }
        .with_context(|| format!("reading '{}' as a {layout:?} probe", path.display()))?;
        (probe, vec![path])
    };
    let h = probe.irradiance_up();
    let lum = 0.2126 * h[0] + 0.7152 * h[1] + 0.0722 * h[2];
    outln!(
        "irradiance on an upward surface H = ∫ L cosθ dω: rgb {:.6} {:.6} {:.6} W/m², luminance {lum:.6}",
        h[0],
        h[1],
        h[2]
    );
    let Some(out) = &a.output else { return Ok(()) };
    match a.to {
        Layout::Equirect => save(&probe.to_equirect(2 * a.size, a.size), Path::new(out), a.exposure, &inputs)?,
        Layout::Ball => save(&probe.to_mirror_ball(a.size), Path::new(out), a.exposure, &inputs)?,
        Layout::Cross => save(&faces_to_cross(&probe.to_cube_faces(a.size)), Path::new(out), a.exposure, &inputs)?,
        Layout::Cube => {
            for (face, img) in FACE_NAMES.iter().zip(probe.to_cube_faces(a.size)) {
                save(&img, &face_path(out, face)?, a.exposure, &inputs)?;
            }
        }
    }
    outln!("wrote {out}");
    Ok(())
}
