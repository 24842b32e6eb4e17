//! BVH speed on the peer benchmark's 100k-triangle torus (shared/bench/data/torus.ply):
//! build time, and closest-hit throughput for coherent camera rays and incoherent diffuse
//! bounce rays, one thread. Skipped when the file is absent.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use glam::{Vec2, Vec3};
use render::camera::{look_at, Camera, FovAxis};
use render::ray::{spawn_ray, Ray};
use render::sampler::Sampler;
use render::shape::Geometry;
use render::{Scene, SceneBuilder, Shape};
use std::hint::black_box;
use std::path::Path;

fn torus_scene() -> Option<Scene> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/bench/data/torus.ply");
    let mesh = render::io::load_mesh(&p, false).ok()?;
    // The camera of shared/bench/scenes/mesh.xml.
    let cam = Camera::new(look_at(Vec3::new(0.0, 1.4, 5.0), Vec3::ZERO, Vec3::Y)?, 40.0, FovAxis::X, 512, 512);
    let mut b = SceneBuilder::new(cam);
    let brdf: std::sync::Arc<dyn brdf::Brdf> = brdf::build("lambert", &[]).ok()?.into();
    b.shape(Shape::new(Geometry::Mesh(mesh), brdf));
    b.build().ok()
}

fn rays(scene: &Scene) -> (Vec<Ray>, Vec<Ray>) {
    let cam = &scene.camera;
    let primary: Vec<Ray> = (0..cam.height)
        .flat_map(|y| (0..cam.width).map(move |x| cam.ray(Vec2::new(x as f32 + 0.5, y as f32 + 0.5))))
        .collect();
    // Bounce rays: from each primary hit, a cosine-weighted direction about the normal.
    let mut s = Sampler::new(1, 0, 0);
    let bounce = primary
        .iter()
        .filter_map(|r| scene.intersect(r))
        .map(|si| {
            let d = si.frame.to_world(radiometry::warp::cosine_hemisphere(s.next_2d()));
            spawn_ray(si.p, si.ng, d)
        })
        .collect();
    (primary, bounce)
}

fn bench(c: &mut Criterion) {
    let Some(scene) = torus_scene() else {
        eprintln!("torus.ply not found: BVH benchmark skipped");
        return;
    };
    let (primary, bounce) = rays(&scene);
    let mut g = c.benchmark_group("bvh_torus");
    g.sample_size(10);
    g.throughput(Throughput::Elements(primary.len() as u64));
    g.bench_function("primary_rays", |b| {
        b.iter(|| primary.iter().filter(|r| scene.intersect_t(black_box(r)).is_some()).count())
    });
    g.throughput(Throughput::Elements(bounce.len() as u64));
    g.bench_function("bounce_rays", |b| {
        b.iter(|| bounce.iter().filter(|r| scene.intersect_t(black_box(r)).is_some()).count())
    });
    g.throughput(Throughput::Elements(scene.primitive_count() as u64));
    g.bench_function("build", |b| {
        let mesh = match &scene.shapes()[0].geometry {
            Geometry::Mesh(m) => m.clone(),
            _ => unreachable!(),
        };
        let bounds: Vec<_> = (0..mesh.len()).map(|i| mesh.triangle_bounds(i)).collect();
        b.iter(|| render::bvh::Bvh::build(black_box(&bounds)).node_count())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
