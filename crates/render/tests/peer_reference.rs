//! Conventions checked against Mitsuba 3's reference renders in shared/bench/ref (when that
//! folder is present): the camera and the environment-map lookup must place every
//! background texel where Mitsuba does.

use glam::{Vec2, Vec3};
use render::camera::{look_at, Camera, FovAxis};
use render::light::{EnvMap, Light};
use render::{render, Image, Integrator, RenderOptions, SceneBuilder};
use std::path::PathBuf;

fn bench_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/bench")
}

#[test]
fn envmap_background_matches_mitsuba() {
    let (Ok(sky), Ok(reference)) =
        (Image::load(bench_dir().join("data/sky.exr")), Image::load(bench_dir().join("ref/envmap.exr")))
    else {
        eprintln!("shared/bench not present: skipped");
        return;
    };
    // shared/bench/scenes/envmap.xml without its ball: every pixel sees the sky.
    let cam = Camera::new(look_at(Vec3::new(0.0, 0.6, 4.0), Vec3::ZERO, Vec3::Y).unwrap(), 40.0, FovAxis::X, 512, 512);
    let mut b = SceneBuilder::new(cam.clone());
    b.light(Light::EnvMap(Box::new(EnvMap::new(&sky, 1.0).unwrap())));
    let spp = 16;
    let img = render(
        &b.build().unwrap(),
        &RenderOptions { spp, seed: 1, threads: 0, integrator: Integrator::DIRECT, ..Default::default() },
        |_| {},
    );
    // Compare the pixels whose whole footprint misses the unit ball of the reference.
    let misses = |f: Vec2| {
        let r = cam.ray(f, Vec2::splat(0.5));
        let b = r.o.dot(r.d);
        b * b - (r.o.length_squared() - 1.0) < 0.0
    };
    let (mut sum_d, mut sum_ref, mut sum_d2, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for y in 0..512 {
        for x in 0..512 {
            let (fx, fy) = (x as f32, y as f32);
            if ![(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)].iter().all(|&(a, c)| misses(Vec2::new(fx + a, fy + c)))
            {
                continue;
            }
            let (g, r) = (img.get(x, y).0[1] as f64, reference.get(x, y).0[1] as f64);
            sum_d += g - r;
            sum_d2 += (g - r) * (g - r);
            sum_ref += r;
            n += 1;
        }
    }
    let bias = sum_d / sum_ref;
    let rms = (sum_d2 / n as f64).sqrt() / (sum_ref / n as f64);
    eprintln!("{n} background pixels: mean relative difference {bias:.2e}, relative RMS {rms:.2e}");
    assert!(n > 100_000);
    // Both images estimate the same pixel integrals; what differs is sub-pixel jitter noise
    // (rms per pixel), so the mean difference has σ ≈ rms/√n; 1e-5 allows for the reference's
    // rounding. A half-texel shift of v alone moves the mean by ~9e-4.
    let tol = 4.0 * rms / (n as f64).sqrt() + 1e-5;
    assert!(bias.abs() < tol, "mean relative difference {bias} beyond {tol}");
    assert!(rms < 2e-3, "per-pixel relative RMS {rms}: more than 16-spp jitter noise");
}
