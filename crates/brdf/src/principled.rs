//! Mitsuba 3.9.1's `principled` BSDF: the Disney "principled" model (Burley 2012), with the
//! specular transmission of Burley 2015, evaluated as Mitsuba 3.9.1 evaluates it, quirks included.
//!
//! Notation (gonio's directions: wo towards the viewer, Mitsuba's `si.wi`; wi towards the light):
//! c_o = wo.z, c_i = wi.z, C = base_color, M = metallic, S = spec_trans, T = spec_tint,
//! brdf = (1 − M)(1 − S), bsdf = (1 − M) S. The side of wo decides: "front" is c_o > 0,
//! η_p = η on the front, 1/η behind; a pair reflects when c_o c_i > 0 and refracts when < 0.
//! h = normalize(wo + wi) for a reflection, normalize(wo + η_p wi) for a refraction, turned
//! to z ≥ 0; F = F_dielectric(wo·h, η). D and G = G1(wo, h) G1(wi, h) are GGX with separable
//! Smith masking, α from roughness and anisotropic (`principled_common`). Then ρ is the sum of
//!
//! - main specular reflection, where F > 0 and both directions see h:
//!   F_p D G / (4 |c_o c_i|), with on the front
//!   F_p = (1−M)(1−T) F + M·Schlick(C) + (1−M) T·Schlick(C/lum(C)·R0(η)),
//!   and behind F_p = bsdf·F (no metal, no tint; zero without spec_trans);
//! - specular transmission, where F < 1 and wi is across h:
//!   √C bsdf |(1 − F) D G (wo·h)(wi·h) / (c_o c_i (wo·h + η_p wi·h)²)|
//!   (Radiance mode: Walter's BTDF over η_p², so ρ(wi, wo) n_i² = ρ(wo, wi) n_o²);
//! - on the front, reflecting only: clearcoat 0.25·clearcoat·Schlick_0.04(wo·h)·D_GTR1(h)·G_cc,
//!   D_GTR1(m) = (α² − 1)/(π ln α² (1 + (α² − 1) m_z²)), α = 0.1 − 0.099·clearcoat_gloss,
//!   G_cc the product of two Smith GGX G1 at α = 0.25 (Mitsuba's form: no 1/(4 c_o c_i));
//!   diffuse brdf·C/π·(Disney diffuse with retro-reflection, blended with the fake subsurface
//!   by flatness), and sheen·(1 − M)·schlick_weight(h·wi)·lerp(1, C/lum(C), sheen_tint) (no 1/π
//!   and no (1 − S), as Mitsuba has it).
//!
//! Quirks kept as Mitsuba has them: the surface is one-sided except for its dielectric part (wo
//! below sees only bsdf·F reflection and the transmission, so it is black without spec_trans);
//! metallic = 1 with η = 1 (specular = 0) is black, since F = 0 switches the whole main lobe off;
//! with spec_trans given, η = 1 becomes 1.001 and specular = 0 becomes 1e-3; η comes from
//! specular when not given, η = 2/(1 − √(0.08 specular)) − 1 (here `eta` = 0, its default,
//! stands for Mitsuba's absent eta, and giving both is refused); energy is not conserved in general
//! (the diffuse lobe is not reduced by the specular F, the clearcoat is up to 4× Disney's).
//!
//! Sampling: a GGX visible normal m seen from wo (mirrored up when wo is below) is drawn first;
//! lobe weights, on the front rate_spec (1 − bsdf (1 − F)), rate_spec bsdf (1 − F),
//! 0.25 clearcoat rate_cc and rate_diff brdf (behind F and 1 − F), with F at m, normalised,
//! pick diffuse (cosine hemisphere), clearcoat (GTR1 normal, reflected), transmission (refracted
//! through m, `eta` = η_it) or reflection (about m) with uc. The returned pdf is the whole
//! mixture's, pdf(wi, wo) = Σ p_k pdf_k: the GGX and GTR1 normal densities times the Jacobians
//! 1/(4|wi·h|) and |η_p² (wi·h) / (wo·h + η_p wi·h)²|, and c_i/π. Mitsuba's pdf is also non-zero
//! below the surface without spec_trans, where eval and sample give nothing; it is kept.
//! gonio's visible-normal warp is not Mitsuba's: same density, other directions for the same u.
//!
//! Sources: Mitsuba 3.9.1, `src/bsdfs/principled.cpp` and `principledhelpers.h` (behaviour, read
//! for the conventions and checked against its numbers); B. Burley, "Physically Based Shading at
//! Disney", SIGGRAPH 2012 course notes; B. Burley, "Extending the Disney BRDF to a BSDF with
//! Integrated Subsurface Scattering", SIGGRAPH 2015 course notes; B. Walter et al., "Microfacet
//! Models for Refraction through Rough Surfaces", EGSR 2007.

use crate::model::{reflect, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::principled_common::{
    alphas, calc_schlick, compatible, diffuse_shape, fresnel, has, lerp_rgb, pick, schlick_r0, schlick_weight, tint,
    SmithGgx,
};
use crate::registry::{by_value, ModelSpec};
use radiometry::trig::sin_cos_pi;
use radiometry::warp::cosine_hemisphere;
use radiometry::{Rgb, Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// Which of the optional lobes and terms Mitsuba switches on (its `has_*` flags).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Has {
    spec_trans: bool,
    clearcoat: bool,
    flatness: bool,
    sheen: bool,
    sheen_tint: bool,
    spec_tint: bool,
    metallic: bool,
}

/// Mitsuba 3.9.1's `principled` BSDF at one surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principled {
    /// Base colour C.
    base_color: Rgb,
    /// √C, the transmission colour.
    trans_color: Rgb,
    /// C / lum(C), the tint colour.
    tint: Rgb,
    /// Roughness r (α = r²), for the retro-reflection.
    roughness: f32,
    /// Metallic weight M.
    metallic: f32,
    /// (1 − M)(1 − S): the diffuse weight.
    brdf: f32,
    /// (1 − M) S: the dielectric transmission weight.
    bsdf: f32,
    /// Relative index η, interior over exterior (after Mitsuba's bump).
    eta: f32,
    /// Specular tint weight T.
    spec_tint: f32,
    /// Sheen weight.
    sheen: f32,
    /// Sheen tint weight.
    sheen_tint: f32,
    /// Fake-subsurface blend weight.
    flatness: f32,
    /// Clearcoat weight.
    clearcoat: f32,
    /// GTR1 roughness of the clearcoat, 0.1 − 0.099·clearcoat_gloss.
    clearcoat_alpha: f32,
    /// Sampling rate of the main specular lobes.
    rate_spec: f32,
    /// Sampling rate of the clearcoat.
    rate_clearcoat: f32,
    /// Sampling rate of the diffuse lobe.
    rate_diffuse: f32,
    /// The optional terms present.
    has: Has,
    /// The main GGX distribution.
    dist: SmithGgx,
}

/// The clearcoat's GTR1 ("Berry") distribution of roughness `a`, zero unless D m_z > 1e-20.
#[inline]
fn gtr1_d(m: Vec3, a: f32) -> f32 {
    let a2 = a * a;
    let d = (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * m.z * m.z));
    if d * m.z > 1e-20 {
        d
    } else {
        0.0
    }
}

/// Density of `gtr1_sample`: m_z D_GTR1(m).
#[inline]
fn gtr1_pdf(m: Vec3, a: f32) -> f32 {
    if m.z >= 0.0 {
        m.z * gtr1_d(m, a)
    } else {
        0.0
    }
}

/// A GTR1 normal with density m_z D(m): φ = 2π u_x, cos²θ = (1 − α^(2(1 − u_y)))/(1 − α²).
#[inline]
fn gtr1_sample(u: Vec2, a: f32) -> Vec3 {
    let a2 = a * a;
    let cos2 = (1.0 - a2.powf(1.0 - u.y)) / (1.0 - a2);
    let sin = (1.0 - cos2).max(0.0).sqrt();
    let (sp, cp) = sin_cos_pi(2.0 * u.x);
    Vec3::new(cp * sin, sp * sin, cos2.max(0.0).sqrt())
}

/// The clearcoat's Smith GGX masking at the fixed α = 0.25: 2/(1 + √(1 + α² tan²θ)).
#[inline]
fn clearcoat_g1(v: Vec3, m: Vec3) -> f32 {
    if v.dot(m) * v.z <= 0.0 {
        return 0.0;
    }
    if v.z == 1.0 {
        return 1.0;
    }
    let z2 = v.z * v.z;
    let tan2 = (1.0 - z2).max(0.0) / z2;
    2.0 / (1.0 + (1.0 + 0.0625 * tan2).sqrt())
}

impl Principled {
    /// The front-side reflectance F_p at facet cosine `c` given the dielectric F there.
    #[inline]
    fn front_fresnel(&self, f: f32, c: f32) -> Rgb {
        let m = self.metallic;
        let mut fp = Rgb::splat((1.0 - m) * (1.0 - self.spec_tint) * f);
        if self.has.metallic {
            fp += calc_schlick(self.base_color, c, self.eta) * m;
        }
        if self.has.spec_tint {
            let eta_it = if c >= 0.0 { self.eta } else { 1.0 / self.eta };
            fp += calc_schlick(self.tint * schlick_r0(eta_it), c, self.eta) * ((1.0 - m) * self.spec_tint);
        }
        fp
    }

    /// The lobe probabilities (spec reflection, spec transmission, clearcoat, diffuse),
    /// normalised, for wo on the front or not and the Fresnel F of the facet.
    #[inline]
    fn lobe_probabilities(&self, front: bool, f: f32) -> [f32; 4] {
        let p = if front {
            [
                self.rate_spec * (1.0 - self.bsdf * (1.0 - f)),
                if self.has.spec_trans { self.rate_spec * self.bsdf * (1.0 - f) } else { 0.0 },
                if self.has.clearcoat { 0.25 * self.clearcoat * self.rate_clearcoat } else { 0.0 },
                self.rate_diffuse * self.brdf,
            ]
        } else {
            [f, if self.has.spec_trans { 1.0 - f } else { 0.0 }, 0.0, 0.0]
        };
        let sum: f32 = p.iter().sum();
        if sum > 0.0 && sum.is_finite() {
            p.map(|x| x / sum)
        } else {
            [0.0; 4]
        }
    }

    /// ρ(wi, wo) and pdf(wi | wo) together: they share the half vector, D, G and F.
    fn evaluate(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        let (co, ci) = (wo.z, wi.z);
        if co == 0.0 || ci == 0.0 || !(co.is_finite() && ci.is_finite()) {
            return (Rgb::ZERO, 0.0);
        }
        let front = co > 0.0;
        let reflect = co * ci > 0.0;
        let eta_p = if front { self.eta } else { 1.0 / self.eta };
        let h = (wo + wi * if reflect { 1.0 } else { eta_p }).normalize_or_zero();
        if h == Vec3::ZERO {
            return (Rgb::ZERO, 0.0);
        }
        let h = if h.z < 0.0 { -h } else { h };
        let (wo_h, wi_h) = (wo.dot(h), wi.dot(h));
        let f = fresnel(wo_h, self.eta).f;
        let d = self.dist.d(h);
        let g = self.dist.g(wo, wi, h);
        let sees_reflect = reflect && compatible(h, wo, wi, co, true);
        let sees_refract = !reflect && self.has.spec_trans && compatible(h, wo, wi, co, false);

        let mut rho = Rgb::ZERO;
        if sees_reflect && f > 0.0 {
            let fp = if front { self.front_fresnel(f, wo_h) } else { Rgb::splat(self.bsdf * f) };
            rho += fp * (d * g / (4.0 * (co * ci).abs()));
        }
        let refract_denom = wo_h + eta_p * wi_h;
        if sees_refract && self.bsdf > 0.0 && f < 1.0 {
            let t = ((1.0 - f) * d * g * wo_h * wi_h / (co * ci * refract_denom * refract_denom)).abs();
            rho += self.trans_color * (self.bsdf * t);
        }
        if front && reflect {
            if self.has.clearcoat && self.clearcoat > 0.0 && sees_reflect {
                let fcc = calc_schlick(Rgb::splat(0.04), wo_h, self.eta);
                let gcc = clearcoat_g1(wo, h) * clearcoat_g1(wi, h);
                rho += fcc * (0.25 * self.clearcoat * gtr1_d(h, self.clearcoat_alpha) * gcc);
            }
            if self.brdf > 0.0 {
                let cd = h.dot(wi);
                let flat = self.has.flatness.then_some(self.flatness);
                rho += self.base_color * (self.brdf * FRAC_1_PI * diffuse_shape(self.roughness, cd, co, ci, flat));
                if self.has.sheen && self.sheen > 0.0 && 1.0 - self.metallic > 0.0 {
                    let c_sheen =
                        if self.has.sheen_tint { lerp_rgb(Rgb::ONE, self.tint, self.sheen_tint) } else { Rgb::ONE };
                    rho += c_sheen * (self.sheen * (1.0 - self.metallic) * schlick_weight(cd.abs()));
                }
            }
        }

        let [p_sr, p_st, p_cc, p_d] = self.lobe_probabilities(front, f);
        let jacobian = if reflect || !self.has.spec_trans {
            1.0 / (4.0 * wi_h.abs())
        } else {
            (eta_p * eta_p * wi_h / (refract_denom * refract_denom)).abs()
        };
        let wo_up = if front { wo } else { -wo };
        let mut pdf = 0.0;
        if sees_reflect {
            pdf += p_sr * self.dist.pdf(wo_up, h) * jacobian;
            if self.has.clearcoat {
                pdf += p_cc * gtr1_pdf(h, self.clearcoat_alpha) * jacobian;
            }
        }
        if reflect && front {
            pdf += p_d * ci * FRAC_1_PI;
        }
        if sees_refract {
            pdf += p_st * self.dist.pdf(wo_up, h) * jacobian;
        }
        if !(rho.is_finite() && pdf.is_finite()) {
            return (Rgb::ZERO, 0.0);
        }
        (rho, pdf)
    }
}

impl Brdf for Principled {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        self.evaluate(wi, wo).0
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.evaluate(wi, wo).1
    }

    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        self.evaluate(wi, wo)
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        let co = wo.z;
        if co == 0.0 || !wo.is_finite() {
            return None;
        }
        let front = co > 0.0;
        // Behind the surface only the dielectric part scatters.
        if !(front || self.transmits()) {
            return None;
        }
        let wo_up = if front { wo } else { -wo };
        let m = self.dist.sample(wo_up, u);
        let fr = fresnel(wo.dot(m), self.eta);
        let [p_sr, p_st, p_cc, p_d] = self.lobe_probabilities(front, fr.f);
        if p_sr + p_st + p_cc + p_d <= 0.0 {
            return None;
        }
        // Mitsuba's order: diffuse, clearcoat, transmission, and reflection takes the rest.
        let (wi, eta) = match pick(&[p_d, p_cc, p_st], uc) {
            Some(0) => {
                let wi = cosine_hemisphere(u);
                (wi.z * co > 0.0).then_some((wi, 1.0))?
            }
            Some(1) => {
                let mc = gtr1_sample(u, self.clearcoat_alpha);
                let wi = reflect(wo, mc).normalize();
                (wi.z * co > 0.0 && compatible(mc, wo, wi, co, true)).then_some((wi, 1.0))?
            }
            Some(_) => {
                let wi = (m * (wo.dot(m) * fr.eta_ti + fr.cos_t) - wo * fr.eta_ti).normalize();
                (wi.z * co < 0.0 && compatible(m, wo, wi, co, false)).then_some((wi, fr.eta_it))?
            }
            None => {
                let wi = reflect(wo, m).normalize();
                (wi.z * co > 0.0 && compatible(m, wo, wi, co, true)).then_some((wi, 1.0))?
            }
        };
        let (rho, pdf) = self.evaluate(wi, wo);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = rho * (wi.z.abs() / pdf);
        weight.is_finite().then_some(BrdfSample { wi, pdf, weight, delta: false, eta })
    }

    fn claims(&self) -> Claims {
        // Energy: provable only where the model reduces to single-scattering microfacet lobes
        // of reflectance ≤ 1: a metal (Schlick(C) ≤ 1), or clear glass (F + (1 − F) = 1, the
        // rough dielectric); the clearcoat is up to 4× Disney's and the diffuse lobe ignores F.
        let no_coat = !self.has.clearcoat || self.clearcoat == 0.0;
        let metal = self.metallic == 1.0;
        let glass = self.metallic == 0.0 && self.bsdf == 1.0 && self.spec_tint == 0.0;
        Claims { reciprocal: true, energy_conserving: no_coat && (metal || glass), isotropic: self.dist.is_isotropic() }
    }

    fn transmits(&self) -> bool {
        self.has.spec_trans && self.bsdf > 0.0
    }

    fn back_side(&self) -> bool {
        // Behind, only the dielectric part (weight bsdf) scatters.
        self.transmits()
    }

    fn eta(&self) -> f32 {
        if self.transmits() {
            self.eta
        } else {
            1.0
        }
    }
}

fn params() -> Vec<ParamSpec> {
    let w = |name, doc| ParamSpec::float(name, 0.0, 1.0, 0.0, doc);
    let rate = |name, doc| ParamSpec::float(name, 0.0, 100.0, 1.0, doc).fixed();
    vec![
        ParamSpec::rgb("base_color", 0.0, 1.0, 0.5, "base colour C: diffuse albedo, metal F0, √C tints transmission"),
        ParamSpec::float("roughness", 0.0, 1.0, 0.5, "roughness r of the main lobes, GGX α = r²"),
        w("anisotropic", "anisotropy a: α_x = r²/√(1 − 0.9a), α_y = r²·√(1 − 0.9a)"),
        w("metallic", "metallic weight: blends the dielectric towards a Schlick metal of F0 = base_color"),
        w("spec_trans", "specular transmission weight (rough glass)"),
        ParamSpec::float(
            "eta",
            0.0,
            10.0,
            0.0,
            "relative index of refraction, interior over exterior (≥ 1); 0: derived from specular",
        )
        .fixed(),
        ParamSpec::float(
            "specular",
            0.0,
            1.0,
            0.5,
            "specular level, used when eta is not given: η = 2/(1 − √(0.08 s)) − 1",
        )
        .fixed(),
        w("spec_tint", "tints the dielectric reflection towards base_color"),
        w("sheen", "sheen weight: a grazing retro-reflective lobe for cloth"),
        w("sheen_tint", "tints the sheen towards base_color"),
        w("flatness", "blends the diffuse lobe towards a fake subsurface (Hanrahan-Krueger-like) one"),
        w("clearcoat", "clearcoat weight: a second, GTR1 specular lobe of F0 = 0.04"),
        w("clearcoat_gloss", "clearcoat glossiness: GTR1 α = 0.1 − 0.099·gloss"),
        rate("main_specular_sampling_rate", "relative rate of sampling the main specular lobes"),
        rate("clearcoat_sampling_rate", "relative rate of sampling the clearcoat"),
        rate("diffuse_reflectance_sampling_rate", "relative rate of sampling the diffuse lobe"),
    ]
}

/// η from Mitsuba's `specular`: 2/(1 − √(0.08 specular)) − 1 (0.5 gives 1.5).
pub fn eta_from_specular(specular: f32) -> f32 {
    2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
}

fn make(p: &dyn ParamSource) -> Result<Principled, ParamError> {
    let eta_given = has(p, "eta");
    if eta_given && p.was_given("specular") {
        return Err(ParamError::Inconsistent(
            "parameters 'eta' and 'specular': give one of them (η is derived from specular when eta is absent)".into(),
        ));
    }
    let has_flags = Has {
        spec_trans: has(p, "spec_trans"),
        clearcoat: has(p, "clearcoat"),
        flatness: has(p, "flatness"),
        sheen: has(p, "sheen"),
        sheen_tint: has(p, "sheen_tint"),
        spec_tint: has(p, "spec_tint"),
        metallic: has(p, "metallic"),
    };
    // With spec_trans, Mitsuba moves η off 1, where a rough interface has no refraction half vector.
    let eta = if eta_given {
        let eta = p.float("eta");
        if eta < 1.0 {
            return Err(ParamError::Inconsistent(format!(
                "parameter 'eta': {eta} is neither 0 (derive it from specular) nor at least 1"
            )));
        }
        if has_flags.spec_trans && eta == 1.0 {
            1.001
        } else {
            eta
        }
    } else {
        let s = p.float("specular");
        eta_from_specular(if has_flags.spec_trans && s == 0.0 { 1e-3 } else { s })
    };
    let base_color = p.rgb("base_color");
    let (metallic, spec_trans) = (p.float("metallic"), p.float("spec_trans"));
    let (ax, ay) = alphas(p.float("roughness"), p.float("anisotropic"));
    Ok(Principled {
        base_color,
        trans_color: base_color.map(f32::sqrt),
        tint: tint(base_color),
        roughness: p.float("roughness"),
        metallic,
        brdf: (1.0 - metallic) * (1.0 - spec_trans),
        bsdf: (1.0 - metallic) * spec_trans,
        eta,
        spec_tint: p.float("spec_tint"),
        sheen: p.float("sheen"),
        sheen_tint: p.float("sheen_tint"),
        flatness: p.float("flatness"),
        clearcoat: p.float("clearcoat"),
        clearcoat_alpha: crate::principled_common::lerp(0.1, 0.001, p.float("clearcoat_gloss")),
        rate_spec: p.float("main_specular_sampling_rate"),
        rate_clearcoat: p.float("clearcoat_sampling_rate"),
        rate_diffuse: p.float("diffuse_reflectance_sampling_rate"),
        has: has_flags,
        dist: SmithGgx::new(ax, ay),
    })
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "principled",
    summary:
        "Disney principled BSDF as Mitsuba 3.9.1's principled: diffuse, GGX specular, metal, glass, sheen, clearcoat",
    reference: "Burley 2012, Physically Based Shading at Disney; Burley 2015; Mitsuba 3 principled.cpp",
    params,
    build: by_value!(make),
    // Brushed metal; rough glass (the transmission and the dielectric back side); a coated,
    // sheened, tinted plastic with every diffuse-side term, partly metallic and partly
    // transmitting (every lobe of the mixture at once).
    showcase: &[
        &[("base_color", "0.9,0.6,0.3"), ("metallic", "1"), ("roughness", "0.3"), ("anisotropic", "0.5")],
        &[("base_color", "0.8,0.9,1"), ("spec_trans", "1"), ("roughness", "0.3"), ("eta", "1.5")],
        &[
            ("base_color", "0.8,0.3,0.1"),
            ("clearcoat", "1"),
            ("clearcoat_gloss", "0.5"),
            ("sheen", "1"),
            ("sheen_tint", "0.5"),
            ("spec_tint", "0.3"),
            ("flatness", "0.4"),
            ("metallic", "0.2"),
            ("spec_trans", "0.3"),
        ],
    ],
};

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::check::albedo_f64;

    /// `a` within a relative `tol` of `b`; a zero reference must be met exactly.
    fn close(a: f32, b: f32, tol: f32) -> bool {
        if b == 0.0 {
            return a == 0.0;
        }
        (a - b).abs() <= tol * a.abs().max(b.abs())
    }

    fn v3(a: [f32; 3]) -> Vec3 {
        Vec3::from_array(a)
    }

    /// Mitsuba's (si.wi, wo, eval with its cosine, pdf) against gonio's eval(wo, si.wi)·|wo.z|.
    pub(crate) fn check_pair(b: &dyn Brdf, label: &str, m_wi: [f32; 3], m_wo: [f32; 3], eval: [f32; 3], pdf: f32) {
        let (view, light) = (v3(m_wi), v3(m_wo));
        let tol = if eval.iter().any(|&e| e > 50.0) { 1e-3 } else { 1e-4 };
        let got = b.eval(light, view) * light.z.abs();
        for c in 0..3 {
            assert!(close(got.0[c], eval[c], tol), "{label}: eval {:?} but Mitsuba {eval:?}", got.0);
        }
        let p = b.pdf(light, view);
        assert!(close(p, pdf, tol), "{label}: pdf {p} but Mitsuba {pdf}");
    }

    /// One of Mitsuba's sample rows: si.wi, sample1, sample2, wo, pdf, weight, sampled type.
    pub(crate) type SampleRow = ([f32; 3], f32, [f32; 2], [f32; 3], f32, [f32; 3], u32);

    /// A sample row: the returned wo's pdf and weight are eval and pdf there (Mitsuba's
    /// reference for those), gonio's own sample for the same numbers is consistent, and where
    /// the lobe's warp is Mitsuba's (diffuse, clearcoat) it is the same direction.
    pub(crate) fn check_sample_row(b: &dyn Brdf, label: &str, row: &SampleRow, same_warp: bool) {
        let (m_wi, uc, u, m_wo, pdf, weight, kind) = *row;
        let view = v3(m_wi);
        if kind == 0 {
            for uc in [0.1, 0.5, 0.9] {
                assert!(b.sample(view, uc, Vec2::from_array(u)).is_none(), "{label}: Mitsuba's sample is invalid");
            }
            return;
        }
        let eval = weight.map(|w| w * pdf);
        check_pair(b, label, m_wi, m_wo, eval, pdf);
        let s = b.sample(view, uc, Vec2::from_array(u));
        if same_warp {
            let s = s.unwrap_or_else(|| panic!("{label}: no sample"));
            assert!((s.wi - v3(m_wo)).abs().max_element() < 2e-6, "{label}: wi {} but Mitsuba {m_wo:?}", s.wi);
            assert!(close(s.pdf, pdf, 1e-4), "{label}: pdf {} but Mitsuba {pdf}", s.pdf);
            for c in 0..3 {
                assert!(close(s.weight.0[c], weight[c], 1e-4), "{label}: weight {:?} but {weight:?}", s.weight);
            }
        }
        if let Some(s) = s {
            assert_eq!(s.pdf, b.pdf(s.wi, view), "{label}");
            let want = b.eval(s.wi, view) * (s.wi.z.abs() / s.pdf);
            for c in 0..3 {
                assert!(close(s.weight.0[c], want.0[c], 1e-6), "{label}: weight {:?} vs {:?}", s.weight, want);
            }
        }
    }

    fn build(set: &[(&str, &str)]) -> Box<dyn Brdf> {
        SPEC.build_with(set).unwrap()
    }

    const WIS: [[f32; 3]; 8] = [
        [0.0, 0.6, 0.8],
        [0.48, 0.6, 0.64],
        [0.0, 0.0, 1.0],
        [0.96, 0.0, 0.28],
        [0.0, 0.6, 0.8],
        [0.48, 0.6, 0.64],
        [0.0, 0.6, -0.8],
        [0.0, 0.6, -0.8],
    ];
    const WOS: [[f32; 3]; 8] = [
        [0.6, 0.0, 0.8],
        [-0.48, -0.6, 0.64],
        [-0.36, 0.48, 0.8],
        [-0.64, -0.48, 0.6],
        [0.0, -0.6, -0.8],
        [0.36, -0.48, -0.8],
        [0.6, 0.0, -0.8],
        [0.0, -0.6, 0.8],
    ];

    /// Mitsuba 3.9.1 (scalar_rgb, Radiance) at the eight pairs A–H: eval (with cos θo) and pdf.
    pub(crate) type Table = [([f32; 3], f32); 8];

    /// Checks `b` at the eight pairs against Mitsuba's `table`.
    pub(crate) fn check_table(b: &dyn Brdf, name: &str, table: &Table) {
        for (k, (eval, pdf)) in table.iter().enumerate() {
            let label = format!("{name} pair {}", (b'A' + k as u8) as char);
            check_pair(b, &label, WIS[k], WOS[k], *eval, *pdf);
        }
    }

    const P1: Table = [
        ([0.1308047; 3], 0.1701359),
        ([0.212323; 3], 1.07513),
        ([0.1354568; 3], 0.2291831),
        ([0.1014023; 3], 0.1601652),
        ([0.0; 3], 0.0),
        ([0.0; 3], 0.0),
        ([0.0; 3], 0.08562388),
        ([0.0; 3], 0.0),
    ];
    const P2: Table = [
        ([0.005667994; 3], 0.01135933),
        ([7.674959; 3], 15.30405),
        ([0.01564318; 3], 0.03132218),
        ([0.005953951; 3], 0.0116867),
        ([0.0; 3], 0.0),
        ([0.0; 3], 0.0),
        ([0.0; 3], 0.01135933),
        ([0.0; 3], 0.0),
    ];
    const P3: Table = [
        ([0.02892469; 3], 0.05903516),
        ([0.1309247; 3], 0.4337178),
        ([0.03358464; 3], 0.08185256),
        ([0.02847424; 3], 0.06040122),
        ([0.3318112; 3], 0.8875135),
        ([0.0; 3], 0.0),
        ([0.003083885; 3], 0.003888444),
        ([0.7465751; 3], 0.5916756),
    ];
    const P4: Table = [
        ([0.1326983; 3], 0.1577369),
        ([0.3624675; 3], 1.860547),
        ([0.1395793; 3], 0.2181559),
        ([0.117136; 3], 0.1501335),
        ([0.0; 3], 0.0),
        ([0.0; 3], 0.0),
        ([0.0; 3], 0.08562388),
        ([0.0; 3], 0.0),
    ];
    const P5: Table = [
        ([0.09356041, 0.03566534, 0.01250732], 0.09598753),
        ([2.514929, 1.401187, 0.9556909], 8.550764),
        ([0.1164739, 0.04511309, 0.01656878], 0.1362276),
        ([0.09571446, 0.03813555, 0.01510398], 0.08314662),
        ([0.01543034, 0.009449117, 0.00545545], 0.03036406),
        ([2.897641e-06, 1.774436e-06, 1.024471e-06], 5.70671e-06),
        ([0.0004749685; 3], 0.002651663),
        ([0.04049575, 0.02479848, 0.01431741], 0.09609376),
    ];

    const P2_SET: &[(&str, &str)] = &[("metallic", "1"), ("roughness", "0.3"), ("anisotropic", "0.5")];
    const P3_SET: &[(&str, &str)] = &[("spec_trans", "0.8"), ("eta", "1.5")];
    const P4_SET: &[(&str, &str)] = &[("clearcoat", "1"), ("clearcoat_gloss", "0.5"), ("sheen", "1")];
    const P5_SET: &[(&str, &str)] = &[
        ("base_color", "0.8,0.3,0.1"),
        ("metallic", "0.4"),
        ("spec_tint", "0.6"),
        ("sheen", "0.5"),
        ("sheen_tint", "0.7"),
        ("flatness", "0.4"),
        ("clearcoat", "0.3"),
        ("clearcoat_gloss", "0.9"),
        ("spec_trans", "0.3"),
        ("anisotropic", "0.3"),
        ("roughness", "0.4"),
        ("specular", "0.7"),
    ];

    #[test]
    fn eval_and_pdf_reproduce_mitsuba() {
        check_table(build(&[]).as_ref(), "P1 defaults", &P1);
        check_table(build(P2_SET).as_ref(), "P2 metal", &P2);
        check_table(build(P3_SET).as_ref(), "P3 glass", &P3);
        check_table(build(P4_SET).as_ref(), "P4 coat+sheen", &P4);
        check_table(build(P5_SET).as_ref(), "P5 everything", &P5);
    }

    const P1_ROWS: [SampleRow; 8] = [
        ([0.48, 0.6, 0.64], 0.1, [0.3, 0.7], [-0.2828427, 0.2828427, 0.9165152], 0.1883377, [0.7942974; 3], 2),
        ([0.48, 0.6, 0.64], 0.5, [0.3, 0.7], [-0.5574018, -0.5475327, 0.6241084], 0.931238, [0.2094093; 3], 8),
        ([0.48, 0.6, 0.64], 0.9, [0.8, 0.2], [-0.07358392, -0.4782479, 0.8751369], 0.3619649, [0.4396376; 3], 8),
        ([0.48, 0.6, 0.64], 0.97, [0.55, 0.45], [-0.3818273, -0.5195429, 0.764384], 0.8954135, [0.2220748; 3], 8),
        ([0.0, 0.6, -0.8], 0.1, [0.3, 0.7], [0.0; 3], 0.0, [0.0; 3], 0),
        ([0.0, 0.6, -0.8], 0.5, [0.3, 0.7], [0.0; 3], 0.0, [0.0; 3], 0),
        ([0.0, 0.6, -0.8], 0.9, [0.8, 0.2], [0.0; 3], 0.0, [0.0; 3], 0),
        ([0.0, 0.6, -0.8], 0.97, [0.55, 0.45], [0.0; 3], 0.0, [0.0; 3], 0),
    ];
    const P2_ROWS: [SampleRow; 8] = [
        ([0.48, 0.6, 0.64], 0.1, [0.3, 0.7], [-0.5300759, -0.588511, 0.6104707], 12.07196, [0.5017654; 3], 8),
        ([0.48, 0.6, 0.64], 0.5, [0.3, 0.7], [-0.5300759, -0.588511, 0.6104707], 12.07196, [0.5017654; 3], 8),
        ([0.48, 0.6, 0.64], 0.9, [0.8, 0.2], [-0.3356298, -0.6076224, 0.7198247], 4.982397, [0.5007848; 3], 8),
        ([0.48, 0.6, 0.64], 0.97, [0.55, 0.45], [-0.4501061, -0.5963076, 0.6646968], 14.2344, [0.5012407; 3], 8),
        ([0.0, 0.6, -0.8], 0.1, [0.3, 0.7], [0.0; 3], 0.0, [0.0; 3], 0),
        ([0.0, 0.6, -0.8], 0.5, [0.3, 0.7], [0.0; 3], 0.0, [0.0; 3], 0),
        ([0.0, 0.6, -0.8], 0.9, [0.8, 0.2], [0.0; 3], 0.0, [0.0; 3], 0),
        ([0.0, 0.6, -0.8], 0.97, [0.55, 0.45], [0.0; 3], 0.0, [0.0; 3], 0),
    ];
    const P3_ROWS: [SampleRow; 8] = [
        ([0.48, 0.6, 0.64], 0.1, [0.3, 0.7], [-0.2828427, 0.2828427, 0.9165152], 0.06508897, [0.5021239; 3], 2),
        ([0.48, 0.6, 0.64], 0.5, [0.3, 0.7], [-0.2934823, -0.4179752, -0.859747], 12.02222, [0.3750669; 3], 16),
        ([0.48, 0.6, 0.64], 0.9, [0.8, 0.2], [-0.07358392, -0.4782479, 0.8751369], 0.1338845, [0.355732; 3], 8),
        ([0.48, 0.6, 0.64], 0.97, [0.55, 0.45], [-0.3818273, -0.5195429, 0.764384], 0.3505009, [0.2896606; 3], 8),
        ([0.0, 0.6, -0.8], 0.1, [0.3, 0.7], [-0.0612499, -0.9249296, 0.3751718], 1.693223, [1.170175; 3], 16),
        ([0.0, 0.6, -0.8], 0.5, [0.3, 0.7], [-0.0612499, -0.9249296, 0.3751718], 1.693223, [1.170175; 3], 16),
        ([0.0, 0.6, -0.8], 0.9, [0.8, 0.2], [0.08712272, -0.7861684, 0.6118407], 3.140745, [1.241185; 3], 16),
        ([0.0, 0.6, -0.8], 0.97, [0.55, 0.45], [0.03049525, -0.494777, -0.868485], 0.0987722, [0.7959687; 3], 8),
    ];
    const P4_ROWS: [SampleRow; 8] = [
        ([0.48, 0.6, 0.64], 0.1, [0.3, 0.7], [-0.2828427, 0.2828427, 0.9165152], 0.1729878, [0.8756365; 3], 2),
        // The clearcoat (component 1, reported as glossy reflection): GTR1 is Mitsuba's warp.
        ([0.48, 0.6, 0.64], 0.5, [0.3, 0.7], [-0.6696254, -0.01639328, 0.7425179], 0.1876514, [0.685401; 3], 1),
        ([0.48, 0.6, 0.64], 0.9, [0.8, 0.2], [-0.07358392, -0.4782479, 0.8751369], 0.3458271, [0.4789078; 3], 8),
        ([0.48, 0.6, 0.64], 0.97, [0.55, 0.45], [-0.3818273, -0.5195429, 0.764384], 0.9921446, [0.2414275; 3], 8),
        ([0.0, 0.6, -0.8], 0.1, [0.3, 0.7], [0.0; 3], 0.0, [0.0; 3], 0),
        ([0.0, 0.6, -0.8], 0.5, [0.3, 0.7], [0.0; 3], 0.0, [0.0; 3], 0),
        ([0.0, 0.6, -0.8], 0.9, [0.8, 0.2], [0.0; 3], 0.0, [0.0; 3], 0),
        ([0.0, 0.6, -0.8], 0.97, [0.55, 0.45], [0.0; 3], 0.0, [0.0; 3], 0),
    ];
    const P5_ROWS: [SampleRow; 8] = [
        (
            [0.48, 0.6, 0.64],
            0.1,
            [0.3, 0.7],
            [-0.2828427, 0.2828427, 0.9165152],
            0.09736107,
            [1.026637, 0.3895602, 0.1347292],
            2,
        ),
        (
            [0.48, 0.6, 0.64],
            0.5,
            [0.3, 0.7],
            [-0.5471854, -0.5762211, 0.6070893],
            2.488699,
            [0.6423689, 0.2705599, 0.1218363],
            8,
        ),
        (
            [0.48, 0.6, 0.64],
            0.9,
            [0.8, 0.2],
            [-0.220563, -0.5833373, 0.7817095],
            0.8354259,
            [0.7038379, 0.2830053, 0.1146723],
            8,
        ),
        (
            [0.48, 0.6, 0.64],
            0.97,
            [0.55, 0.45],
            [-0.4204603, -0.5784659, 0.6989922],
            2.694614,
            [0.631176, 0.2640064, 0.1171386],
            8,
        ),
        ([0.0, 0.6, -0.8], 0.1, [0.3, 0.7], [-0.08792463, -0.643048, -0.760762], 3.052477, [0.1793824; 3], 8),
        ([0.0, 0.6, -0.8], 0.5, [0.3, 0.7], [-0.08792463, -0.643048, -0.760762], 3.052477, [0.1793824; 3], 8),
        ([0.0, 0.6, -0.8], 0.9, [0.8, 0.2], [0.1764756, -0.4480591, -0.8764128], 0.1393602, [0.1797171; 3], 8),
        ([0.0, 0.6, -0.8], 0.97, [0.55, 0.45], [0.02191566, -0.5617468, -0.8270188], 0.7067785, [0.1796126; 3], 8),
    ];

    #[test]
    fn samples_agree_with_mitsubas_rows() {
        for (set, name, rows) in [
            (&[][..], "P1", &P1_ROWS),
            (P2_SET, "P2", &P2_ROWS),
            (P3_SET, "P3", &P3_ROWS),
            (P4_SET, "P4", &P4_ROWS),
            (P5_SET, "P5", &P5_ROWS),
        ] {
            let b = build(set);
            for (k, row) in rows.iter().enumerate() {
                // Diffuse (type 2) and clearcoat rows use Mitsuba's own warps here.
                let same_warp = row.6 == 2 || row.6 == 1;
                check_sample_row(b.as_ref(), &format!("{name} sample row {k}"), row, same_warp);
            }
        }
    }

    #[test]
    fn sample_is_consistent_and_carries_the_index_it_crosses() {
        let b = build(P5_SET);
        let mut refracted = [0usize; 2];
        for wo in [Vec3::new(0.48, 0.6, 0.64), Vec3::new(0.0, 0.6, -0.8), Vec3::new(0.3, -0.1, 0.948_683_3)] {
            for i in 0..32 {
                for j in 0..32 {
                    let u = Vec2::new((i as f32 + 0.5) / 32.0, (j as f32 + 0.3) / 32.0);
                    let uc = ((i * 32 + j) as f32 * 0.618_034).fract();
                    let Some(s) = b.sample(wo, uc, u) else { continue };
                    assert_eq!(s.pdf, b.pdf(s.wi, wo));
                    let want = b.eval(s.wi, wo) * (s.wi.z.abs() / s.pdf);
                    assert!(s.weight.0.iter().zip(want.0).all(|(a, b)| close(*a, b, 1e-6)));
                    if s.wi.z * wo.z < 0.0 {
                        let eta = eta_from_specular(0.7);
                        assert_eq!(s.eta, if wo.z > 0.0 { eta } else { 1.0 / eta });
                        refracted[(wo.z < 0.0) as usize] += 1;
                    } else {
                        assert_eq!(s.eta, 1.0);
                    }
                }
            }
        }
        assert!(refracted[0] > 50 && refracted[1] > 50, "{refracted:?}");
    }

    #[test]
    fn intermediate_values() {
        assert_eq!(eta_from_specular(0.5), 1.5);
        assert!((eta_from_specular(0.7) - 1.620_006_8).abs() < 1e-6);
        assert!((eta_from_specular(1.0) - 1.788_788_6).abs() < 1e-6);
        assert!((eta_from_specular(1e-3) - 1.018_05).abs() < 1e-6);
        assert_eq!(eta_from_specular(0.0), 1.0);
        // η from specular, and Mitsuba's bumps when spec_trans is present.
        let eta = |set: &[(&str, &str)]| SPEC.build_with(set).unwrap().eta();
        assert_eq!(eta(&[("spec_trans", "0.5")]), 1.5);
        assert!((eta(&[("spec_trans", "0.5"), ("specular", "0.7")]) - 1.620_006_8).abs() < 1e-6);
        assert!((eta(&[("spec_trans", "0.5"), ("specular", "0")]) - 1.018_05).abs() < 1e-6);
        assert_eq!(eta(&[("spec_trans", "0.5"), ("eta", "1")]), 1.001);
        assert_eq!(eta(&[("spec_trans", "0.5"), ("eta", "1.33")]), 1.33);
        let p = |set: &[(&str, &str)]| make(&crate::Params::resolve("principled", &params(), set).unwrap()).unwrap();
        assert_eq!(p(&[("eta", "1")]).eta, 1.0, "no bump without spec_trans");
        assert_eq!(p(&[("specular", "0")]).eta, 1.0);
        let m = p(P2_SET);
        assert_eq!((m.dist.ggx.alpha_x, m.dist.ggx.alpha_y), (0.121_355_97, 0.066_745_795));
        assert_eq!(p(P4_SET).clearcoat_alpha, 0.0505);
        // Giving both is refused, naming both; eta below 1 is refused, naming it.
        let e = SPEC.build_with(&[("eta", "1.5"), ("specular", "0.5")]).unwrap_err();
        assert!(matches!(&e, ParamError::Inconsistent(s) if s.contains("'eta'") && s.contains("'specular'")), "{e}");
        let e = SPEC.build_with(&[("eta", "0.5")]).unwrap_err().to_string();
        assert!(e.contains("'eta'"), "{e}");
        assert!(SPEC.build_with(&[("eta", "0"), ("specular", "0.3")]).is_ok(), "eta 0 reads as absent");
    }

    #[test]
    fn metallic_quirks() {
        // A metal with η = 1 is black at the mirror pair, though its pdf is not.
        let wi = Vec3::new(-0.48, -0.6, 0.64);
        let wo = Vec3::new(0.48, 0.6, 0.64);
        let b = build(&[("metallic", "1"), ("specular", "0")]);
        assert_eq!(b.eval(wi, wo), Rgb::ZERO);
        assert!(close(b.pdf(wi, wo), 1.946_542, 1e-4), "{}", b.pdf(wi, wo));
        for set in
            [&[("metallic", "1"), ("specular", "1e-6")][..], &[("metallic", "1"), ("eta", "1"), ("spec_trans", "0.5")]]
        {
            let f = build(set).eval(wi, wo).0[0] * wi.z;
            assert!(close(f, 0.958_044, 1e-4), "{set:?}: {f}");
        }
    }

    #[test]
    fn flags_and_claims() {
        let d = build(&[]);
        assert!(!d.transmits() && !d.back_side() && d.eta() == 1.0);
        assert!(d.claims().isotropic && d.claims().reciprocal && !d.claims().energy_conserving);
        let g = build(P3_SET);
        assert!(g.transmits() && g.back_side() && g.eta() == 1.5);
        assert!(!build(P2_SET).claims().isotropic && build(P2_SET).claims().energy_conserving);
        assert!(!build(&[("metallic", "1"), ("spec_trans", "1")]).transmits());
        assert!(build(&[("spec_trans", "1"), ("eta", "1.5")]).claims().energy_conserving);
        assert!(!build(P4_SET).claims().energy_conserving);
    }

    #[test]
    fn the_model_gains_energy_where_the_notes_say() {
        // White, rough, coated: the diffuse lobe is not reduced by the specular F and
        // the clearcoat lacks 1/(4 cos θi cos θo); at normal incidence the albedo passes 1.
        let b = build(&[("base_color", "1"), ("clearcoat", "1"), ("roughness", "1"), ("sheen", "1")]);
        let (a, se) = albedo_f64(b.as_ref(), Vec3::Z, 200_000, 3);
        assert!(a[0] - 4.0 * se[0] > 1.0, "albedo {} ± {}", a[0], se[0]);
        assert!(!b.claims().energy_conserving);
    }
}
