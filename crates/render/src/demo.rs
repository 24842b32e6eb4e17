//! The built-in demo scene, embedded in the binary so that `gonio render` needs no files:
//! the Suzanne monkey behind a row of spheres in the lecture's models (Lambert, Phong,
//! Blinn-Phong, Ward, Cook-Torrance, GGX conductor) on a grey floor, lit by a real light
//! probe (Poly Haven's `studio_small_03`, CC0, downsampled to 512×256).
//!
//! Also the one-object scenes `gonio compare` renders side by side.

use crate::camera::{look_at, Camera, FovAxis};
use crate::envmap_convert::Probe;
use crate::error::{Error, Result};
use crate::image::Image;
use crate::integrator::Integrator;
use crate::light::{ConstantEnv, EnvMap, Light, PointLight};
use crate::scene::{Scene, SceneBuilder, Shape};
use crate::shape::{Geometry, Rectangle, Sphere, TriangleMesh};
use brdf::Brdf;
use glam::{Mat4, Vec3};
use radiometry::Rgb;
use std::f32::consts::FRAC_PI_2;
use std::sync::Arc;

/// The Blender monkey (968 triangles, OBJ text).
pub const SUZANNE_OBJ: &[u8] = include_bytes!("../assets/suzanne.obj");
/// The light probe (equirectangular Radiance RGBE, 512×256).
pub const PROBE_HDR: &[u8] = include_bytes!("../assets/studio_small_03.hdr");

/// The spheres of the demo, left to right: model name and parameters.
pub const DEMO_MODELS: &[(&str, &[(&str, &str)])] = &[
    ("lambert", &[("albedo", "0.75,0.22,0.15")]),
    ("phong", &[("ks", "0.4"), ("ke", "40"), ("diffuse", "0.1,0.25,0.7")]),
    ("blinn-phong", &[("ks", "0.4"), ("ke", "120"), ("diffuse", "0.15,0.55,0.15")]),
    ("ward", &[("ks", "0.25"), ("alpha", "0.12"), ("diffuse", "0.6,0.5,0.1")]),
    ("cook-torrance", &[("m", "0.2"), ("diffuse", "0.55,0.12,0.5")]),
    ("ggx", &[("alpha", "0.15")]),
];

/// The embedded probe as an image.
pub fn probe_image() -> Result<Image> {
    crate::io::hdr::parse_hdr(PROBE_HDR).map_err(|m| Error::Invalid(format!("embedded probe: {m}")))
}

/// The scale that brings a probe's upward irradiance H to π (so a white floor reads ≈ 1).
pub fn probe_scale(image: &Image) -> Result<f32> {
    let h = Probe::equirect(image)?.irradiance_up();
    let lum = 0.2126 * h[0] + 0.7152 * h[1] + 0.0722 * h[2];
    Ok(if lum > 0.0 && lum.is_finite() { (std::f64::consts::PI / lum) as f32 } else { 1.0 })
}

/// Parses OBJ text (vertices and polygon faces, fan-triangulated; other lines ignored).
pub fn parse_obj(text: &str) -> Result<(Vec<Vec3>, Vec<[u32; 3]>)> {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let bad = || Error::Invalid(format!("OBJ line {}: cannot read '{line}'", n + 1));
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => {
                let c: Vec<f32> = it.take(3).map(|t| t.parse().map_err(|_| bad())).collect::<Result<_>>()?;
                if c.len() != 3 {
                    return Err(bad());
                }
                positions.push(Vec3::new(c[0], c[1], c[2]));
            }
            Some("f") => {
                let idx: Vec<u32> = it
                    .map(|t| {
                        let i: i64 = t.split('/').next().unwrap_or("").parse().map_err(|_| bad())?;
                        // OBJ indices count from 1; negative ones count back from the last vertex.
                        let i = if i < 0 { positions.len() as i64 + i } else { i - 1 };
                        if i < 0 || i >= positions.len() as i64 {
                            return Err(bad());
                        }
                        Ok(i as u32)
                    })
                    .collect::<Result<_>>()?;
                if idx.len() < 3 {
                    return Err(bad());
                }
                for k in 1..idx.len() - 1 {
                    indices.push([idx[0], idx[k], idx[k + 1]]);
                }
            }
            _ => {}
        }
    }
    Ok((positions, indices))
}

/// Area-weighted vertex normals: the sum of the unnormalised face normals around each vertex.
pub fn smooth_normals(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<Vec3> {
    let mut n = vec![Vec3::ZERO; positions.len()];
    for t in indices {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let face = (b - a).cross(c - a);
        for &i in t {
            n[i as usize] += face;
        }
    }
    n.into_iter().map(|v| v.try_normalize().unwrap_or(Vec3::Y)).collect()
}

/// Suzanne with smooth normals, in her file's frame (+Y up, facing +Z, about 2.7 wide).
pub fn suzanne() -> Result<TriangleMesh> {
    let text = std::str::from_utf8(SUZANNE_OBJ).map_err(|_| Error::Invalid("embedded OBJ is not UTF-8".into()))?;
    let (positions, indices) = parse_obj(text)?;
    let normals = smooth_normals(&positions, &indices);
    TriangleMesh::new(positions, Some(normals), indices)
}

fn model(name: &str, params: &[(&str, &str)]) -> Result<Arc<dyn Brdf>> {
    brdf::build(name, params).map(Arc::from).map_err(|e| Error::Invalid(e.to_string()))
}

fn env_light(image: &Image) -> Result<Light> {
    Ok(Light::EnvMap(Box::new(EnvMap::new(image, probe_scale(image)?)?)))
}

/// The demo scene at `width` × `height` pixels, lit by the probe.
pub fn demo_scene(width: u32, height: u32) -> Result<Scene> {
    demo_scene_lit(width, height, false)
}

/// The demo scene; `phong_lights` swaps the probe for what the Phong model knows: two point
/// lights (key and fill) and a dim constant ambient.
pub fn demo_scene_lit(width: u32, height: u32, phong_lights: bool) -> Result<Scene> {
    let eye = Vec3::new(0.0, 2.4, 8.6);
    let to_world = look_at(eye, Vec3::new(0.0, 0.75, 0.0), Vec3::Y).expect("the view is not degenerate");
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
        let ball = Sphere { center: Vec3::new(x, r, 1.3), radius: r };
        b.shape_with_model(Geometry::Sphere(ball), name, params)?;
    }
    if phong_lights {
        let key = PointLight { position: Vec3::new(-4.0, 6.0, 5.0), intensity: Rgb::splat(60.0) };
        let fill = PointLight { position: Vec3::new(5.0, 3.0, 3.0), intensity: Rgb::new(10.0, 12.0, 16.0) };
        b.light(Light::Point(key)).light(Light::Point(fill));
        b.light(Light::Constant(ConstantEnv { radiance: Rgb::splat(0.12) }));
    } else {
        b.light(env_light(&probe_image()?)?);
    }
    b.build()
}

/// The estimator the demo uses: paths of up to 5 vertices (3 bounces), roulette from 3.
pub fn demo_integrator() -> Integrator {
    Integrator::Path { max_depth: 5, rr_depth: 3 }
}

/// One object in model `brdf` under `env` (the embedded probe when None), seen from +Z at
/// `width` × `height`: a unit sphere, or `mesh` scaled and centred to fit one.
pub fn object_scene(
    brdf: Arc<dyn Brdf>,
    mesh: Option<&TriangleMesh>,
    env: Option<&Image>,
    width: u32,
    height: u32,
) -> Result<Scene> {
    let to_world = look_at(Vec3::new(0.0, 0.6, 4.4), Vec3::ZERO, Vec3::Y).expect("the view is not degenerate");
    let mut b = SceneBuilder::new(Camera::new(to_world, 32.0, FovAxis::Smaller, width, height));
    let geometry = match mesh {
        None => Geometry::Sphere(Sphere { center: Vec3::ZERO, radius: 1.0 }),
        Some(m) => {
            let mut m = m.clone();
            let (lo, hi) = m
                .positions
                .iter()
                .fold((Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)), |(lo, hi), &p| {
                    (lo.min(p), hi.max(p))
                });
            let half = 0.5 * (hi - lo).max_element();
            if !(half > 0.0 && half.is_finite()) {
                return Err(Error::Invalid("the mesh has no extent".into()));
            }
            m.transform(&(Mat4::from_scale(Vec3::splat(1.0 / half)) * Mat4::from_translation(-0.5 * (lo + hi))));
            Geometry::Mesh(m)
        }
    };
    b.shape(Shape::new(geometry, brdf));
    match env {
        Some(img) => b.light(env_light(img)?),
        None => b.light(env_light(&probe_image()?)?),
    };
    b.build()
}

/// The model `name` with `params`, for [`object_scene`].
pub fn build_model(name: &str, params: &[(&str, &str)]) -> Result<Arc<dyn Brdf>> {
    model(name, params)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::renderer::{render, RenderOptions};

    #[test]
    fn embedded_assets_load() {
        let m = suzanne().unwrap();
        assert_eq!(m.len(), 968);
        let p = probe_image().unwrap();
        assert_eq!((p.width, p.height), (512, 256));
        let s = probe_scale(&p).unwrap();
        assert!(s > 0.0 && s.is_finite());
        assert!(parse_obj("v 0 0 0\nf 1 2 3\n").is_err());
        let (_, idx) = parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1/1 2/2 3/3 -1/4\n").unwrap();
        assert_eq!(idx, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn demo_renders_finite_and_lit() {
        let scene = demo_scene(32, 18).unwrap();
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
