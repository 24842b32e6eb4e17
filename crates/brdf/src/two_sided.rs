//! Two one-sided models back to back (Mitsuba 3's `twosided`): the front model where wo is
//! above the surface, the back model, mirrored, where it is below.
//!
//!   ρ(wi, wo) = ρ_front(wi, wo)          for wo.z > 0,
//!   ρ(wi, wo) = ρ_back(M wi, M wo)       for wo.z < 0,   M(x, y, z) = (x, y, −z),
//!
//! likewise for the pdf, and a back sample is drawn for M wo and mirrored back. The mirror keeps
//! the tangent frame (x, y) as Mitsuba does, so an anisotropic back side is aligned with the
//! front. Nothing crosses the surface: a pair on opposite sides gets zero from the nested
//! models, which only reflect. Like Mitsuba, a model that transmits cannot be nested (its two
//! sides are already defined). Source: Mitsuba 3, `src/bsdfs/twosided.cpp` (behaviour only).

use crate::model::{BoxedBrdf, Brdf, BrdfSample, Claims, PhongTerms};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{build_item, by_value, ModelSpec};
use radiometry::{Rgb, Vec2, Vec3};

/// A surface that reflects on both sides.
#[derive(Clone, Copy, Debug)]
pub struct TwoSided<F, B> {
    front: F,
    back: B,
}

/// Why a model cannot be made two-sided.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("only models without transmission can be made two-sided (Mitsuba's twosided refuses them too)")]
pub struct TransmissiveNested;

/// The mirror image of `w` in the surface plane.
#[inline]
fn mirror(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

impl<F: Brdf, B: Brdf> TwoSided<F, B> {
    /// `front` on the front side and `back` on the back side (the same model for both is the
    /// usual case); an error when either transmits.
    pub fn new(front: F, back: B) -> Result<Self, TransmissiveNested> {
        if front.transmits() || back.transmits() {
            return Err(TransmissiveNested);
        }
        Ok(TwoSided { front, back })
    }
}

impl<F: Brdf, B: Brdf> Brdf for TwoSided<F, B> {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wo.z > 0.0 {
            self.front.eval(wi, wo)
        } else if wo.z < 0.0 {
            self.back.eval(mirror(wi), mirror(wo))
        } else {
            Rgb::ZERO
        }
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wo.z > 0.0 {
            self.front.pdf(wi, wo)
        } else if wo.z < 0.0 {
            self.back.pdf(mirror(wi), mirror(wo))
        } else {
            0.0
        }
    }

    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        if wo.z > 0.0 {
            self.front.eval_pdf(wi, wo)
        } else if wo.z < 0.0 {
            self.back.eval_pdf(mirror(wi), mirror(wo))
        } else {
            (Rgb::ZERO, 0.0)
        }
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z > 0.0 {
            self.front.sample(wo, uc, u)
        } else if wo.z < 0.0 {
            let s = self.back.sample(mirror(wo), uc, u)?;
            Some(BrdfSample { wi: mirror(s.wi), ..s })
        } else {
            None
        }
    }

    fn claims(&self) -> Claims {
        let (f, b) = (self.front.claims(), self.back.claims());
        Claims {
            reciprocal: f.reciprocal && b.reciprocal,
            energy_conserving: f.energy_conserving && b.energy_conserving,
            isotropic: f.isotropic && b.isotropic,
        }
    }

    fn has_delta(&self) -> bool {
        self.front.has_delta() || self.back.has_delta()
    }

    fn back_side(&self) -> bool {
        true
    }

    fn fresnel(&self) -> Option<crate::fresnel::Fresnel> {
        self.front.fresnel()
    }

    fn phong_terms(&self) -> Option<PhongTerms> {
        self.front.phong_terms()
    }
}

fn params() -> Vec<ParamSpec> {
    vec![
        ParamSpec::model("bsdf", "lambert", "the model on the front side (and the back, unless 'back' is given)"),
        ParamSpec::model("back", "", "the model on the back side; empty: the front one, mirrored"),
    ]
}

fn make(p: &dyn ParamSource) -> Result<TwoSided<BoxedBrdf, BoxedBrdf>, ParamError> {
    let back = if p.model("back").is_empty() { p.model("bsdf") } else { p.model("back") };
    TwoSided::new(build_item(p.model("bsdf"))?, build_item(back)?)
        .map_err(|e| ParamError::Inconsistent(format!("parameters 'bsdf' and 'back': {e}")))
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "twosided",
    summary: "Mitsuba's twosided: a one-sided model on both sides, or two models back to back",
    reference: "Mitsuba 3 twosided",
    params,
    build: by_value!(make),
    showcase: &[&[("bsdf", "ward:alpha_u=0.1:alpha_v=0.3"), ("back", "lambert:albedo=0.3")]],
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lambert::Lambert;
    use std::sync::Arc;

    #[test]
    fn back_side_is_the_mirrored_back_model() {
        let front: Arc<dyn Brdf> = Arc::new(Lambert { albedo: Rgb::splat(0.8) });
        let back: Arc<dyn Brdf> = Arc::new(Lambert { albedo: Rgb::splat(0.2) });
        let t = TwoSided::new(front.clone(), back.clone()).unwrap();
        let (wi, wo) = (Vec3::new(0.6, 0.0, 0.8), Vec3::new(0.0, 0.6, 0.8));
        assert_eq!(t.eval(wi, wo), front.eval(wi, wo));
        assert_eq!(t.eval(mirror(wi), mirror(wo)), back.eval(wi, wo));
        assert_eq!(t.eval(mirror(wi), wo), Rgb::ZERO, "nothing crosses the surface");
        assert_eq!(t.pdf(mirror(wi), mirror(wo)), back.pdf(wi, wo));
        let s = t.sample(mirror(wo), 0.3, Vec2::new(0.2, 0.7)).unwrap();
        let b = back.sample(wo, 0.3, Vec2::new(0.2, 0.7)).unwrap();
        assert_eq!(s.wi, mirror(b.wi));
        assert_eq!(s.weight, b.weight);
        assert!(t.back_side() && !t.transmits());
        assert!(t.sample(Vec3::X, 0.3, Vec2::splat(0.5)).is_none());
    }

    #[test]
    fn refuses_a_transmitting_model() {
        let glass: Arc<dyn Brdf> =
            Arc::new(crate::dielectric::Dielectric { eta: 1.5, reflectance: Rgb::ONE, transmittance: Rgb::ONE });
        assert!(TwoSided::new(glass.clone(), glass).is_err());
    }
}
