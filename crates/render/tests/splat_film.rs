//! The splatting film (Gaussian filter) against filter importance sampling, its determinism
//! across thread counts and its cancelled renders (fixed seeds, statistical thresholds).

use glam::{Vec2, Vec3};
use radiometry::Rgb;
use render::camera::{look_at, Camera, FovAxis};
use render::filter::Filter;
use render::light::{ConstantEnv, EnvMap, Light};
use render::sampler::PixelKey;
use render::shape::{Geometry, Sphere};
use render::{render, Image, Integrator, RenderOptions, Scene, SceneBuilder, Shape};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

const N: u32 = 16;

fn opts(spp: u32, seed: u64, threads: usize) -> RenderOptions {
    RenderOptions { spp, seed, threads, integrator: Integrator::DIRECT, ..Default::default() }
}

/// A diffuse sphere whose silhouette crosses the image, under a sky with a bright spot: sharp
/// edges where the filter matters, and light-sampling noise besides.
fn scene() -> Scene {
    let mut cam = Camera::new(look_at(Vec3::new(0.0, 0.5, 3.0), Vec3::ZERO, Vec3::Y).unwrap(), 45.0, FovAxis::X, N, N);
    cam.filter = Filter::gaussian(0.5).unwrap();
    let mut b = SceneBuilder::new(cam);
    let white: Arc<dyn brdf::Brdf> = brdf::build("lambert", &[("albedo", "0.8")]).unwrap().into();
    b.shape(Shape::new(Geometry::Sphere(Sphere::new(Vec3::ZERO, 1.0)), white));
    let mut sky = Image::new(64, 32);
    for (k, p) in sky.pixels.iter_mut().enumerate() {
        let (i, j) = (k % 64, k / 64);
        *p = if (20..26).contains(&i) && (7..11).contains(&j) {
            Rgb::new(20.0, 18.0, 15.0)
        } else {
            Rgb::new(0.1, 0.12, 0.15)
        };
    }
    b.light(Light::EnvMap(Box::new(EnvMap::new(&sky, 1.0).unwrap())));
    b.build().unwrap()
}

/// The filter-importance-sampled image (the Gaussian's `sample`), green channel.
fn importance_sampled(scene: &Scene, spp: u32, seed: u64) -> Vec<f64> {
    let mut out = Vec::with_capacity((N * N) as usize);
    for y in 0..N {
        for x in 0..N {
            let key = PixelKey::new(seed, (y * N + x) as u64);
            let mut sum = 0.0f64;
            for s in 0..spp {
                let mut sampler = key.sampler(s as u64);
                let Filter::Gaussian(g) = &scene.camera.filter else { unreachable!("a Gaussian camera") };
                let (offset, w) = g.sample(sampler.next_2d());
                let film = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) + offset;
                let ray = scene.camera.ray(film, Vec2::splat(0.5));
                sum += (Integrator::DIRECT.li(scene, ray, &mut sampler).0[1] * w) as f64;
            }
            out.push(sum / spp as f64);
        }
    }
    out
}

/// Per-pixel mean and variance over replicate images.
fn mean_var(reps: &[Vec<f64>]) -> Vec<(f64, f64)> {
    let k = reps.len() as f64;
    (0..reps[0].len())
        .map(|p| {
            let m = reps.iter().map(|r| r[p]).sum::<f64>() / k;
            (m, reps.iter().map(|r| (r[p] - m).powi(2)).sum::<f64>() / (k - 1.0))
        })
        .collect()
}

#[test]
fn splatting_agrees_with_importance_sampling_with_less_variance() {
    let scene = scene();
    // K independent replicates of each estimate at 32 spp.
    let (k, spp) = (32u64, 32);
    let splat: Vec<Vec<f64>> = (0..k)
        .map(|i| render(&scene, &opts(spp, 100 + i, 2), |_| {}).pixels.iter().map(|p| p.0[1] as f64).collect())
        .collect();
    let fis: Vec<Vec<f64>> = (0..k).map(|i| importance_sampled(&scene, spp, 200 + i)).collect();
    let (s, f) = (mean_var(&splat), mean_var(&fis));
    // Away from the image's edges (2 px, the filter's reach) the two estimate the same image.
    // Per pixel, z = Δmean / its standard error is t-distributed with ~2(K − 1) = 62 degrees
    // of freedom; P(|t| > 5) ≈ 5e-6, so over 144 pixels a false alarm has probability < 1e-3.
    // (The splat's ratio bias, O(1/N) with N ≈ 16·32 samples per pixel, is far below that.)
    let (mut vs, mut vf, mut zmax) = (0.0, 0.0, 0.0f64);
    for y in 2..N - 2 {
        for x in 2..N - 2 {
            let p = (y * N + x) as usize;
            let z = (s[p].0 - f[p].0) / ((s[p].1 + f[p].1) / k as f64).sqrt();
            assert!(z.abs() < 5.0, "pixel ({x}, {y}): splat {:?} vs importance {:?}, z = {z}", s[p], f[p]);
            zmax = zmax.max(z.abs());
            vs += s[p].1;
            vf += f[p].1;
        }
    }
    // Variance ratio over the interior: were splatting no better (ratio ≥ 1), an observed
    // ratio below 1/2 would need an F(31, 31) variate (its least degrees of freedom, pixels
    // fully correlated) below 1/2: probability 0.03 at worst, far less for 144 real pixels.
    let ratio = vs / vf;
    eprintln!("splat/importance variance ratio {ratio:.3} (max |z| {zmax:.2})");
    assert!(ratio < 0.5, "variance ratio {ratio}");
}

#[test]
fn gaussian_renders_are_the_same_whatever_the_thread_count() {
    let scene = scene();
    let one = render(&scene, &opts(4, 5, 1), |_| {});
    for threads in [2, 3] {
        let many = render(&scene, &opts(4, 5, threads), |_| {});
        assert!(one.pixels.iter().zip(&many.pixels).all(|(a, b)| a.0.map(f32::to_bits) == b.0.map(f32::to_bits)));
    }
    assert_ne!(one, render(&scene, &opts(4, 6, 1), |_| {}), "a different seed gives a different image");
}

#[test]
fn a_cancelled_gaussian_render_is_still_a_whole_image() {
    // A white furnace: every sample is 1, so every normalised pixel is 1 whatever arrived.
    let mut cam = Camera::new(look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y).unwrap(), 40.0, FovAxis::X, N, N);
    cam.filter = Filter::gaussian(0.5).unwrap();
    let mut b = SceneBuilder::new(cam);
    let white: Arc<dyn brdf::Brdf> = brdf::build("lambert", &[("albedo", "1")]).unwrap().into();
    b.shape(Shape::new(Geometry::Sphere(Sphere::new(Vec3::ZERO, 1.0)), white));
    b.light(Light::Constant(ConstantEnv { radiance: Rgb::ONE }));
    let scene = b.build().unwrap();
    let cancel = Arc::new(AtomicBool::new(false));
    let o = RenderOptions { cancel: Some(cancel.clone()), integrator: Integrator::path(1000, 5), ..opts(64, 1, 2) };
    let img = render(&scene, &o, |p| {
        if p.done >= (N * N) as u64 {
            cancel.store(true, Ordering::Relaxed);
        }
    });
    assert!(img.pixels.iter().all(|p| (p.0[1] - 1.0).abs() < 1e-3), "{:?}", img.mean());
}

#[test]
fn disjoint_sample_ranges_average_to_the_whole_render() {
    // Box filter: each pixel is the mean of its samples, so samples 0..5 and 5..16 weighted by
    // their counts give the 16-sample image up to the rounding of the two f32 means.
    let mut s = scene();
    s.camera.filter = Filter::Box;
    let whole = render(&s, &opts(16, 3, 2), |_| {});
    let head = render(&s, &opts(5, 3, 2), |_| {});
    let tail = render(&s, &RenderOptions { first_sample: 5, ..opts(11, 3, 2) }, |_| {});
    assert_ne!(head, tail, "the two ranges draw different samples");
    for ((w, a), b) in whole.pixels.iter().zip(&head.pixels).zip(&tail.pixels) {
        for c in 0..3 {
            let mixed = (5.0 * a.0[c] as f64 + 11.0 * b.0[c] as f64) / 16.0;
            assert!((mixed - w.0[c] as f64).abs() <= 1e-6 * (1.0 + w.0[c].abs() as f64), "{mixed} vs {}", w.0[c]);
        }
    }
}
