//! Mitsuba 3's `thindielectric`: a thin pane of glass, both faces parallel, so light leaves it
//! going the way it came in (window glass, a soap film). With r = F(|cos θo|, η) the exact
//! Fresnel reflectance of one face, the pane's inter-reflections sum to
//!
//!   R = r + (1 − r)² r / (1 − r²) = 2r / (1 + r),   T = 1 − R,
//!
//! a delta reflection wi = (−wo_x, −wo_y, wo_z) of weight R·`specular_reflectance` and a delta
//! transmission wi = −wo of weight T·`specular_transmittance`; a sample picks reflection with
//! probability R, so the weights are the tints. Both faces behave alike; nothing refracts (η = 1).
//! Source: Mitsuba 3, `src/bsdfs/thindielectric.cpp` (behaviour only); Born & Wolf §1.5.

use crate::dielectric::eta_from_params;
use crate::fresnel;
use crate::fresnel::Fresnel;
use crate::model::{reflect_z, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource};
use crate::registry::{by_value, ModelSpec};
use radiometry::{Rgb, Vec2, Vec3};

/// A thin dielectric pane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectric {
    /// Relative index int_ior / ext_ior of the pane.
    pub eta: f32,
    /// Tint of the reflected lobe.
    pub reflectance: Rgb,
    /// Tint of the transmitted lobe.
    pub transmittance: Rgb,
}

impl ThinDielectric {
    /// The pane's reflectance R at incidence cosine `cos` (either side).
    pub fn reflectance_at(&self, cos: f32) -> f32 {
        let r = fresnel::dielectric(cos.abs(), self.eta);
        2.0 * r / (1.0 + r)
    }
}

impl Brdf for ThinDielectric {
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
        if wo.z == 0.0 {
            return None;
        }
        let r = self.reflectance_at(wo.z);
        Some(if uc < r {
            BrdfSample { wi: reflect_z(wo), pdf: r, weight: self.reflectance, delta: true, eta: 1.0 }
        } else {
            BrdfSample { wi: -wo, pdf: 1.0 - r, weight: self.transmittance, delta: true, eta: 1.0 }
        })
    }

    fn claims(&self) -> Claims {
        Claims {
            reciprocal: true,
            energy_conserving: self.reflectance.max_channel().max(self.transmittance.max_channel()) <= 1.0,
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
}

fn make(p: &dyn ParamSource) -> Result<ThinDielectric, ParamError> {
    Ok(ThinDielectric {
        eta: eta_from_params(p),
        reflectance: p.rgb("specular_reflectance"),
        transmittance: p.rgb("specular_transmittance"),
    })
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "thindielectric",
    summary: "a thin glass pane: delta reflection 2r/(1+r) and straight-through transmission (transmits)",
    reference: "Mitsuba 3 thindielectric; Born & Wolf, Principles of Optics, §1.5",
    params: crate::dielectric::interface_params,
    build: by_value!(make),
    showcase: &[&[("int_ior", "water")]],
};

#[cfg(test)]
#[allow(clippy::excessive_precision)] // Mitsuba's reference numbers, as it prints them
mod tests {
    use super::*;

    #[test]
    fn pane_reflectance_matches_mitsuba() {
        // Mitsuba 3.9.1 with its defaults (bk7 in air, η = 1.50418).
        let t = SPEC.build_with(&[]).unwrap();
        let pane = ThinDielectric { eta: 1.5046 / 1.000277, reflectance: Rgb::ONE, transmittance: Rgb::ONE };
        for (deg, want) in [(0.0f32, 0.077914354), (30.0, 0.080739049), (60.0, 0.16493541), (89.0, 0.94974338)] {
            let r = pane.reflectance_at(deg.to_radians().cos());
            assert!((r - want).abs() < 2e-6, "{deg}°: {r} vs {want}");
        }
        let wo = radiometry::spherical_direction(0.5, 1.0);
        let refl = t.sample(wo, 0.01, Vec2::ZERO).unwrap();
        assert!(refl.delta && refl.wi == reflect_z(wo) && refl.weight == Rgb::ONE);
        let through = t.sample(-wo, 0.9, Vec2::ZERO).unwrap();
        assert!(through.wi == wo && through.eta == 1.0 && (through.pdf + pane.reflectance_at(wo.z) - 1.0).abs() < 1e-6);
    }
}
