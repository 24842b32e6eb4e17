//! Diffuse + glossy: a Lambert lobe added to any other lobe.
//!
//! ρ = ρ_diffuse + ρ_glossy. Sampling picks the diffuse lobe with probability
//! P = a_d / (a_d + a_s), where a_d is the diffuse albedo and a_s an estimate of the glossy
//! lobe's albedo, and the density is the mixture P·pdf_d + (1 − P)·pdf_s, so the weight
//! ρ cos θi / pdf stays exact whichever lobe was drawn (Veach 1997, one-sample MIS).
//! With a black diffuse lobe the sum is the glossy lobe itself, bit for bit.

use crate::lambert::Lambert;
use crate::model::{Brdf, BrdfSample, Claims, PhongTerms};
use crate::params::{ParamSource, ParamSpec};
use radiometry::{Rgb, Vec2, Vec3};

/// The `diffuse` parameter every glossy model takes: the albedo of an added Lambert lobe.
pub fn diffuse_param() -> ParamSpec {
    ParamSpec::rgb("diffuse", 0.0, 1.0, 0.0, "albedo of an added Lambert lobe (ρ_d); 0 for none")
}

/// `glossy` plus the Lambert lobe of the resolved `diffuse` parameter (none when it is black).
/// `specular_albedo` is an upper estimate of the glossy lobe's albedo (its largest reflectance),
/// used for the lobe-selection probability and the energy claim.
pub fn with_diffuse<G: Brdf>(p: &dyn ParamSource, glossy: G, specular_albedo: f32) -> DiffuseGlossy<G> {
    DiffuseGlossy::new(Lambert { albedo: p.rgb("diffuse") }, glossy, specular_albedo)
}

/// A Lambert lobe plus a glossy lobe, sampled by lobe selection.
#[derive(Clone, Copy, Debug)]
pub struct DiffuseGlossy<G> {
    /// None when the diffuse albedo is black.
    diffuse: Option<Lambert>,
    glossy: G,
    glossy_albedo: f32,
    p_diffuse: f32,
}

impl<G: Brdf> DiffuseGlossy<G> {
    /// Combines the two lobes; `specular_albedo` estimates the glossy lobe's albedo.
    pub fn new(diffuse: Lambert, glossy: G, specular_albedo: f32) -> Self {
        let d = diffuse.albedo.mean().max(0.0);
        let s = specular_albedo.max(0.0);
        let p_diffuse = if d + s > 0.0 { (d / (d + s)).clamp(0.05, 0.95) } else { 0.5 };
        let diffuse = (!diffuse.albedo.is_black()).then_some(diffuse);
        DiffuseGlossy { diffuse, glossy, glossy_albedo: s, p_diffuse: if diffuse.is_some() { p_diffuse } else { 0.0 } }
    }

    /// Probability of sampling the diffuse lobe.
    pub fn diffuse_probability(&self) -> f32 {
        self.p_diffuse
    }
}

impl<G: Brdf> Brdf for DiffuseGlossy<G> {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        match &self.diffuse {
            Some(d) => d.eval(wi, wo) + self.glossy.eval(wi, wo),
            None => self.glossy.eval(wi, wo),
        }
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        match &self.diffuse {
            Some(d) => self.p_diffuse * d.pdf(wi, wo) + (1.0 - self.p_diffuse) * self.glossy.pdf(wi, wo),
            None => self.glossy.pdf(wi, wo),
        }
    }

    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        match &self.diffuse {
            Some(_) => (self.eval(wi, wo), self.pdf(wi, wo)),
            None => self.glossy.eval_pdf(wi, wo),
        }
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        let Some(diffuse) = &self.diffuse else { return self.glossy.sample(wo, uc, u) };
        let pd = self.p_diffuse;
        let s = if uc < pd {
            diffuse.sample(wo, uc / pd, u)?
        } else {
            let s = self.glossy.sample(wo, ((uc - pd) / (1.0 - pd)).min(1.0 - f32::EPSILON), u)?;
            if s.delta {
                // A delta lobe is not in the mixture density: weight by its selection probability.
                return Some(BrdfSample { pdf: s.pdf * (1.0 - pd), weight: s.weight / (1.0 - pd), ..s });
            }
            s
        };
        let pdf = self.pdf(s.wi, wo);
        if pdf <= 0.0 || s.wi.z <= 0.0 {
            return None;
        }
        let weight = self.eval(s.wi, wo) * (s.wi.z / pdf);
        Some(BrdfSample { wi: s.wi, pdf, weight, delta: false, eta: 1.0 })
    }

    fn claims(&self) -> Claims {
        let g = self.glossy.claims();
        let Some(d) = &self.diffuse else { return g };
        // Adding a lobe can push the albedo past 1: the sum is claimed conserving only when
        // the glossy lobe is and the two albedos cannot add past 1.
        let bounded = d.albedo.max_channel() + self.glossy_albedo <= 1.0;
        Claims { energy_conserving: g.energy_conserving && bounded, ..g }
    }

    fn has_delta(&self) -> bool {
        self.glossy.has_delta()
    }

    fn fresnel(&self) -> Option<crate::fresnel::Fresnel> {
        self.glossy.fresnel()
    }

    fn phong_terms(&self) -> Option<PhongTerms> {
        let g = self.glossy.phong_terms()?;
        let Some(d) = &self.diffuse else { return Some(g) };
        let base = PhongTerms::diffuse(d.albedo);
        Some(PhongTerms { ka: base.ka + g.ka, kd: base.kd + g.kd, ..g })
    }
}
