//! Ward's anisotropic elliptical Gaussian reflection model.
//!
//!   ρ(wi, wo) = ρ_d/π + ρ_s exp(−tan²θh (cos²φh/α_x² + sin²φh/α_y²)) / (4π α_x α_y √(cos θi cos θo)),
//!
//! with h = (wi + wo)/|wi + wo| at polar angle θh and azimuth φh from the tangent (local x), so
//! tan²θh cos²φh = h_x²/h_z² and tan²θh sin²φh = h_y²/h_z². The lobe is reciprocal, and isotropic
//! exactly when α_x = α_y. Its constant makes the slope distribution (h_x/h_z, h_y/h_z) an exact
//! Gaussian, but ρ_s only approximates the albedo: at normal incidence it is ρ_s (1 − 3α² + O(α⁴)),
//! and the 1/√(cos θi cos θo) drives it past 1 at grazing for rough surfaces, so energy
//! conservation is not claimed.
//!
//! Sampling after Walter: with r² = −ln u₁ and ψ = 2π u₂, the slope (α_x r cos ψ, α_y r sin ψ) is
//! that Gaussian, i.e. φh = atan2(α_y sin ψ, α_x cos ψ) and
//! tan²θh = −ln u₁ / (cos²φh/α_x² + sin²φh/α_y²); the density of h in solid angle is
//! p_h = exp(−tan²θh (…)) / (π α_x α_y cos³θh) (slope area = dω_h / cos³θh), wi = 2(wo·h)h − wo,
//! and pdf(wi) = p_h / (4 wo·h). Draws that land below the surface are returned as `None`. The
//! specular weight is ρ_s (wo·h) cos³θh √(cos θi / cos θo).
//!
//! Sources: G. J. Ward, "Measuring and Modeling Anisotropic Reflection", SIGGRAPH 1992;
//! B. Walter, "Notes on the Ward BRDF", Cornell PCG technical report PCG-05-06, 2005.

use crate::combine;
use crate::model::{reflect_about_half_vector, same_upper_hemisphere, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use crate::roughness;
use radiometry::trig::sin_cos_pi;
use radiometry::{Rgb, Vec2, Vec3};
use std::f32::consts::PI;

// The smallest roughness, `roughness::ALPHA_MIN`, keeps the peak 1/(4π α_x α_y) far inside f32.
pub use crate::roughness::ALPHA_MIN;

/// Exponents beyond this give exp(−x) < 2⁻¹¹⁵, below anything visible; cutting there keeps
/// exp normal in f32 and keeps cos θh ≥ 1/√(1 + 80) away from the 1/cos³θh pole (α ≤ 1).
const EXPONENT_MAX: f32 = 80.0;

/// Smallest cos θi cos θo under the square root: ρ grows as 1/√(cos θi cos θo) towards grazing
/// (integrably); the clamp only keeps it finite within 1e-6 rad of the horizon.
const COS_PRODUCT_FLOOR: f32 = 1e-12;

/// Ward's specular lobe (the diffuse term is the `diffuse` parameter's Lambert lobe).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ward {
    /// Specular reflectance ρ_s per channel.
    pub ks: Rgb,
    /// Roughness along the tangent (local x).
    pub alpha_x: f32,
    /// Roughness along the bitangent (local y).
    pub alpha_y: f32,
}

/// The half-vector quantities of a direction pair.
struct Half {
    /// exp(−tan²θh (cos²φh/α_x² + sin²φh/α_y²)).
    gauss: f32,
    /// cos θh.
    cos_h: f32,
    /// wo·h.
    wo_h: f32,
}

impl Ward {
    /// The half-vector quantities of two upper-hemisphere directions; `None` where the lobe is
    /// negligible or h undefined.
    #[inline]
    fn half(&self, wi: Vec3, wo: Vec3) -> Option<Half> {
        if !same_upper_hemisphere(wi, wo) {
            return None;
        }
        // The exponent from the unnormalised h = wi + wo: tan²θh cos²φh = s_x²/s_z², and so on.
        // No normalisation rounding enters it, and it is symmetric in wi, wo bit for bit.
        let s = wi + wo;
        let e = (s.x * s.x / (self.alpha_x * self.alpha_x) + s.y * s.y / (self.alpha_y * self.alpha_y)) / (s.z * s.z);
        if e.is_nan() || e > EXPONENT_MAX {
            return None;
        }
        let len = s.length();
        // For unit wi, wo: wo·h = (1 + wi·wo)/|s| = |s|/2.
        Some(Half { gauss: (-e).exp(), cos_h: s.z / len, wo_h: 0.5 * len })
    }

    /// The solid-angle density of the sampled half vector, e^(−…)/(π α_x α_y cos³θh).
    #[inline]
    fn half_pdf(&self, h: &Half) -> f32 {
        h.gauss / (PI * self.alpha_x * self.alpha_y * h.cos_h * h.cos_h * h.cos_h)
    }

    /// ρ_s, the lobe's nominal albedo, used for the lobe-selection probability.
    pub fn nominal_albedo(&self) -> f32 {
        self.ks.max_channel()
    }
}

impl Brdf for Ward {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let Some(h) = self.half(wi, wo) else { return Rgb::ZERO };
        let norm = 4.0 * PI * self.alpha_x * self.alpha_y * (wi.z * wo.z).max(COS_PRODUCT_FLOOR).sqrt();
        self.ks * (h.gauss / norm)
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        let Some(h) = self.half(wi, wo) else { return 0.0 };
        self.half_pdf(&h) / (4.0 * h.wo_h)
    }

    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        // The slope m = (α_x r cos ψ, α_y r sin ψ), r² = −ln u₁, is the elliptical Gaussian;
        // the Gaussian is even, so h = (m, 1)/|(m, 1)| has the same law as (−m, 1)/|…|.
        let (sp, cp) = sin_cos_pi(2.0 * u.y);
        let r = (-u.x.ln()).sqrt();
        let h = Vec3::new(self.alpha_x * r * cp, self.alpha_y * r * sp, 1.0).normalize_or_zero();
        reflect_about_half_vector(self, wo, h)
    }

    fn claims(&self) -> Claims {
        Claims { reciprocal: true, energy_conserving: false, isotropic: self.alpha_x == self.alpha_y }
    }
}

fn params() -> Vec<ParamSpec> {
    let mut v = vec![ParamSpec::rgb("ks", 0.0, 1.0, 0.2, "specular reflectance ρ_s")];
    v.extend(roughness::params(
        0.1,
        "roughness α: RMS slope of the surface (√2 × the RMS slope along one axis), as Beckmann m",
    ));
    v.push(combine::diffuse_param());
    v
}

fn make(p: &dyn ParamSource) -> Result<combine::DiffuseGlossy<Ward>, ParamError> {
    let (ax, ay) = roughness::from_params(p)?;
    let lobe = Ward { ks: p.rgb("ks"), alpha_x: ax, alpha_y: ay };
    Ok(combine::with_diffuse(p, lobe, lobe.nominal_albedo()))
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "ward",
    summary: "Ward's anisotropic Gaussian lobe ρ_s e^(−tan²θh(…))/(4π α_x α_y √(cos θi cos θo)): reciprocal",
    reference: "Ward 1992, Measuring and Modeling Anisotropic Reflection; Walter 2005, Notes on the Ward BRDF",
    params,
    build: by_value!(make),
    // Brushed metal (anisotropic); a rough white lobe, much of it cut off by the horizon (its albedo
    // passes 1 only within ~0.3° of grazing, see the tests); a sharp lobe on a diffuse one.
    showcase: &[
        &[("ks", "0.8"), ("alpha_u", "0.05"), ("alpha_v", "0.3")],
        // Rough and bright: the 1/√(cos θi cos θo) factor lifts the albedo past 1 at grazing.
        &[("ks", "1"), ("alpha", "0.5")],
        &[("ks", "0.1"), ("alpha", "0.02"), ("diffuse", "0.7")],
    ],
};

#[cfg(test)]
mod tests {
    use super::*;
    use radiometry::integrate::irradiance_quadrature;
    use radiometry::spherical_direction;

    fn ward(ks: f32, ax: f32, ay: f32) -> Ward {
        Ward { ks: Rgb::splat(ks), alpha_x: ax, alpha_y: ay }
    }

    #[test]
    fn half_vector_density_integrates_to_one() {
        // The slope distribution is an exact Gaussian, so ∫ p_h dω_h = 1 over the hemisphere of h
        // (the cut at exponent 80 drops e^(−80) of it). half(h, h) describes the half vector h.
        for (ax, ay) in [(0.05f32, 0.05f32), (0.1, 0.3), (0.5, 0.5), (1.0, 0.2)] {
            let w = ward(1.0, ax, ay);
            let total = irradiance_quadrature(
                |d| {
                    let h = d.as_vec3();
                    w.half(h, h).map_or(0.0, |q| w.half_pdf(&q) as f64) / d.z.max(1e-300)
                },
                4096,
                1024,
            );
            assert!((total - 1.0).abs() < 2e-4, "α = ({ax}, {ay}): {total}");
        }
    }

    #[test]
    fn albedo_at_normal_incidence_tends_to_rho_s() {
        // At wo = n, wi = R(h) and the albedo is E[√(cos 2θh) cos⁴θh] over the slope Gaussian;
        // with t = tan²θh ~ Exp(mean α²) that is E[(1−t)^½ (1+t)^(−5/2)] = 1 − 3α² + 11α⁴ − 51α⁶ + …
        for alpha in [0.02f32, 0.05, 0.1] {
            let w = ward(1.0, alpha, alpha);
            let a = irradiance_quadrature(|d| w.eval(d.as_vec3(), Vec3::Z).0[0] as f64, 16384, 4);
            let a2 = (alpha as f64).powi(2);
            let series = 1.0 - 3.0 * a2 + 11.0 * a2 * a2 - 51.0 * a2 * a2 * a2;
            assert!((a - series).abs() < 2e-5, "α = {alpha}: {a} vs {series}");
        }
    }

    #[test]
    fn sample_weight_is_walters_closed_form() {
        // weight = ρ_s (wo·h) cos³θh √(cos θi / cos θo), h the half vector of the returned pair.
        let w = ward(0.7, 0.1, 0.25);
        let wo = spherical_direction(0.8, 2.0);
        let mut returned = 0;
        for i in 0..64 {
            for j in 0..64 {
                let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                let Some(s) = w.sample(wo, 0.5, u) else { continue };
                returned += 1;
                assert_eq!(s.pdf, w.pdf(s.wi, wo));
                let (wi, o) = (s.wi.as_dvec3(), wo.as_dvec3());
                let h = (wi + o).normalize();
                let want = 0.7 * o.dot(h) * h.z.powi(3) * (wi.z / o.z).sqrt();
                assert!((s.weight.0[0] as f64 - want).abs() < 1e-5 * want, "{s:?} vs {want}");
            }
        }
        assert!(returned > 3500, "{returned}");
    }

    #[test]
    fn anisotropy_follows_the_roughnesses() {
        let wo = spherical_direction(0.6, 0.0);
        let wi = spherical_direction(0.7, 3.0);
        let quarter = |w: Vec3| Vec3::new(-w.y, w.x, w.z);
        let aniso = ward(1.0, 0.1, 0.4);
        let iso = ward(1.0, 0.2, 0.2);
        assert!(!aniso.claims().isotropic && iso.claims().isotropic);
        let (a, b) = (aniso.eval(wi, wo).0[0], aniso.eval(quarter(wi), quarter(wo)).0[0]);
        assert!((a - b).abs() > 0.1 * a.max(b), "{a} {b}");
        let (a, b) = (iso.eval(wi, wo).0[0], iso.eval(quarter(wi), quarter(wo)).0[0]);
        assert!((a - b).abs() < 1e-5 * a, "{a} {b}");
        // Reciprocal bit for bit.
        assert_eq!(aniso.eval(wi, wo), aniso.eval(wo, wi));
    }

    #[test]
    fn albedo_passes_one_near_grazing_so_energy_is_not_claimed() {
        // ρ grows as 1/√cos θo: for α = 0.2 the albedo is 0.90 at normal incidence, 0.24 at 89°,
        // and 2.08 at 89.99° (measured with the sampler, 400k draws, ±0.006).
        let w = ward(1.0, 0.2, 0.2);
        let wo = spherical_direction(89.99f32.to_radians(), 0.3);
        let (m, se) = crate::check::albedo_f64(&w, wo, 100_000, 7);
        assert!(m[0] - 4.0 * se[0] > 1.0, "albedo {} ± {}", m[0], se[0]);
        assert!(!w.claims().energy_conserving);
    }

    #[test]
    fn roughness_zero_means_alpha_and_tiny_is_refused() {
        let spec = SPEC;
        assert!(spec.build_with(&[("alpha_u", "0"), ("alpha", "0.3")]).is_ok());
        let e = spec.build_with(&[("alpha_u", "0.0001")]).unwrap_err().to_string();
        assert!(e.contains("alpha_u"), "{e}");
    }
}
