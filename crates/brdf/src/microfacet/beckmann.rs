//! The Beckmann distribution of microfacet normals, anisotropic.
//!
//! D(h) = exp(−(h_x²/α_x² + h_y²/α_y²) / h_z²) / (π α_x α_y h_z⁴) for h_z > 0: Gaussian
//! slopes, P22(x̃, ỹ) = exp(−x̃² − ỹ²)/π for α = 1, stretched by (α_x, α_y).
//! Smith: Λ(w) = (erf(a) − 1)/2 + exp(−a²) / (2a√π), a = 1/(α(w) tan θ) = w_z / √(w_x²α_x² + w_y²α_y²).
//! Visible normals (E. Heitz & E. d'Eon, "Importance Sampling Microfacet-Based BSDFs using
//! the Distribution of Visible Normals", EGSR 2014): stretch wo to α = 1, where for incidence θ
//! in the xz plane the visible slope density is ∝ (cos θ − x̃ sin θ) exp(−x̃² − ỹ²)/π on
//! x̃ < cot θ. It factors: ỹ is N(0, ½) on its own, ỹ = erfinv(2u − 1), and x̃ has the CDF
//! [cos θ (1 + erf x̃) + sin θ exp(−x̃²)/√π] / (2 cos θ (1 + Λ)), inverted as in W. Jakob, "An
//! Improved Visible Normal Sampling Routine for the Beckmann Distribution" (2014): in the variable
//! b = erf x̃ the CDF is nearly linear, and safeguarded Newton from his fitted initial guess
//! reaches |CDF − u| ≤ 10⁻⁶ in about three steps, all in f32 (`erf.rs`). The density of what is
//! sampled is D_wo to that tolerance: `pdf_visible` stays the exact D_wo. The slopes are then
//! rotated to wo's azimuth and unstretched.
//! Source: P. Beckmann & A. Spizzichino, *The Scattering of Electromagnetic Waves from Rough
//! Surfaces*, 1963; B. Walter et al., EGSR 2007 (Λ).

use super::erf::{erf, erfc, erfinv};
use super::{stretched_tan2, Ndf, MIN_ALPHA};
use radiometry::trig::sin_cos_pi;
use radiometry::{Vec2, Vec3};
use std::f32::consts::PI;

/// 1/√π.
const FRAC_1_SQRT_PI: f32 = 0.564_189_6;

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

/// Past a = 4, Λ(a) < 3·10⁻¹⁰: 1 + Λ rounds to 1 in f32, so Λ is taken as 0 there.
const LAMBDA_CUTOFF: f32 = 4.0;

/// Smith's Λ of the α = 1 Beckmann distribution as a function of a = cot θ.
fn lambda_of_a(a: f32) -> f32 {
    if a.is_nan() || a <= 0.0 {
        return f32::INFINITY;
    }
    if a >= LAMBDA_CUTOFF {
        return 0.0;
    }
    // (erf a − 1) written as −erfc a keeps the tail's relative accuracy at large a.
    (0.5 * ((-a * a).exp() * FRAC_1_SQRT_PI / a - erfc(a))).max(0.0)
}

/// Iterations stop once the CDF is within this of u (relative to its normaliser); f32 rounding
/// of the CDF is ≈ 2⁻²³ of it, so this is reachable, and the sampled CDF is off by at most this.
const CDF_TOLERANCE: f32 = 1e-6;

/// Samples the α = 1 visible slope x̃ for incidence angle θ (cos, sin given), from u ∈ [0, 1).
///
/// Jakob's parameterisation: in b = erf(x̃) the unnormalised CDF is
/// F(b) = cos θ (1 + b) + sin θ exp(−erfinv(b)²)/√π, with F′(b) = cos θ − x̃ sin θ, nearly linear,
/// on b ∈ [−1, erf(cot θ)]; F(erf cot θ) = 2 cos θ (1 + Λ). Safeguarded Newton from his fitted
/// initial guess b₀ = b_max − (1 + b_max)(1 − u)^q(θ) takes one to three steps.
fn sample_visible_slope_x(cos_t: f32, sin_t: f32, u: f32) -> f32 {
    if sin_t <= 0.0 {
        // Normal incidence: x̃ is N(0, ½) like ỹ.
        return erfinv(2.0 * u - 1.0);
    }
    let cos_t = cos_t.max(0.0);
    let cot = cos_t / sin_t;
    let b_max = erf(cot);
    let norm = cos_t * (1.0 + b_max) + sin_t * FRAC_1_SQRT_PI * (-cot * cot).exp();
    let target = u * norm;
    let theta = sin_t.atan2(cos_t);
    let q = 1.0 + theta * (-0.876 + theta * (0.4265 - 0.0594 * theta));
    let (mut lo, mut hi) = (-1.0f32, b_max);
    let mut b = b_max - (1.0 + b_max) * (q * (1.0 - u).ln()).exp();
    for _ in 0..24 {
        if !(b > lo && b < hi) {
            b = 0.5 * (lo + hi);
        }
        let x = erfinv(b);
        let g = cos_t * (1.0 + b) + sin_t * FRAC_1_SQRT_PI * (-x * x).exp() - target;
        if g.abs() <= CDF_TOLERANCE * norm {
            return x;
        }
        if g > 0.0 {
            hi = b;
        } else {
            lo = b;
        }
        b -= g / (cos_t - x * sin_t);
    }
    erfinv(b.clamp(lo, hi))
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

    #[inline]
    fn lambda(&self, w: Vec3) -> f32 {
        let t = stretched_tan2(w, self.alpha_x, self.alpha_y);
        lambda_of_a(1.0 / t.sqrt())
    }

    #[inline]
    fn alphas(&self) -> (f32, f32) {
        (self.alpha_x, self.alpha_y)
    }

    fn sample_normal(&self, u: Vec2) -> Vec3 {
        let r = (-(1.0 - u.x).max(f32::MIN_POSITIVE).ln()).sqrt();
        let (s, c) = sin_cos_pi(2.0 * u.y);
        super::normal_from_slopes(r * c * self.alpha_x, r * s * self.alpha_y)
    }

    fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        let (ax, ay) = (self.alpha_x, self.alpha_y);
        // Stretch wo to the α = 1 configuration.
        let v = Vec3::new(ax * wo.x, ay * wo.y, wo.z).normalize();
        let sin_t = (v.x * v.x + v.y * v.y).sqrt();
        let (cos_p, sin_p) = if sin_t > 0.0 { (v.x / sin_t, v.y / sin_t) } else { (1.0, 0.0) };
        // Visible slopes for incidence in the xz plane.
        let sx = sample_visible_slope_x(v.z, sin_t, u.x);
        let sy = erfinv(2.0 * u.y - 1.0);
        // Rotate to wo's azimuth, unstretch.
        let x = (cos_p * sx - sin_p * sy) * ax;
        let y = (sin_p * sx + cos_p * sy) * ay;
        super::normal_from_slopes(x, y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use statrs::function::erf as reference;

    /// Λ(a) in f64 from the reference erfc.
    fn lambda_f64(a: f64) -> f64 {
        0.5 * ((-a * a).exp() / (a * std::f64::consts::PI.sqrt()) - reference::erfc(a))
    }

    #[test]
    fn lambda_closed_form_limits() {
        // Normal incidence: no masking. a → 0 (grazing): Λ → ∞. Λ(1) by hand:
        // (erf 1 − 1)/2 + e⁻¹/(2√π) = (0.8427008 − 1)/2 + 0.3678794/3.5449077 = 0.0251274.
        assert_eq!(lambda_of_a(f32::INFINITY), 0.0);
        assert_eq!(lambda_of_a(0.0), f32::INFINITY);
        assert!(lambda_of_a(1e-9) > 1e7);
        assert!((lambda_of_a(1.0) - 0.025_127_4).abs() < 1e-6, "{}", lambda_of_a(1.0));
        // Λ decreases with a.
        let mut prev = f32::INFINITY;
        for i in 1..200 {
            let l = lambda_of_a(i as f32 * 0.05);
            assert!(l <= prev && l >= 0.0);
            prev = l;
        }
    }

    #[test]
    fn lambda_matches_f64_to_f32_rounding_of_g1() {
        // What enters the model is G1 = 1/(1 + Λ): compare that, relative, against f64 with the
        // reference erfc. erfc's error (≤ 1.2e-7 + ε(8 + 3a²) relative, times erfc ≤ 1) and
        // the f32 rounding of e^{−a²}/(a√π) (a few ε relative to a term ≤ 1 + Λ) bound it by
        // ≈ 4e-7 (1 + Λ)/(1 + Λ) = 4e-7; the cut-off at a = 4 adds < 3e-10.
        let mut worst = 0.0f64;
        for i in 1..=40_000 {
            let a = i as f32 * 1e-4 + (i as f32 * 1e-3).powi(2);
            let want = 1.0 / (1.0 + lambda_f64(a as f64));
            let got = 1.0 / (1.0 + lambda_of_a(a) as f64);
            worst = worst.max((got - want).abs() / want);
        }
        println!("G1 from f32 Λ: max relative error {worst:.2e}");
        assert!(worst < 4e-7, "{worst}");
    }

    /// The exact (f64) CDF of the α = 1 visible slope x̃ for incidence θ, at x.
    fn slope_cdf_f64(cos_t: f64, sin_t: f64, x: f64) -> f64 {
        let f = |x: f64| cos_t * (1.0 + reference::erf(x)) + sin_t * (-x * x).exp() / std::f64::consts::PI.sqrt();
        let cot = if sin_t > 0.0 { cos_t / sin_t } else { f64::INFINITY };
        f(x) / f(cot)
    }

    #[test]
    fn visible_slope_inverse_is_monotone_accurate_and_in_support() {
        // The sampler inverts the CDF to CDF_TOLERANCE; erfinv's relative error 2.6e-7 moves x̃
        // by 2.6e-7 |x̃|, i.e. the CDF by that times the density (≤ 1.2 here), and erf's 2e-7
        // error in the normaliser adds as much: |F(x̃) − u| ≤ 1e-6 + 3.2e-7 + 2e-7 + rounding.
        let bound = CDF_TOLERANCE as f64 + 6e-7;
        let mut worst = 0.0f64;
        for theta in
            [0.0f32, 1e-3, 0.3, 1.0, 1.4, 1.55, std::f32::consts::FRAC_PI_2 - 1e-4, std::f32::consts::FRAC_PI_2]
        {
            let (s, c) = theta.sin_cos();
            let mut prev = f32::NEG_INFINITY;
            for i in 0..=10_000 {
                let u = i as f32 / 10_000.0 * 0.999_999;
                let x = sample_visible_slope_x(c, s, u);
                assert!(x.is_finite() && x >= prev, "θ={theta} u={u}: {x} after {prev}");
                if s > 0.0 {
                    assert!(x as f64 <= c as f64 / s as f64 + 1e-5, "θ={theta} u={u}: {x} beyond cot θ");
                }
                prev = x;
                // Below u = 3.5e-8 (x̃ < −3.9) the slope is clamped where erfinv's argument is.
                if u > 1e-7 {
                    let err = (slope_cdf_f64(c as f64, s as f64, x as f64) - u as f64).abs();
                    assert!(err <= bound, "θ={theta} u={u}: CDF(x̃ = {x}) off by {err:.2e}");
                    worst = worst.max(err);
                }
            }
        }
        println!("visible slope sampler: max |F(x̃) − u| = {worst:.2e} (bound {bound:.1e})");
    }
}
