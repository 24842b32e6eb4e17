//! Renders the peer benchmark's `spheres` layout (with gonio's own models) and an
//! environment-lit metal ball, as PNG: `cargo run --release -p render --example spheres -- OUT_DIR [SPP]`.

use glam::{Mat4, Vec3};
use radiometry::Rgb;
use render::camera::{look_at, Camera, FovAxis};
use render::light::{ConstantEnv, EnvMap, Light, PointLight};
use render::shape::{Geometry, Rectangle, Sphere};
use render::{render, Image, Integrator, RenderOptions, SceneBuilder, Shape};
use std::path::PathBuf;
use std::sync::Arc;

fn model(name: &str, params: &[(&str, &str)]) -> Arc<dyn brdf::Brdf> {
    brdf::build(name, params).unwrap_or_else(|e| panic!("{name}: {e}")).into()
}

fn main() -> render::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let out = PathBuf::from(args.get(1).map(String::as_str).unwrap_or("."));
    let spp: u32 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(64);
    let opts = RenderOptions { spp, integrator: Integrator::path(8, 5), ..Default::default() };
    let progress = |_| {};

    let cam = Camera::new(
        look_at(Vec3::new(0.0, 3.5, 11.5), Vec3::new(0.0, 0.9, 0.0), Vec3::Y).unwrap(),
        45.0,
        FovAxis::X,
        384,
        384,
    );
    let mut b = SceneBuilder::new(cam);
    let floor =
        Mat4::from_cols_array(&[10., 0., 0., 0., 0., 0., 10., 0., 0., -10., 0., 0., 0., 0., 0., 1.]).transpose();
    b.shape(Shape::new(Geometry::Rectangle(Rectangle::new(&floor).unwrap()), model("lambert", &[("albedo", "0.5")])));
    let balls = [
        model("lambert", &[("albedo", "0.5")]),
        model("beckmann", &[("alpha", "0.1"), ("material", "Au")]),
        model("ggx", &[("alpha", "0.3"), ("material", "Cu")]),
        model("mirror", &[]),
    ];
    for (i, m) in balls.into_iter().enumerate() {
        let center = Vec3::new(-3.3 + 2.2 * i as f32, 1.0, 0.0);
        b.shape(Shape::new(Geometry::Sphere(Sphere::new(center, 1.0)), m));
    }
    b.light(Light::Constant(ConstantEnv { radiance: Rgb::ONE }));
    b.light(Light::Point(PointLight { position: Vec3::new(3.0, 7.0, 4.0), intensity: Rgb::splat(150.0) }));
    let t = std::time::Instant::now();
    let img = render(&b.build()?, &opts, progress);
    eprintln!("spheres: {:?}, mean {:?}", t.elapsed(), img.mean());
    img.save_png(out.join("spheres.png"), -1.0)?;
    img.save(out.join("spheres.exr"))?;

    let sky = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/bench/data/sky.exr");
    if let Ok(sky) = Image::load(&sky) {
        let cam =
            Camera::new(look_at(Vec3::new(0.0, 0.6, 4.0), Vec3::ZERO, Vec3::Y).unwrap(), 40.0, FovAxis::X, 256, 256);
        let mut b = SceneBuilder::new(cam);
        b.shape(Shape::new(
            Geometry::Sphere(Sphere::new(Vec3::ZERO, 1.0)),
            model("ggx", &[("alpha", "0.05"), ("material", "Al")]),
        ));
        b.light(Light::EnvMap(Box::new(EnvMap::new(&sky, 1.0)?)));
        let t = std::time::Instant::now();
        let img = render(&b.build()?, &opts, progress);
        eprintln!("envmap: {:?}, mean {:?}", t.elapsed(), img.mean());
        img.save_png(out.join("envmap.png"), 0.0)?;

        // shared/bench/scenes/mesh.xml with a diffuse-plus-GGX model instead of roughplastic.
        let torus = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/bench/data/torus.ply");
        if let Ok(mesh) = render::io::load_mesh(&torus) {
            let cam = Camera::new(
                look_at(Vec3::new(0.0, 1.4, 5.0), Vec3::ZERO, Vec3::Y).unwrap(),
                40.0,
                FovAxis::X,
                256,
                256,
            );
            let mut b = SceneBuilder::new(cam);
            b.shape(Shape::new(Geometry::Mesh(mesh), model("lambert", &[("albedo", "0.7,0.25,0.08")])));
            b.light(Light::EnvMap(Box::new(EnvMap::new(&sky, 1.0)?)));
            let t = std::time::Instant::now();
            let img = render(&b.build()?, &opts, progress);
            eprintln!("mesh: {:?}, mean {:?}", t.elapsed(), img.mean());
            img.save_png(out.join("mesh.png"), 0.0)?;
        }
    }
    Ok(())
}
