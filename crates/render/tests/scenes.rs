//! Whole-renderer tests on tiny scenes against closed forms, with thresholds derived from
//! the estimators' statistics (fixed seeds).

use glam::{Vec2, Vec3};
use radiometry::Rgb;
use render::camera::{look_at, Camera, FovAxis};
use render::light::{ConstantEnv, EnvMap, Light, PointLight};
use render::shape::{Geometry, Rectangle, Sphere, TriangleMesh};
use render::simd::Simd;
use render::texture::Texture;
use render::{render, Image, Integrator, RenderOptions, Scene, SceneBuilder, Shape};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

fn lambert(albedo: f32) -> Arc<dyn brdf::Brdf> {
    brdf::build("lambert", &[("albedo", &albedo.to_string())]).unwrap().into()
}

fn camera(origin: Vec3, target: Vec3, fov: f32, w: u32, h: u32) -> Camera {
    Camera::new(look_at(origin, target, Vec3::Y).unwrap(), fov, FovAxis::X, w, h)
}

fn opts(spp: u32, seed: u64, integrator: Integrator) -> RenderOptions {
    RenderOptions { spp, seed, threads: 2, integrator, ..Default::default() }
}

/// Mean of the green channel over the pixels, and the standard error of that mean from the
/// pixels' spread (pixels are independent estimates).
fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

fn channel(img: &Image, c: usize) -> Vec<f64> {
    img.pixels.iter().map(|p| p.0[c] as f64).collect()
}

fn furnace_scene(w: u32) -> Scene {
    furnace_with(w, lambert(1.0))
}

fn furnace_with(w: u32, model: Arc<dyn brdf::Brdf>) -> Scene {
    let mut b = SceneBuilder::new(camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 40.0, w, w));
    b.shape(Shape::new(Geometry::Sphere(Sphere::new(Vec3::ZERO, 1.0)), model));
    b.light(Light::Constant(ConstantEnv { radiance: Rgb::ONE }));
    b.build().unwrap()
}

#[test]
fn white_furnace_is_one_everywhere() {
    let scene = furnace_scene(32);
    let integrator = Integrator::path(1000, 5);
    let a = render(&scene, &opts(16, 1, integrator), |_| {});
    let b = render(&scene, &opts(16, 2, integrator), |_| {});
    // Per-pixel noise from two independent renders: Var(a − b) = 2σ².
    let d: Vec<f64> = a.pixels.iter().zip(&b.pixels).map(|(x, y)| (x.0[1] - y.0[1]) as f64).collect();
    let sigma = (d.iter().map(|v| v * v).sum::<f64>() / d.len() as f64 / 2.0).sqrt();
    let mean = a.mean();
    for c in mean {
        assert!((c - 1.0).abs() < 1e-3, "furnace mean {mean:?}");
    }
    // 5σ over 1024 pixels: a Gaussian exceeds it with probability < 1e-3; 1e-5 is f32 rounding.
    let worst = a.pixels.iter().flat_map(|p| p.0).map(|v| (v as f64 - 1.0).abs()).fold(0.0, f64::max);
    assert!(worst < 5.0 * sigma + 1e-5, "worst pixel off by {worst}, noise σ {sigma}");
    eprintln!("furnace: mean {mean:?}, worst pixel error {worst:.2e}, σ {sigma:.2e}");
}

/// The inside of a 2×2×2 cube, faces wound so that their normals point inwards.
fn inward_cube() -> TriangleMesh {
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for axis in 0..3 {
        for s in [-1.0f32, 1.0] {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |a: f32, b: f32| {
                let mut p = Vec3::ZERO;
                p[axis] = s;
                p[u] = a;
                p[v] = b;
                p
            };
            let base = pos.len() as u32;
            pos.extend([corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)]);
            let n = (pos[base as usize + 1] - pos[base as usize]).cross(pos[base as usize + 2] - pos[base as usize]);
            if n[axis] * s < 0.0 {
                idx.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
            } else {
                idx.extend([[base, base + 2, base + 1], [base, base + 3, base + 2]]);
            }
        }
    }
    TriangleMesh::new(pos, None, idx).unwrap()
}

#[test]
fn white_mirror_furnace_is_one_everywhere() {
    // A perfect mirror (a delta lobe: found only by BRDF sampling) in a constant environment.
    let mirror: Arc<dyn brdf::Brdf> =
        brdf::build("mirror", &[("reflectance", "1"), ("fresnel", "none")]).unwrap().into();
    let img = render(&furnace_with(16, mirror), &opts(4, 1, Integrator::path(64, 5)), |_| {});
    let worst = img.pixels.iter().flat_map(|p| p.0).map(|v| (v - 1.0).abs()).fold(0.0, f32::max);
    assert!(worst < 1e-5, "mirror furnace: worst pixel off by {worst}");
}

#[test]
fn glowing_enclosure_follows_the_neumann_series_at_every_depth() {
    // Inside a closed surface of albedo a emitting Le, radiance is Le Σ_{i<k} a^i when paths
    // have at most k vertices (max_depth = k), and Le/(1 − a) unbounded.
    let (albedo, le) = (0.5f32, 1.0f32);
    let mut b = SceneBuilder::new(camera(Vec3::new(0.1, 0.2, 0.3), Vec3::new(0.0, 0.0, -1.0), 90.0, 16, 16));
    b.shape(Shape {
        geometry: Geometry::Mesh(inward_cube()),
        material: lambert(albedo).into(),
        emission: Some(Texture::Constant(Rgb::splat(le))),
    });
    let scene = b.build().unwrap();
    let cases = [
        (Integrator::path(1, 5), 1.0),
        (Integrator::DIRECT, 1.5),
        (Integrator::path(3, 1000), 1.75),
        (Integrator::path(3, 1), 1.75),
        (Integrator::path(u32::MAX, 5), 2.0),
    ];
    for (integrator, expected) in cases {
        let img = render(&scene, &opts(32, 7, integrator), |_| {});
        let (mean, err) = mean_and_error(&channel(&img, 1));
        assert!((mean - expected).abs() < 4.0 * err + 1e-5, "{integrator:?}: {mean} ± {err}, expected {expected}");
        assert!(err < 0.01 * expected, "{integrator:?}: noise {err} too large to mean anything");
        eprintln!("enclosure {integrator:?}: {mean:.5} ± {err:.5} (expected {expected})");
    }
}

/// Renders `scene` (a plane z = 0 filling the view of `cam`) and checks it against
/// `radiance(p)`, the closed-form radiance leaving plane point p. When the estimate at a
/// given film position is exact (`per_pixel`: a point light), every pixel is held to the
/// jitter noise alone; otherwise 4×4-pixel blocks and the whole image are held to the noise
/// measured between two independent renders.
fn check_plane_against(
    scene: &Scene,
    cam: &Camera,
    spp: u32,
    per_pixel: bool,
    what: &str,
    radiance: impl Fn(glam::DVec3) -> f64,
) {
    let at = |f: Vec2| -> f64 {
        let ray = cam.ray(f, Vec2::splat(0.5));
        let (o, d) = (ray.o.as_dvec3(), ray.d.as_dvec3());
        radiance(o - d * (o.z / d.z))
    };
    // The pixel's expectation is the mean radiance over its area: midpoint rule on n×n.
    let pixel_mean = |x: u32, y: u32, n: u32| -> (f64, f64, f64) {
        let (mut s, mut lo, mut hi) = (0.0, f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..n {
            for j in 0..n {
                let v = at(Vec2::new(x as f32 + (i as f32 + 0.5) / n as f32, y as f32 + (j as f32 + 0.5) / n as f32));
                s += v;
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        (s / (n * n) as f64, lo, hi)
    };
    let (w, h) = (cam.width, cam.height);
    assert!(w % 4 == 0 && h % 4 == 0, "whole 4×4 blocks");
    let expected: Vec<(f64, f64, f64, f64)> = (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let (q8, lo, hi) = pixel_mean(x, y, 8);
            (q8, pixel_mean(x, y, 4).0, lo, hi)
        })
        .collect();
    for integrator in [Integrator::path(8, 5), Integrator::DIRECT] {
        let a = render(scene, &opts(spp, 3, integrator), |_| {});
        let b = render(scene, &opts(spp, 4, integrator), |_| {});
        let (mut worst, mut sum_q) = (0.0f64, 0.0f64);
        // Per block (and image): Σ error, Σ estimated variance, Σ quadrature error bound.
        let mut blocks = vec![(0.0f64, 0.0f64, 0.0f64); ((w / 4) * (h / 4) + 1) as usize];
        let image = blocks.len() - 1;
        for y in 0..h {
            for x in 0..w {
                let (q8, q4, lo, hi) = expected[(y * w + x) as usize];
                let (ga, gb) = (a.get(x, y).0[1] as f64, b.get(x, y).0[1] as f64);
                let quad = 2.0 * (q8 - q4).abs() + 1e-5 * q8;
                if per_pixel {
                    // Popoviciu: a variable in [lo, hi] has σ ≤ (hi − lo)/2, so the mean of spp
                    // samples has σ ≤ (hi − lo)/(2√spp); the quadrature error is below |q8 − q4|.
                    let tol = 4.0 * (hi - lo) / (2.0 * (spp as f64).sqrt()) + quad;
                    assert!((ga - q8).abs() <= tol, "{what} {integrator:?} pixel ({x},{y}): {ga} vs {q8} ± {tol}");
                }
                worst = worst.max((ga - q8).abs() / q8);
                sum_q += q8;
                // (a − b)²/2 estimates the variance of one render's pixel without bias.
                for k in [((y / 4) * (w / 4) + x / 4) as usize, image] {
                    blocks[k].0 += ga - q8;
                    blocks[k].1 += (ga - gb).powi(2) / 2.0;
                    blocks[k].2 += quad;
                }
            }
        }
        // 16-pixel blocks: error / √(estimated variance) is Student-t with 16 degrees of
        // freedom, P(|t| > 6) ≈ 2e-5 per block, about 1e-3 over all blocks of both integrators.
        for (k, &(err, var, quad)) in blocks.iter().enumerate() {
            let z = if k == image { 4.0 } else { 6.0 };
            assert!(
                err.abs() <= z * var.sqrt() + quad,
                "{what} {integrator:?} block {k}: error {err}, σ {}",
                var.sqrt()
            );
        }
        let (err, var, _) = blocks[image];
        eprintln!(
            "{what} {integrator:?}: worst pixel {worst:.2e}, image mean {:.2e} ± {:.1e} (relative)",
            err / sum_q,
            var.sqrt() / sum_q
        );
    }
}

fn plane_scene(cam: &Camera, albedo: f64) -> SceneBuilder {
    let mut b = SceneBuilder::new(cam.clone());
    let plane = Rectangle::new(&glam::Mat4::IDENTITY).unwrap();
    b.shape(Shape::new(Geometry::Rectangle(plane), lambert(albedo as f32)));
    b
}

#[test]
fn lambert_plane_under_a_point_light_matches_the_inverse_square_law() {
    let (albedo, intensity) = (0.5f64, 10.0f64);
    let light = Vec3::new(0.3, -0.2, 1.0);
    let cam = camera(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 30.0, 32, 24);
    let mut b = plane_scene(&cam, albedo);
    b.light(Light::Point(PointLight { position: light, intensity: Rgb::splat(intensity as f32) }));
    // L = ρ/π · E, E = I cos θ / r².
    check_plane_against(&b.build().unwrap(), &cam, 16, true, "point light", |p| {
        let to_light = light.as_dvec3() - p;
        let r2 = to_light.length_squared();
        albedo / std::f64::consts::PI * intensity * (to_light.z / r2.sqrt()) / r2
    });
}

#[test]
fn lambert_plane_under_a_point_light_and_a_sky_is_exact_at_every_sample() {
    // L = ρ/π · I cos θ / r² + ρ L_sky. The sky is sampled at every vertex beside the point
    // light (not chosen against it), cosine-weighted like the BRDF sample that also finds it,
    // so the two MIS halves add to ρ L_sky exactly: each sample is exact for its film position.
    let (albedo, intensity, sky) = (0.5f64, 10.0f64, 0.3f64);
    let light = Vec3::new(0.3, -0.2, 1.0);
    let cam = camera(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 30.0, 32, 24);
    let mut b = plane_scene(&cam, albedo);
    b.light(Light::Constant(ConstantEnv { radiance: Rgb::splat(sky as f32) }));
    b.light(Light::Point(PointLight { position: light, intensity: Rgb::splat(intensity as f32) }));
    check_plane_against(&b.build().unwrap(), &cam, 16, true, "point light and sky", |p| {
        let to_light = light.as_dvec3() - p;
        let r2 = to_light.length_squared();
        albedo / std::f64::consts::PI * intensity * (to_light.z / r2.sqrt()) / r2 + albedo * sky
    });
}

#[test]
fn lambert_plane_under_a_sphere_light_matches_the_closed_form() {
    // A sphere of radiance L and radius R wholly above the horizon gives E = π L (R/d)² cos θ
    // (it looks like a disk of solid-angle-weighted area π sin²α, sin α = R/d).
    let (albedo, le, radius) = (0.8f64, 3.0f64, 0.25f64);
    let center = Vec3::new(-0.2, 0.1, 0.6);
    let cam = camera(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, 30.0, 24, 24);
    let mut b = plane_scene(&cam, albedo);
    b.shape(Shape {
        geometry: Geometry::Sphere(Sphere::new(center, radius as f32)),
        material: lambert(0.0).into(),
        emission: Some(Texture::Constant(Rgb::splat(le as f32))),
    });
    check_plane_against(&b.build().unwrap(), &cam, 64, false, "sphere light", |p| {
        let to_c = center.as_dvec3() - p;
        let d2 = to_c.length_squared();
        // Pixels that see the sphere itself are not plane points: expect its radiance.
        let ray_hits_sphere = {
            let o = glam::DVec3::new(0.0, 0.0, 3.0);
            let dir = (p - o).normalize();
            let oc = o - center.as_dvec3();
            let bq = oc.dot(dir);
            bq * bq - (oc.length_squared() - radius * radius) >= 0.0
        };
        if ray_hits_sphere {
            return le;
        }
        albedo * le * radius * radius / d2 * (to_c.z / d2.sqrt())
    });
}

/// A 64×32 map: dim sky 0.1 with a 6×4-texel spot of 20 about 45° up.
fn spot_map() -> Image {
    let mut img = Image::new(64, 32);
    for p in &mut img.pixels {
        *p = Rgb::new(0.1, 0.12, 0.15);
    }
    for j in 7..11 {
        for i in 20..26 {
            img.set(i, j, Rgb::new(20.0, 18.0, 15.0));
        }
    }
    img
}

fn env_scene(importance: bool) -> Scene {
    let mut b = SceneBuilder::new(camera(Vec3::new(0.0, 0.5, 3.0), Vec3::ZERO, 45.0, 32, 32));
    b.shape(Shape::new(Geometry::Sphere(Sphere::new(Vec3::ZERO, 1.0)), lambert(0.8)));
    let mut env = EnvMap::new(&spot_map(), 1.0).unwrap();
    env.importance = importance;
    b.light(Light::EnvMap(Box::new(env)));
    b.build().unwrap()
}

#[test]
fn environment_importance_sampling_agrees_with_uniform_sampling() {
    // Uniform sampling is far noisier: it gets 16× the samples so that the comparison can
    // see a bias of under 2 % (4σ).
    let is = env_scene(true);
    let uni = env_scene(false);
    let a1 = render(&is, &opts(256, 11, Integrator::DIRECT), |_| {});
    let a2 = render(&is, &opts(128, 12, Integrator::DIRECT), |_| {});
    let b1 = render(&uni, &opts(4096, 13, Integrator::DIRECT), |_| {});
    let b2 = render(&uni, &opts(128, 14, Integrator::DIRECT), |_| {});
    let b3 = render(&uni, &opts(128, 15, Integrator::DIRECT), |_| {});
    for c in 0..3 {
        // Same expectation: the per-pixel differences have mean 0. Test the whole image and
        // each 8×8 block (16 blocks: |z| < 4.5 keeps the family-wise false alarm < 1e-4).
        let d: Vec<f64> = a1.pixels.iter().zip(&b1.pixels).map(|(x, y)| (x.0[c] - y.0[c]) as f64).collect();
        let (m, e) = mean_and_error(&d);
        assert!(m.abs() < 4.0 * e, "channel {c}: image mean difference {m} ± {e}");
        assert!(e < 0.004 * a1.mean()[c], "channel {c}: the comparison is too noisy to see a 2 % bias: ±{e}");
        for by in 0..4 {
            for bx in 0..4 {
                let block: Vec<f64> = (0..64).map(|k| d[(by * 8 + k / 8) * 32 + bx * 8 + k % 8]).collect();
                let (m, e) = mean_and_error(&block);
                assert!(m.abs() < 4.5 * e, "channel {c} block ({bx},{by}): {m} ± {e}");
            }
        }
    }
    // And importance sampling is the better estimator: less noise between two seeds at equal spp.
    let noise = |p: &Image, q: &Image| -> f64 {
        p.pixels.iter().zip(&q.pixels).map(|(x, y)| ((x.0[1] - y.0[1]) as f64).powi(2)).sum::<f64>()
    };
    let (ni, nu) = (noise(&a1, &a2), noise(&b2, &b3));
    assert!(ni < nu, "importance sampling noise {ni} ≥ uniform {nu}");
    eprintln!("envmap: squared noise IS {ni:.3e} vs uniform {nu:.3e}; means {:?} vs {:?}", a1.mean(), b1.mean());
}

#[test]
fn same_seed_same_image_whatever_the_thread_count() {
    let scene = env_scene(true);
    let integrator = Integrator::path(8, 2);
    let one = render(&scene, &RenderOptions { threads: 1, ..opts(4, 5, integrator) }, |_| {});
    for threads in [2, 3] {
        let many = render(&scene, &RenderOptions { threads, ..opts(4, 5, integrator) }, |_| {});
        assert!(one.pixels.iter().zip(&many.pixels).all(|(a, b)| a.0.map(f32::to_bits) == b.0.map(f32::to_bits)));
    }
    let other = render(&scene, &opts(4, 6, integrator), |_| {});
    assert_ne!(one, other, "a different seed gives a different image");
}

#[test]
fn a_cancelled_render_keeps_whole_passes() {
    let scene = furnace_scene(16);
    let cancel = Arc::new(AtomicBool::new(false));
    let o = RenderOptions { cancel: Some(cancel.clone()), ..opts(64, 1, Integrator::default()) };
    let total = std::sync::atomic::AtomicU64::new(0);
    let img = render(&scene, &o, |p| {
        total.store(p.total, Ordering::Relaxed);
        // Stop once the first pass (one sample per pixel) is complete.
        if p.done >= 16 * 16 {
            cancel.store(true, Ordering::Relaxed);
        }
    });
    assert_eq!(total.load(Ordering::Relaxed), 16 * 16 * 64);
    // Every row finished at least one pass, so every pixel is a furnace estimate of 1.
    assert!(img.pixels.iter().all(|p| (p.0[1] - 1.0).abs() < 1e-3), "{:?}", img.mean());
}

#[test]
fn bvh_hits_equal_brute_force() {
    // 3000 random small triangles, spheres and rectangles in a box; random rays through it.
    let mut s = render::sampler::Sampler::new(99, 0, 0);
    let mut rnd = |lo: f32, hi: f32| lo + (hi - lo) * s.next_1d();
    let mut pos = Vec::new();
    let mut idx = Vec::new();
    for t in 0..3000u32 {
        let c = Vec3::new(rnd(-5.0, 5.0), rnd(-5.0, 5.0), rnd(-5.0, 5.0));
        for _ in 0..3 {
            pos.push(c + Vec3::new(rnd(-0.4, 0.4), rnd(-0.4, 0.4), rnd(-0.4, 0.4)));
        }
        idx.push([3 * t, 3 * t + 1, 3 * t + 2]);
    }
    let mut b = SceneBuilder::new(camera(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, 40.0, 8, 8));
    b.shape(Shape::new(Geometry::Mesh(TriangleMesh::new(pos, None, idx).unwrap()), lambert(0.5)));
    for _ in 0..20 {
        let center = Vec3::new(rnd(-5.0, 5.0), rnd(-5.0, 5.0), rnd(-5.0, 5.0));
        b.shape(Shape::new(Geometry::Sphere(Sphere::new(center, rnd(0.1, 0.6))), lambert(0.5)));
        let m = glam::Mat4::from_scale_rotation_translation(
            Vec3::new(rnd(0.2, 1.0), rnd(0.2, 1.0), 1.0),
            glam::Quat::from_euler(glam::EulerRot::XYZ, rnd(0.0, 6.0), rnd(0.0, 6.0), rnd(0.0, 6.0)),
            Vec3::new(rnd(-5.0, 5.0), rnd(-5.0, 5.0), rnd(-5.0, 5.0)),
        );
        b.shape(Shape::new(Geometry::Rectangle(Rectangle::new(&m).unwrap()), lambert(0.5)));
    }
    let scene = b.build().unwrap();
    let (mut hits, mut n) = (0, 20_000);
    while n > 0 {
        n -= 1;
        let o = Vec3::new(rnd(-6.0, 6.0), rnd(-6.0, 6.0), rnd(-6.0, 6.0));
        let d = radiometry::warp::uniform_sphere(Vec2::new(rnd(0.0, 1.0), rnd(0.0, 1.0)));
        let mut ray = render::ray::Ray::new(o, d);
        if n % 3 == 0 {
            ray.t_max = rnd(0.0, 8.0);
        }
        let fast = scene.intersect_t(&ray);
        let slow = scene.intersect_t_linear(&ray);
        match (fast, slow) {
            (Some((kf, tf)), Some((ks, ts))) => {
                // Equal distances; a different primitive only at an exact tie (a shared point).
                assert!(kf == ks || tf == ts, "ray {ray:?}: BVH {fast:?} vs brute force {slow:?}");
                assert_eq!(tf, ts);
                hits += 1;
            }
            (None, None) => {}
            _ => panic!("ray {ray:?}: BVH {fast:?} vs brute force {slow:?}"),
        }
        assert_eq!(scene.occluded(&ray), slow.is_some());
    }
    assert!(hits > 5000, "the test must exercise hits: {hits}");
}

/// A closed room of triangles with an analytic sphere, a glass sphere and a rectangle light in
/// it (leaves mixing triangles and other primitives), lit also by a point light.
fn room_scene(gaussian: bool) -> Scene {
    let mut cam = camera(Vec3::new(0.0, 0.0, 0.9), Vec3::new(0.0, -0.2, -1.0), 70.0, 24, 18);
    if gaussian {
        cam.filter = render::filter::Filter::gaussian(0.5).unwrap();
    }
    let mut b = SceneBuilder::new(cam);
    b.shape(Shape::new(Geometry::Mesh(inward_cube()), lambert(0.7)));
    let ggx: Arc<dyn brdf::Brdf> = brdf::build("ggx", &[("alpha", "0.2")]).unwrap().into();
    b.shape(Shape::new(Geometry::Sphere(Sphere::new(Vec3::new(-0.4, -0.6, -0.4), 0.35)), ggx));
    let glass: Arc<dyn brdf::Brdf> = brdf::build("dielectric", &[]).unwrap().into();
    b.shape(Shape::new(Geometry::Sphere(Sphere::new(Vec3::new(0.45, -0.7, -0.2), 0.3)), glass));
    let m = glam::Mat4::from_translation(Vec3::new(0.0, 0.99, -0.3))
        * glam::Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2)
        * glam::Mat4::from_scale(Vec3::splat(0.3));
    let mut light = Shape::new(Geometry::Rectangle(Rectangle::new(&m).unwrap()), lambert(0.0));
    light.emission = Some(Texture::Constant(Rgb::splat(8.0)));
    b.shape(light);
    b.light(Light::Point(PointLight { position: Vec3::new(0.5, 0.5, 0.5), intensity: Rgb::splat(0.5) }));
    b.build().unwrap()
}

#[test]
fn every_instruction_set_renders_the_scalar_image_bit_for_bit() {
    // The packets round as single rays do, so any difference is a bug, not rounding.
    let direct = Integrator::Direct {
        samples: render::integrator::direct::DirectSamples { emitter: 4, bsdf: 1 },
        hide_emitters: false,
    };
    let choices: Vec<Simd> = Simd::ALL.iter().map(|&(_, s)| s).filter(|s| s.available()).collect();
    assert!(choices.contains(&Simd::Sse2), "the forced-SSE2 path always runs");
    let hidden = Integrator::Path { max_depth: 8, rr_depth: 3, hide_emitters: true };
    let cases = [(false, Integrator::path(8, 3)), (true, Integrator::path(8, 3)), (false, direct), (false, hidden)];
    for (gaussian, integrator) in cases {
        let mut scene = room_scene(gaussian);
        scene.set_simd(Simd::Scalar);
        let scalar = render(&scene, &opts(6, 3, integrator), |_| {});
        assert!(scalar.mean()[1] > 0.05, "the room is lit: {:?}", scalar.mean());
        for &simd in &choices {
            scene.set_simd(simd);
            let img = render(&scene, &opts(6, 3, integrator), |_| {});
            let same =
                scalar.pixels.iter().zip(&img.pixels).all(|(a, b)| a.0.map(f32::to_bits) == b.0.map(f32::to_bits));
            assert!(same, "{simd:?} with {integrator:?} (Gaussian filter: {gaussian})");
        }
    }
}
