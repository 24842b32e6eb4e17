//! The Beckmann distribution of microfacet normals, anisotropic.
//!
//! D(h) = exp(−(h_x²/α_x² + h_y²/α_y²) / h_z²) / (π α_x α_y h_z⁴) for h_z > 0: Gaussian
//! slopes, P22(x̃, ỹ) = exp(−x̃² − ỹ²)/π for α = 1, stretched by (α_x, α_y).
//! Smith: Λ(w) = (erf(a) − 1)/2 + exp(−a²) / (2a√π), a = 1/(α(w) tan θ) = w_z / √(w_x²α_x² + w_y²α_y²).
//! Visible normals (E. Heitz & E. d'Eon, "Importance Sampling Microfacet-Based BSDFs using
//! the Distribution of Visible Normals", EGSR 2014; W. Jakob's slope sampler): stretch wo to
//! α = 1, where for incidence θ in the xz plane the visible slope density is
//! ∝ (cos θ − x̃ sin θ) exp(−x̃² − ỹ²)/π on x̃ < cot θ. It factors: ỹ is N(0, ½) on its own, and
//! x̃ has the CDF [cos θ (1 + erf x̃)/2 + sin θ exp(−x̃²)/(2√π)] / (cos θ (1 + Λ)), inverted here by
//! safeguarded Newton iteration. The slopes are then rotated to wo's azimuth and unstretched.
//! Source: P. Beckmann & A. Spizzichino, *The Scattering of Electromagnetic Waves from Rough
//! Surfaces*, 1963; B. Walter et al., EGSR 2007 (Λ).

use super::{stretched_tan2, Ndf, MIN_ALPHA};
use radiometry::{Vec2, Vec3};
use statrs::function::erf::{erf, erf_inv, erfc};
use std::f32::consts::{PI, TAU};

/// 1/√π.
const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// The anisotropic Beckmann distribution with roughnesses `alpha_x`, `alpha_y` (RMS slopes · √2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beckmann {
    /// Roughness along the local x (tangent) axis.
    pub alpha_x: f32,
    /// Roughness along the local y (bitangent) axis.
    pub alpha_y: f32,
}

impl Beckmann {
    /// A Beckmann distribution; roughnesses below `MIN_ALPHA` are raised to it.
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        Beckmann { alpha_x: alpha_x.max(MIN_ALPHA), alpha_y: alpha_y.max(MIN_ALPHA) }
    }
}

/// Smith's Λ of the α = 1 Beckmann distribution as a function of a = cot θ.
fn lambda_of_a(a: f64) -> f64 {
    if a.is_infinite() {
        return 0.0;
    }
    if a <= 0.0 {
        return f64::INFINITY;
    }
    // (erf a − 1) written as −erfc a keeps the tail's relative accuracy at large a.
    (0.5 * ((-a * a).exp() * FRAC_1_SQRT_PI / a - erfc(a))).max(0.0)
}

/// Samples the α = 1 visible slope x̃ for incidence angle θ (cos, sin given), from u ∈ [0, 1).
fn sample_visible_slope_x(cos_t: f64, sin_t: f64, u: f64) -> f64 {
    // Unnormalised CDF and its derivative (the unnormalised density).
    let cdf = |x: f64| 0.5 * cos_t * (1.0 + erf(x)) + 0.5 * sin_t * (-x * x).exp() * FRAC_1_SQRT_PI;
    let pdf = |x: f64| (cos_t - x * sin_t) * (-x * x).exp() * FRAC_1_SQRT_PI;
    // Beyond |x̃| = 9 the Gaussian carries less than 1e-35 of the mass.
    let a = if sin_t > 0.0 { cos_t / sin_t } else { f64::INFINITY };
    let (mut lo, mut hi) = (-9.0f64, a.min(9.0));
    if lo >= hi {
        return hi;
    }
    let target = u * cdf(hi);
    let mut x = (erf_inv((2.0 * u - 1.0).clamp(-1.0 + 1e-15, 1.0 - 1e-15))).clamp(lo, hi);
    for _ in 0..100 {
        let g = cdf(x) - target;
        if g > 0.0 {
            hi = x;
        } else {
            lo = x;
        }
        let d = pdf(x);
        let newton = x - g / d;
        // Newton where it stays inside the bracket, bisection where it would leave it.
        let next = if d > 0.0 && newton > lo && newton < hi { newton } else { 0.5 * (lo + hi) };
        if (next - x).abs() <= 1e-12 * (1.0 + x.abs()) || hi - lo <= 1e-12 {
            return next;
        }
        x = next;
    }
    x
}

impl Ndf for Beckmann {
    #[inline]
    fn d(&self, h: Vec3) -> f32 {
        if h.z <= 0.0 {
            return 0.0;
        }
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        let z2 = h.z * h.z;
        let e = ((h.x / ax) * (h.x / ax) + (h.y / ay) * (h.y / ay)) / z2;
        // Past e = 80 D is below 1e-30 wherever h_z⁴ is representable: call it zero rather than
        // risk exp(−e)/h_z⁴ = 0/0 near the horizon.
        if e.is_nan() || e >= 80.0 {
            return 0.0;
        }
        (-e).exp() / (PI * ax * ay * z2 * z2)
    }

    fn lambda(&self, w: Vec3) -> f32 {
        let t = stretched_tan2(w, self.alpha_x, self.alpha_y);
        lambda_of_a(1.0 / (t as f64).sqrt()) as f32
    }

    #[inline]
    fn alphas(&self) -> (f32, f32) {
        (self.alpha_x, self.alpha_y)
    }

    fn sample_normal(&self, u: Vec2) -> Vec3 {
        let r = (-(1.0 - u.x).max(f32::MIN_POSITIVE).ln()).sqrt();
        let (s, c) = (TAU * u.y).sin_cos();
        super::normal_from_slopes(r * c * self.alpha_x, r * s * self.alpha_y)
    }

    fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let (ax, ay) = (self.alpha_x as f64, self.alpha_y as f64);
        // Stretch wo to the α = 1 configuration.
        let (vx, vy, vz) = (ax * wo.x as f64, ay * wo.y as f64, wo.z as f64);
        let len = (vx * vx + vy * vy + vz * vz).sqrt();
        let (vx, vy, vz) = (vx / len, vy / len, vz / len);
        let sin_t = (vx * vx + vy * vy).sqrt();
        let (cos_p, sin_p) = if sin_t > 0.0 { (vx / sin_t, vy / sin_t) } else { (1.0, 0.0) };
        // Visible slopes for incidence in the xz plane.
        let sx = sample_visible_slope_x(vz, sin_t, u.x as f64);
        let sy = erf_inv((2.0 * u.y as f64 - 1.0).clamp(-1.0 + 1e-15, 1.0 - 1e-15));
        // Rotate to wo's azimuth, unstretch.
        let x = (cos_p * sx - sin_p * sy) * ax;
        let y = (sin_p * sx + cos_p * sy) * ay;
        super::normal_from_slopes(x as f32, y as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lambda_closed_form_limits() {
        // Normal incidence: no masking. a → 0 (grazing): Λ → ∞. Λ(1) by hand:
        // (erf 1 − 1)/2 + e⁻¹/(2√π) = (0.8427008 − 1)/2 + 0.3678794/3.5449077 = 0.0251274.
        assert_eq!(lambda_of_a(f64::INFINITY), 0.0);
        assert!(lambda_of_a(1e-9) > 1e7);
        assert!((lambda_of_a(1.0) - 0.025_127_4).abs() < 1e-6, "{}", lambda_of_a(1.0));
        // Λ decreases with a.
        let mut prev = f64::INFINITY;
        for i in 1..200 {
            let l = lambda_of_a(i as f64 * 0.05);
            assert!(l <= prev && l >= 0.0);
            prev = l;
        }
    }

    #[test]
    fn visible_slope_inverse_is_monotone_and_in_support() {
        for theta in [0.0f64, 0.3, 1.0, 1.4, 1.55, std::f64::consts::FRAC_PI_2 - 1e-4, std::f64::consts::FRAC_PI_2] {
            let (s, c) = theta.sin_cos();
            let mut prev = f64::NEG_INFINITY;
            for i in 0..=100 {
                let u = i as f64 / 100.0 * 0.999_999;
                let x = sample_visible_slope_x(c, s, u);
                assert!(x.is_finite() && x >= prev - 1e-9, "θ={theta} u={u}: {x} after {prev}");
                if s > 0.0 {
                    assert!(x <= c / s + 1e-9);
                }
                prev = x;
            }
        }
    }
}
