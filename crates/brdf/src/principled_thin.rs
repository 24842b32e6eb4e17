//! Mitsuba 3.9.1's `principledthin` BSDF: the thin-surface variant of the Disney principled
//! model (Burley 2015, §4.3 "thin surfaces"), a two-sided sheet with the same medium on both
//! sides, evaluated as Mitsuba 3.9.1 evaluates it, quirks included.
//!
//! Notation (gonio's directions: wo towards the viewer, Mitsuba's `si.wi`; wi towards the light):
//! both are first mirrored so that wo is above, s = sign(wo.z), wo ← s wo, wi ← s wi; c_o = wo.z,
//! c_i = wi.z; a pair reflects when c_i > 0 and is transmitted when c_i < 0. The sheet does not
//! bend light, so one half vector serves both: h = normalize(wo + wi_r), wi_r = (wi.x, wi.y, |c_i|),
//! and F = F_dielectric(wo·h, η). C = base_color, S = spec_trans, T = spec_tint, dt = diff_trans/2.
//! GGX with separable Smith masking, α from (roughness, anisotropic) for reflection and from
//! (anisotropic, r_t) for transmission, r_t = (0.65 η − 0.35)·roughness. Then ρ is the sum of
//!
//! - specular reflection (only with spec_trans): S·lerp(F, Schlick(C/lum(C)·R0(η)), T)·D G / (4 c_o c_i);
//! - specular transmission, where wi is across h (wi·h < 0: every θi beyond 60° at normal
//!   incidence is cut off): S·C·(1 − F)·D_t G_t / (4 c_o |c_i|) (colour C, not √C; no η²);
//! - diffuse reflection, where S < 1 and dt < 1: (1 − S)(1 − dt)·C/π·(Disney diffuse with
//!   retro-reflection and the flatness blend, as `principled`), plus sheen
//!   sheen·(1 − S)(1 − dt)·schlick_weight(h·wi)·lerp(1, C/lum(C), sheen_tint);
//! - diffuse transmission, where S < 1: (1 − S)·dt·C/π.
//!
//! Sampling picks with uc, by the normalised weights S·rate_sr/2, S·rate_st/2,
//! rate_dr (1 − S)(1 − dt) and rate_dt (1 − S) dt: a GGX visible normal and reflection about it;
//! a GGX_t visible normal, reflection and the z flipped; a cosine-weighted direction above; or
//! below. The pdf is the mixture's: the visible-normal densities over 4|wi_r·h|, c_i/π and |c_i|/π.
//! No index is crossed (η is only the sheet's Fresnel), so `eta` is 1 everywhere, as in Mitsuba.
//! gonio's visible-normal warp is not Mitsuba's: same density, other directions for the same u.
//!
//! The spec transmission's cut-off makes the model non-reciprocal wherever spec_trans > 0 (ρ(wi, wo)
//! is cut where ρ(wo, wi) is not); without it the model is reciprocal.
//!
//! Sources: Mitsuba 3.9.1, `src/bsdfs/principledthin.cpp` and `principledhelpers.h` (behaviour,
//! read for the conventions and checked against its numbers); B. Burley, "Extending the Disney
//! BRDF to a BSDF with Integrated Subsurface Scattering", SIGGRAPH 2015 course notes; B. Burley,
//! "Physically Based Shading at Disney", SIGGRAPH 2012 course notes.

use crate::model::{reflect, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::principled_common::{
    alphas, calc_schlick, compatible, diffuse_shape, fresnel, has, lerp_rgb, pick, schlick_r0, schlick_weight, tint,
    SmithGgx,
};
use crate::registry::{by_value, ModelSpec};
use radiometry::warp::cosine_hemisphere;
use radiometry::{Rgb, Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Which of the optional lobes and terms Mitsuba switches on (its `has_*` flags).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Has {
    spec_trans: bool,
    spec_tint: bool,
    sheen: bool,
    sheen_tint: bool,
    flatness: bool,
    diff_trans: bool,
}

/// Mitsuba 3.9.1's `principledthin` BSDF at one surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipledThin {
    /// Base colour C.
    base_color: Rgb,
    /// C / lum(C), the tint colour.
    tint: Rgb,
    /// Roughness, for the retro-reflection.
    roughness: f32,
    /// Specular weight S (reflection and transmission).
    spec_trans: f32,
    /// The sheet's relative index η, for its Fresnel term and the transmission roughness.
    eta: f32,
    /// Specular tint weight T.
    spec_tint: f32,
    /// Sheen weight.
    sheen: f32,
    /// Sheen tint weight.
    sheen_tint: f32,
    /// Fake-subsurface blend weight.
    flatness: f32,
    /// diff_trans / 2: the diffuse transmission share.
    dt: f32,
    /// Sampling rates: specular reflection, specular transmission, diffuse reflection, diffuse
    /// transmission.
    rates: [f32; 4],
    /// The optional terms present.
    has: Has,
    /// GGX of the reflection.
    dist: SmithGgx,
    /// GGX of the transmission (roughness r_t).
    dist_t: SmithGgx,
}

impl PrincipledThin {
    /// The lobe probabilities (spec reflection, spec transmission, diffuse reflection, diffuse
    /// transmission), normalised.
    #[inline]
    fn lobe_probabilities(&self) -> [f32; 4] {
        let s = self.spec_trans;
        let st = if self.has.spec_trans { s * 0.5 } else { 0.0 };
        let p = [
            st * self.rates[0],
            st * self.rates[1],
            self.rates[2] * (1.0 - s) * (1.0 - self.dt),
            if self.has.diff_trans { self.rates[3] * (1.0 - s) * self.dt } else { 0.0 },
        ];
        let sum: f32 = p.iter().sum();
        if sum > 0.0 && sum.is_finite() {
            p.map(|x| x / sum)
        } else {
            [0.0; 4]
        }
    }

    /// ρ(wi, wo) and pdf(wi | wo) together: they share the half vector, D, G and F.
    fn evaluate(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        if wo.z == 0.0 || wi.z == 0.0 || !(wo.z.is_finite() && wi.z.is_finite()) {
            return (Rgb::ZERO, 0.0);
        }
        // Two-sided: work with wo above.
        let (wo, wi) = if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) };
        let (co, ci) = (wo.z, wi.z);
        let reflect = ci > 0.0;
        let wi_r = Vec3::new(wi.x, wi.y, ci.abs());
        let h = (wo + wi_r).normalize_or_zero();
        if h == Vec3::ZERO {
            return (Rgb::ZERO, 0.0);
        }
        let [p_sr, p_st, p_dr, p_dt] = self.lobe_probabilities();
        let (s, dt) = (self.spec_trans, self.dt);
        let mut rho = Rgb::ZERO;
        let mut pdf = 0.0;
        if self.has.spec_trans {
            let wo_h = wo.dot(h);
            let f = fresnel(wo_h, self.eta).f;
            let jacobian = 1.0 / (4.0 * wi_r.dot(h).abs());
            if reflect && compatible(h, wo, wi, co, true) {
                if s > 0.0 {
                    let schlick = if self.has.spec_tint {
                        calc_schlick(self.tint * schlick_r0(self.eta), wo_h, self.eta)
                    } else {
                        Rgb::ZERO
                    };
                    let f_thin = lerp_rgb(Rgb::splat(f), schlick, self.spec_tint);
                    rho += f_thin * (s * self.dist.d(h) * self.dist.g(wo, wi, h) / (4.0 * co * ci));
                }
                pdf += p_sr * self.dist.pdf(wo, h) * jacobian;
            }
            if !reflect && compatible(h, wo, wi, co, false) {
                if s > 0.0 {
                    let t = s * (1.0 - f) * self.dist_t.d(h) * self.dist_t.g(wo, wi, h) / (4.0 * co * ci.abs());
                    rho += self.base_color * t;
                }
                pdf += p_st * self.dist_t.pdf(wo, h) * jacobian;
            }
        }
        if reflect {
            if s < 1.0 && dt < 1.0 {
                let cd = h.dot(wi);
                let flat = self.has.flatness.then_some(self.flatness);
                let w = (1.0 - s) * (1.0 - dt);
                rho += self.base_color * (w * FRAC_1_PI * diffuse_shape(self.roughness, cd, co, ci, flat));
                if self.has.sheen {
                    let c_sheen =
                        if self.has.sheen_tint { lerp_rgb(Rgb::ONE, self.tint, self.sheen_tint) } else { Rgb::ONE };
                    rho += c_sheen * (self.sheen * w * schlick_weight(cd.abs()));
                }
            }
            pdf += p_dr * ci * FRAC_1_PI;
        } else if self.has.diff_trans {
            if s < 1.0 && dt > 0.0 {
                rho += self.base_color * ((1.0 - s) * dt * FRAC_1_PI);
            }
            pdf += p_dt * -ci * FRAC_1_PI;
        }
        if !(rho.is_finite() && pdf.is_finite()) {
            return (Rgb::ZERO, 0.0);
        }
        (rho, pdf)
    }
}

impl Brdf for PrincipledThin {
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
        if wo.z == 0.0 || !wo.is_finite() {
            return None;
        }
        let side = if wo.z < 0.0 { -1.0 } else { 1.0 };
        let up = wo * side;
        let [p_sr, p_st, p_dr, _] = self.lobe_probabilities();
        // Mitsuba's order; the rest goes to diffuse transmission, when there is one.
        let lobe = pick(&[p_sr, p_st, p_dr], uc).or(self.has.diff_trans.then_some(3))?;
        let wi = match lobe {
            0 => {
                let m = self.dist.sample(up, u);
                let wi = reflect(up, m).normalize();
                (wi.z > 0.0 && compatible(m, up, wi, up.z, true)).then_some(wi)?
            }
            1 => {
                let m = self.dist_t.sample(up, u);
                let r = reflect(up, m).normalize();
                let wi = Vec3::new(r.x, r.y, -r.z);
                (wi.z < 0.0 && compatible(m, up, wi, up.z, false)).then_some(wi)?
            }
            2 => cosine_hemisphere(u),
            _ => -cosine_hemisphere(u),
        } * side;
        let (rho, pdf) = self.evaluate(wi, wo);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = rho * (wi.z.abs() / pdf);
        weight.is_finite().then_some(BrdfSample::reflected(wi, pdf, weight, false))
    }

    fn claims(&self) -> Claims {
        let specular = self.has.spec_trans && self.spec_trans > 0.0;
        // Energy: provable for a pure Lambertian transmitter only (spec_trans 0, diff_trans 2:
        // ρ = C/π below, nothing above); the Disney diffuse passes 1 at grazing, and the
        // specular lobes use two different distributions.
        let lambert_transmitter = !specular && self.dt == 1.0 && self.has.diff_trans;
        Claims {
            reciprocal: !specular,
            energy_conserving: lambert_transmitter,
            isotropic: self.dist.is_isotropic() && self.dist_t.is_isotropic(),
        }
    }

    fn transmits(&self) -> bool {
        let specular = self.has.spec_trans && self.spec_trans > 0.0;
        let diffuse = self.has.diff_trans && self.dt > 0.0 && self.spec_trans < 1.0;
        specular || diffuse
    }

    fn back_side(&self) -> bool {
        true
    }

    fn eta(&self) -> f32 {
        // Both sides are the same medium: nothing is refracted, radiance is not rescaled.
        1.0
    }
}

fn params() -> Vec<ParamSpec> {
    let w = |name, doc| ParamSpec::float(name, 0.0, 1.0, 0.0, doc);
    let rate = |name, doc| ParamSpec::float(name, 0.0, 100.0, 1.0, doc).fixed();
    vec![
        ParamSpec::rgb("base_color", 0.0, 1.0, 0.5, "base colour C: diffuse albedo and transmission colour"),
        ParamSpec::float("roughness", 0.0, 1.0, 0.5, "roughness r: GGX α = r² (transmission: ((0.65η − 0.35) r)²)"),
        w("anisotropic", "anisotropy a: α_x = α/√(1 − 0.9a), α_y = α·√(1 − 0.9a)"),
        w("spec_trans", "specular weight S: the glossy reflection and transmission (0: purely diffuse)"),
        ParamSpec::float("eta", 1.0, 10.0, 1.5, "index of refraction of the sheet (its Fresnel term and r_t)"),
        w("spec_tint", "tints the specular reflection towards base_color"),
        w("sheen", "sheen weight: a grazing retro-reflective lobe for cloth"),
        w("sheen_tint", "tints the sheen towards base_color"),
        w("flatness", "blends the diffuse lobe towards a fake subsurface (Hanrahan-Krueger-like) one"),
        ParamSpec::float(
            "diff_trans",
            0.0,
            2.0,
            0.0,
            "diffuse transmission: diff_trans/2 of the diffuse light goes through",
        ),
        rate("specular_reflectance_sampling_rate", "relative rate of sampling the specular reflection"),
        rate("specular_transmittance_sampling_rate", "relative rate of sampling the specular transmission"),
        rate("diffuse_reflectance_sampling_rate", "relative rate of sampling the diffuse reflection"),
        rate("diffuse_transmittance_sampling_rate", "relative rate of sampling the diffuse transmission"),
    ]
}

/// The transmission roughness factor of the sheet, 0.65 η − 0.35 (0.625 at η = 1.5).
pub fn transmission_roughness_factor(eta: f32) -> f32 {
    0.65 * eta - 0.35
}

fn make(p: &dyn ParamSource) -> Result<PrincipledThin, ParamError> {
    let base_color = p.rgb("base_color");
    let (roughness, anisotropic, eta) = (p.float("roughness"), p.float("anisotropic"), p.float("eta"));
    let (ax, ay) = alphas(roughness, anisotropic);
    let (tx, ty) = alphas(transmission_roughness_factor(eta) * roughness, anisotropic);
    Ok(PrincipledThin {
        base_color,
        tint: tint(base_color),
        roughness,
        spec_trans: p.float("spec_trans"),
        eta,
        spec_tint: p.float("spec_tint"),
        sheen: p.float("sheen"),
        sheen_tint: p.float("sheen_tint"),
        flatness: p.float("flatness"),
        dt: 0.5 * p.float("diff_trans"),
        rates: [
            p.float("specular_reflectance_sampling_rate"),
            p.float("specular_transmittance_sampling_rate"),
            p.float("diffuse_reflectance_sampling_rate"),
            p.float("diffuse_transmittance_sampling_rate"),
        ],
        has: Has {
            spec_trans: has(p, "spec_trans"),
            spec_tint: has(p, "spec_tint"),
            sheen: has(p, "sheen"),
            sheen_tint: has(p, "sheen_tint"),
            flatness: has(p, "flatness"),
            diff_trans: has(p, "diff_trans"),
        },
        dist: SmithGgx::new(ax, ay),
        dist_t: SmithGgx::new(tx, ty),
    })
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "principledthin",
    summary: "thin-sheet Disney principled BSDF as Mitsuba 3.9.1's principledthin: glossy and diffuse transmission",
    reference: "Burley 2015, Extending the Disney BRDF to a BSDF; Mitsuba 3 principledthin.cpp",
    params,
    build: by_value!(make),
    // A glossy tinted sheet (both specular lobes, anisotropic, some diffuse transmission); a
    // diffusing, sheened fabric without specular lobes (reciprocal).
    showcase: &[
        &[
            ("base_color", "0.7,0.4,0.3"),
            ("spec_trans", "0.8"),
            ("roughness", "0.3"),
            ("anisotropic", "0.4"),
            ("spec_tint", "0.2"),
            ("eta", "1.33"),
            ("diff_trans", "0.3"),
        ],
        &[
            ("base_color", "0.3,0.5,0.8"),
            ("diff_trans", "1.2"),
            ("sheen", "0.6"),
            ("sheen_tint", "0.5"),
            ("flatness", "0.5"),
        ],
    ],
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::principled::tests::{check_sample_row, check_table, SampleRow, Table};

    fn build(set: &[(&str, &str)]) -> Box<dyn Brdf> {
        SPEC.build_with(set).unwrap()
    }

    const T1: Table = [
        ([0.12735; 3], 0.2546479),
        ([0.1017478; 3], 0.2037183),
        ([0.1273403; 3], 0.2546479),
        ([0.09116005; 3], 0.1909859),
        ([0.0; 3], 0.0),
        ([0.0; 3], 0.0),
        ([0.12735; 3], 0.2546479),
        ([0.0; 3], 0.0),
    ];
    const T2: Table = [
        ([0.02823376; 3], 0.08517914),
        ([0.1088097; 3], 0.8193604),
        ([0.03196133; 3], 0.1324169),
        ([0.02642579; 3], 0.08993497),
        ([3.978352; 3], 4.166571),
        ([0.006446143; 3], 0.006740842),
        ([0.02823376; 3], 0.08517914),
        ([3.978352; 3], 4.166571),
    ];
    const T3: Table = [
        ([0.03031283, 0.004339822, 0.004339822], 0.04358738),
        ([7.279686, 6.226654, 6.226654], 98.25969),
        ([0.03034289, 0.004361588, 0.004361588], 0.0441535),
        ([0.02083912, 0.003003474, 0.003003474], 0.03277865),
        ([1534.477, 219.211, 219.211], 1121.645),
        ([0.005457447, 0.0007796353, 0.0007796353], 0.007719641),
        ([0.03031283, 0.004339822, 0.004339822], 0.04358738),
        ([1534.477, 219.211, 219.211], 1121.645),
    ];
    const T4: Table = [
        ([0.01668011, 0.02763486, 0.04406699], 0.08574919),
        ([0.0199316, 0.03017795, 0.04554746], 0.2325641),
        ([0.0161456, 0.02662152, 0.04233541], 0.1050644),
        ([0.01919941, 0.03004898, 0.04632334], 0.08302379),
        ([2.691856, 4.486426, 7.178282], 4.578929),
        ([0.02846126, 0.04743543, 0.07589669], 0.0932879),
        ([0.01668011, 0.02763486, 0.04406699], 0.08574919),
        ([2.691856, 4.486426, 7.178282], 4.578929),
    ];

    const T2_SET: &[(&str, &str)] = &[("spec_trans", "0.8"), ("eta", "1.5")];
    const T3_SET: &[(&str, &str)] = &[
        ("base_color", "0.7,0.1,0.1"),
        ("roughness", "0.15"),
        ("spec_tint", "0.1"),
        ("anisotropic", "0.5"),
        ("spec_trans", "0.8"),
        ("diff_trans", "0.3"),
        ("eta", "1.33"),
    ];
    const T4_SET: &[(&str, &str)] = &[
        ("base_color", "0.3,0.5,0.8"),
        ("spec_trans", "0.4"),
        ("diff_trans", "1.2"),
        ("sheen", "0.6"),
        ("sheen_tint", "0.5"),
        ("flatness", "0.5"),
        ("roughness", "0.6"),
        ("eta", "1.2"),
        ("spec_tint", "0.4"),
    ];

    #[test]
    fn eval_and_pdf_reproduce_mitsuba() {
        for (set, name, table) in
            [(&[][..], "T1 defaults", &T1), (T2_SET, "T2 spec_trans", &T2), (T3_SET, "T3", &T3), (T4_SET, "T4", &T4)]
        {
            check_table(build(set).as_ref(), name, table);
        }
    }

    const UP: [f32; 3] = [0.48, 0.6, 0.64];
    const DOWN: [f32; 3] = [0.0, 0.6, -0.8];

    const T1_ROWS: [SampleRow; 8] = [
        (UP, 0.1, [0.3, 0.7], [-0.2828427, 0.2828427, 0.9165152], 0.2917358, [0.5009386; 3], 2),
        (UP, 0.5, [0.3, 0.7], [-0.2828427, 0.2828427, 0.9165152], 0.2917358, [0.5009386; 3], 2),
        (UP, 0.9, [0.8, 0.2], [0.4242641, -0.4242641, 0.8], 0.2546479, [0.500734; 3], 2),
        (UP, 0.97, [0.55, 0.45], [0.07071069, -0.0707107, 0.9949874], 0.3167143, [0.5009498; 3], 2),
        (DOWN, 0.1, [0.3, 0.7], [0.2828427, -0.2828427, -0.9165152], 0.2917358, [0.5000457; 3], 2),
        (DOWN, 0.5, [0.3, 0.7], [0.2828427, -0.2828427, -0.9165152], 0.2917358, [0.5000457; 3], 2),
        (DOWN, 0.9, [0.8, 0.2], [-0.4242641, 0.4242641, -0.8], 0.2546479, [0.5001432; 3], 2),
        (DOWN, 0.97, [0.55, 0.45], [-0.07071069, 0.0707107, -0.9949874], 0.3167143, [0.5000671; 3], 2),
    ];
    const T2_ROWS: [SampleRow; 8] = [
        (UP, 0.1, [0.3, 0.7], [-0.5574018, -0.5475327, 0.6241084], 0.7052584, [0.1368142; 3], 8),
        (UP, 0.5, [0.3, 0.7], [-0.5228923, -0.5949721, -0.6104029], 4.115801, [0.9360449; 3], 16),
        (UP, 0.9, [0.8, 0.2], [0.4242641, -0.4242641, 0.8], 0.07807285, [0.3554821; 3], 2),
        (UP, 0.97, [0.55, 0.45], [0.07071069, -0.0707107, 0.9949874], 0.1206107, [0.3017846; 3], 2),
        (DOWN, 0.1, [0.3, 0.7], [-0.1153776, -0.6469602, -0.7537441], 0.5735787, [0.1232657; 3], 8),
        (DOWN, 0.5, [0.3, 0.7], [-0.04642599, -0.6354641, 0.7707335], 3.186579, [0.9538487; 3], 16),
        (DOWN, 0.9, [0.8, 0.2], [-0.4242641, 0.4242641, -0.8], 0.0692726, [0.3887342; 3], 2),
        (DOWN, 0.97, [0.55, 0.45], [-0.07071069, 0.0707107, -0.9949874], 0.1407378, [0.2691876; 3], 2),
    ];
    const T3_ROWS: [SampleRow; 8] = [
        (UP, 0.1, [0.3, 0.7], [-0.4955329, -0.5980011, 0.6299537], 71.63596, [0.07526293, 0.0644785, 0.0644785], 8),
        (UP, 0.5, [0.3, 0.7], [-0.4843303, -0.5995294, -0.6371726], 998.1372, [1.352772, 0.1932532, 0.1932532], 16),
        (UP, 0.9, [0.8, 0.2], [0.4242641, -0.4242641, 0.8], 0.04412664, [0.6864644, 0.09869038, 0.09869038], 2),
        (
            UP,
            0.97,
            [0.55, 0.45],
            [-0.07071069, 0.0707107, -0.9949874],
            0.009524491,
            [0.7016253, 0.1002322, 0.1002322],
            4,
        ),
        (DOWN, 0.1, [0.3, 0.7], [-0.01486743, -0.6078457, -0.793916], 56.3519, [0.05413605, 0.04311488, 0.04311488], 8),
        (DOWN, 0.5, [0.3, 0.7], [-0.003957414, -0.6021531, 0.798371], 794.6852, [1.368019, 0.1954313, 0.1954313], 16),
        (DOWN, 0.9, [0.8, 0.2], [-0.4242641, 0.4242641, -0.8], 0.04336188, [0.6988256, 0.09988352, 0.09988352], 2),
        (
            DOWN,
            0.97,
            [0.55, 0.45],
            [0.07071069, -0.0707107, 0.9949874],
            0.009567598,
            [0.7046449, 0.1006636, 0.1006636],
            4,
        ),
    ];
    const T4_ROWS: [SampleRow; 8] = [
        (UP, 0.1, [0.3, 0.7], [-0.5656759, -0.484225, 0.6674852], 0.2083098, [0.09240428, 0.1426797, 0.2180929], 8),
        (UP, 0.5, [0.3, 0.7], [-0.2828427, 0.2828427, 0.9165152], 0.09529308, [0.202786, 0.3361667, 0.536238], 2),
        (UP, 0.9, [0.8, 0.2], [-0.4242641, 0.4242641, -0.8], 0.09262735, [0.3030327, 0.5050545, 0.8080871], 4),
        (UP, 0.97, [0.55, 0.45], [-0.07071069, 0.0707107, -0.9949874], 0.1170258, [0.3075813, 0.5126355, 0.8202167], 4),
        (DOWN, 0.1, [0.3, 0.7], [-0.1659037, -0.6272212, -0.7609663], 0.1881432, [0.09491386, 0.1524791, 0.238827], 8),
        (DOWN, 0.5, [0.3, 0.7], [0.2828427, -0.2828427, -0.9165152], 0.1483103, [0.1300458, 0.213092, 0.3376614], 2),
        (DOWN, 0.9, [0.8, 0.2], [0.4242641, -0.4242641, 0.8], 0.105369, [0.338225, 0.5637082, 0.9019332], 4),
        (DOWN, 0.97, [0.55, 0.45], [0.07071069, -0.0707107, 0.9949874], 0.1261028, [0.32827, 0.5471166, 0.8753866], 4),
    ];

    #[test]
    fn samples_agree_with_mitsubas_rows() {
        for (set, name, rows) in
            [(&[][..], "T1", &T1_ROWS), (T2_SET, "T2", &T2_ROWS), (T3_SET, "T3", &T3_ROWS), (T4_SET, "T4", &T4_ROWS)]
        {
            let b = build(set);
            for (k, row) in rows.iter().enumerate() {
                // Diffuse reflection (2) and transmission (4) use Mitsuba's own warp here.
                let same_warp = row.6 == 2 || row.6 == 4;
                check_sample_row(b.as_ref(), &format!("{name} sample row {k}"), row, same_warp);
            }
        }
    }

    #[test]
    fn sample_is_consistent_and_never_crosses_an_index() {
        let b = build(T3_SET);
        let mut through = 0;
        for wo in [Vec3::from_array(UP), Vec3::from_array(DOWN), Vec3::new(0.3, -0.1, 0.948_683_3)] {
            for i in 0..32 {
                for j in 0..32 {
                    let u = Vec2::new((i as f32 + 0.5) / 32.0, (j as f32 + 0.3) / 32.0);
                    let uc = ((i * 32 + j) as f32 * 0.618_034).fract();
                    let Some(s) = b.sample(wo, uc, u) else { continue };
                    assert_eq!(s.pdf, b.pdf(s.wi, wo));
                    let want = b.eval(s.wi, wo) * (s.wi.z.abs() / s.pdf);
                    assert!(s.weight.0.iter().zip(want.0).all(|(a, b)| (a - b).abs() <= 1e-6 * a.abs().max(b.abs())));
                    assert_eq!(s.eta, 1.0);
                    through += (s.wi.z * wo.z < 0.0) as usize;
                }
            }
        }
        assert!(through > 500, "{through}");
    }

    #[test]
    fn transmission_cut_off_and_roughness_factor() {
        assert_eq!(transmission_roughness_factor(1.5), 0.625);
        assert!((transmission_roughness_factor(1.33) - 0.5145).abs() < 1e-6);
        // At normal incidence the glossy transmission ends at θ = 60°.
        let b = build(&[("spec_trans", "1"), ("roughness", "0.6")]);
        for (deg, eval, pdf) in [(30.0f32, 0.1033009, 0.1077912), (59.9, 0.01065888, 0.01128178), (60.1, 0.0, 0.0)] {
            let (s, c) = deg.to_radians().sin_cos();
            let light = Vec3::new(s, 0.0, -c);
            let f = b.eval(light, Vec3::Z).0[0] * c;
            let p = b.pdf(light, Vec3::Z);
            let ok = |a: f32, b: f32| if b == 0.0 { a == 0.0 } else { (a - b).abs() <= 1e-4 * b };
            assert!(ok(f, eval) && ok(p, pdf), "θ {deg}: {f} {p}");
        }
    }

    #[test]
    fn flags_and_claims() {
        let d = build(&[]);
        assert!(!d.transmits() && d.back_side() && d.eta() == 1.0);
        assert!(d.claims().reciprocal && d.claims().isotropic && !d.claims().energy_conserving);
        let t = build(T3_SET);
        assert!(t.transmits() && !t.claims().reciprocal && !t.claims().isotropic);
        let lambert = build(&[("diff_trans", "2"), ("base_color", "0.7")]);
        assert!(lambert.transmits() && lambert.claims().energy_conserving);
        let (a, _) = crate::check::albedo_f64(lambert.as_ref(), Vec3::new(0.0, 0.6, 0.8), 1000, 1);
        assert!((a[0] - 0.7).abs() < 1e-5, "{a:?}");
        assert!(build(&[("diff_trans", "1")]).transmits());
    }
}
