//! The Cook-Torrance model (model `cook-torrance`), as the lecture writes it.
//!
//! ρ(L, V) = D(H) G(L, V) F(V·H) / (4 (N·L)(N·V)) + ρ_d/π, H = (L + V)/|L + V|, with
//!   D(H) = exp(−tan²α / m²) / (π m² cos⁴α), α the angle between N and H (Beckmann, roughness m),
//!   G = min{1, 2(N·H)(N·V)/(V·H), 2(N·H)(N·L)/(V·H)} (the V-groove shadowing-masking term),
//!   F the Fresnel term (default: dielectric, η = 1.5).
//! Cook & Torrance (1982) wrote D without the 1/π and π in place of the 4 in the denominator.
//! With the normalised D above (∫ D cos α dω = 1, see `microfacet/`), 4 is the constant that
//! follows from the Jacobian of reflection, dω_H/dω_L = 1/(4 V·H), and it makes the model
//! agree with the microfacet model when both use the same D, G and F.
//! Sampling draws H with density D(H) cos α and reflects V about it: pdf(L) = D(H)(N·H)/(4 V·H),
//! and the weight ρ (N·L)/pdf = F G (V·H)/((N·V)(N·H)) is at most 2F since G ≤ 2(N·H)(N·V)/(V·H).
//! Source: R. L. Cook & K. E. Torrance, "A Reflectance Model for Computer Graphics", ACM TOG
//! 1(1), 1982; the V-groove G from K. E. Torrance & E. M. Sparrow, JOSA 57(9), 1967.

use crate::combine;
use crate::fresnel::{self, Fresnel};
use crate::microfacet::{Beckmann, Ndf};
use crate::model::{reflect_about_half_vector, same_upper_hemisphere, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use radiometry::{Rgb, Vec2, Vec3};

/// The Cook-Torrance specular lobe.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CookTorrance {
    /// Beckmann distribution with α = m.
    beckmann: Beckmann,
    /// Reflectance of one facet.
    pub fresnel: Fresnel,
}

impl CookTorrance {
    /// A Cook-Torrance lobe with Beckmann roughness `m` and Fresnel term `fresnel`.
    pub fn new(m: f32, fresnel: Fresnel) -> Self {
        CookTorrance { beckmann: Beckmann::new(m, m), fresnel }
    }

    /// The roughness m.
    pub fn m(&self) -> f32 {
        self.beckmann.alpha_x
    }

    /// The V-groove G divided by 4(N·L)(N·V), written as the minimum of three terms so that a
    /// grazing cosine makes one term large instead of producing 0/0.
    #[inline]
    fn g_over_cosines(n_l: f32, n_v: f32, n_h: f32, v_h: f32) -> f32 {
        let a = 1.0 / (4.0 * (n_l * n_v));
        let b = n_h / (2.0 * v_h * n_l);
        let c = n_h / (2.0 * v_h * n_v);
        a.min(b).min(c)
    }
}

impl Brdf for CookTorrance {
    fn fresnel(&self) -> Option<Fresnel> {
        Some(self.fresnel)
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        let h = (wi + wo).normalize_or_zero();
        if h.z <= 0.0 {
            return Rgb::ZERO;
        }
        // V·H = L·H in exact arithmetic; their mean keeps ρ exactly reciprocal in f32.
        let v_h = 0.5 * (wi.dot(h) + wo.dot(h));
        let d = self.beckmann.d(h);
        if d <= 0.0 || v_h <= 0.0 {
            return Rgb::ZERO;
        }
        let g = Self::g_over_cosines(wi.z, wo.z, h.z, v_h);
        if !g.is_finite() {
            return Rgb::ZERO;
        }
        self.fresnel.eval(v_h) * (d * g)
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !same_upper_hemisphere(wi, wo) {
            return 0.0;
        }
        let h = (wi + wo).normalize_or_zero();
        // The same symmetric V·H as eval: near grazing, rounding makes wo·h and wi·h differ by
        // percents, and the weight ρ cos/pdf keeps its bound 2F only if both use one value.
        let v_h = 0.5 * (wi.dot(h) + wo.dot(h));
        if h.z <= 0.0 || v_h <= 0.0 {
            return 0.0;
        }
        self.beckmann.pdf_normal(h) / (4.0 * v_h)
    }

    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        reflect_about_half_vector(self, wo, self.beckmann.sample_normal(u))
    }

    fn claims(&self) -> Claims {
        // Energy: measured by quadrature with F = 1 for m in [0.001, 1] and θo up to 89°
        // (test `albedo_stays_below_one`): the V-groove G is at most Smith-like masking of the
        // visible facets, and the albedo never exceeded 1.
        Claims::PLAUSIBLE
    }
}

fn params() -> Vec<ParamSpec> {
    let mut v = vec![ParamSpec::float(
        "m",
        0.001,
        1.0,
        0.3,
        "Beckmann roughness m: RMS slope of the surface (√2 × the RMS slope along one axis)",
    )];
    v.extend(fresnel::params("dielectric"));
    v.push(combine::diffuse_param());
    v
}

fn make(p: &dyn ParamSource) -> Result<combine::DiffuseGlossy<CookTorrance>, ParamError> {
    let fresnel = fresnel::from_params(p)?;
    let lobe = CookTorrance::new(p.float("m"), fresnel);
    Ok(combine::with_diffuse(p, lobe, fresnel.max_reflectance()))
}

/// Registry entry.
pub const SPEC: ModelSpec = ModelSpec {
    name: "cook-torrance",
    summary: "Cook-Torrance: Beckmann D, V-groove G, Fresnel F, ρ = DGF/(4 cos θi cos θo) + ρ_d/π",
    reference: "Cook & Torrance 1982, A Reflectance Model for Computer Graphics",
    params,
    build: by_value!(make),
    showcase: &[
        &[("m", "0.05")],
        &[("m", "1")],
        &[("m", "0.3"), ("diffuse", "0.5")],
        &[("m", "0.2"), ("material", "Cu")],
    ],
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::microfacet::{Distribution, Shadowing};
    use crate::microfacet_brdf::tests::albedo;
    use crate::microfacet_brdf::MicrofacetBrdf;
    use rand::{Rng, SeedableRng};

    #[test]
    fn albedo_stays_below_one() {
        // F = 1, m across its range, θo from 0 to 89°; quadrature over half vectors on a grid
        // that follows the lobe's width m (error checked against a doubled grid).
        let mut worst = (0.0f64, 0.0f32, 0.0f32);
        for m in [0.001f32, 0.01, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0] {
            let ct = CookTorrance::new(m, Fresnel::None);
            for deg in [0.0f32, 20.0, 40.0, 60.0, 70.0, 80.0, 85.0, 88.0, 89.0] {
                let wo = radiometry::spherical_direction(deg.to_radians(), 0.0);
                let a = albedo(&ct, wo, m as f64, 1500, 256);
                let a2 = albedo(&ct, wo, m as f64, 3000, 512);
                // The tolerance is the quadrature's own error estimate plus f32 evaluation error.
                let tol = (a - a2).abs() + 1e-5;
                assert!(tol < 1e-3, "m={m} θo={deg}: quadrature unsettled, {a} vs {a2}");
                assert!(a2 <= 1.0 + tol, "m={m} θo={deg}: albedo {a2}");
                if a2 > worst.0 {
                    worst = (a2, m, deg);
                }
            }
        }
        println!("cook-torrance, F = 1: max albedo {:.7} at m = {}, θo = {}°", worst.0, worst.1, worst.2);
    }

    #[test]
    fn matches_microfacet_where_they_coincide() {
        // Normal incidence: V-groove and Smith both give G = 1 at wi = wo = N, so ρ(N, N) must
        // equal the microfacet model's with the same Beckmann D and F: D(N) F(1) / 4 = F/(4π m²).
        let m = 0.3f32;
        let f = Fresnel::Dielectric { eta: 1.5 };
        let ct = CookTorrance::new(m, f);
        let mf = MicrofacetBrdf {
            distribution: Distribution::Beckmann(Beckmann::new(m, m)),
            shadowing: Shadowing::Correlated,
            fresnel: f,
            tint: Rgb::ONE,
        };
        let closed = 0.04 / (4.0 * std::f32::consts::PI * m * m);
        for v in [ct.eval(Vec3::Z, Vec3::Z).0[0], mf.eval(Vec3::Z, Vec3::Z).0[0]] {
            assert!((v - closed).abs() < 1e-6 * closed.max(1.0), "{v} vs {closed}");
        }
    }

    #[test]
    fn v_groove_term_is_the_lectures() {
        // G/(4 N·L N·V) from the min-of-three form against the lecture's G divided afterwards.
        let mut rng = rand_pcg::Pcg64::seed_from_u64(9);
        for _ in 0..10_000 {
            let wi = radiometry::spherical_direction(rng.gen::<f32>() * 1.5, rng.gen::<f32>() * std::f32::consts::TAU);
            let wo = radiometry::spherical_direction(rng.gen::<f32>() * 1.5, rng.gen::<f32>() * std::f32::consts::TAU);
            let h = (wi + wo).normalize();
            let (nl, nv, nh, vh) = (wi.z, wo.z, h.z, wo.dot(h));
            let g = 1f32.min(2.0 * nh * nv / vh).min(2.0 * nh * nl / vh);
            let expect = g / (4.0 * nl * nv);
            let got = CookTorrance::g_over_cosines(nl, nv, nh, vh);
            assert!((got - expect).abs() <= 1e-5 * expect, "{got} vs {expect}");
        }
    }

    #[test]
    fn reciprocal_finite_and_sampled_consistently() {
        let ct = CookTorrance::new(0.001, Fresnel::Conductor { eta: fresnel::AU.eta, k: fresnel::AU.k });
        let ct2 = CookTorrance::new(1.0, Fresnel::Dielectric { eta: 1.5 });
        let mut rng = rand_pcg::Pcg64::seed_from_u64(4);
        for m in [ct, ct2] {
            for _ in 0..20_000 {
                let mut w = || {
                    let z: f32 = if rng.gen::<f32>() < 0.2 { rng.gen::<f32>() * 1e-6 } else { rng.gen() };
                    radiometry::spherical_direction(z.acos(), rng.gen::<f32>() * std::f32::consts::TAU)
                };
                let (wi, wo) = (w(), w());
                let a = m.eval(wi, wo);
                assert!(a.is_finite() && a.min_channel() >= 0.0, "{wi} {wo}: {a:?}");
                assert_eq!(a, m.eval(wo, wi));
                if let Some(s) = m.sample(wo, 0.5, Vec2::new(rng.gen(), rng.gen())) {
                    assert!(s.weight.is_finite() && s.weight.max_channel() <= 2.0 + 1e-4, "{:?}", s.weight);
                    let expect = m.eval(s.wi, wo) * (s.wi.z / m.pdf(s.wi, wo));
                    assert!((s.weight - expect).map(f32::abs).max_channel() <= 1e-5 * expect.max_channel().max(1.0));
                }
            }
        }
    }

    #[test]
    fn sampler_matches_pdf() {
        let ct = CookTorrance::new(0.4, Fresnel::None);
        for deg in [0.0f32, 50.0, 85.0] {
            let wo = radiometry::spherical_direction(deg.to_radians(), 0.3);
            let p = crate::microfacet::tests::chi_square_hemisphere(
                &|u| ct.sample(wo, 0.5, u).map(|s| s.wi),
                &|wi| ct.pdf(wi, wo) as f64,
                200_000,
                100 + deg as u64,
            );
            assert!(p > 1e-4, "θo={deg}: p = {p}");
        }
    }

    #[test]
    fn spec_builds() {
        let b = SPEC.build_with(&[]).unwrap();
        assert_eq!(b.claims(), Claims::PLAUSIBLE);
        for set in SPEC.showcase {
            SPEC.build_with(set).unwrap();
        }
    }
}
