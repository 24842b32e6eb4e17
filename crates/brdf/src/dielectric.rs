//! A smooth dielectric interface (Mitsuba 3's `dielectric`): glass, water, diamond.
//!
//! With η = int_ior / ext_ior (the interior, below the surface, over the exterior above), a
//! direction wo meets the interface at cos θo = wo.z; light from the side of wo sees the
//! relative index η_t = η when wo.z > 0 and 1/η when wo.z < 0. Two delta lobes:
//!
//!   reflection   wi = (−wo_x, −wo_y, wo_z),          weight R_s F(cos θo)
//!   refraction   wi = (−wo_x/η_t, −wo_y/η_t, −sgn(wo_z) cos θt),  cos²θt = 1 − (1 − cos²θo)/η_t²,
//!                weight T_s (1 − F(cos θo)) / η_t²,
//!
//! F the exact unpolarised Fresnel reflectance (`fresnel::dielectric`), R_s and T_s the
//! `specular_reflectance` and `specular_transmittance` tints (1 is physical). Total internal
//! reflection (sin θt > 1) gives F = 1. The 1/η_t² is radiance's change of solid angle across
//! the interface (L/n² is invariant along a ray): refraction from outside into glass of η 1.5
//! brightens radiance by 2.25 in the glass. A sample picks reflection with probability F and
//! refraction otherwise, so the Fresnel factor cancels from the weights; the refracted sample
//! carries `eta` = η_t (the index ratio crossed, n(wi side)/n(wo side)).
//!
//! As functions ρ and pdf are zero almost everywhere; only `sample` produces light.
//! Sources: Snell's law and the Fresnel equations (Born & Wolf, *Principles of Optics*, §1.5);
//! radiance scaling and generalised reciprocity, E. Veach, *Robust Monte Carlo Methods for
//! Light Transport Simulation*, 1997, §5.2; Mitsuba 3, `src/bsdfs/dielectric.cpp`, for the
//! parameter names and defaults.

use crate::fresnel;
use crate::fresnel::Fresnel;
use crate::model::{reflect_z, refract, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use radiometry::{Rgb, Vec2, Vec3};

/// A smooth dielectric interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// Relative index int_ior / ext_ior of the medium below the surface over the one above.
    pub eta: f32,
    /// Tint of the reflected lobe, in [0, 1].
    pub reflectance: Rgb,
    /// Tint of the refracted lobe, in [0, 1].
    pub transmittance: Rgb,
}

/// η_t seen from a direction with this cos θ, for an interface of relative index `eta` (below
/// over above): the index across the surface over the index on the direction's side.
#[inline]
pub fn eta_seen_from(eta: f32, cos: f32) -> f32 {
    if cos > 0.0 {
        eta
    } else {
        1.0 / eta
    }
}

impl Brdf for Dielectric {
    fn fresnel(&self) -> Option<Fresnel> {
        Some(Fresnel::Dielectric { eta: self.eta })
    }

    fn eval(&self, _wi: Vec3, _wo: Vec3) -> Rgb {
        Rgb::ZERO
    }

    fn pdf(&self, _wi: Vec3, _wo: Vec3) -> f32 {
        0.0
    }

    fn sample(&self, wo: Vec3, uc: f32, _u: Vec2) -> Option<BrdfSample> {
        let cos_o = wo.z;
        if cos_o == 0.0 || !cos_o.is_finite() {
            return None;
        }
        let f = fresnel::dielectric(cos_o, self.eta);
        // Strictly below F, so that F = 0 (η = 1) never picks reflection with probability 0.
        if uc < f {
            return Some(BrdfSample::reflected(reflect_z(wo), f, self.reflectance, true));
        }
        let eta_t = eta_seen_from(self.eta, cos_o);
        let wi = refract(wo, Vec3::Z, eta_t)?;
        let weight = self.transmittance * (1.0 / (eta_t * eta_t));
        Some(BrdfSample { wi, pdf: 1.0 - f, weight, delta: true, eta: eta_t })
    }

    fn claims(&self) -> Claims {
        Claims {
            reciprocal: true,
            energy_conserving: self.reflectance.max_channel() <= 1.0 && self.transmittance.max_channel() <= 1.0,
            isotropic: true,
        }
    }

    fn has_delta(&self) -> bool {
        true
    }

    fn delta_only(&self) -> bool {
        true
    }

    fn transmits(&self) -> bool {
        true
    }

    fn eta(&self) -> f32 {
        self.eta
    }
}

/// Mitsuba's defaults: BK7 glass inside, air outside.
pub const DEFAULT_INT_IOR: f64 = 1.5046;
/// Air at standard conditions.
pub const DEFAULT_EXT_IOR: f64 = 1.000277;

/// `int_ior`, `ext_ior`, `specular_reflectance`, `specular_transmittance`, shared with
/// `roughdielectric`.
pub fn interface_params() -> Vec<ParamSpec> {
    vec![
        crate::ior::param("int_ior", DEFAULT_INT_IOR, "index of refraction inside, below the surface (BK7 1.5046)"),
        crate::ior::param("ext_ior", DEFAULT_EXT_IOR, "index of refraction outside, above the surface (air 1.000277)"),
        ParamSpec::rgb("specular_reflectance", 0.0, 1.0, 1.0, "tint of the reflected light (1 is physical)"),
        ParamSpec::rgb("specular_transmittance", 0.0, 1.0, 1.0, "tint of the transmitted light (1 is physical)"),
    ]
}

/// The relative index int_ior / ext_ior.
pub fn eta_from_params(p: &dyn ParamSource) -> f32 {
    (p.float("int_ior") as f64 / p.float("ext_ior") as f64) as f32
}

fn make(p: &dyn ParamSource) -> Result<Dielectric, ParamError> {
    Ok(Dielectric {
        eta: eta_from_params(p),
        reflectance: p.rgb("specular_reflectance"),
        transmittance: p.rgb("specular_transmittance"),
    })
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "dielectric",
    summary: "smooth glass: Fresnel-weighted delta reflection and refraction, total internal reflection (transmits)",
    reference: "Born & Wolf, Principles of Optics, §1.5; Veach 1997, §5.2 (radiance across an interface)",
    params: interface_params,
    build: by_value!(make),
    showcase: &[
        &[("int_ior", "1"), ("ext_ior", "1.333")],
        &[("int_ior", "2.419"), ("specular_transmittance", "0.9,0.6,0.3")],
    ],
};

#[cfg(test)]
mod tests {
    use super::*;
    use radiometry::spherical_direction;

    fn glass() -> Dielectric {
        Dielectric { eta: 1.5, reflectance: Rgb::ONE, transmittance: Rgb::ONE }
    }

    #[test]
    fn snell_law_holds_and_refraction_reverses() {
        let g = glass();
        for theta in [0.0f32, 0.3, 0.9, 1.4, 1.56] {
            let wo = spherical_direction(theta, 0.8);
            // uc just below 1 always refracts (F < 1 from outside).
            let s = g.sample(wo, 0.999_999, Vec2::ZERO).unwrap();
            assert!(s.wi.z < 0.0 && (s.wi.length() - 1.0).abs() < 1e-6, "{s:?}");
            let sin_o = (1.0 - wo.z * wo.z).sqrt();
            let sin_t = (1.0 - s.wi.z * s.wi.z).sqrt();
            assert!((sin_o - 1.5 * sin_t).abs() < 1e-5, "n1 sin θ1 = n2 sin θ2 at θ {theta}");
            assert_eq!(s.eta, 1.5);
            // Back from inside along the refracted ray: the original direction, η inverted.
            let back = g.sample(s.wi, 0.999_999, Vec2::ZERO).unwrap();
            assert!((back.wi - wo).length() < 1e-5 && (back.eta - 1.0 / 1.5).abs() < 1e-7, "{back:?}");
        }
    }

    #[test]
    fn weights_are_tints_over_eta_squared_and_probabilities_are_fresnel() {
        let g = Dielectric { eta: 1.5, reflectance: Rgb::new(0.9, 0.8, 0.7), transmittance: Rgb::new(0.5, 0.6, 1.0) };
        let r0 = ((1.5f32 - 1.0) / 2.5).powi(2);
        let r = g.sample(Vec3::Z, 0.0, Vec2::ZERO).unwrap();
        assert!(r.delta && r.wi == Vec3::Z && (r.pdf - r0).abs() < 1e-7 && r.eta == 1.0);
        assert_eq!(r.weight, g.reflectance);
        let t = g.sample(Vec3::Z, 0.5, Vec2::ZERO).unwrap();
        assert!((t.pdf - (1.0 - r0)).abs() < 1e-7 && t.wi == -Vec3::Z);
        assert!((t.weight - g.transmittance * (1.0 / 2.25)).max_channel().abs() < 1e-7);
        let inside = g.sample(-Vec3::Z, 0.5, Vec2::ZERO).unwrap();
        assert!((inside.weight - g.transmittance * 2.25).max_channel().abs() < 1e-6 && inside.wi == Vec3::Z);
        assert!(g.sample(Vec3::X, 0.5, Vec2::ZERO).is_none(), "grazing wo has no sample");
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        let g = glass();
        let critical = (1.0f32 / 1.5).asin();
        for theta in [critical + 1e-3, 1.0, 1.5] {
            let wo = -spherical_direction(theta, 0.3);
            let wo = Vec3::new(-wo.x, -wo.y, wo.z);
            for uc in [0.0, 0.5, 0.999_999] {
                let s = g.sample(wo, uc, Vec2::ZERO).unwrap();
                assert!(s.wi.z < 0.0 && s.pdf == 1.0 && s.weight == Rgb::ONE, "θ {theta}: {s:?}");
            }
        }
        // Just inside the critical angle light still leaves.
        let wo = spherical_direction(critical - 1e-3, 0.3);
        let s = g.sample(Vec3::new(wo.x, wo.y, -wo.z), 0.999_999, Vec2::ZERO).unwrap();
        assert!(s.wi.z > 0.0);
    }

    #[test]
    fn refraction_agrees_with_fresnel_on_total_internal_reflection() {
        for cos in [-1.0f32, -0.9, -0.75, -0.7, -0.5, -0.1, 0.1, 0.5, 1.0] {
            let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
            let eta_t = if cos > 0.0 { 1.5 } else { 1.0 / 1.5 };
            let tir = refract(wo, Vec3::Z, eta_t).is_none();
            assert_eq!(tir, fresnel::dielectric(cos, 1.5) == 1.0, "cos {cos}");
        }
    }
}
