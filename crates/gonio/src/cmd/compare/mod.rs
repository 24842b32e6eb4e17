//! `gonio compare MODEL_A MODEL_B …`: the same object in the same light in each model, side by
//! side and labelled, in one image: the lecture's "which one is Phong, which is Cook-Torrance?".
//! By default the object is Mitsuba's material-preview object on its checkerboard under a
//! bright probe, every model over the same diffuse base, each panel rendered until its noise
//! is below a threshold, so that the panels differ by their model and not by their noise.

mod object;
mod panel;

use crate::cmd::render::{noise_target, save_image};
use crate::converge::{self, Target};
use crate::demo_scene::Lighting;
use anyhow::{bail, Context, Result};
use clap::Args;
use object::{Object, Subject};
use render::{Image, RenderOptions};
use std::path::PathBuf;

/// `gonio compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Models, each optionally followed by its parameters as :NAME=VALUE (ward:alpha=0.1:ks=0.3).
    #[arg(required = true, num_args = 1..)]
    pub models: Vec<String>,
    /// Light probe: an equirectangular .hdr or .exr, or a built-in one, `dawn` (Poly Haven's
    /// kiara_1_dawn, bright sky) or `studio` (studio_small_03, soft boxes in a dark room);
    /// not for --scene, which keeps its own lights.
    #[arg(long, default_value = "studio")]
    pub env: String,
    /// Scale on the probe (after the scale that brings its upward irradiance to π); 0 leaves it
    /// out (not for --scene).
    #[arg(long, default_value_t = 1.0)]
    pub env_scale: f32,
    /// A point light in direction X,Y,Z from the object (+Y up, the camera on +Z).
    #[arg(long, value_name = "X,Y,Z")]
    pub light: Option<String>,
    /// Irradiance of the point light at the object's centre, W/m².
    #[arg(long, default_value_t = 3.0)]
    pub light_irradiance: f32,
    /// Stand this object on the checkerboard in place of the material-preview object (scaled
    /// to its size, turned to the camera): an .obj, .ply or .serialized mesh (+Y up, facing
    /// +Z), `suzanne` (the built-in monkey) or `sphere`.
    #[arg(long, conflicts_with = "scene")]
    pub mesh: Option<PathBuf>,
    /// What the object stands on: the material-preview scene's checkerboard, or none (the
    /// object alone in front of the probe; --mesh only).
    #[arg(long, value_enum, default_value = "checkerboard")]
    pub backdrop: Backdrop,
    /// Crease angle in degrees for a --mesh without normals: smooth shading across edges that
    /// turn less than this, sharp beyond (0: flat facets; a mesh with normals keeps them).
    #[arg(long, default_value_t = 60.0)]
    pub smooth: f32,
    /// Phong-tessellation steps for a --mesh smooth-shaded by --smooth (each splits every
    /// triangle in four, rounding its silhouette and shadow terminator; none past 100,000).
    #[arg(long, default_value_t = 2)]
    pub subdivide: u32,
    /// A Mitsuba 3 scene instead of the material-preview scene: the models replace its BSDF
    /// --bsdf (panels have the scene's own film size and lights).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// The id of the `<bsdf>` in --scene that the models replace (default: the only BSDF with
    /// an id that a shape references).
    #[arg(long, requires = "scene")]
    pub bsdf: Option<String>,
    /// Scene parameter for --scene's $name references, NAME=VALUE (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE", requires = "scene")]
    pub define: Vec<String>,
    /// Diffuse colour under every model that has one (its `diffuse`, `diffuse_reflectance`,
    /// `albedo` or `base_color`) and was not given it; `none` leaves the models' defaults.
    #[arg(long, default_value = "0.5,0.1,0.1")]
    pub base: String,
    /// Render each panel until the estimated noise of its PNG values (0..1) is at most this,
    /// or --spp is reached (0: always --spp).
    #[arg(long, default_value_t = 0.01)]
    pub noise: f32,
    /// Samples per pixel: the most each panel takes.
    #[arg(long, default_value_t = 512)]
    pub spp: u32,
    /// Lay the panels out in a grid (one row per model with --sweep) rather than one row.
    #[arg(long)]
    pub grid: bool,
    /// Render each model at each of these values of one parameter, NAME=V1,V2,… (one column
    /// per value): `--sweep ke=5,20,100`.
    #[arg(long, value_name = "NAME=V1,V2,…")]
    pub sweep: Option<String>,
    /// Add each model's directional albedo at normal incidence to its label.
    #[arg(long)]
    pub albedo: bool,
    /// Output image: .png or .exr.
    #[arg(short, long, default_value = "compare.png")]
    pub output: PathBuf,
    /// Side of each square panel, in pixels (the built-in object and --mesh).
    #[arg(long, default_value_t = 256)]
    pub size: u32,
    /// Seed of every random stream.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (0: every core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Exposure in stops for PNG output (and for the noise threshold).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub exposure: f32,
}

/// Triangles past which --subdivide stops splitting.
const SUBDIVIDE_UP_TO: usize = 100_000;

/// What the object stands on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Backdrop {
    /// The material-preview scene's checkerboard.
    Checkerboard,
    /// Nothing: the object alone, the probe seen behind it.
    None,
}

/// The object the panels show, from the arguments, and the files it reads.
fn object(a: &CompareArgs) -> Result<(Object, Vec<PathBuf>)> {
    if let Some(path) = &a.scene {
        let defines = crate::cmd::render::parse_defines(&a.define)?;
        return Ok((Object::scene_file(path, a.bsdf.clone(), defines)?, vec![path.clone()]));
    }
    let mut inputs = Vec::new();
    let probe = match a.env.as_str() {
        name @ ("dawn" | "studio") => crate::demo_scene::builtin_probe(name)?,
        path => {
            inputs.push(PathBuf::from(path));
            Image::load(path).with_context(|| format!("reading the probe '{path}'"))?
        }
    };
    let subject = match a.mesh.as_ref().map(|p| (p, p.to_str())) {
        None => Subject::Matpreview,
        Some((_, Some("sphere"))) => Subject::Sphere,
        Some((_, Some("suzanne"))) => Subject::Mesh(crate::demo_scene::suzanne()?),
        Some((p, _)) => {
            inputs.push(p.clone());
            let mut m = render::io::read_mesh(p).with_context(|| format!("reading the mesh '{}'", p.display()))?;
            if m.normals.is_none() {
                // At 0 every corner takes its own face's normal: flat facets.
                m.compute_smooth_normals(a.smooth.to_radians());
                if a.smooth > 0.0 {
                    for _ in 0..a.subdivide {
                        if m.len() >= SUBDIVIDE_UP_TO {
                            break;
                        }
                        m.phong_tessellate();
                    }
                }
            }
            Subject::Mesh(m)
        }
    };
    let point = match &a.light {
        Some(text) => Some((crate::cmd::eval::parse_direction("light", text)?, a.light_irradiance)),
        None => None,
    };
    if a.backdrop == Backdrop::Checkerboard {
        return Ok((Object::matpreview(&probe, a.env_scale, a.size, subject, point)?, inputs));
    }
    let mesh = match subject {
        Subject::Matpreview => {
            bail!("--backdrop none shows an object alone: give it with --mesh (a file, suzanne or sphere)")
        }
        Subject::Sphere => None,
        Subject::Mesh(m) => Some(m),
    };
    let env = (a.env_scale > 0.0).then(|| crate::demo_scene::probe_light(Some(&probe), a.env_scale)).transpose()?;
    Ok((Object::Alone { mesh, lighting: Box::new(Lighting { env, point }), size: a.size }, inputs))
}

/// Runs the command.
pub fn run(a: &CompareArgs) -> Result<()> {
    if a.spp == 0 || a.size < 16 || a.size > 4096 {
        bail!("--spp must be at least 1 and --size in 16..=4096");
    }
    if !(a.env_scale >= 0.0 && a.env_scale.is_finite() && a.light_irradiance >= 0.0 && a.light_irradiance.is_finite()) {
        bail!("--env-scale and --light-irradiance must be finite and at least 0");
    }
    if !(0.0..=180.0).contains(&a.smooth) {
        bail!("--smooth is a crease angle in degrees, 0..=180, not {}", a.smooth);
    }
    if !a.exposure.is_finite() {
        bail!("--exposure must be a finite number of stops");
    }
    let noise = noise_target(Some(a.noise))?;
    let sweep = a.sweep.as_deref().map(panel::parse_sweep).transpose()?;
    let base = (a.base != "none").then_some(a.base.as_str());
    let panels = panel::panels(&a.models, sweep.as_ref(), base)?;
    let (object, inputs) = object(a)?;
    let (cols, rows) = match &sweep {
        Some((_, values)) => (values.len(), panels.len() / values.len()),
        None if a.grid => {
            let cols = (panels.len() as f64).sqrt().ceil() as usize;
            (cols, panels.len().div_ceil(cols))
        }
        None => (panels.len(), 1),
    };
    let opts = RenderOptions { seed: a.seed, threads: a.threads, ..Default::default() };
    let target = Target { max_spp: a.spp, noise, exposure: a.exposure };
    let mut sheet: Option<Image> = None;
    for (k, p) in panels.iter().enumerate() {
        let (scene, integrator) = object.scene(p)?;
        let opts = RenderOptions { integrator, ..opts.clone() };
        let done = converge::render(&scene, &opts, target, p.title());
        let mut img = done.image;
        let (w, h) = (img.width, img.height);
        let sheet = sheet.get_or_insert_with(|| Image::new(w * cols as u32, h * rows as u32));
        let mut lines = vec![p.title().to_string(), p.subtitle()];
        if a.albedo {
            let (m, _) = brdf::check::albedo(&*p.build()?, glam::Vec3::Z, brdf::check::ALBEDO_SAMPLES, a.seed);
            lines.push(format!("albedo at 0°: {:.2}, {:.2}, {:.2}", m.0[0], m.0[1], m.0[2]));
        }
        let size = crate::label::size_for(w.min(h));
        crate::label::draw(&mut img, &lines, (size / 3.0) as u32, (size / 3.0) as u32, w, size, a.exposure)?;
        let (x0, y0) = ((k % cols) as u32 * w, (k / cols) as u32 * h);
        for y in 0..h {
            for x in 0..w {
                sheet.set(x0 + x, y0 + y, img.get(x, y));
            }
        }
        let noise = done.noise.map(|n| format!(", noise {n:.4}")).unwrap_or_default();
        outln!("{} ({}): {} spp{noise}", p.title(), p.subtitle(), done.spp);
        if done.cancelled {
            eprintln!("gonio: interrupted: saving the panels rendered so far");
            break;
        }
    }
    let sheet = sheet.context("no panel was rendered")?;
    save_image(&sheet, &a.output, a.exposure, &inputs)?;
    outln!(
        "wrote {} ({} panels, {cols}x{rows}, of {}x{})",
        a.output.display(),
        panels.len(),
        sheet.width / cols as u32,
        sheet.height / rows as u32
    );
    Ok(())
}
