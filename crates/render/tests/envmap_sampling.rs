//! Environment-map importance sampling on a map with a 1000× spot: the samples follow the
//! reported density at the cell level and within cells, the density is continuous across
//! cells, positive wherever there is radiance, and unchanged in meaning under a rotation.

use glam::{Mat3, Vec2, Vec3};
use radiometry::Rgb;
use render::light::envmap::{direction_to_uv, uv_to_direction};
use render::light::EnvMap;
use render::sampler::Sampler;
use render::Image;
use std::f32::consts::PI;

const W: u32 = 32;
const H: u32 = 17;

/// A sky that brightens towards the top (luminance ~1) with a 2×2-texel spot 1000× brighter.
fn spot_map() -> Image {
    let mut img = Image::new(W, H);
    for j in 0..H {
        for i in 0..W {
            let t = j as f32 / (H - 1) as f32;
            img.set(i, j, Rgb::new(1.2 - 0.6 * t, 1.1 - 0.5 * t, 1.0 + 0.1 * (i as f32 * 0.7).sin()));
        }
    }
    for (i, j) in [(9, 5), (10, 5), (9, 6), (10, 6)] {
        img.set(i, j, Rgb::new(1100.0, 1000.0, 900.0));
    }
    img
}

/// The density on (u, v) ∈ [0, 1]²: pdf(d)·2π² sin θ, bilinear over each cell of the grid of
/// texel centres.
fn uv_density(env: &EnvMap, u: f32, v: f32) -> f64 {
    let u = u.rem_euclid(1.0);
    env.pdf(uv_to_direction(Vec2::new(u, v))) as f64 * 2.0 * (PI as f64).powi(2) * (PI * v).sin().max(0.0) as f64
}

/// Pearson's χ² of `counts` against `expected`, bins with fewer than 5 expected pooled;
/// returns it with its degrees of freedom.
fn chi2(counts: &[u64], expected: &[f64]) -> (f64, f64) {
    let (mut chi2, mut dof) = (0.0, 0usize);
    let (mut pool_c, mut pool_e) = (0.0, 0.0);
    for (&c, &e) in counts.iter().zip(expected) {
        if e >= 5.0 {
            chi2 += (c as f64 - e).powi(2) / e;
            dof += 1;
        } else {
            pool_c += c as f64;
            pool_e += e;
        }
    }
    if pool_e > 0.0 {
        chi2 += (pool_c - pool_e).powi(2) / pool_e;
        dof += 1;
    }
    (chi2, (dof - 1) as f64)
}

#[test]
fn samples_follow_the_density_per_cell_and_within_cells() {
    let env = EnvMap::new(&spot_map(), 1.0).unwrap();
    // Bins: each cell of the grid of texel centres (x = uW − ½, y = v(H − 1)) cut 3 × 3.
    let (cx, cy, sub) = (W as usize, H as usize - 1, 3usize);
    let (bx, by) = (cx * sub, cy * sub);
    let n = 1_000_000u64;
    let mut counts = vec![0u64; bx * by];
    let mut rng = Sampler::new(5, 0, 0);
    for _ in 0..n {
        let s = env.sample(Vec3::ZERO, rng.next_1d(), rng.next_2d()).unwrap();
        let uv = direction_to_uv(s.wi);
        let x = (uv.x * W as f32 - 0.5).rem_euclid(W as f32) * sub as f32;
        let y = uv.y * cy as f32 * sub as f32;
        counts[(y as usize).min(by - 1) * bx + (x as usize).min(bx - 1)] += 1;
    }
    // The density is bilinear over each bin: its integral is the mean of its corners × area.
    let at = |a: usize, b: usize| uv_density(&env, (a as f32 / sub as f32 + 0.5) / W as f32, b as f32 / by as f32);
    let mut expected = vec![0.0; bx * by];
    for b in 0..by {
        for a in 0..bx {
            let mean = (at(a, b) + at(a + 1, b) + at(a, b + 1) + at(a + 1, b + 1)) / 4.0;
            expected[b * bx + a] = mean / (bx * by) as f64 * n as f64;
        }
    }
    let total: f64 = expected.iter().sum();
    assert!((total / n as f64 - 1.0).abs() < 1e-4, "the density integrates to {}", total / n as f64);
    // The spot's cells hold most samples, and within them the bilinear ramp is steep: a
    // density that is flat within cells would fail the sub-cell test by far.
    let (c2, dof) = chi2(&counts, &expected);
    eprintln!("environment sampling: sub-cell χ² {c2:.1} with {dof} degrees of freedom");
    assert!(c2 < dof + 4.0 * (2.0 * dof).sqrt(), "sub-cell χ² {c2} with {dof} degrees of freedom");
    let cell = |v: &[f64]| -> Vec<f64> {
        (0..cx * cy)
            .map(|k| {
                let (i, j) = (k % cx, k / cx);
                (0..sub * sub).map(|s| v[(j * sub + s / sub) * bx + i * sub + s % sub]).sum()
            })
            .collect()
    };
    let cell_counts: Vec<u64> =
        cell(&counts.iter().map(|&c| c as f64).collect::<Vec<_>>()).iter().map(|&c| c as u64).collect();
    let (c2, dof) = chi2(&cell_counts, &cell(&expected));
    eprintln!("environment sampling: cell χ² {c2:.1} with {dof} degrees of freedom");
    assert!(c2 < dof + 4.0 * (2.0 * dof).sqrt(), "cell χ² {c2} with {dof} degrees of freedom");
}

#[test]
fn density_is_continuous_across_cells() {
    let env = EnvMap::new(&spot_map(), 1.0).unwrap();
    // Within a cell the (u, v) density is linear along x at fixed y and along y at fixed x, so
    // two points on each side extrapolate exactly to the edge. The limits then differ only by
    // the f32 rounding of the cell probabilities (2⁻²³ over a row's or a column's
    // probability, ≥ 1e-4 here: 1e-3 relative), and by the round trip (u, v) → direction →
    // (u, v), good to ~3e-7 (a few ulp), so 1e-5 in x = uW, times the slope, 3× for the
    // extrapolation.
    let h = 0.05;
    let (w, cy) = (W as f32, (H - 1) as f32);
    let dens = |x: f32, y: f32| uv_density(&env, (x + 0.5) / w, y / cy);
    let limit = |q1: f64, q2: f64| (2.0 * q1 - q2, 3e-5 * (q1 - q2).abs() / h as f64);
    let close = |(a, ea): (f64, f64), (b, eb): (f64, f64)| (a - b).abs() <= 1e-3 * a.max(b) + ea + eb;
    let mut checked = 0;
    for k in 0..W {
        for j in 0..H - 1 {
            for t in [0.25f32, 0.5, 0.9] {
                // An edge x = k (a column of texel centres) at height y = j + t.
                let (x, y) = (k as f32, j as f32 + t);
                let left = limit(dens(x - h, y), dens(x - 2.0 * h, y));
                let right = limit(dens(x + h, y), dens(x + 2.0 * h, y));
                assert!(close(left, right), "x edge {k} at y {y}: {left:?} vs {right:?}");
                if j >= 1 {
                    // An edge y = j (a row of texel centres) at x = k + t.
                    let (x, y) = (k as f32 + t, j as f32);
                    let below = limit(dens(x, y - h), dens(x, y - 2.0 * h));
                    let above = limit(dens(x, y + h), dens(x, y + 2.0 * h));
                    assert!(close(below, above), "y edge {j} at x {x}: {below:?} vs {above:?}");
                }
                checked += 1;
            }
        }
    }
    assert_eq!(checked, W * (H - 1) * 3);
}

#[test]
fn density_is_positive_wherever_there_is_radiance() {
    let env = EnvMap::new(&spot_map(), 1.0).unwrap();
    let mut dirs = vec![Vec3::Y, -Vec3::Y, Vec3::new(1e-30, 1.0, 0.0), Vec3::new(0.0, -1.0, 1e-20)];
    for a in 0..64 {
        for b in 0..=64 {
            dirs.push(uv_to_direction(Vec2::new(a as f32 / 64.0, b as f32 / 64.0)));
        }
    }
    for d in dirs {
        let (l, p) = (env.eval(d), env.pdf(d));
        assert!(l.luminance() > 0.0 && p > 0.0 && p.is_finite(), "{d:?}: L {l:?}, pdf {p}");
    }
    // At a pole the density is the limit of its neighbourhood's.
    let (pole, near) = (env.pdf(Vec3::Y), env.pdf(Vec3::new(0.0, 1.0, -1e-4).normalize()));
    assert!((pole - near).abs() < 1e-3 * near, "{pole} vs {near}");
}

#[test]
fn maps_without_light_to_sample_by_are_sampled_uniformly() {
    // All black, and two rows only (both at a pole, where sin θ weights everything to 0).
    let mut two_rows = Image::new(4, 2);
    two_rows.pixels.iter_mut().for_each(|p| *p = Rgb::ONE);
    for img in [Image::new(8, 4), two_rows] {
        let env = EnvMap::new(&img, 1.0).unwrap();
        let mut rng = Sampler::new(1, 0, 0);
        for _ in 0..100 {
            let s = env.sample(Vec3::ZERO, rng.next_1d(), rng.next_2d()).unwrap();
            assert!((s.pdf - 0.25 / PI).abs() < 1e-7 && env.pdf(s.wi) == s.pdf);
            assert_eq!(s.li, env.eval(s.wi));
        }
    }
}

#[test]
fn rotated_maps_sample_what_they_report() {
    let r = Mat3::from_axis_angle(Vec3::new(1.0, 2.0, 0.5).normalize(), 0.7);
    let env = EnvMap::new(&spot_map(), 1.0).unwrap().with_rotation(r).unwrap();
    let plain = EnvMap::new(&spot_map(), 1.0).unwrap();
    let mut rng = Sampler::new(2, 0, 0);
    for _ in 0..1000 {
        let s = env.sample(Vec3::ZERO, rng.next_1d(), rng.next_2d()).unwrap();
        let map_d = r.transpose() * s.wi;
        // As in the unit tests: the round trip through (u, v) moves the density by at most
        // the rounding of u times W times the largest log-slope in a cell (~1000).
        let tol = 1e-2 * s.pdf;
        assert!((env.pdf(s.wi) - s.pdf).abs() < tol && (plain.pdf(map_d) - s.pdf).abs() < tol);
        assert!(((plain.eval(map_d) - s.li) / s.li).max_channel().abs() < 1e-2);
    }
}
