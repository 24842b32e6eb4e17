//! Ideal specular reflection: a perfect mirror, optionally weighted by a Fresnel term.
//!
//!   ρ(wi, wo) = R F(cos θo) δ(wi − R(wo)) / cos θi,   R(w) = (−w_x, −w_y, w_z),
//!
//! a delta lobe: all the light arriving from R(wo) leaves towards wo, scaled by the reflectance
//! R and the Fresnel reflectance F at incidence θo (F = 1 with `fresnel=none`). As a function ρ
//! is zero almost everywhere, so `eval` and `pdf` return 0; `sample` returns wi = R(wo) with the
//! lobe probability 1 as its pdf and the weight ρ cos θi / pdf = R F(cos θo), flagged `delta`.
//! Reciprocal (cos θi = cos θo on the lobe), isotropic, and energy conserving since R ≤ 1, F ≤ 1.
//! Source: the law of reflection (Hero of Alexandria, *Catoptrica*); Fresnel terms in `fresnel.rs`.

use crate::fresnel::{self, Fresnel};
use crate::model::{reflect_z, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use radiometry::{Rgb, Vec2, Vec3};

/// A perfect mirror.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// Reflectance per channel, in [0, 1].
    pub reflectance: Rgb,
    /// Angle-dependent reflectance multiplying it.
    pub fresnel: Fresnel,
}

impl Brdf for Mirror {
    fn fresnel(&self) -> Option<Fresnel> {
        Some(self.fresnel)
    }

    fn eval(&self, _wi: Vec3, _wo: Vec3) -> Rgb {
        Rgb::ZERO
    }

    fn pdf(&self, _wi: Vec3, _wo: Vec3) -> f32 {
        0.0
    }

    fn sample(&self, wo: Vec3, _uc: f32, _u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let weight = self.reflectance * self.fresnel.eval(wo.z);
        Some(BrdfSample { wi: reflect_z(wo), pdf: 1.0, weight, delta: true, eta: 1.0 })
    }

    fn claims(&self) -> Claims {
        Claims {
            reciprocal: true,
            energy_conserving: self.reflectance.max_channel() * self.fresnel.max_reflectance() <= 1.0,
            isotropic: true,
        }
    }

    fn has_delta(&self) -> bool {
        true
    }

    fn delta_only(&self) -> bool {
        true
    }
}

fn params() -> Vec<ParamSpec> {
    let mut v = vec![ParamSpec::rgb("reflectance", 0.0, 1.0, 1.0, "reflectance R multiplying the Fresnel term")];
    v.extend(fresnel::params("none"));
    v
}

fn make(p: &dyn ParamSource) -> Result<Mirror, ParamError> {
    Ok(Mirror { reflectance: p.rgb("reflectance"), fresnel: fresnel::from_params(p)? })
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "mirror",
    summary: "ideal specular reflection (a delta lobe), reflectance × optional Fresnel term",
    reference: "the law of reflection; Born & Wolf, Principles of Optics, §1.5 for the Fresnel terms",
    params,
    build: by_value!(make),
    showcase: &[&[("material", "Au"), ("fresnel", "conductor")], &[("fresnel", "dielectric"), ("eta", "1.5")]],
};

#[cfg(test)]
mod tests {
    use super::*;
    use radiometry::spherical_direction;

    #[test]
    fn reflects_about_the_normal_with_weight_r_times_f() {
        let m = Mirror { reflectance: Rgb::new(0.9, 0.5, 0.2), fresnel: Fresnel::None };
        let wo = spherical_direction(0.7, 1.3);
        let s = m.sample(wo, 0.3, Vec2::new(0.1, 0.9)).unwrap();
        assert!(s.delta && s.pdf == 1.0);
        assert_eq!(s.wi, Vec3::new(-wo.x, -wo.y, wo.z));
        assert_eq!(s.weight, Rgb::new(0.9, 0.5, 0.2));
        assert_eq!(m.eval(s.wi, wo), Rgb::ZERO);
        assert_eq!(m.pdf(s.wi, wo), 0.0);
        assert!(m.has_delta());
        assert!(m.sample(Vec3::new(0.6, 0.0, -0.8), 0.5, Vec2::splat(0.5)).is_none());
        assert!(m.sample(Vec3::X, 0.5, Vec2::splat(0.5)).is_none());
    }

    #[test]
    fn fresnel_weighting_at_normal_and_grazing_incidence() {
        // Glass: R0 = ((1.5 − 1)/(1.5 + 1))² = 0.04 at normal incidence, → 1 at grazing.
        let b = SPEC.build_with(&[("fresnel", "dielectric"), ("eta", "1.5")]).unwrap();
        let s = b.sample(Vec3::Z, 0.0, Vec2::ZERO).unwrap();
        assert!((s.weight.0[1] - 0.04).abs() < 1e-6, "{s:?}");
        let s = b.sample(spherical_direction(89.99f32.to_radians(), 0.0), 0.0, Vec2::ZERO).unwrap();
        assert!(s.weight.0[1] > 0.99, "{s:?}");
        // Gold at normal incidence: ((η−1)² + k²)/((η+1)² + k²) per channel.
        let b = SPEC.build_with(&[("material", "Au"), ("reflectance", "0.5")]).unwrap_err();
        assert!(b.to_string().contains("fresnel"), "{b}");
        let g = SPEC.build_with(&[("material", "Au"), ("fresnel", "conductor"), ("reflectance", "0.5")]).unwrap();
        let s = g.sample(Vec3::Z, 0.0, Vec2::ZERO).unwrap();
        let au = fresnel::AU;
        for c in 0..3 {
            let want = 0.5 * fresnel::normal_reflectance(au.eta.0[c], au.k.0[c]);
            assert!((s.weight.0[c] - want).abs() < 1e-5, "channel {c}: {s:?} vs {want}");
        }
    }
}
