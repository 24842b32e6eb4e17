//! Mitsuba 3's `blendbsdf`: two models mixed by a weight w ∈ [0, 1] (0: the first, 1: the
//! second), ρ = (1 − w) ρ_0 + w ρ_1, pdf = (1 − w) p_0 + w p_1.
//!
//! Sampling picks model k with probability P_k (w for the second) and, as Mitsuba 3.9.1 does,
//! completes the sample with the mixture: pdf = P_k p_k + P_j p_j(wi) and weight =
//! (P_k ρ_k cos + P_j ρ_j(wi) cos) / pdf, where a delta lobe's p_k is its selection probability
//! and its ρ_k cos that times its weight. For two smooth lobes this is the one-sample mixture
//! estimator; a delta lobe mixed with a smooth one comes out weighted low (e.g. half a mirror on
//! black: 0.38 instead of 0.5 under uniform light), which gonio keeps so that scenes render as
//! in Mitsuba. Source: Mitsuba 3, `src/bsdfs/blendbsdf.cpp` (behaviour only).

use crate::model::{BoxedBrdf, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use radiometry::{Rgb, Vec2, Vec3};

/// Two models, mixed.
#[derive(Clone, Copy, Debug)]
pub struct Blend<A, B> {
    /// The weight of `second`, in [0, 1].
    pub weight: f32,
    /// The model at weight 0.
    pub first: A,
    /// The model at weight 1.
    pub second: B,
}

impl<A: Brdf, B: Brdf> Brdf for Blend<A, B> {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        self.first.eval(wi, wo) * (1.0 - self.weight) + self.second.eval(wi, wo) * self.weight
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        (1.0 - self.weight) * self.first.pdf(wi, wo) + self.weight * self.second.pdf(wi, wo)
    }

    /// Each nested model's own `eval_pdf`, mixed as `eval` and `pdf` mix them.
    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        let ((r1, p1), (r2, p2)) = (self.first.eval_pdf(wi, wo), self.second.eval_pdf(wi, wo));
        let w = self.weight;
        (r1 * (1.0 - w) + r2 * w, (1.0 - w) * p1 + w * p2)
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        let w = self.weight;
        let (second, p_k, uc) = if w >= 1.0 || (w > 0.0 && uc <= w) {
            (true, w, (uc / w).min(1.0 - f32::EPSILON))
        } else {
            (false, 1.0 - w, ((uc - w) / (1.0 - w)).clamp(0.0, 1.0 - f32::EPSILON))
        };
        let s = if second { self.second.sample(wo, uc, u)? } else { self.first.sample(wo, uc, u)? };
        let (rho_j, pdf_j) = if second { self.first.eval_pdf(s.wi, wo) } else { self.second.eval_pdf(s.wi, wo) };
        let p_j = 1.0 - p_k;
        let pdf = p_k * s.pdf + p_j * pdf_j;
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let value = s.weight * (p_k * s.pdf) + rho_j * (p_j * s.wi.z.abs());
        Some(BrdfSample { pdf, weight: value / pdf, ..s })
    }

    fn claims(&self) -> Claims {
        let (a, b) = (self.first.claims(), self.second.claims());
        Claims {
            reciprocal: a.reciprocal && b.reciprocal,
            energy_conserving: a.energy_conserving && b.energy_conserving,
            isotropic: a.isotropic && b.isotropic,
        }
    }

    fn has_delta(&self) -> bool {
        self.first.has_delta() || self.second.has_delta()
    }

    fn transmits(&self) -> bool {
        self.first.transmits() || self.second.transmits()
    }

    fn back_side(&self) -> bool {
        self.first.back_side() || self.second.back_side()
    }

    fn eta(&self) -> f32 {
        if self.first.transmits() {
            self.first.eta()
        } else {
            self.second.eta()
        }
    }
}

fn params() -> Vec<ParamSpec> {
    vec![
        ParamSpec::float("weight", 0.0, 1.0, 0.5, "weight w of the second model (0: the first alone, 1: the second)"),
        ParamSpec::model("bsdf_0", "lambert", "the model at weight 0"),
        ParamSpec::model("bsdf_1", "ggx", "the model at weight 1"),
    ]
}

fn make(p: &dyn ParamSource) -> Result<Blend<BoxedBrdf, BoxedBrdf>, ParamError> {
    Ok(Blend {
        weight: p.float("weight"),
        first: crate::registry::build_item(p.model("bsdf_0"))?,
        second: crate::registry::build_item(p.model("bsdf_1"))?,
    })
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "blendbsdf",
    summary: "Mitsuba's blendbsdf: (1 − w) × one model + w × another",
    reference: "Mitsuba 3 blendbsdf",
    params,
    build: by_value!(make),
    showcase: &[&[("weight", "0.3"), ("bsdf_0", "lambert:albedo=0.2"), ("bsdf_1", "beckmann:alpha=0.3")]],
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lambert::Lambert;

    #[test]
    fn mixture_and_mitsubas_delta_weighting() {
        let first = Lambert { albedo: Rgb::splat(0.2) };
        let mirror = crate::mirror::Mirror { reflectance: Rgb::ONE, fresnel: crate::fresnel::Fresnel::None };
        let b = Blend { weight: 0.3, first, second: mirror };
        // Mitsuba 3.9.1, wi = normalize(0.3, −0.2, 0.9) (our wo): s1 = 0.1 → the mirror, pdf
        // 0.5068363, weight 0.673526; s1 = 0.5 → diffuse, pdf 0.21831509, weight 0.2.
        let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
        let s = b.sample(wo, 0.1, Vec2::new(0.4, 0.6)).unwrap();
        assert!(s.delta && (s.pdf - 0.5068363).abs() < 1e-6 && (s.weight.0[0] - 0.673526).abs() < 1e-6, "{s:?}");
        let s = b.sample(wo, 0.5, Vec2::new(0.4, 0.6)).unwrap();
        assert!(!s.delta && (s.pdf - 0.7 * s.wi.z / std::f32::consts::PI).abs() < 1e-6);
        assert!((s.weight.0[0] - 0.2).abs() < 1e-6);
        assert_eq!(b.eval(s.wi, wo), first.eval(s.wi, wo) * 0.7);
    }
}
