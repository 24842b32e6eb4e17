//! Phong's specular lobe, as the lecture's illumination model writes it (`phong`) and in
//! Lafortune & Willems' physically based form (`modified-phong`).
//!
//! Let R(w) = (−w_x, −w_y, w_z) be the mirror direction and cos α = R(wi)·wo = R(wo)·wi the
//! cosine between the reflected light direction and the viewer (zero when negative).
//!
//! `phong`: the illumination model L_o = L_light k_s (R·V)^k_e, read as a BRDF against the
//! irradiance E = L_light cos θi that a point light delivers:
//!   ρ(wi, wo) = k_s cos^k_e α / cos θi.
//! The 1/cos θi makes it non-reciprocal, and its albedo k_s ∫ cos^k_e α dω reaches
//! 2π k_s/(k_e + 1): it claims neither reciprocity nor energy conservation.
//!
//! `modified-phong`: ρ(wi, wo) = k_s (k_e + 2)/(2π) cos^k_e α, reciprocal; at normal incidence
//! the albedo is exactly k_s (∫ cos^k_e θ cos θ dω = 2π/(k_e + 2)) and it is largest there, so
//! the lobe conserves energy for k_s ≤ 1 (and with a diffuse lobe, for ρ_d + k_s ≤ 1).
//!
//! Sampling (both): wi about R(wo) with density (k_e + 1)/(2π) cos^k_e α, cos α = u^(1/(k_e+1));
//! draws below the surface are returned as `None`, so `pdf` is that density on the upper
//! hemisphere only and integrates to less than 1 when the lobe reaches under the horizon.
//! Weights: raw 2π k_s/(k_e + 1), modified k_s (k_e + 2)/(k_e + 1) cos θi.
//!
//! Sources: B. T. Phong, "Illumination for Computer Generated Pictures", CACM 18(6), 1975;
//! E. P. Lafortune & Y. D. Willems, "Using the modified Phong reflectance model for physically
//! based rendering", Report CW 197, KU Leuven, 1994.

use crate::combine;
use crate::model::{reflect_z, same_upper_hemisphere, Brdf, BrdfSample, Claims, PhongTerms};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::ModelSpec;
use radiometry::trig::sin_cos_pi;
use radiometry::{Frame, Rgb, Vec2, Vec3};
use std::f32::consts::TAU;

/// Smallest cos θi the raw models divide by: their 1/cos θi would reach infinity at the horizon,
/// and below 1e-6 (0.00006° from grazing) the clamp changes nothing visible.
pub const RAW_COS_FLOOR: f32 = 1e-6;

/// A direction about +z with density (n + 1)/(2π) cos^n θ on the upper hemisphere.
#[inline]
pub fn cos_power_hemisphere(n: f32, u: Vec2) -> Vec3 {
    // cos θ = u^(1/(n+1)); 1 − cos θ through expm1 keeps sin θ accurate for sharp lobes.
    let one_minus_c = -(u.x.ln() / (n + 1.0)).exp_m1();
    let c = 1.0 - one_minus_c;
    let s = (one_minus_c * (2.0 - one_minus_c)).max(0.0).sqrt();
    let (sp, cp) = sin_cos_pi(2.0 * u.y);
    Vec3::new(s * cp, s * sp, c)
}

/// The density (n + 1)/(2π) cos^n θ of [`cos_power_hemisphere`], 0 for cos θ ≤ 0.
#[inline]
pub fn cos_power_hemisphere_pdf(n: f32, cos_theta: f32) -> f32 {
    if cos_theta <= 0.0 {
        return 0.0;
    }
    (n + 1.0) / TAU * cos_theta.min(1.0).powf(n)
}

/// Which of the two Phong BRDFs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PhongForm {
    /// The lecture's illumination model: ρ = k_s cos^k_e α / cos θi.
    Raw,
    /// Lafortune & Willems: ρ = k_s (k_e + 2)/(2π) cos^k_e α.
    Modified,
}

/// A Phong specular lobe about the mirror direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phong {
    /// Specular coefficient k_s per channel.
    pub ks: Rgb,
    /// Exponent k_e (shininess).
    pub ke: f32,
    /// Raw or modified.
    pub form: PhongForm,
}

impl Phong {
    /// cos^k_e α for two upper-hemisphere directions.
    #[inline]
    fn lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        let c = reflect_z(wo).dot(wi);
        if c.is_nan() || c <= 0.0 {
            return 0.0;
        }
        // Near the peak, 1 − cos α = |wi − R(wo)|²/2 avoids the cancellation in 1 − c that would
        // quantise cos^k_e α in steps of k_e · 2⁻²⁴; elsewhere c itself is accurate. Both forms,
        // and the choice between them, are symmetric in wi and wo bit for bit.
        let ln_c = if c > 0.5 { (-0.5 * (wi - reflect_z(wo)).length_squared()).ln_1p() } else { c.ln() };
        (self.ke * ln_c).exp()
    }

    /// The largest directional albedo of the lobe (at normal incidence), for the lobe-selection
    /// probability and the energy claim of an added diffuse lobe.
    pub fn max_albedo(&self) -> f32 {
        match self.form {
            PhongForm::Raw => self.ks.max_channel() * TAU / (self.ke + 1.0),
            PhongForm::Modified => self.ks.max_channel(),
        }
    }
}

impl Brdf for Phong {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        let l = self.lobe(wi, wo);
        match self.form {
            PhongForm::Raw => self.ks * (l / wi.z.max(RAW_COS_FLOOR)),
            PhongForm::Modified => self.ks * (l * (self.ke + 2.0) / TAU),
        }
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !same_upper_hemisphere(wi, wo) {
            return 0.0;
        }
        (self.ke + 1.0) / TAU * self.lobe(wi, wo)
    }

    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = Frame::from_normal(reflect_z(wo)).to_world(cos_power_hemisphere(self.ke, u));
        if wi.z <= 0.0 {
            return None;
        }
        // pdf from the returned wi, by the same code as pdf(), so the two agree bit for bit.
        let pdf = self.pdf(wi, wo);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = match self.form {
            PhongForm::Raw => self.ks * (TAU / (self.ke + 1.0) * (wi.z / wi.z.max(RAW_COS_FLOOR))),
            PhongForm::Modified => self.ks * ((self.ke + 2.0) / (self.ke + 1.0) * wi.z),
        };
        Some(BrdfSample { wi, pdf, weight, delta: false, eta: 1.0 })
    }

    fn claims(&self) -> Claims {
        match self.form {
            PhongForm::Raw => Claims { reciprocal: false, energy_conserving: false, isotropic: true },
            PhongForm::Modified => {
                Claims { reciprocal: true, energy_conserving: self.ks.max_channel() <= 1.0, isotropic: true }
            }
        }
    }

    fn phong_terms(&self) -> Option<PhongTerms> {
        Some(PhongTerms { ka: Rgb::ZERO, kd: Rgb::ZERO, ks: self.ks, ke: self.ke, half_vector: false })
    }
}

/// The parameters of a cosine-power lobe: `ks` (up to 10 in the lecture's raw form, whose
/// albedo is unbounded anyway; up to 1 when normalised), the exponent `ke`, and `diffuse`.
pub(crate) fn lobe_params(raw: bool, ke_doc: &'static str) -> Vec<ParamSpec> {
    let ks_max = if raw { 10.0 } else { 1.0 };
    vec![
        ParamSpec::rgb("ks", 0.0, ks_max, 0.5, "specular coefficient k_s"),
        ParamSpec::float("ke", 0.0, 10000.0, 20.0, ke_doc),
        combine::diffuse_param(),
    ]
}

fn raw_params() -> Vec<ParamSpec> {
    lobe_params(true, "Phong exponent k_e: larger is shinier")
}

fn modified_params() -> Vec<ParamSpec> {
    lobe_params(false, "Phong exponent k_e: larger is shinier")
}

fn make(p: &dyn ParamSource, form: PhongForm) -> Result<combine::DiffuseGlossy<Phong>, ParamError> {
    let lobe = Phong { ks: p.rgb("ks"), ke: p.float("ke"), form };
    Ok(combine::with_diffuse(p, lobe, lobe.max_albedo()))
}

fn make_raw(p: &dyn ParamSource) -> Result<combine::DiffuseGlossy<Phong>, ParamError> {
    make(p, PhongForm::Raw)
}

fn make_modified(p: &dyn ParamSource) -> Result<combine::DiffuseGlossy<Phong>, ParamError> {
    make(p, PhongForm::Modified)
}

/// Registry entry: the lecture's raw Phong.
pub const SPEC: ModelSpec = ModelSpec {
    name: "phong",
    summary:
        "the lecture's Phong specular term as a BRDF, k_s (R·V)^k_e / cos θi: not reciprocal, not energy conserving",
    reference: "Phong 1975, Illumination for Computer Generated Pictures",
    params: raw_params,
    build: crate::registry::by_value!(make_raw),
    // Broad lobes, where the albedo at normal incidence 2π k_s/(k_e + 1) is π, and π/2 + 0.3
    // with a diffuse lobe: both far over 1, and the 1/cos θi asymmetry is of order one.
    showcase: &[&[("ks", "1"), ("ke", "1")], &[("ks", "0.5"), ("ke", "1"), ("diffuse", "0.3")]],
};

/// Registry entry: Lafortune & Willems' modified Phong.
pub const MODIFIED_SPEC: ModelSpec = ModelSpec {
    name: "modified-phong",
    summary: "normalised Phong lobe k_s (k_e+2)/(2π) cos^k_e α: reciprocal, energy conserving for k_s ≤ 1",
    reference: "Lafortune & Willems 1994, Using the modified Phong reflectance model for physically based rendering",
    params: modified_params,
    build: crate::registry::by_value!(make_modified),
    // k_s = 1 and a broad lobe put the albedo at exactly 1 at normal incidence: the sharpest
    // test of the energy claim; then a sharp lobe under a diffuse one filling the budget.
    showcase: &[&[("ks", "1"), ("ke", "1")], &[("ks", "0.4"), ("ke", "2000"), ("diffuse", "0.6")]],
};

#[cfg(test)]
mod tests {
    use super::*;
    use radiometry::integrate::irradiance_quadrature;
    use radiometry::spherical_direction;

    fn lobe(form: PhongForm, ks: f32, ke: f32) -> Phong {
        Phong { ks: Rgb::splat(ks), ke, form }
    }

    /// Directional albedo ∫ ρ cos θi dωi by quadrature about +z (f64 sum of f32 values).
    fn albedo(b: &dyn Brdf, wo: Vec3, n_theta: usize, n_phi: usize) -> f64 {
        irradiance_quadrature(|w| b.eval(w.as_vec3(), wo).0[0] as f64, n_theta, n_phi)
    }

    #[test]
    fn cos_power_pdf_integrates_to_one() {
        for n in [0.0f32, 1.0, 20.0, 500.0] {
            let total =
                irradiance_quadrature(|w| cos_power_hemisphere_pdf(n, w.z as f32) as f64 / w.z.max(1e-300), 4096, 4);
            assert!((total - 1.0).abs() < 1e-3, "n={n}: {total}");
        }
    }

    #[test]
    fn modified_albedo_at_normal_incidence_is_ks() {
        // ∫ k_s (k_e+2)/(2π) cos^k_e θ cos θ dω = k_s, exactly, for every k_e.
        for ke in [0.0f32, 1.0, 5.0, 20.0, 100.0] {
            let b = lobe(PhongForm::Modified, 0.7, ke);
            let a = albedo(&b, Vec3::Z, 4096, 8);
            assert!((a - 0.7).abs() < 1e-3, "ke={ke}: {a}");
        }
    }

    #[test]
    fn raw_albedo_at_normal_incidence_is_2pi_ks_over_ke_plus_1() {
        // ρ cos θi = k_s cos^k_e θi, whose integral is 2π k_s/(k_e + 1): π for k_e = 1.
        for ke in [1.0f32, 4.0, 20.0] {
            let b = lobe(PhongForm::Raw, 0.5, ke);
            let a = albedo(&b, Vec3::Z, 4096, 8);
            let want = std::f64::consts::TAU * 0.5 / (ke as f64 + 1.0);
            assert!((a - want).abs() < 1e-3 * want, "ke={ke}: {a} vs {want}");
        }
    }

    #[test]
    fn raw_phong_is_not_reciprocal_at_a_concrete_pair() {
        // wi at 60°, wo at the normal: cos α = cos 60° either way, so ρ(wi, wo) = k_s cos^k_e 60°/0.5
        // while ρ(wo, wi) = k_s cos^k_e 60°/1: the swap halves ρ.
        let b = lobe(PhongForm::Raw, 1.0, 2.0);
        let wi = spherical_direction(60f32.to_radians(), 0.0);
        let (f, g) = (b.eval(wi, Vec3::Z).0[0], b.eval(Vec3::Z, wi).0[0]);
        assert!((f - 0.25 / 0.5).abs() < 1e-5 && (g - 0.25).abs() < 1e-5, "{f} {g}");
        assert!((f / g - 2.0).abs() < 1e-5);
        // The modified lobe at the same pair is symmetric.
        let m = lobe(PhongForm::Modified, 1.0, 2.0);
        assert_eq!(m.eval(wi, Vec3::Z), m.eval(Vec3::Z, wi));
    }

    #[test]
    fn modified_albedo_never_exceeds_its_normal_incidence_value() {
        // The energy claim rests on the albedo peaking at normal incidence: measure it over θo.
        for ke in [0.0f32, 1.0, 3.0, 10.0, 50.0] {
            let b = lobe(PhongForm::Modified, 1.0, ke);
            let mut worst = 0.0f64;
            for deg in (0..=89).step_by(4).chain([89]) {
                let wo = spherical_direction((deg as f32).to_radians(), 0.3);
                worst = worst.max(albedo(&b, wo, 1024, 512));
            }
            assert!(worst <= 1.0 + 2e-3, "ke={ke}: max albedo {worst}");
        }
    }

    #[test]
    fn sample_matches_pdf_and_eval() {
        for form in [PhongForm::Raw, PhongForm::Modified] {
            let b = lobe(form, 0.6, 30.0);
            let wo = spherical_direction(0.9, 1.0);
            let mut returned = 0;
            for i in 0..64 {
                for j in 0..64 {
                    let u = Vec2::new((i as f32 + 0.5) / 64.0, (j as f32 + 0.5) / 64.0);
                    let Some(s) = b.sample(wo, 0.5, u) else { continue };
                    returned += 1;
                    assert_eq!(s.pdf, b.pdf(s.wi, wo));
                    let want = b.eval(s.wi, wo) * (s.wi.z / s.pdf);
                    assert!((s.weight.0[0] - want.0[0]).abs() <= 1e-5 * want.0[0], "{form:?}: {s:?} vs {want:?}");
                }
            }
            assert!(returned > 3000, "{form:?}: {returned}");
        }
    }

    #[test]
    fn grazing_and_extreme_parameters_stay_finite() {
        let dirs = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(-1.0, 0.0, 1e-30), Vec3::new(0.0, 1.0, 1e-7), Vec3::Z];
        for form in [PhongForm::Raw, PhongForm::Modified] {
            for ke in [0.0f32, 10000.0] {
                let b = Phong { ks: Rgb::splat(10.0), ke, form };
                for &wi in &dirs {
                    for &wo in &dirs {
                        assert!(b.eval(wi, wo).is_finite() && b.pdf(wi, wo).is_finite());
                        for u in [Vec2::ZERO, Vec2::splat(1.0 - f32::EPSILON / 2.0), Vec2::splat(0.5)] {
                            if let Some(s) = b.sample(wo, 0.0, u) {
                                assert!(s.weight.is_finite() && s.pdf > 0.0 && s.pdf.is_finite(), "{s:?}");
                            }
                        }
                    }
                }
            }
        }
    }
}
