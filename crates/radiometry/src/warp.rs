//! Sample warps: maps from uniform [0,1)² to directions or points, with the
//! density each produces (solid angle for directions, area for the disk).
//! Formulas as in pbrt-v4, `util/sampling.h`, and Shirley & Chiu 1997 for the disk.

use crate::trig::{sin_cos_pi, sin_cos_pi_quarter};
use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// Uniform direction on the unit sphere.
#[inline]
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = sin_cos_pi(2.0 * u.y);
    Vec3::new(r * c, r * s, z)
}

/// Density of `uniform_sphere`: 1/(4π).
#[inline]
pub fn uniform_sphere_pdf() -> f32 {
    0.25 * FRAC_1_PI
}

/// Uniform direction on the upper (z ≥ 0) hemisphere.
#[inline]
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = sin_cos_pi(2.0 * u.y);
    Vec3::new(r * c, r * s, z)
}

/// Density of `uniform_hemisphere`: 1/(2π).
#[inline]
pub fn uniform_hemisphere_pdf() -> f32 {
    0.5 * FRAC_1_PI
}

/// Uniform point on a triangle: the barycentric weights (b1, b2) of its second and third corners,
/// by the square-root map (pbrt's `SampleUniformTriangle` before its low-distortion variant).
#[inline]
pub fn uniform_triangle(u: Vec2) -> Vec2 {
    let su = u.x.sqrt();
    Vec2::new(su * (1.0 - u.y), su * u.y)
}

/// Uniform point on the unit disk by Shirley & Chiu's concentric map (low distortion).
#[inline]
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    // Selections, not branches, so that a loop over lanes vectorizes. Near the y axis the
    // angle is π/2 − a, whose sine and cosine are a's cosine and sine; at the centre r = 0.
    let steep = o.x.abs() <= o.y.abs();
    let (r, across) = if steep { (o.y, o.x) } else { (o.x, o.y) };
    let (s, c) = sin_cos_pi_quarter(0.25 * (across / if r != 0.0 { r } else { 1.0 }));
    r * if steep { Vec2::new(s, c) } else { Vec2::new(c, s) }
}

/// Area density of `concentric_disk`: 1/π.
#[inline]
pub fn concentric_disk_pdf() -> f32 {
    FRAC_1_PI
}

/// Cosine-weighted direction on the upper hemisphere (Malley's method).
#[inline]
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Density of `cosine_hemisphere`: cos θ / π (zero below the horizon).
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Uniform direction in the cone of half-angle acos(`cos_max`) around +z.
#[inline]
pub fn uniform_cone(u: Vec2, cos_max: f32) -> Vec3 {
    let z = 1.0 - u.x * (1.0 - cos_max);
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (s, c) = sin_cos_pi(2.0 * u.y);
    Vec3::new(r * c, r * s, z)
}

/// Density of `uniform_cone`: 1 / (2π(1 − cos_max)).
#[inline]
pub fn uniform_cone_pdf(cos_max: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_max))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// Monte Carlo estimate of ∫ 1/pdf(ω) over samples: equals the measure of the domain.
    fn measure(n: usize, warp: impl Fn(Vec2) -> (Vec3, f32)) -> f64 {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(7);
        let mut sum = 0.0f64;
        for _ in 0..n {
            let (w, pdf) = warp(Vec2::new(rng.gen(), rng.gen()));
            assert!((w.length() - 1.0).abs() < 1e-4, "unit direction");
            sum += 1.0 / pdf as f64;
        }
        sum / n as f64
    }

    #[test]
    fn sphere_and_hemisphere_measures() {
        let s = measure(10_000, |u| (uniform_sphere(u), uniform_sphere_pdf()));
        assert!((s - 4.0 * std::f64::consts::PI).abs() < 1e-3);
        let h = measure(10_000, |u| {
            let w = uniform_hemisphere(u);
            assert!(w.z >= 0.0);
            (w, uniform_hemisphere_pdf())
        });
        assert!((h - 2.0 * std::f64::consts::PI).abs() < 1e-3);
    }

    #[test]
    fn cosine_hemisphere_has_cosine_density() {
        // Under pdf = cos θ/π, cos²θ is uniform on [0, 1]: P(cos θ < 1/2) = 1/4.
        let mut rng = rand_pcg::Pcg64::seed_from_u64(5);
        let n = 100_000;
        let mut below = 0;
        for _ in 0..n {
            let w = cosine_hemisphere(Vec2::new(rng.gen(), rng.gen()));
            assert!(w.z >= 0.0 && (w.length() - 1.0).abs() < 1e-4);
            if w.z < 0.5 {
                below += 1;
            }
        }
        let sigma = (n as f64 * 0.25 * 0.75).sqrt();
        assert!((below as f64 - 0.25 * n as f64).abs() < 4.0 * sigma, "{below}");
    }

    #[test]
    fn disk_points_cover_unit_disk_uniformly() {
        let mut rng = rand_pcg::Pcg64::seed_from_u64(3);
        let n = 100_000;
        let mut inner = 0;
        for _ in 0..n {
            let p = concentric_disk(Vec2::new(rng.gen(), rng.gen()));
            assert!(p.length() <= 1.0 + 1e-6);
            if p.length() < 0.5 {
                inner += 1;
            }
        }
        // Area fraction of radius 1/2 is 1/4; binomial σ = sqrt(n p (1-p)).
        let sigma = (n as f64 * 0.25 * 0.75).sqrt();
        assert!((inner as f64 - 0.25 * n as f64).abs() < 4.0 * sigma);
    }

    #[test]
    fn cone_stays_inside() {
        let cos_max = 0.8;
        let m = measure(10_000, |u| {
            let w = uniform_cone(u, cos_max);
            assert!(w.z >= cos_max - 1e-6);
            (w, uniform_cone_pdf(cos_max))
        });
        assert!((m - 2.0 * std::f64::consts::PI * 0.2).abs() < 1e-3);
    }
}
