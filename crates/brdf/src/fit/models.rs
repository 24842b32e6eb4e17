//! The models `gonio fit` fits, each as ρ = k_d/π + k_s · S(wi, wo; p): a Lambert term and a
//! specular shape S with one nonlinear parameter p and unit scale, so that ρ is linear in the
//! per-channel k_d and k_s (solved in closed form) and only p is searched by LM.
//!
//! - `ward`: S = Ward's lobe with ρ_s = 1, p = α (isotropic); k_s is the model's `ks`.
//! - `cook-torrance`: S = Cook-Torrance with F = 1, p = m; k_s stands for a constant Fresnel term.
//! - `modified-blinn-phong` (asked for as `blinn-phong` too): S = the normalised lobe with k_s = 1,
//!   p = k_e; the raw `blinn-phong` is not fitted, since its 1/cos θi makes it non-reciprocal and
//!   its scale depends on θi, where the normalised one is the form Ngan et al. fit.
//! - `ggx`, `beckmann`: S = D G/(4 cos θi cos θo) with height-correlated Smith G and F = 1,
//!   p = α; k_s stands for a constant Fresnel term.
//!
//! p is searched in an unconstrained variable t with p = exp(ln lo + (ln hi − ln lo) σ(t)),
//! σ the logistic: p stays in [lo, hi] and the search is in log p near the middle of the range.

use crate::blinn_phong::{BlinnPhong, BlinnPhongForm};
use crate::cook_torrance::CookTorrance;
use crate::fresnel::Fresnel;
use crate::microfacet::{Distribution, Shadowing};
use crate::microfacet_brdf::MicrofacetBrdf;
use crate::ward::Ward;
use crate::Brdf;
use radiometry::Rgb;

/// A model `gonio fit` knows how to fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitModel {
    /// Ward's isotropic Gaussian lobe.
    Ward,
    /// Cook-Torrance (Beckmann D, V-groove G), constant Fresnel.
    CookTorrance,
    /// The normalised Blinn-Phong lobe.
    BlinnPhong,
    /// GGX microfacet, height-correlated Smith G, constant Fresnel.
    Ggx,
    /// Beckmann microfacet, height-correlated Smith G, constant Fresnel.
    Beckmann,
}

impl FitModel {
    /// Every fit model, in the order `--all` tries them.
    pub const ALL: [FitModel; 5] =
        [FitModel::Ward, FitModel::CookTorrance, FitModel::BlinnPhong, FitModel::Ggx, FitModel::Beckmann];

    /// The registry name of the model fitted.
    pub fn name(self) -> &'static str {
        match self {
            FitModel::Ward => "ward",
            FitModel::CookTorrance => "cook-torrance",
            FitModel::BlinnPhong => "modified-blinn-phong",
            FitModel::Ggx => "ggx",
            FitModel::Beckmann => "beckmann",
        }
    }

    /// The model for a name; `blinn-phong` means the normalised `modified-blinn-phong`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "blinn-phong" => Some(FitModel::BlinnPhong),
            _ => Self::ALL.into_iter().find(|m| m.name() == name),
        }
    }

    /// The names accepted by `from_name`, for error messages.
    pub fn names() -> &'static str {
        "ward, cook-torrance, blinn-phong (fits modified-blinn-phong), ggx, beckmann"
    }

    /// The shape parameter's registry name.
    pub fn shape_name(self) -> &'static str {
        match self {
            FitModel::CookTorrance => "m",
            FitModel::BlinnPhong => "ke",
            _ => "alpha",
        }
    }

    /// The range the shape parameter is kept in (the registry's range; k_e from 0.5, where the
    /// lobe is already near-uniform, so that log k_e stays defined).
    pub fn shape_range(self) -> (f64, f64) {
        match self {
            FitModel::BlinnPhong => (0.5, 10000.0),
            _ => (crate::roughness::ALPHA_MIN, 1.0),
        }
    }

    /// Starting values of the shape parameter: LM runs from each and the best fit is kept, so
    /// a sharp and a broad lobe are both reached without a local minimum in between.
    pub fn starts(self) -> &'static [f64] {
        match self {
            FitModel::BlinnPhong => &[4.0, 40.0, 400.0, 4000.0],
            _ => &[0.02, 0.08, 0.25, 0.6],
        }
    }

    /// The shape parameter from the unconstrained search variable.
    pub fn shape_from_free(self, t: f64) -> f64 {
        let (lo, hi) = self.shape_range();
        let s = 1.0 / (1.0 + (-t).exp());
        (lo.ln() + (hi.ln() - lo.ln()) * s).exp().clamp(lo, hi)
    }

    /// The unconstrained search variable of a shape parameter (clamped just inside the range).
    pub fn free_from_shape(self, p: f64) -> f64 {
        let (lo, hi) = self.shape_range();
        let s = ((p.ln() - lo.ln()) / (hi.ln() - lo.ln())).clamp(1e-9, 1.0 - 1e-9);
        (s / (1.0 - s)).ln()
    }

    /// The specular shape S with unit scale, for shape parameter `p`.
    pub fn lobe(self, p: f64) -> Box<dyn Brdf> {
        let (lo, hi) = self.shape_range();
        let p = p.clamp(lo, hi) as f32;
        let microfacet = |name: &str| -> Box<dyn Brdf> {
            let distribution = Distribution::named(name, p, p).expect("known distribution");
            Box::new(MicrofacetBrdf {
                distribution,
                shadowing: Shadowing::Correlated,
                fresnel: Fresnel::None,
                tint: Rgb::ONE,
            })
        };
        match self {
            FitModel::Ward => Box::new(Ward { ks: Rgb::ONE, alpha_x: p, alpha_y: p }),
            FitModel::CookTorrance => Box::new(CookTorrance::new(p, Fresnel::None)),
            FitModel::BlinnPhong => Box::new(BlinnPhong { ks: Rgb::ONE, ke: p, form: BlinnPhongForm::Modified }),
            FitModel::Ggx => microfacet("ggx"),
            FitModel::Beckmann => microfacet("beckmann"),
        }
    }

    /// The registry parameters, as `gonio` options, that give S for shape `p` (k_s and the
    /// diffuse albedo π k_d are reported beside them).
    pub fn registry_shape_params(self, p: f64) -> Vec<(&'static str, String)> {
        let mut v = vec![(self.shape_name(), format!("{p:.6}"))];
        if matches!(self, FitModel::CookTorrance | FitModel::Ggx | FitModel::Beckmann) {
            v.push(("fresnel", "none".into()));
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transform_round_trips_and_stays_in_range() {
        for m in FitModel::ALL {
            let (lo, hi) = m.shape_range();
            for &p in m.starts() {
                let back = m.shape_from_free(m.free_from_shape(p));
                assert!((back / p - 1.0).abs() < 1e-9, "{m:?} {p} {back}");
            }
            for t in [-1e3, -30.0, 0.0, 30.0, 1e3] {
                let p = m.shape_from_free(t);
                assert!(p >= lo && p <= hi, "{m:?} {t} {p}");
            }
        }
    }

    #[test]
    fn names_resolve() {
        for m in FitModel::ALL {
            assert_eq!(FitModel::from_name(m.name()), Some(m));
            assert!(crate::registry::find(m.name()).is_ok());
        }
        assert_eq!(FitModel::from_name("blinn-phong"), Some(FitModel::BlinnPhong));
        assert_eq!(FitModel::from_name("phong"), None);
    }
}
