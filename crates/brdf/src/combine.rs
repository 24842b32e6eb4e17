//! Diffuse + glossy: a Lambert lobe added to any other lobe.
//!
//! ρ = ρ_diffuse + ρ_glossy. Sampling picks the diffuse lobe with probability
//! P = a_d / (a_d + a_s), where a_d is the diffuse albedo and a_s an estimate of the glossy
//! lobe's albedo, and the density is the mixture P·pdf_d + (1 − P)·pdf_s, so the weight
//! ρ cos θi / pdf stays exact whichever lobe was drawn (Veach 1997, one-sample MIS).

use crate::lambert::Lambert;
use crate::model::{Brdf, BrdfSample, Claims};
use crate::params::{ParamSpec, Params};
use radiometry::{Rgb, Vec2, Vec3};

/// The `diffuse` parameter every glossy model takes: the albedo of an added Lambert lobe.
pub fn diffuse_param() -> ParamSpec {
    ParamSpec::rgb("diffuse", 0.0, 1.0, 0.0, "albedo of an added Lambert lobe (ρ_d); 0 for none")
}

/// `glossy`, plus a Lambert lobe when the resolved `diffuse` parameter is not black.
/// `specular_albedo` is an upper estimate of the glossy lobe's albedo (its largest reflectance),
/// used for the lobe-selection probability and the energy claim.
pub fn with_diffuse(p: &Params, glossy: Box<dyn Brdf>, specular_albedo: f32) -> Box<dyn Brdf> {
    let albedo = p.rgb("diffuse");
    if albedo.is_black() {
        glossy
    } else {
        Box::new(DiffuseGlossy::new(Lambert { albedo }, glossy, specular_albedo))
    }
}

/// A Lambert lobe plus a glossy lobe, sampled by lobe selection.
#[derive(Debug)]
pub struct DiffuseGlossy {
    diffuse: Lambert,
    glossy: Box<dyn Brdf>,
    glossy_albedo: f32,
    p_diffuse: f32,
}

impl DiffuseGlossy {
    /// Combines the two lobes; `specular_albedo` estimates the glossy lobe's albedo.
    pub fn new(diffuse: Lambert, glossy: Box<dyn Brdf>, specular_albedo: f32) -> Self {
        let d = diffuse.albedo.mean().max(0.0);
        let s = specular_albedo.max(0.0);
        let p_diffuse = if d + s > 0.0 { (d / (d + s)).clamp(0.05, 0.95) } else { 0.5 };
        DiffuseGlossy { diffuse, glossy, glossy_albedo: s, p_diffuse }
    }

    /// Probability of sampling the diffuse lobe.
    pub fn diffuse_probability(&self) -> f32 {
        self.p_diffuse
    }
}

impl Brdf for DiffuseGlossy {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        self.diffuse.eval(wi, wo) + self.glossy.eval(wi, wo)
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.p_diffuse * self.diffuse.pdf(wi, wo) + (1.0 - self.p_diffuse) * self.glossy.pdf(wi, wo)
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        let pd = self.p_diffuse;
        let s = if uc < pd {
            self.diffuse.sample(wo, uc / pd, u)?
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
        // Adding a lobe can push the albedo past 1: the sum is claimed conserving only when
        // the glossy lobe is and the two albedos cannot add past 1.
        let bounded = self.diffuse.albedo.max_channel() + self.glossy_albedo <= 1.0;
        Claims { energy_conserving: g.energy_conserving && bounded, ..g }
    }

    fn has_delta(&self) -> bool {
        self.glossy.has_delta()
    }
}
