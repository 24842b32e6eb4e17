//! `gonio compare MODEL_A MODEL_B …`: the same object in each model side by side, labelled,
//! in one image: the lecture's "which one is Phong, which is Cook-Torrance?".

use crate::cmd::render::{render_with_progress, save_image};
use anyhow::{bail, Context, Result};
use clap::Args;
use radiometry::Rgb;
use render::{Image, RenderOptions};
use std::path::PathBuf;

/// `gonio compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Models, each optionally followed by its parameters as :NAME=VALUE (ward:alpha=0.1:ks=0.3).
    #[arg(required = true, num_args = 1..)]
    pub models: Vec<String>,
    /// Light probe, equirectangular .hdr or .exr (default: the built-in studio probe).
    #[arg(long)]
    pub env: Option<PathBuf>,
    /// Scale on the probe (after the scale that brings its upward irradiance to π); 0 leaves it out.
    #[arg(long, default_value_t = 1.0)]
    pub env_scale: f32,
    /// A point light in direction X,Y,Z from the object (+Y up, the camera on +Z).
    #[arg(long, value_name = "X,Y,Z")]
    pub light: Option<String>,
    /// Irradiance of the point light at the object's centre, W/m².
    #[arg(long, default_value_t = 3.0)]
    pub light_irradiance: f32,
    /// Mesh (.obj or .ply, or `suzanne` for the built-in monkey) shown instead of a sphere.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// Output image: .png or .exr.
    #[arg(short, long, default_value = "compare.png")]
    pub output: PathBuf,
    /// Side of each square panel, in pixels.
    #[arg(long, default_value_t = 256)]
    pub size: u32,
    /// Samples per pixel.
    #[arg(long, default_value_t = 32)]
    pub spp: u32,
    /// Seed of every random stream.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (0: every core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Exposure in stops for PNG output.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub exposure: f32,
}

/// Splits `ward:alpha=0.1:ks=0.3` into the name and its (name, value) pairs.
fn parse_model(spec: &str) -> Result<(String, Vec<(String, String)>)> {
    let mut parts = spec.split(':');
    let name = parts.next().unwrap_or_default().to_string();
    let params = parts
        .map(|p| {
            p.split_once('=')
                .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
                .with_context(|| format!("'{p}' in '{spec}' is not NAME=VALUE"))
        })
        .collect::<Result<_>>()?;
    Ok((name, params))
}

/// Runs the command.
pub fn run(a: &CompareArgs) -> Result<()> {
    if a.spp == 0 || a.size < 16 || a.size > 4096 {
        bail!("--spp must be at least 1 and --size in 16..=4096");
    }
    if !(a.env_scale >= 0.0 && a.env_scale.is_finite() && a.light_irradiance >= 0.0 && a.light_irradiance.is_finite()) {
        bail!("--env-scale and --light-irradiance must be finite and at least 0");
    }
    let point = match &a.light {
        Some(text) => Some((crate::cmd::eval::parse_direction("light", text)?, a.light_irradiance)),
        None => None,
    };
    let mut inputs = Vec::new();
    let env = match &a.env {
        Some(p) => {
            inputs.push(p.clone());
            Some(Image::load(p).with_context(|| format!("reading the probe '{}'", p.display()))?)
        }
        None => None,
    };
    let mesh = match &a.mesh {
        Some(p) if p.as_os_str() == "suzanne" => Some(crate::demo_scene::suzanne()?),
        Some(p) => {
            inputs.push(p.clone());
            Some(render::io::load_mesh(p).with_context(|| format!("reading the mesh '{}'", p.display()))?)
        }
        None => None,
    };
    let env = (a.env_scale > 0.0).then(|| crate::demo_scene::probe_light(env.as_ref(), a.env_scale)).transpose()?;
    let lighting = crate::demo_scene::Lighting { env, point };
    let n = a.models.len() as u32;
    let mut sheet = Image::new(n * a.size, a.size);
    let opts = RenderOptions { spp: a.spp, seed: a.seed, threads: a.threads, ..Default::default() };
    let mut cancelled = false;
    for (k, spec) in a.models.iter().enumerate() {
        let (name, params) = parse_model(spec)?;
        let given: Vec<(&str, &str)> = params.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
        let brdf = crate::demo_scene::build_model(&name, &given).with_context(|| format!("model '{spec}'"))?;
        let scene = crate::demo_scene::object_scene(brdf, mesh.as_ref(), &lighting, a.size, a.size)?;
        let (panel, stop) = render_with_progress(&scene, &opts, &name);
        for y in 0..a.size {
            for x in 0..a.size {
                sheet.set(k as u32 * a.size + x, y, panel.get(x, y));
            }
        }
        // White text on a dark band, scaled so that the label survives the PNG exposure.
        let white = Rgb::splat(4.0 * (-a.exposure).exp2());
        let scale = (a.size / 128).max(1);
        draw_text(&mut sheet, &name.to_ascii_lowercase(), k as u32 * a.size + 4 * scale, 4 * scale, scale, white);
        if stop {
            cancelled = true;
            break;
        }
    }
    save_image(&sheet, &a.output, a.exposure, &inputs)?;
    if cancelled {
        eprintln!("gonio: interrupted: saved the panels rendered so far");
    }
    outln!("wrote {} ({} panels of {}x{})", a.output.display(), n, a.size, a.size);
    Ok(())
}

/// 5×7 glyphs, one 5-bit row each from the top (bit 4 = left column).
fn glyph(c: char) -> Option<[u8; 7]> {
    Some(match c {
        'a' => [0, 0, 14, 1, 15, 17, 15],
        'b' => [16, 16, 22, 25, 17, 17, 30],
        'c' => [0, 0, 14, 16, 16, 17, 14],
        'd' => [1, 1, 13, 19, 17, 17, 15],
        'e' => [0, 0, 14, 17, 31, 16, 14],
        'f' => [6, 9, 8, 28, 8, 8, 8],
        'g' => [0, 0, 15, 17, 15, 1, 14],
        'h' => [16, 16, 22, 25, 17, 17, 17],
        'i' => [4, 0, 12, 4, 4, 4, 14],
        'j' => [2, 0, 6, 2, 2, 18, 12],
        'k' => [16, 16, 18, 20, 24, 20, 18],
        'l' => [12, 4, 4, 4, 4, 4, 14],
        'm' => [0, 0, 26, 21, 21, 17, 17],
        'n' => [0, 0, 22, 25, 17, 17, 17],
        'o' => [0, 0, 14, 17, 17, 17, 14],
        'p' => [0, 0, 30, 17, 30, 16, 16],
        'q' => [0, 0, 13, 19, 15, 1, 1],
        'r' => [0, 0, 22, 25, 16, 16, 16],
        's' => [0, 0, 14, 16, 14, 1, 30],
        't' => [8, 8, 28, 8, 8, 9, 6],
        'u' => [0, 0, 17, 17, 17, 19, 13],
        'v' => [0, 0, 17, 17, 17, 10, 4],
        'w' => [0, 0, 17, 17, 21, 21, 10],
        'x' => [0, 0, 17, 10, 4, 10, 17],
        'y' => [0, 0, 17, 17, 15, 1, 14],
        'z' => [0, 0, 31, 2, 4, 8, 31],
        '0' => [14, 17, 19, 21, 25, 17, 14],
        '1' => [4, 12, 4, 4, 4, 4, 14],
        '2' => [14, 17, 1, 2, 4, 8, 31],
        '3' => [31, 2, 4, 2, 1, 17, 14],
        '4' => [2, 6, 10, 18, 31, 2, 2],
        '5' => [31, 16, 30, 1, 1, 17, 14],
        '6' => [6, 8, 16, 30, 17, 17, 14],
        '7' => [31, 1, 2, 4, 8, 8, 8],
        '8' => [14, 17, 17, 14, 17, 17, 14],
        '9' => [14, 17, 17, 15, 1, 2, 12],
        '-' => [0, 0, 0, 31, 0, 0, 0],
        '+' => [0, 4, 4, 31, 4, 4, 0],
        '.' => [0, 0, 0, 0, 0, 12, 12],
        ' ' => [0; 7],
        _ => return None,
    })
}

/// Draws `text` with its top-left corner at (x, y), each glyph pixel a `scale`² block, on a
/// darkened band; unknown characters draw as a box; anything past the image edge is clipped.
pub fn draw_text(img: &mut Image, text: &str, x: u32, y: u32, scale: u32, color: Rgb) {
    let advance = 6 * scale;
    let (w, h) = (text.chars().count() as u32 * advance + scale, 9 * scale);
    for py in y.saturating_sub(scale)..(y + h).min(img.height) {
        for px in x.saturating_sub(scale)..(x + w).min(img.width) {
            img.set(px, py, img.get(px, py) * 0.25);
        }
    }
    for (i, c) in text.chars().enumerate() {
        let rows = glyph(c).unwrap_or([31, 17, 17, 17, 17, 17, 31]);
        for (r, bits) in rows.iter().enumerate() {
            for col in 0..5u32 {
                if bits & (16 >> col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let (px, py) = (x + i as u32 * advance + col * scale + dx, y + r as u32 * scale + dy);
                        if px < img.width && py < img.height {
                            img.set(px, py, color);
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_lands_where_asked_and_clips() {
        let mut img = Image::new(40, 12);
        draw_text(&mut img, "l1", 2, 2, 1, Rgb::ONE);
        // 'l' row 0 is 01100: columns 1 and 2 lit.
        assert_eq!(img.get(3, 2), Rgb::ONE);
        assert_eq!(img.get(2, 2), Rgb::ZERO);
        // Far past the edge: no panic.
        draw_text(&mut img, "cook-torrance", 30, 8, 2, Rgb::ONE);
        assert!(parse_model("ward:alpha=0.1:ks=0.2,0.3,0.4").unwrap().1[1].1 == "0.2,0.3,0.4");
        assert!(parse_model("ward:alpha").is_err());
    }
}
