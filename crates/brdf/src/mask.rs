//! Mitsuba 3's `mask`: a nested model seen through an opacity α ∈ [0, 1]; the rest of the
//! light passes straight through the surface.
//!
//!   ρ(wi, wo) = α ρ_n(wi, wo),   pdf = α p_n,
//!
//! plus a delta transmission wi = −wo of weight 1 − α (a leaf cut out of a card). Sampling
//! picks the nested model with probability α (its sample, pdf × α, weight unchanged) and the
//! pass-through otherwise (pdf 1 − α, weight 1). Nothing refracts (η = 1), so the model is
//! reciprocal and conserves energy when the nested one does.
//! Source: Mitsuba 3, `src/bsdfs/mask.cpp` (behaviour only).

use crate::model::{Brdf, BrdfSample, Claims, PhongTerms};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use radiometry::{Rgb, Vec2, Vec3};

/// A nested model with an opacity.
#[derive(Clone, Copy, Debug)]
pub struct Mask<N> {
    /// The opacity α, in [0, 1].
    pub opacity: f32,
    /// The model seen where the surface is opaque.
    pub nested: N,
}

impl<N: Brdf> Brdf for Mask<N> {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        self.nested.eval(wi, wo) * self.opacity
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.nested.pdf(wi, wo) * self.opacity
    }

    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        let (f, p) = self.nested.eval_pdf(wi, wo);
        (f * self.opacity, p * self.opacity)
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        let a = self.opacity;
        if uc < a {
            let s = self.nested.sample(wo, (uc / a).min(1.0 - f32::EPSILON), u)?;
            return Some(BrdfSample { pdf: s.pdf * a, ..s });
        }
        if wo.z == 0.0 {
            return None;
        }
        Some(BrdfSample { wi: -wo, pdf: 1.0 - a, weight: Rgb::ONE, delta: true, eta: 1.0 })
    }

    fn claims(&self) -> Claims {
        self.nested.claims()
    }

    fn has_delta(&self) -> bool {
        true
    }

    fn transmits(&self) -> bool {
        true
    }

    fn fresnel(&self) -> Option<crate::fresnel::Fresnel> {
        self.nested.fresnel()
    }

    fn phong_terms(&self) -> Option<PhongTerms> {
        self.nested.phong_terms()
    }
}

fn params() -> Vec<ParamSpec> {
    vec![
        ParamSpec::float("opacity", 0.0, 1.0, 0.5, "opacity α: the share of light that meets the nested model"),
        ParamSpec::model("bsdf", "lambert", "the model where the surface is opaque"),
    ]
}

fn make(p: &dyn ParamSource) -> Result<Mask<crate::model::BoxedBrdf>, ParamError> {
    Ok(Mask { opacity: p.float("opacity"), nested: crate::registry::build_item(p.model("bsdf"))? })
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "mask",
    summary: "Mitsuba's mask: α × a nested model, the rest passing straight through (cut-outs)",
    reference: "Mitsuba 3 mask",
    params,
    build: by_value!(make),
    showcase: &[&[("opacity", "0.2"), ("bsdf", "ward:alpha=0.2:diffuse=0.5")]],
};

#[cfg(test)]
#[allow(clippy::excessive_precision)] // Mitsuba's reference numbers, as it prints them
mod tests {
    use super::*;
    use crate::lambert::Lambert;

    #[test]
    fn opacity_scales_the_lobe_and_the_rest_passes_through() {
        // Mitsuba 3.9.1: opacity 0.3 over diffuse 0.5, wi = normalize(0.3, −0.2, 0.9) (our wo),
        // wo = normalize(−0.4, 0.1, 0.8) (our wi): eval·cos 0.04244132, pdf 0.084882639.
        let m = Mask { opacity: 0.3, nested: Lambert { albedo: Rgb::splat(0.5) } };
        let view = Vec3::new(0.3, -0.2, 0.9).normalize();
        let light = Vec3::new(-0.4, 0.1, 0.8).normalize();
        assert!((m.eval(light, view).0[0] * light.z - 0.04244132).abs() < 1e-7);
        assert!((m.pdf(light, view) - 0.084882639).abs() < 1e-7);
        let s = m.sample(view, 0.2999, Vec2::new(0.4, 0.6)).unwrap();
        assert!(!s.delta && s.weight == Rgb::splat(0.5) && (s.pdf - 0.3 * s.wi.z / std::f32::consts::PI).abs() < 1e-6);
        let s = m.sample(view, 0.3, Vec2::new(0.4, 0.6)).unwrap();
        assert!(s.delta && s.wi == -view && (s.pdf - 0.7).abs() < 1e-7 && s.weight == Rgb::ONE);
        assert!(m.transmits() && m.has_delta());
    }
}
