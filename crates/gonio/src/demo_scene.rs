//! The built-in demo scene, embedded in the binary so that `gonio render` needs no files:
//! the Suzanne monkey behind a row of spheres in the lecture's models (Lambert, Phong,
//! Blinn-Phong, Ward, Cook-Torrance, GGX conductor) on a grey floor, lit by a real light
//! probe seen behind them (Poly Haven's `kiara_1_dawn`, CC0, downsampled to 512×256).
//!
//! Also the one-object scenes that `gonio compare --backdrop none` and the explorer's lit view
//! render, and the built-in probes.

use brdf::Brdf;
use glam::{Mat4, Vec3};
use radiometry::Rgb;
use render::camera::{look_at, Camera, FovAxis};
use render::envmap_convert::Probe;
use render::error::{Error, Result};
use render::image::Image;
use render::integrator::Integrator;
use render::light::{ConstantEnv, EnvMap, Light, PointLight};
use render::scene::{Scene, SceneBuilder, Shape};
use render::shape::{Geometry, Rectangle, Sphere, TriangleMesh};
use std::f32::consts::FRAC_PI_2;
use std::sync::Arc;

/// The Blender monkey (968 triangles, OBJ text).
pub const SUZANNE_OBJ: &[u8] = include_bytes!("../assets/suzanne.obj");
/// The studio light probe (equirectangular Radiance RGBE, 512×256): soft boxes in a dark room.
pub const PROBE_HDR: &[u8] = include_bytes!("../assets/studio_small_03.hdr");
/// The dawn light probe (Poly Haven's `kiara_1_dawn`, CC0, 512×256): a bright sky over hills.
const DAWN_HDR: &[u8] = include_bytes!("../assets/kiara_1_dawn.hdr");

/// The spheres of the demo, left to right: model name and parameters.
pub const DEMO_MODELS: &[(&str, &[(&str, &str)])] = &[
    ("lambert", &[("albedo", "0.75,0.22,0.15")]),
    ("phong", &[("ks", "0.4"), ("ke", "40"), ("diffuse", "0.1,0.25,0.7")]),
    ("blinn-phong", &[("ks", "0.4"), ("ke", "120"), ("diffuse", "0.15,0.55,0.15")]),
    ("ward", &[("ks", "0.25"), ("alpha", "0.12"), ("diffuse", "0.6,0.5,0.1")]),
    ("cook-torrance", &[("m", "0.2"), ("diffuse", "0.55,0.12,0.5")]),
    ("ggx", &[("alpha", "0.15")]),
];

/// The embedded studio probe as an image.
pub fn probe_image() -> Result<Image> {
    builtin_probe("studio")
}

/// A built-in probe by name: `studio` or `dawn`.
pub fn builtin_probe(name: &str) -> Result<Image> {
    let bytes = match name {
        "studio" => PROBE_HDR,
        "dawn" => DAWN_HDR,
        _ => return Err(Error::Invalid(format!("no built-in probe '{name}'; they are studio and dawn"))),
    };
    render::io::hdr::parse_hdr(bytes).map_err(|m| Error::Invalid(format!("embedded probe {name}: {m}")))
}

/// The scale that brings a probe's upward irradiance H to π (so a white floor reads ≈ 1).
pub fn probe_scale(image: &Image) -> Result<f32> {
    let h = Probe::equirect(image)?.irradiance_up();
    let lum = 0.2126 * h[0] + 0.7152 * h[1] + 0.0722 * h[2];
    Ok(if lum > 0.0 && lum.is_finite() { (std::f64::consts::PI / lum) as f32 } else { 1.0 })
}

/// Edges of Suzanne sharper than this (degrees) stay sharp: her eye rims and ear edges.
const SUZANNE_CREASE: f32 = 60.0;

/// Phong-tessellation steps (each splits every triangle in four): 968 → 15,488 triangles, so
/// that her silhouette and shadow terminator are round, not facets.
pub const SUZANNE_TESSELLATION: u32 = 2;

/// Suzanne with smooth normals, in her file's frame (+Y up, facing +Z, about 2.7 wide).
pub fn suzanne() -> Result<TriangleMesh> {
    let mut m = render::io::obj::parse_obj(SUZANNE_OBJ, false, true)
        .map_err(|e| Error::Invalid(format!("embedded Suzanne: {e}")))?;
    m.normals = None;
    m.compute_smooth_normals(SUZANNE_CREASE.to_radians());
    for _ in 0..SUZANNE_TESSELLATION {
        m.phong_tessellate();
    }
    Ok(m)
}

fn env_light(image: &Image) -> Result<Light> {
    Ok(Light::EnvMap(Box::new(EnvMap::new(image, probe_scale(image)?)?)))
}

/// The demo scene; `phong_lights` swaps the probe for what the Phong model knows: two point
/// lights (key and fill) and a dim constant ambient.
pub fn demo_scene_lit(width: u32, height: u32, phong_lights: bool) -> Result<Scene> {
    // Low and nearly level, so that the probe's horizon and sky show above the floor.
    let eye = Vec3::new(0.0, 1.5, 8.6);
    let to_world = look_at(eye, Vec3::new(0.0, 0.85, 0.0), Vec3::Y).expect("the view is not degenerate");
    let mut b = SceneBuilder::new(Camera::new(to_world, 50.0, FovAxis::X, width, height));
    // A 24 × 24 floor at y = 0 (local +Z turned to +Y).
    let floor = Mat4::from_rotation_x(-FRAC_PI_2) * Mat4::from_scale(Vec3::splat(12.0));
    let floor = Rectangle::new(&floor).expect("the floor has area");
    b.shape_with_model(Geometry::Rectangle(floor), "lambert", &[("albedo", "0.35")])?;
    let mut monkey = suzanne()?;
    // Sitting on the floor behind the spheres, turned a little towards the camera's left.
    monkey.transform(
        &(Mat4::from_translation(Vec3::new(0.0, 0.98, -1.2))
            * Mat4::from_rotation_y(-0.35)
            * Mat4::from_rotation_x(0.12)
            * Mat4::from_scale(Vec3::splat(1.05))),
    );
    b.shape_with_model(Geometry::Mesh(monkey), "cook-torrance", &[("m", "0.3"), ("diffuse", "0.55,0.53,0.5")])?;
    let (r, gap) = (0.45f32, 1.12f32);
    for (k, (name, params)) in DEMO_MODELS.iter().enumerate() {
        let x = (k as f32 - 0.5 * (DEMO_MODELS.len() - 1) as f32) * gap;
        let ball = Sphere::new(Vec3::new(x, r, 1.3), r);
        b.shape_with_model(Geometry::Sphere(ball), name, params)?;
    }
    if phong_lights {
        let key = PointLight { position: Vec3::new(-4.0, 6.0, 5.0), intensity: Rgb::splat(60.0) };
        let fill = PointLight { position: Vec3::new(5.0, 3.0, 3.0), intensity: Rgb::new(10.0, 12.0, 16.0) };
        b.light(Light::Point(key)).light(Light::Point(fill));
        b.light(Light::Constant(ConstantEnv { radiance: Rgb::splat(0.12) }));
    } else {
        b.light(env_light(&builtin_probe("dawn")?)?);
    }
    b.build()
}

/// The estimator the demo uses: paths of up to 5 vertices (3 bounces), roulette from 3.
pub fn demo_integrator() -> Integrator {
    Integrator::path(5, 3)
}

/// How the one-object scenes are lit.
#[derive(Clone, Debug, Default)]
pub struct Lighting {
    /// The light probe, as [`probe_light`] makes it; None leaves it out.
    pub env: Option<EnvMap>,
    /// A point light: the direction towards it (world space, +Y up, the camera on +Z) and the
    /// irradiance it gives at the object's centre, W/m².
    pub point: Option<(Vec3, f32)>,
}

/// A probe (the embedded one when None) as a light, scaled by `scale` after the scale that
/// brings its upward irradiance to π.
pub fn probe_light(image: Option<&Image>, scale: f32) -> Result<EnvMap> {
    let embedded;
    let img = match image {
        Some(img) => img,
        None => {
            embedded = probe_image()?;
            &embedded
        }
    };
    EnvMap::new(img, probe_scale(img)? * scale)
}

/// Distance of the point light from the object's centre (object radius 1).
const POINT_DISTANCE: f32 = 6.0;

/// The corners of a mesh's bounding box; an error for a mesh with no extent.
pub fn mesh_bounds(m: &TriangleMesh) -> Result<(Vec3, Vec3)> {
    let (lo, hi) = m
        .positions
        .iter()
        .fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let size = (hi - lo).max_element();
    if !(size > 0.0 && size.is_finite()) {
        return Err(Error::Invalid("the mesh has no extent".into()));
    }
    Ok((lo, hi))
}

/// One object in model `brdf` under `light`, seen from +Z at `width` × `height`: a unit
/// sphere, or `mesh` scaled and centred to fit one.
pub fn object_scene(
    brdf: Arc<dyn Brdf>,
    mesh: Option<&TriangleMesh>,
    light: &Lighting,
    width: u32,
    height: u32,
) -> Result<Scene> {
    let to_world = look_at(Vec3::new(0.0, 0.6, 4.4), Vec3::ZERO, Vec3::Y).expect("the view is not degenerate");
    let mut b = SceneBuilder::new(Camera::new(to_world, 32.0, FovAxis::Smaller, width, height));
    let geometry = match mesh {
        None => Geometry::Sphere(Sphere::new(Vec3::ZERO, 1.0)),
        Some(m) => {
            let mut m = m.clone();
            let (lo, hi) = mesh_bounds(&m)?;
            let half = 0.5 * (hi - lo).max_element();
            m.transform(&(Mat4::from_scale(Vec3::splat(1.0 / half)) * Mat4::from_translation(-0.5 * (lo + hi))));
            Geometry::Mesh(m)
        }
    };
    b.shape(Shape::new(geometry, brdf));
    if let Some(env) = &light.env {
        b.light(Light::EnvMap(Box::new(env.clone())));
    }
    if let Some((dir, irradiance)) = light.point {
        let dir = dir.try_normalize().ok_or_else(|| Error::Invalid("the point light's direction is zero".into()))?;
        let intensity = Rgb::splat(irradiance * POINT_DISTANCE * POINT_DISTANCE);
        b.light(Light::Point(PointLight { position: dir * POINT_DISTANCE, intensity }));
    }
    b.build()
}

#[cfg(test)]
mod tests {
    use super::*;
    use render::{render, RenderOptions};

    #[test]
    fn embedded_assets_load() {
        let m = suzanne().unwrap();
        assert_eq!(m.len(), 968 << (2 * SUZANNE_TESSELLATION));
        let p = probe_image().unwrap();
        assert_eq!((p.width, p.height), (512, 256));
        let s = probe_scale(&p).unwrap();
        assert!(s > 0.0 && s.is_finite());
    }

    #[test]
    fn demo_renders_finite_and_lit() {
        let scene = demo_scene_lit(32, 18, false).unwrap();
        let img =
            render(&scene, &RenderOptions { spp: 2, integrator: demo_integrator(), ..Default::default() }, |_| {});
        assert!(img.pixels.iter().all(|p| p.is_finite()));
        let m = img.mean();
        assert!(m.iter().all(|&c| c > 0.05 && c < 20.0), "{m:?}");
        let scene = demo_scene_lit(32, 18, true).unwrap();
        let opts = RenderOptions { spp: 1, integrator: Integrator::Phong { shadows: true }, ..Default::default() };
        let m = render(&scene, &opts, |_| {}).mean();
        assert!(m.iter().all(|&c| c > 0.05 && c < 20.0), "{m:?}");
    }
}
