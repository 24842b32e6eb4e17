//! Blinn's half-vector form of the Phong lobe, as the lecture's illumination model writes it
//! (`blinn-phong`) and normalised (`modified-blinn-phong`).
//!
//! h = (wi + wo)/|wi + wo|, cos θh = N·H = h_z.
//!
//! `blinn-phong`: the illumination model's specular term L_o = L_light k_s (N·H)^k_e read as a
//! BRDF against the irradiance E = L_light cos θi of a point light:
//!   ρ(wi, wo) = k_s cos^k_e θh / cos θi,
//! non-reciprocal through the 1/cos θi and with albedo up to 8π k_s (1 − 2^(−(k_e+2)/2))/(k_e + 2)
//! at normal incidence: it claims only isotropy.
//!
//! `modified-blinn-phong`: ρ(wi, wo) = k_s (k_e + 8)/(8π) cos^k_e θh, reciprocal. The factor
//! (k_e + 8)/(8π) is Akenine-Möller, Haines & Hoffman's approximation of the exact normal-incidence
//! normalisation (k_e + 2)(k_e + 4)/(8π (2^(−k_e/2) + k_e)) derived by Giesen, so the albedo at
//! normal incidence is k_s (k_e + 8)(k_e + 2^(−k_e/2))/((k_e + 2)(k_e + 4)): exactly k_s for
//! k_e = 0, up to 7.6 % more near k_e = 9, tending to k_s (1 + 2/k_e). The albedo is largest at
//! normal incidence (measured over θo and k_e in the tests), so energy conservation is claimed
//! exactly when k_s times that factor is at most 1.
//!
//! Sampling (both): h about the normal with density (k_e + 1)/(2π) cos^k_e θh (normalised over the
//! upper hemisphere of h), wi = 2(wo·h)h − wo; the Jacobian dωi/dωh = 4 (wo·h) gives
//! pdf(wi) = (k_e + 1) cos^k_e θh / (8π (wo·h)). Draws with wo·h ≤ 0 or wi below the surface
//! are returned as `None`, so `pdf` integrates to less than 1 at grazing wo.
//! Weights: raw 8π k_s (wo·h)/(k_e + 1), modified k_s (k_e + 8)(wo·h) cos θi/(k_e + 1).
//!
//! Sources: J. F. Blinn, "Models of Light Reflection for Computer Synthesized Pictures",
//! SIGGRAPH 1977; T. Akenine-Möller, E. Haines, N. Hoffman, *Real-Time Rendering*, 3rd ed.,
//! 2008, §7.6; F. Giesen, "Derivation of Phong and Blinn-Phong BRDF normalization factors", 2009.

use crate::combine;
use crate::model::{same_upper_hemisphere, Brdf, BrdfSample, Claims, PhongTerms};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::phong::lobe_params;
use crate::phong::{cos_power_hemisphere, RAW_COS_FLOOR};
use crate::registry::ModelSpec;
use radiometry::{Rgb, Vec2, Vec3};
use std::f32::consts::PI;

/// Which of the two Blinn-Phong BRDFs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BlinnPhongForm {
    /// The lecture's illumination model: ρ = k_s cos^k_e θh / cos θi.
    Raw,
    /// Normalised: ρ = k_s (k_e + 8)/(8π) cos^k_e θh.
    Modified,
}

/// A Blinn-Phong specular lobe about the normal, in the half vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlinnPhong {
    /// Specular coefficient k_s per channel.
    pub ks: Rgb,
    /// Exponent k_e (shininess).
    pub ke: f32,
    /// Raw or modified.
    pub form: BlinnPhongForm,
}

/// Directional albedo of the modified lobe with k_s = 1 at normal incidence:
/// (k_e + 8)(k_e + 2^(−k_e/2)) / ((k_e + 2)(k_e + 4)).
pub fn modified_normal_albedo(ke: f64) -> f64 {
    (ke + 8.0) * (ke + (-0.5 * ke).exp2()) / ((ke + 2.0) * (ke + 4.0))
}

impl BlinnPhong {
    /// cos^k_e θh and wo·h, or `None` where ρ is zero.
    #[inline]
    fn lobe(&self, wi: Vec3, wo: Vec3) -> Option<(f32, f32)> {
        if !same_upper_hemisphere(wi, wo) {
            return None;
        }
        let s = wi + wo;
        let sxy2 = s.x * s.x + s.y * s.y;
        let len2 = sxy2 + s.z * s.z;
        // |wi + wo| < 1e-6 only for wi and wo within 1e-6 rad of opposite, both on the horizon.
        if len2.is_nan() || len2 <= 1e-12 {
            return None;
        }
        let z2 = s.z * s.z;
        // ln cos²θh from whichever of cos²θh = s_z²/|s|² and sin²θh = |s_xy|²/|s|² is the smaller,
        // so that neither 1 − cos²θh near the peak nor 1 − sin²θh near the horizon cancels (which
        // would quantise cos^k_e θh in steps of k_e · 2⁻²⁴). Everything is symmetric in wi, wo.
        let ln_cos2 = if z2 < sxy2 { (z2 / len2).ln() } else { (-sxy2 / len2).ln_1p() };
        let l = (0.5 * self.ke * ln_cos2).exp();
        if !l.is_finite() {
            return None;
        }
        // For unit wi, wo: wo·h = (1 + wi·wo)/|s| = |s|/2.
        Some((l, 0.5 * len2.sqrt()))
    }

    /// The directional albedo at normal incidence (largest channel): the lobe-selection weight,
    /// and for the modified form the largest albedo over θo (measured in the tests), so the
    /// energy bound.
    pub fn max_albedo(&self) -> f32 {
        let ke = self.ke as f64;
        let a = match self.form {
            BlinnPhongForm::Raw => 8.0 * std::f64::consts::PI * (1.0 - (-0.5 * (ke + 2.0)).exp2()) / (ke + 2.0),
            BlinnPhongForm::Modified => modified_normal_albedo(ke),
        };
        self.ks.max_channel() * a as f32
    }
}

impl Brdf for BlinnPhong {
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        let Some((l, _)) = self.lobe(wi, wo) else { return Rgb::ZERO };
        match self.form {
            BlinnPhongForm::Raw => self.ks * (l / wi.z.max(RAW_COS_FLOOR)),
            BlinnPhongForm::Modified => self.ks * (l * (self.ke + 8.0) / (8.0 * PI)),
        }
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        let Some((l, wo_h)) = self.lobe(wi, wo) else { return 0.0 };
        (self.ke + 1.0) * l / (8.0 * PI * wo_h)
    }

    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let h = cos_power_hemisphere(self.ke, u);
        let d = wo.dot(h);
        if d <= 0.0 {
            return None;
        }
        let wi = 2.0 * d * h - wo;
        // pdf and wo·h from the returned wi, by the same code as pdf(), so the two agree exactly.
        let (l, wo_h) = self.lobe(wi, wo)?;
        let pdf = (self.ke + 1.0) * l / (8.0 * PI * wo_h);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let weight = match self.form {
            BlinnPhongForm::Raw => self.ks * (8.0 * PI * wo_h / (self.ke + 1.0) * (wi.z / wi.z.max(RAW_COS_FLOOR))),
            BlinnPhongForm::Modified => self.ks * ((self.ke + 8.0) / (self.ke + 1.0) * wo_h * wi.z),
        };
        Some(BrdfSample { wi, pdf, weight, delta: false, eta: 1.0 })
    }

    fn claims(&self) -> Claims {
        match self.form {
            BlinnPhongForm::Raw => Claims { reciprocal: false, energy_conserving: false, isotropic: true },
            BlinnPhongForm::Modified => {
                Claims { reciprocal: true, energy_conserving: self.max_albedo() <= 1.0, isotropic: true }
            }
        }
    }

    fn phong_terms(&self) -> Option<PhongTerms> {
        Some(PhongTerms { ka: Rgb::ZERO, kd: Rgb::ZERO, ks: self.ks, ke: self.ke, half_vector: true })
    }
}

fn raw_params() -> Vec<ParamSpec> {
    lobe_params(true, "Blinn-Phong exponent k_e on N·H: larger is shinier")
}

fn modified_params() -> Vec<ParamSpec> {
    lobe_params(false, "Blinn-Phong exponent k_e on N·H: larger is shinier")
}

fn make(p: &dyn ParamSource, form: BlinnPhongForm) -> Result<combine::DiffuseGlossy<BlinnPhong>, ParamError> {
    let lobe = BlinnPhong { ks: p.rgb("ks"), ke: p.float("ke"), form };
    Ok(combine::with_diffuse(p, lobe, lobe.max_albedo()))
}

fn make_raw(p: &dyn ParamSource) -> Result<combine::DiffuseGlossy<BlinnPhong>, ParamError> {
    make(p, BlinnPhongForm::Raw)
}

fn make_modified(p: &dyn ParamSource) -> Result<combine::DiffuseGlossy<BlinnPhong>, ParamError> {
    make(p, BlinnPhongForm::Modified)
}

/// Registry entry: the lecture's raw Blinn-Phong.
pub const SPEC: ModelSpec = ModelSpec {
    name: "blinn-phong",
    summary: "the lecture's Blinn-Phong term as a BRDF, k_s (N·H)^k_e / cos θi: not reciprocal, not energy conserving",
    reference: "Blinn 1977, Models of Light Reflection for Computer Synthesized Pictures",
    params: raw_params,
    build: crate::registry::by_value!(make_raw),
    // A broad lobe: albedo 8π(1 − 2^(−3/2))/3 ≈ 5.4 k_s at normal incidence.
    showcase: &[&[("ks", "1"), ("ke", "2")]],
};

/// Registry entry: the normalised Blinn-Phong.
pub const MODIFIED_SPEC: ModelSpec = ModelSpec {
    name: "modified-blinn-phong",
    summary: "normalised Blinn-Phong k_s (k_e+8)/(8π) (N·H)^k_e: reciprocal; energy claimed while k_s·albedo(k_e) ≤ 1",
    reference: "Akenine-Möller, Haines & Hoffman 2008, Real-Time Rendering 3rd ed. §7.6; Giesen 2009",
    params: modified_params,
    build: crate::registry::by_value!(make_modified),
    // k_e = 9 is where the approximate normalisation overshoots most (albedo 1.076 at k_s = 1,
    // energy not claimed); k_s = 0.92 is just under the bound and claims it; a sharp lobe on
    // a diffuse one.
    showcase: &[
        &[("ks", "1"), ("ke", "9")],
        &[("ks", "0.92"), ("ke", "9")],
        &[("ks", "0.3"), ("ke", "3000"), ("diffuse", "0.6")],
    ],
};

#[cfg(test)]
mod tests {
    use super::*;
    use radiometry::integrate::irradiance_quadrature;
    use radiometry::spherical_direction;

    fn lobe(form: BlinnPhongForm, ks: f32, ke: f32) -> BlinnPhong {
        BlinnPhong { ks: Rgb::splat(ks), ke, form }
    }

    /// Directional albedo ∫ ρ cos θi dωi by midpoint quadrature in (θi, φi).
    fn albedo(b: &dyn Brdf, wo: Vec3, n_theta: usize, n_phi: usize) -> f64 {
        irradiance_quadrature(|w| b.eval(w.as_vec3(), wo).0[0] as f64, n_theta, n_phi)
    }

    #[test]
    fn modified_albedo_at_normal_incidence_matches_giesen() {
        // wo = n: θh = θi/2, and ∫ cos^n(θ/2) cos θ dω = 8π (n + 2^(−n/2))/((n + 2)(n + 4)).
        for ke in [0.0f32, 1.0, 8.76, 30.0, 200.0] {
            let b = lobe(BlinnPhongForm::Modified, 1.0, ke);
            let a = albedo(&b, Vec3::Z, 4096, 8);
            let want = modified_normal_albedo(ke as f64);
            assert!((a - want).abs() < 1e-4, "ke={ke}: {a} vs {want}");
        }
        assert_eq!(modified_normal_albedo(0.0), 1.0);
        assert!((modified_normal_albedo(8.76) - 1.0752).abs() < 1e-4);
    }

    #[test]
    fn raw_albedo_at_normal_incidence() {
        // ρ cos θi = k_s cos^k_e(θi/2): ∫ = 8π k_s (1 − 2^(−(k_e+2)/2))/(k_e + 2).
        for ke in [0.0f32, 2.0, 20.0] {
            let b = lobe(BlinnPhongForm::Raw, 0.5, ke);
            let a = albedo(&b, Vec3::Z, 4096, 8);
            assert!((a - b.max_albedo() as f64).abs() < 1e-4 * a, "ke={ke}: {a} vs {}", b.max_albedo());
        }
    }

    #[test]
    fn modified_albedo_peaks_at_normal_incidence() {
        // The energy claim bounds the albedo by its normal-incidence value: measure every θo.
        for ke in [0.0f32, 1.0, 4.0, 8.76, 20.0, 60.0] {
            let b = lobe(BlinnPhongForm::Modified, 1.0, ke);
            let a0 = modified_normal_albedo(ke as f64);
            for deg in (0..=88).step_by(4).chain([89]) {
                let wo = spherical_direction((deg as f32).to_radians(), 0.3);
                let a = albedo(&b, wo, 1024, 512);
                assert!(a <= a0 + 1e-3, "ke={ke}, θo={deg}°: albedo {a} > {a0}");
            }
        }
    }

    #[test]
    fn raw_blinn_phong_is_not_reciprocal_at_a_concrete_pair() {
        // wi at 60°, wo at the normal: θh = 30° either way, so the swap changes only 1/cos θi:
        // ρ(wi, wo) = k_s cos^k_e 30°/0.5 = 2 ρ(wo, wi).
        let b = lobe(BlinnPhongForm::Raw, 1.0, 4.0);
        let wi = spherical_direction(60f32.to_radians(), 0.0);
        let (f, g) = (b.eval(wi, Vec3::Z).0[0], b.eval(Vec3::Z, wi).0[0]);
        let c4 = 30f32.to_radians().cos().powi(4);
        assert!((f - c4 / 0.5).abs() < 1e-5 && (g - c4).abs() < 1e-5, "{f} {g}");
        let m = lobe(BlinnPhongForm::Modified, 1.0, 4.0);
        assert_eq!(m.eval(wi, Vec3::Z), m.eval(Vec3::Z, wi));
    }

    #[test]
    fn energy_claim_follows_the_bound() {
        assert!(lobe(BlinnPhongForm::Modified, 0.92, 9.0).claims().energy_conserving);
        assert!(!lobe(BlinnPhongForm::Modified, 1.0, 9.0).claims().energy_conserving);
        assert!(lobe(BlinnPhongForm::Modified, 1.0, 0.0).claims().energy_conserving);
    }

    #[test]
    fn sample_matches_pdf_and_eval() {
        for form in [BlinnPhongForm::Raw, BlinnPhongForm::Modified] {
            let b = lobe(form, 0.6, 30.0);
            let wo = spherical_direction(1.1, 1.0);
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
    fn pdf_integrates_to_one_when_nothing_is_cut_off() {
        // At normal incidence every h with θh < 45° reflects above the surface; for k_e = 200 the
        // lobe beyond 45° holds 2^(−101/2) of the mass: ∫ pdf dωi = 1.
        let b = lobe(BlinnPhongForm::Modified, 1.0, 200.0);
        let total = irradiance_quadrature(|w| b.pdf(w.as_vec3(), Vec3::Z) as f64 / w.z.max(1e-300), 8192, 4);
        assert!((total - 1.0).abs() < 1e-4, "{total}");
    }
}
