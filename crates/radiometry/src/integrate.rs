//! Hemisphere integrals of radiance: irradiance H = ∫ L(ω) cos θ dω over the upper
//! hemisphere, by quadrature and by Monte Carlo, exitance, and small-source relations.

use glam::DVec3;
use rand::{Rng, SeedableRng};
use std::f64::consts::PI;

/// ∫ f(ω) dω over the upper hemisphere by the midpoint rule on an `n_theta` × `n_phi` grid in (θ, φ).
/// `f` receives a unit direction in the local z-up frame.
pub fn hemisphere_integral(f: impl Fn(DVec3) -> f64, n_theta: usize, n_phi: usize) -> f64 {
    let dt = 0.5 * PI / n_theta as f64;
    let dp = 2.0 * PI / n_phi as f64;
    let mut sum = 0.0;
    for i in 0..n_theta {
        let t = (i as f64 + 0.5) * dt;
        let (st, ct) = t.sin_cos();
        let mut ring = 0.0;
        for j in 0..n_phi {
            let p = (j as f64 + 0.5) * dp;
            ring += f(DVec3::new(st * p.cos(), st * p.sin(), ct));
        }
        sum += ring * st;
    }
    sum * dt * dp
}

/// Irradiance H = ∫ L(ω) cos θ dω by the midpoint rule on an `n_theta` × `n_phi` grid in (θ, φ).
/// `radiance` receives a unit direction in the local z-up frame.
pub fn irradiance_quadrature(radiance: impl Fn(DVec3) -> f64, n_theta: usize, n_phi: usize) -> f64 {
    hemisphere_integral(|w| radiance(w) * w.z, n_theta, n_phi)
}

/// A Monte Carlo estimate with its standard error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// The estimate.
    pub value: f64,
    /// Its standard error (σ of the mean).
    pub std_error: f64,
}

/// Irradiance by Monte Carlo with cosine-weighted directions: H = π · mean(L).
pub fn irradiance_monte_carlo(radiance: impl Fn(DVec3) -> f64, samples: usize, seed: u64) -> Estimate {
    let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..samples {
        let (u1, u2): (f64, f64) = (rng.gen(), rng.gen());
        let r = u1.sqrt();
        let p = 2.0 * PI * u2;
        let w = DVec3::new(r * p.cos(), r * p.sin(), (1.0 - u1).max(0.0).sqrt());
        let v = PI * radiance(w);
        sum += v;
        sum2 += v * v;
    }
    let n = samples as f64;
    let mean = sum / n;
    let var = (sum2 / n - mean * mean).max(0.0);
    Estimate { value: mean, std_error: (var / n).sqrt() }
}

/// Radiant exitance M = ∫ L_o(ω) cos θ dω of a surface leaving radiance `radiance`:
/// the same integral as irradiance, over outgoing directions.
pub fn exitance(radiance: impl Fn(DVec3) -> f64, n_theta: usize, n_phi: usize) -> f64 {
    irradiance_quadrature(radiance, n_theta, n_phi)
}

/// Intensity (W/sr) of a small flat source of `area` and radiance `radiance`, seen at
/// `cos_theta` from its normal: I = L · A · cos θ.
pub fn intensity_from_radiance(radiance: f64, area: f64, cos_theta: f64) -> f64 {
    radiance * area * cos_theta
}

/// Radiance of a small flat source of `area` with intensity `intensity` towards `cos_theta`: L = I / (A cos θ).
pub fn radiance_from_intensity(intensity: f64, area: f64, cos_theta: f64) -> f64 {
    intensity / (area * cos_theta)
}

/// Irradiance from a point source of `intensity` at `distance`, arriving at `cos_theta`
/// to the receiving normal: E = I cos θ / r².
pub fn point_irradiance(intensity: f64, distance: f64, cos_theta: f64) -> f64 {
    intensity * cos_theta.max(0.0) / (distance * distance)
}

/// Gauss–Legendre nodes and weights on [0, 1] (Newton's iteration on P_n from the Chebyshev guess).
pub fn gauss_legendre01(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            // P_n(x) and P_n'(x) by the three-term recurrence.
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((0.5 * (x + 1.0), 0.5 * w));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_radiance_gives_pi_l() {
        let l = 2.5;
        let q = irradiance_quadrature(|_| l, 256, 64);
        assert!((q - PI * l).abs() < 1e-4 * PI * l, "{q}");
        let mc = irradiance_monte_carlo(|_| l, 1000, 1);
        // Cosine sampling is exact for constant L: zero variance.
        assert!((mc.value - PI * l).abs() < 1e-12 && mc.std_error < 1e-6);
        assert!((exitance(|_| l, 128, 32) - PI * l).abs() < 1e-3);
    }

    #[test]
    fn overhead_disk_gives_pi_l_sin2_alpha() {
        let l = 3.0;
        let alpha: f64 = 0.4;
        let disk = |w: DVec3| if w.z >= alpha.cos() { l } else { 0.0 };
        let exact = PI * l * alpha.sin().powi(2);
        // The midpoint rule on a step function errs by about one θ cell at the edge.
        let q = irradiance_quadrature(disk, 4096, 16);
        assert!((q - exact).abs() < 2e-3 * exact, "quadrature {q} vs {exact}");
        let mc = irradiance_monte_carlo(disk, 400_000, 42);
        assert!((mc.value - exact).abs() < 4.0 * mc.std_error, "MC {:?} vs {exact}", mc);
    }

    #[test]
    fn small_source_relations() {
        let i = intensity_from_radiance(10.0, 0.01, 0.5);
        assert!((i - 0.05).abs() < 1e-12);
        assert!((radiance_from_intensity(i, 0.01, 0.5) - 10.0).abs() < 1e-12);
        // A small source far away: irradiance by the integral over its solid angle matches I cos/r².
        let r: f64 = 50.0;
        let radius: f64 = 0.5;
        let lum = 4.0;
        let intensity = intensity_from_radiance(lum, PI * radius * radius, 1.0);
        let alpha = (radius / r).asin();
        let integral = PI * lum * alpha.sin().powi(2);
        assert!((point_irradiance(intensity, r, 1.0) - integral).abs() < 1e-9);
    }

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        // n nodes integrate degree 2n − 1 exactly: ∫₀¹ x^9 dx = 1/10 with 5 nodes.
        let q = gauss_legendre01(5);
        let s: f64 = q.iter().map(|&(x, w)| w * x.powi(9)).sum();
        assert!((s - 0.1).abs() < 1e-14, "{s}");
        assert!((q.iter().map(|q| q.1).sum::<f64>() - 1.0).abs() < 1e-14);
    }
}
