//! Lambertian (ideal diffuse) reflection.
//!
//! ρ(wi, wo) = a / π, with `a` the albedo (the fraction of irradiance reflected).
//! The lecture's k_d is this BRDF value itself, in 1/sr: k_d = a / π. gonio takes the
//! albedo, which is bounded by 1 and reads the same in every renderer.
//! Sampling: cosine-weighted hemisphere, so the weight ρ cos θi / pdf is exactly `a`.
//! Source: J. H. Lambert, *Photometria*, 1760.

use crate::model::{same_upper_hemisphere, Brdf, BrdfSample, Claims, PhongTerms};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use radiometry::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use radiometry::{Rgb, Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// The ideal diffuse reflector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lambert {
    /// Albedo per channel, in [0, 1].
    pub albedo: Rgb,
}

impl Brdf for Lambert {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        self.albedo * FRAC_1_PI
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !same_upper_hemisphere(wi, wo) {
            return 0.0;
        }
        cosine_hemisphere_pdf(wi.z)
    }

    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = cosine_hemisphere(u);
        if wi.z <= 0.0 {
            return None;
        }
        Some(BrdfSample { wi, pdf: cosine_hemisphere_pdf(wi.z), weight: self.albedo, delta: false, eta: 1.0 })
    }

    fn claims(&self) -> Claims {
        Claims::PLAUSIBLE
    }

    fn phong_terms(&self) -> Option<PhongTerms> {
        Some(PhongTerms::diffuse(self.albedo))
    }

    fn lambertian(&self) -> Option<Rgb> {
        Some(self.albedo)
    }
}

fn params() -> Vec<ParamSpec> {
    vec![ParamSpec::rgb("albedo", 0.0, 1.0, 0.8, "diffuse albedo a; the lecture's k_d = a/π (1/sr)")]
}

fn make(p: &dyn ParamSource) -> Result<Lambert, ParamError> {
    Ok(Lambert { albedo: p.rgb("albedo") })
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "lambert",
    summary: "ideal diffuse reflection, ρ = albedo/π",
    reference: "Lambert 1760, Photometria",
    params,
    build: by_value!(make),
    showcase: &[&[("albedo", "1")]],
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_lambert_albedo_is_one() {
        // Albedo by quadrature of ρ cos θi over the hemisphere: a white Lambert reflects everything.
        let l = Lambert { albedo: Rgb::ONE };
        let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
        let h = radiometry::integrate::irradiance_quadrature(|w| l.eval(w.as_vec3(), wo).0[0] as f64, 512, 64);
        assert!((h - 1.0).abs() < 1e-4, "{h}");
        // The lecture's k_d in 1/sr: albedo = k_d · π.
        assert!((l.eval(Vec3::Z, wo).0[0] * std::f32::consts::PI - 1.0).abs() < 1e-6);
    }
}
