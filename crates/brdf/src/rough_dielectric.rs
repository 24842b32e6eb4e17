//! A rough dielectric interface (Mitsuba 3's `roughdielectric`): frosted glass, after Walter,
//! Marschner, Li and Torrance 2007.
//!
//! η = int_ior / ext_ior, the interior below the surface. Seen from wo, light crossing the
//! surface meets the relative index η_t = η if wo.z > 0, 1/η if wo.z < 0. The facet normal m
//! (always in the upper hemisphere, m.z > 0) that scatters wi into wo is
//!
//!   reflection (wi.z wo.z > 0):    m = ±normalize(wo + wi),
//!   transmission (wi.z wo.z < 0):  m = ±normalize(wo + η_t wi),
//!
//! and, with F = F(wo·m) the exact dielectric Fresnel term, D the Beckmann or GGX distribution
//! and G = G1(wi, m) G1(wo, m) Smith's separable shadowing-masking (G1 zero unless v·m has the
//! sign of v.z: a facet is seen from its own side of the macro-surface only),
//!
//!   ρ_r(wi, wo) = R_s F D G / (4 |cos θi| |cos θo|),
//!   ρ_t(wi, wo) = T_s (1 − F) D G |wi·m| |wo·m| / (|cos θi| |cos θo| (wo·m + η_t wi·m)²).
//!
//! ρ_t is Walter's eq. 21 times 1/η_t² (radiance, not importance, is transported: the term
//! Walter leaves out, which Mitsuba adds). Then generalised reciprocity holds,
//! ρ(wi, wo)/n_o² = ρ(wo, wi)/n_i², with n_o, n_i the indices on wo's and wi's sides.
//! R_s, T_s are the `specular_reflectance` and `specular_transmittance` tints.
//!
//! Sampling, as Mitsuba with `sample_visible`: a facet normal visible from wo (from −wo when
//! wo is below, so that m stays up) with density D_wo(m) = G1(wo) |wo·m| D(m) / |cos θo|
//! (Heitz & d'Eon 2014); reflection about m with probability F, refraction through m
//! otherwise. The Jacobians dm/dwi are 1/(4 |wi·m|) for reflection and
//! η_t² |wi·m| / (wo·m + η_t wi·m)² for refraction, so
//!
//!   pdf = D_wo(m) F / (4 |wi·m|)   or   D_wo(m) (1 − F) η_t² |wi·m| / (wo·m + η_t wi·m)²,
//!   weight = R_s G1(wi, m)         or   T_s G1(wi, m) / η_t²,
//!
//! and a refracted sample carries `eta` = η_t. Single scattering: light that a facet sends
//! into another facet is lost, so reflected + transmitted power falls below 1 at high α.
//! Sources: B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet Models for Refraction
//! through Rough Surfaces", EGSR 2007; E. Heitz, E. d'Eon, "Importance Sampling Microfacet-Based
//! BSDFs using the Distribution of Visible Normals", EGSR 2014; Mitsuba 3,
//! `src/bsdfs/roughdielectric.cpp`, for the conventions, names and defaults.

use crate::dielectric::{eta_from_params, eta_seen_from, interface_params};
use crate::fresnel;
use crate::fresnel::Fresnel;
use crate::microfacet::{visible_density, Distribution, Ndf};
use crate::model::{refract, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use crate::roughness;
use radiometry::{Rgb, Vec2, Vec3};

/// A rough dielectric interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    /// The facet normal distribution.
    pub distribution: Distribution,
    /// Relative index int_ior / ext_ior of the medium below the surface over the one above.
    pub eta: f32,
    /// Tint of the reflected light, in [0, 1].
    pub reflectance: Rgb,
    /// Tint of the transmitted light, in [0, 1].
    pub transmittance: Rgb,
}

/// The facet normal, the relative index η_t and whether the pair is a reflection.
struct Geometry {
    m: Vec3,
    eta_t: f32,
    reflect: bool,
    wo_m: f32,
    wi_m: f32,
}

/// `v` turned into the upper hemisphere: facet normals live there, and the distribution's
/// terms are asked of the upper copy of a direction below the surface.
#[inline]
fn upper(v: Vec3) -> Vec3 {
    if v.z < 0.0 {
        -v
    } else {
        v
    }
}

impl RoughDielectric {
    /// Smith masking of `v` by facet `m`: zero unless `v` sees `m` from its own side.
    #[inline]
    fn g1(&self, v: Vec3, m: Vec3) -> f32 {
        if v.dot(m) * v.z <= 0.0 {
            return 0.0;
        }
        // Λ depends on z² only; the distribution wants the upper-hemisphere copy.
        self.distribution.g1(upper(v))
    }

    /// The facet normal joining `wi` and `wo`; None where no facet can (grazing directions,
    /// a degenerate half vector, a facet seen from its back).
    #[inline]
    fn geometry(&self, wi: Vec3, wo: Vec3) -> Option<Geometry> {
        let (cos_i, cos_o) = (wi.z, wo.z);
        if cos_i == 0.0 || cos_o == 0.0 {
            return None;
        }
        let reflect = cos_i * cos_o > 0.0;
        let eta_t = if reflect { 1.0 } else { eta_seen_from(self.eta, cos_o) };
        let h = wo + wi * eta_t;
        let m = h.try_normalize()?;
        let m = upper(m);
        let (wo_m, wi_m) = (wo.dot(m), wi.dot(m));
        if m.z <= 0.0 || wo_m * cos_o <= 0.0 || wi_m * cos_i <= 0.0 {
            return None;
        }
        Some(Geometry { m, eta_t, reflect, wo_m, wi_m })
    }

    /// ρ given the facet geometry, D(m), G1(wo, m) and F(wo·m).
    #[inline]
    fn value(&self, wi: Vec3, wo: Vec3, g: &Geometry, d: f32, g1_o: f32, f: f32) -> Rgb {
        let shadow = self.g1(wi, g.m) * g1_o;
        let cos = (wi.z * wo.z).abs();
        let value = if g.reflect {
            self.reflectance * (f * d * shadow / (4.0 * cos))
        } else {
            let denom = g.wo_m + g.eta_t * g.wi_m;
            self.transmittance * ((1.0 - f) * d * shadow * (g.wi_m * g.wo_m).abs() / (cos * denom * denom))
        };
        if value.is_finite() {
            value
        } else {
            Rgb::ZERO
        }
    }

    /// The sampling density given the facet geometry, D_wo(m) and F(wo·m).
    #[inline]
    fn density(&self, g: &Geometry, pm: f32, f: f32) -> f32 {
        let p = if g.reflect {
            pm * f / (4.0 * g.wi_m.abs())
        } else {
            let denom = g.wo_m + g.eta_t * g.wi_m;
            pm * (1.0 - f) * g.eta_t * g.eta_t * g.wi_m.abs() / (denom * denom)
        };
        if p.is_finite() {
            p
        } else {
            0.0
        }
    }

    /// D_wo(m): the density of `sample_visible` seen from `wo`'s side.
    #[inline]
    fn visible_pdf(&self, wo: Vec3, m: Vec3) -> f32 {
        self.distribution.pdf_visible(upper(wo), m)
    }
}

impl Brdf for RoughDielectric {
    fn fresnel(&self) -> Option<Fresnel> {
        Some(Fresnel::Dielectric { eta: self.eta })
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let Some(g) = self.geometry(wi, wo) else { return Rgb::ZERO };
        let d = self.distribution.d(g.m);
        let f = fresnel::dielectric(g.wo_m, self.eta);
        self.value(wi, wo, &g, d, self.g1(wo, g.m), f)
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        let Some(g) = self.geometry(wi, wo) else { return 0.0 };
        let pm = self.visible_pdf(wo, g.m);
        self.density(&g, pm, fresnel::dielectric(g.wo_m, self.eta))
    }

    /// Sharing the facet normal, D(m), G1(wo) and F: bit for bit what each returns.
    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        let Some(g) = self.geometry(wi, wo) else { return (Rgb::ZERO, 0.0) };
        let d = self.distribution.d(g.m);
        let f = fresnel::dielectric(g.wo_m, self.eta);
        // `geometry` has checked that wo sees m from its own side: G1(wo, m) is the
        // distribution's G1 of wo's upper copy, the factor `visible_pdf` starts from.
        let up = upper(wo);
        let g1_o = self.distribution.g1(up);
        let up_m = up.dot(g.m);
        let pm = if up_m <= 0.0 { 0.0 } else { visible_density(g1_o, up_m, d, up.z) };
        (self.value(wi, wo, &g, d, g1_o, f), self.density(&g, pm, f))
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        let cos_o = wo.z;
        if cos_o == 0.0 || !cos_o.is_finite() {
            return None;
        }
        let up = upper(wo);
        let m = self.distribution.sample_visible(up, u);
        let pm = self.distribution.pdf_visible(up, m);
        let wo_m = wo.dot(m);
        if pm.is_nan() || pm <= 0.0 || wo_m * cos_o <= 0.0 {
            return None;
        }
        let f = fresnel::dielectric(wo_m, self.eta);
        let (wi, pdf, weight, eta) = if uc < f {
            let wi = (2.0 * wo_m * m - wo).normalize();
            if wi.z * cos_o <= 0.0 {
                return None;
            }
            (wi, pm * f / (4.0 * wi.dot(m).abs()), self.reflectance * self.g1(wi, m), 1.0)
        } else {
            let eta_t = eta_seen_from(self.eta, wo_m);
            let wi = refract(wo, m, eta_t)?.normalize();
            if wi.z * cos_o >= 0.0 {
                return None;
            }
            let wi_m = wi.dot(m);
            let denom = wo_m + eta_t * wi_m;
            let pdf = pm * (1.0 - f) * eta_t * eta_t * wi_m.abs() / (denom * denom);
            (wi, pdf, self.transmittance * (self.g1(wi, m) / (eta_t * eta_t)), eta_t)
        };
        if pdf.is_nan() || pdf <= 0.0 || !pdf.is_finite() || !weight.is_finite() || weight.is_black() {
            return None;
        }
        Some(BrdfSample { wi, pdf, weight, delta: false, eta })
    }

    fn claims(&self) -> Claims {
        Claims {
            reciprocal: true,
            energy_conserving: self.reflectance.max_channel() <= 1.0 && self.transmittance.max_channel() <= 1.0,
            isotropic: self.distribution.is_isotropic(),
        }
    }

    fn transmits(&self) -> bool {
        true
    }

    fn eta(&self) -> f32 {
        self.eta
    }
}

fn params() -> Vec<ParamSpec> {
    let mut v =
        vec![ParamSpec::choice("distribution", &["beckmann", "ggx"], "beckmann", "distribution of facet normals D")];
    v.extend(roughness::params(0.1, "roughness α of the interface (Beckmann: √2 × the RMS slope along one axis)"));
    v.extend(interface_params());
    v
}

fn make(p: &dyn ParamSource) -> Result<RoughDielectric, ParamError> {
    let (ax, ay) = roughness::from_params(p)?;
    let distribution = Distribution::named(p.choice("distribution"), ax, ay)
        .expect("distribution choice list matches Distribution::named");
    let eta = eta_from_params(p);
    // With equal indices a transmitted pair has no facet normal (wo + wi can vanish): the
    // surface is not there at all, which a smooth `dielectric` says better.
    if (eta - 1.0).abs() < 1e-4 {
        return Err(ParamError::Inconsistent(format!(
            "int_ior {} and ext_ior {} are equal: a rough interface needs two different media",
            p.float("int_ior"),
            p.float("ext_ior")
        )));
    }
    Ok(RoughDielectric {
        distribution,
        eta,
        reflectance: p.rgb("specular_reflectance"),
        transmittance: p.rgb("specular_transmittance"),
    })
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "roughdielectric",
    summary: "rough glass: microfacet reflection and refraction (Walter 2007), Beckmann or GGX (transmits)",
    reference: "Walter, Marschner, Li, Torrance 2007, Microfacet Models for Refraction through Rough Surfaces",
    params,
    build: by_value!(make),
    showcase: &[
        &[("distribution", "ggx"), ("alpha", "0.5")],
        &[("alpha_u", "0.05"), ("alpha_v", "0.3"), ("int_ior", "1.333")],
        &[("int_ior", "1"), ("ext_ior", "1.5"), ("alpha", "0.3")],
    ],
};
