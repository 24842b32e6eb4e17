//! The harness must pass a correct model and catch each kind of broken one.

use super::*;
use crate::lambert::Lambert;
use crate::model::{reflect_z, same_upper_hemisphere};
use crate::{BrdfSample, Claims};
use radiometry::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use radiometry::{Frame, Rgb, Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, TAU};

fn finding(r: &Report, p: Property) -> &Finding {
    r.findings.iter().find(|f| f.property == p).expect("every property is reported")
}

/// The density of `cosine_sample` with `pdf_scale` 1.
fn cosine_pdf(wi: Vec3, wo: Vec3) -> f32 {
    if same_upper_hemisphere(wi, wo) {
        cosine_hemisphere_pdf(wi.z)
    } else {
        0.0
    }
}

/// Cosine-weighted sampling of any ρ, with the weight ρ cos θi / pdf computed from `eval`.
fn cosine_sample(b: &dyn Brdf, wo: Vec3, u: Vec2, pdf_scale: f32) -> Option<BrdfSample> {
    if wo.z <= 0.0 {
        return None;
    }
    let wi = cosine_hemisphere(u);
    let pdf = cosine_hemisphere_pdf(wi.z) * pdf_scale;
    if pdf <= 0.0 {
        return None;
    }
    Some(BrdfSample { wi, pdf, weight: b.eval(wi, wo) * (wi.z / pdf), delta: false, eta: 1.0 })
}

/// Lambert whose `pdf()` is `factor` times the true density; with `consistent`, `sample`
/// reports the same wrong density (and the weight from it), so only the χ² test can tell.
#[derive(Debug)]
struct LyingPdf {
    factor: f32,
    consistent: bool,
}

impl Brdf for LyingPdf {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if same_upper_hemisphere(wi, wo) {
            Rgb::splat(0.5 * FRAC_1_PI)
        } else {
            Rgb::ZERO
        }
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if same_upper_hemisphere(wi, wo) {
            self.factor * cosine_hemisphere_pdf(wi.z)
        } else {
            0.0
        }
    }
    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        cosine_sample(self, wo, u, if self.consistent { self.factor } else { 1.0 })
    }
    fn claims(&self) -> Claims {
        Claims::PLAUSIBLE
    }
}

/// The lecture's raw Phong, ρ = k_s (R·V)^n / cos θi with R the mirror of wi (k_s = 1, n = 2):
/// not reciprocal, and its albedo k_s ∫ (R·V)^n dωi reaches 2π k_s/(n + 1) ≈ 2.1.
#[derive(Debug)]
struct RawPhong;

impl Brdf for RawPhong {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        Rgb::splat(reflect_z(wi).dot(wo).max(0.0).powi(2) / wi.z)
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        cosine_pdf(wi, wo)
    }
    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        cosine_sample(self, wo, u, 1.0)
    }
    fn claims(&self) -> Claims {
        Claims::PLAUSIBLE
    }
}

/// A diffuse model with a bug at the horizon: it lets cos θ = 0 through and divides by it.
#[derive(Debug)]
struct NanAtGrazing;

impl Brdf for NanAtGrazing {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z < 0.0 || wo.z < 0.0 {
            return Rgb::ZERO;
        }
        Rgb::splat(0.5 * FRAC_1_PI * (wi.z * wo.z) / (wi.z * wo.z))
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        cosine_pdf(wi, wo)
    }
    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        cosine_sample(self, wo, u, 1.0)
    }
    fn claims(&self) -> Claims {
        Claims::PLAUSIBLE
    }
}

/// Reciprocal, energy conserving, but brighter along x than along y, while claiming isotropy.
#[derive(Debug)]
struct Anisotropic;

impl Brdf for Anisotropic {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        let stretch = |w: Vec3| w.x * w.x - w.y * w.y;
        Rgb::splat(0.5 * FRAC_1_PI * (1.0 + 0.25 * (stretch(wi) + stretch(wo))))
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        cosine_pdf(wi, wo)
    }
    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        cosine_sample(self, wo, u, 1.0)
    }
    fn claims(&self) -> Claims {
        Claims::PLAUSIBLE
    }
}

/// A normalised Phong lobe about the mirror direction, ρ = (n + 2)/(2π) cos^n α, sampled from
/// the density (n + 1)/(2π) cos^m α; with m = n the sampler is exact, otherwise `sample` and
/// `pdf` both report the exponent-n density for directions drawn from exponent m.
#[derive(Debug)]
struct PhongLobe {
    n: f32,
    m: f32,
}

impl PhongLobe {
    fn density(&self, wi: Vec3, wo: Vec3) -> f32 {
        let c = reflect_z(wo).dot(wi);
        if !same_upper_hemisphere(wi, wo) || c <= 0.0 {
            return 0.0;
        }
        (self.n + 1.0) / TAU * c.powf(self.n)
    }
}

impl Brdf for PhongLobe {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let c = reflect_z(wo).dot(wi);
        if !same_upper_hemisphere(wi, wo) || c <= 0.0 {
            return Rgb::ZERO;
        }
        Rgb::splat((self.n + 2.0) / TAU * c.powf(self.n))
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.density(wi, wo)
    }
    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let cos_a = (1.0 - u.x).powf(1.0 / (self.m + 1.0));
        let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
        let (s, c) = (TAU * u.y).sin_cos();
        let wi = Frame::from_normal(reflect_z(wo)).to_world(Vec3::new(sin_a * c, sin_a * s, cos_a));
        let pdf = self.density(wi, wo);
        if wi.z <= 0.0 || pdf <= 0.0 {
            return None;
        }
        Some(BrdfSample { wi, pdf, weight: self.eval(wi, wo) * (wi.z / pdf), delta: false, eta: 1.0 })
    }
    fn claims(&self) -> Claims {
        Claims::PLAUSIBLE
    }
}

/// The crate's ideal mirror with reflectance 0.9: every sample is a delta.
fn mirror() -> crate::mirror::Mirror {
    crate::mirror::Mirror { reflectance: Rgb::splat(0.9), fresnel: crate::fresnel::Fresnel::None }
}

#[test]
fn lambert_passes_everything() {
    let r = check(&Lambert { albedo: Rgb::new(0.8, 0.5, 0.2) }, &Config::default());
    assert!(r.findings.iter().all(|f| f.passed && f.claimed), "{r}");
    assert_eq!(r.findings.len(), Property::ALL.len());
    // ρ is constant: reciprocity and isotropy hold exactly; the albedo is 0.8 up to the f32
    // rounding of ρ cos θo / pdf in the reflected-fraction estimate.
    assert_eq!(finding(&r, Property::Reciprocity).value, 0.0);
    assert_eq!(finding(&r, Property::Isotropy).value, 0.0);
    assert!((finding(&r, Property::Energy).value - 0.8).abs() < 1e-6);
}

#[test]
fn white_lambert_albedo_is_one_at_every_angle() {
    let l = Lambert { albedo: Rgb::ONE };
    for t in [0.0f32, 30.0, 60.0, 89.0, 89.9] {
        let wo = radiometry::spherical_direction(t.to_radians(), 1.0);
        let (m, se) = albedo(&l, wo, 1000, 7);
        assert_eq!((m, se), (Rgb::ONE, Rgb::ZERO), "θo = {t}");
    }
}

#[test]
fn a_pdf_that_lies_is_caught_by_the_sampling_check() {
    let r = check(&LyingPdf { factor: 1.1, consistent: false }, &Config::default());
    assert!(!finding(&r, Property::Sampling).passed, "{r}");
    assert!(finding(&r, Property::Reciprocity).passed && finding(&r, Property::Energy).passed, "{r}");
}

#[test]
fn a_consistent_lie_is_caught_by_the_chi_square_test() {
    let r = check(&LyingPdf { factor: 1.1, consistent: true }, &Config::default());
    assert!(finding(&r, Property::Sampling).passed, "{r}");
    let c = finding(&r, Property::ChiSquare);
    assert!(!c.passed && c.value < 1e-6, "{r}");
}

#[test]
fn a_wrong_lobe_exponent_is_caught_by_the_chi_square_test() {
    // Directions drawn with cos^300 but declared as cos^330: a 10% error in the lobe width.
    let r = check(&PhongLobe { n: 330.0, m: 300.0 }, &Config::default());
    assert!(finding(&r, Property::Sampling).passed, "{r}");
    assert!(!finding(&r, Property::ChiSquare).passed, "{r}");
}

#[test]
fn a_correct_sharp_lobe_passes_everything() {
    let r = check(&PhongLobe { n: 300.0, m: 300.0 }, &Config::default());
    assert!(r.findings.iter().all(|f| f.passed), "{r}");
}

#[test]
fn raw_phong_fails_reciprocity_and_energy() {
    let r = check(&RawPhong, &Config::default());
    let rec = finding(&r, Property::Reciprocity);
    assert!(!rec.passed && rec.value > 0.5, "{r}");
    let e = finding(&r, Property::Energy);
    assert!(!e.passed && e.value > 1.0, "{r}");
    assert!(finding(&r, Property::Sampling).passed && finding(&r, Property::ChiSquare).passed, "{r}");
}

#[test]
fn albedo_above_one_is_caught() {
    let r = check(&Lambert { albedo: Rgb::new(0.5, 1.2, 0.5) }, &Config::default());
    let e = finding(&r, Property::Energy);
    assert!(!e.passed && (e.value - 1.2).abs() < 1e-6, "{r}");
    assert!(e.detail.contains("channel g"), "{}", e.detail);
    assert_eq!(r.claimed_failures().len(), 1, "{r}");
}

#[test]
fn nan_at_grazing_is_caught() {
    let r = check(&NanAtGrazing, &Config::default());
    let f = finding(&r, Property::NonNegative);
    assert!(!f.passed && f.value >= 1.0, "{r}");
    assert!(f.detail.contains("NaN"), "{}", f.detail);
}

#[test]
fn anisotropy_claimed_isotropic_is_caught() {
    let r = check(&Anisotropic, &Config::default());
    assert!(!finding(&r, Property::Isotropy).passed, "{r}");
    assert!(finding(&r, Property::Reciprocity).passed && finding(&r, Property::Energy).passed, "{r}");
    assert_eq!(r.claimed_failures().len(), 1, "{r}");
}

#[test]
fn unclaimed_failures_do_not_fail_the_report() {
    #[derive(Debug)]
    struct Honest(RawPhong);
    impl Brdf for Honest {
        fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
            self.0.eval(wi, wo)
        }
        fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
            self.0.pdf(wi, wo)
        }
        fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
            self.0.sample(wo, uc, u)
        }
        fn claims(&self) -> Claims {
            Claims { reciprocal: false, energy_conserving: false, isotropic: true }
        }
    }
    let r = check(&Honest(RawPhong), &Config::default());
    assert!(r.ok(), "{r}");
    assert!(!finding(&r, Property::Reciprocity).passed && !finding(&r, Property::Energy).passed);
}

#[test]
fn a_pure_delta_lobe_has_no_chi_square_test() {
    let r = check(&mirror(), &Config::default());
    let c = finding(&r, Property::ChiSquare);
    assert!(c.passed && c.detail == "n/a (delta lobe)", "{r}");
    assert!(r.ok(), "{r}");
    // The delta lobe's weight is its albedo.
    let (m, _) = albedo(&mirror(), Vec3::new(0.6, 0.0, 0.8), 100, 1);
    assert!((m.0[0] - 0.9).abs() < 1e-6);
}

#[test]
fn the_same_seed_gives_the_same_report() {
    let b = PhongLobe { n: 50.0, m: 50.0 };
    assert_eq!(check(&b, &Config::default()), check(&b, &Config::default()));
}
