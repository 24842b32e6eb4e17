//! The microfacet reflection model (models `microfacet`, `ggx`, `beckmann`).
//!
//! ρ(wi, wo) = D(h) G(wi, wo) F(wi·h) / (4 cos θi cos θo),  h = (wi + wo)/|wi + wo|,
//! with D Beckmann or GGX (isotropic or anisotropic, `microfacet/`), G Smith's separable or
//! height-correlated shadowing-masking, and F any Fresnel term (`fresnel.rs`).
//! Sampling draws h from the normals visible from wo, D_wo(h) = G1(wo) (wo·h) D(h) / cos θo,
//! and reflects wo about it; the Jacobian of reflection, dωi/dωh = 4 (wo·h), gives
//! pdf(wi) = D_wo(h) / (4 wo·h) and the weight ρ cos θi / pdf = F G / G1(wo) ≤ 1.
//! Energy: ∫ ρ cos θi dωi ≤ ∫ F(wo·h) D_wo(h) dωh ≤ 1, since G ≤ G1(wo) and F ≤ 1: the
//! model only loses the energy of multiple scattering between facets.
//! Sources: B. Walter, S. R. Marschner, H. Li, K. E. Torrance, "Microfacet Models for
//! Refraction through Rough Surfaces", EGSR 2007; R. L. Cook & K. E. Torrance, "A Reflectance
//! Model for Computer Graphics", ACM TOG 1(1), 1982; E. Heitz, JCGT 3(2), 2014 and 7(4), 2018.

use crate::combine;
use crate::fresnel::{self, Fresnel};
use crate::microfacet::{g1_from_lambda, Distribution, Ndf, Shadowing};
use crate::model::{reflect_about_half_vector, same_upper_hemisphere, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use crate::roughness;
use radiometry::{Rgb, Vec2, Vec3};

pub use crate::roughness::ALPHA_MIN;

/// A microfacet BRDF: a distribution of normals, a shadowing term and a Fresnel term.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MicrofacetBrdf {
    /// Distribution of facet normals.
    pub distribution: Distribution,
    /// Shadowing-masking term.
    pub shadowing: Shadowing,
    /// Reflectance of one facet.
    pub fresnel: Fresnel,
    /// A tint multiplying it (1 is physical; Mitsuba's `specular_reflectance`).
    pub tint: Rgb,
}

impl MicrofacetBrdf {
    /// The half vector of two upper-hemisphere directions and the incidence cosine at the facet,
    /// computed symmetrically in wi and wo so that ρ is exactly reciprocal in f32.
    #[inline]
    fn half(wi: Vec3, wo: Vec3) -> Option<(Vec3, f32)> {
        let h = (wi + wo).normalize_or_zero();
        if h.z <= 0.0 {
            return None;
        }
        Some((h, 0.5 * (wi.dot(h) + wo.dot(h))))
    }

    /// ρ from the shared terms: D(h), Λ(wi), Λ(wo) and the facet cosine.
    #[inline]
    fn rho(&self, wi: Vec3, wo: Vec3, cos_d: f32, d: f32, lambda_i: f32, lambda_o: f32) -> Rgb {
        let g = self.shadowing.from_lambdas(lambda_i, lambda_o);
        let denom = 4.0 * (wi.z * wo.z);
        // G vanishes at the horizon faster than the cosines; when even their product underflows
        // the contribution is below f32 resolution.
        if g <= 0.0 || denom <= 0.0 {
            return Rgb::ZERO;
        }
        let v = self.fresnel.eval(cos_d) * self.tint * (d * g / denom);
        if v.is_finite() {
            v
        } else {
            Rgb::ZERO
        }
    }

    /// The sampling density from the shared terms.
    #[inline]
    fn density(wo: Vec3, cos_d: f32, d: f32, lambda_o: f32) -> f32 {
        if cos_d <= 0.0 {
            return 0.0;
        }
        // D_wo(h)/(4 wo·h) = G1(wo) D(h)/(4 cos θo): the wo·h cancels, which spares the
        // rounding of wo·h near grazing.
        g1_from_lambda(lambda_o) * d / (4.0 * wo.z)
    }
}

impl Brdf for MicrofacetBrdf {
    fn fresnel(&self) -> Option<Fresnel> {
        Some(self.fresnel)
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        let Some((h, cos_d)) = Self::half(wi, wo) else { return Rgb::ZERO };
        let dist = &self.distribution;
        self.rho(wi, wo, cos_d, dist.d(h), dist.lambda(wi), dist.lambda(wo))
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !same_upper_hemisphere(wi, wo) {
            return 0.0;
        }
        let Some((h, cos_d)) = Self::half(wi, wo) else { return 0.0 };
        if cos_d <= 0.0 {
            return 0.0;
        }
        Self::density(wo, cos_d, self.distribution.d(h), self.distribution.lambda(wo))
    }

    /// Sharing h, D(h) and Λ(wo): bit for bit what each returns.
    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        if !same_upper_hemisphere(wi, wo) {
            return (Rgb::ZERO, 0.0);
        }
        let Some((h, cos_d)) = Self::half(wi, wo) else { return (Rgb::ZERO, 0.0) };
        let dist = &self.distribution;
        let (d, lambda_o) = (dist.d(h), dist.lambda(wo));
        let rho = self.rho(wi, wo, cos_d, d, dist.lambda(wi), lambda_o);
        (rho, Self::density(wo, cos_d, d, lambda_o))
    }

    fn sample(&self, wo: Vec3, _uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        reflect_about_half_vector(self, wo, self.distribution.sample_visible(wo, u))
    }

    fn claims(&self) -> Claims {
        Claims { reciprocal: true, energy_conserving: true, isotropic: self.distribution.is_isotropic() }
    }
}

/// The parameters; `with_distribution` false for the presets that fix it.
fn params_with(with_distribution: bool) -> Vec<ParamSpec> {
    let mut v = Vec::new();
    if with_distribution {
        v.push(ParamSpec::choice("distribution", &["beckmann", "ggx"], "ggx", "distribution of facet normals D"));
    }
    v.extend(roughness::params(
        0.2,
        "roughness α (Beckmann: the RMS slope of the surface, √2 × the RMS slope along one axis)",
    ));
    v.push(ParamSpec::choice(
        "shadowing",
        &["smith-separable", "smith-correlated"],
        "smith-correlated",
        "Smith shadowing-masking: G1(wi)G1(wo) or height-correlated 1/(1+Λ(wi)+Λ(wo))",
    ));
    // A lone microfacet lobe is a metal: gold shows what the Fresnel term does, where a
    // dielectric would reflect 4% and look black without a diffuse lobe under it.
    v.extend(fresnel::params("conductor"));
    v.push(ParamSpec::rgb("reflectance", 0.0, 1.0, 1.0, "tint R multiplying the Fresnel term (1 is physical)"));
    v.push(combine::diffuse_param());
    v
}

fn params() -> Vec<ParamSpec> {
    params_with(true)
}

fn preset_params() -> Vec<ParamSpec> {
    params_with(false)
}

/// Builds the model with distribution `name`.
fn make_named(p: &dyn ParamSource, name: &str) -> Result<combine::DiffuseGlossy<MicrofacetBrdf>, ParamError> {
    let (ax, ay) = roughness::from_params(p)?;
    let distribution = Distribution::named(name, ax, ay).expect("distribution choice list matches Distribution::named");
    let shadowing = match p.choice("shadowing") {
        "smith-separable" => Shadowing::Separable,
        _ => Shadowing::Correlated,
    };
    let fresnel = fresnel::from_params(p)?;
    let tint = p.rgb("reflectance");
    let glossy = MicrofacetBrdf { distribution, shadowing, fresnel, tint };
    Ok(combine::with_diffuse(p, glossy, fresnel.max_reflectance() * tint.max_channel()))
}

fn make(p: &dyn ParamSource) -> Result<combine::DiffuseGlossy<MicrofacetBrdf>, ParamError> {
    make_named(p, p.choice("distribution"))
}

fn make_ggx(p: &dyn ParamSource) -> Result<combine::DiffuseGlossy<MicrofacetBrdf>, ParamError> {
    make_named(p, "ggx")
}

fn make_beckmann(p: &dyn ParamSource) -> Result<combine::DiffuseGlossy<MicrofacetBrdf>, ParamError> {
    make_named(p, "beckmann")
}

const REFERENCE: &str = "Walter et al. 2007, Microfacet Models for Refraction through Rough Surfaces; Heitz 2014, 2018";

/// Registry entry: the general microfacet model.
pub const SPEC: ModelSpec = ModelSpec {
    name: "microfacet",
    summary: "microfacet reflection D·G·F/(4 cos θi cos θo), Beckmann or GGX, Smith G, any Fresnel",
    reference: REFERENCE,
    params,
    build: by_value!(make),
    showcase: &[
        &[("distribution", "beckmann"), ("alpha", "0.05")],
        &[("alpha_u", "0.05"), ("alpha_v", "0.4")],
        &[("shadowing", "smith-separable"), ("alpha", "1")],
        &[("fresnel", "dielectric"), ("eta", "1.5"), ("diffuse", "0.5")],
    ],
};

/// Registry entry: `microfacet` with the GGX distribution.
pub const GGX_SPEC: ModelSpec = ModelSpec {
    name: "ggx",
    summary: "GGX (Trowbridge-Reitz) microfacet reflection; microfacet with distribution=ggx",
    reference: REFERENCE,
    params: preset_params,
    build: by_value!(make_ggx),
    showcase: &[&[("alpha", "0.5"), ("material", "Cu")], &[("alpha_u", "0.6"), ("alpha_v", "0.1")]],
};

/// Registry entry: `microfacet` with the Beckmann distribution.
pub const BECKMANN_SPEC: ModelSpec = ModelSpec {
    name: "beckmann",
    summary: "Beckmann microfacet reflection; microfacet with distribution=beckmann",
    reference: REFERENCE,
    params: preset_params,
    build: by_value!(make_beckmann),
    showcase: &[&[("alpha", "0.5"), ("material", "Ag")], &[("alpha_u", "0.1"), ("alpha_v", "0.6")]],
};

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::microfacet::{Beckmann, Ggx};
    use rand::{Rng, SeedableRng};
    use std::f64::consts::PI;

    /// Directional albedo ∫ ρ(wi, wo) cos θi dωi, integrated over half vectors (dωi = 4 (wo·h) dωh)
    /// with θh = atan(scale · t), t = s/(1 − s), s on a midpoint grid: the grid follows a lobe of
    /// width `scale` however narrow. Red channel. f64 accumulation of f32 evaluations.
    pub(crate) fn albedo(brdf: &dyn Brdf, wo: Vec3, scale: f64, n_s: usize, n_phi: usize) -> f64 {
        let (ds, dp) = (1.0 / n_s as f64, 2.0 * PI / n_phi as f64);
        let mut sum = 0.0;
        for i in 0..n_s {
            let s = (i as f64 + 0.5) * ds;
            let t = s / (1.0 - s);
            let theta = (scale * t).atan();
            // dθ/ds = scale / (1 + scale² t²) · 1/(1 − s)².
            let jac = scale / (1.0 + scale * scale * t * t) / ((1.0 - s) * (1.0 - s));
            let (st, ct) = theta.sin_cos();
            let mut ring = 0.0;
            for j in 0..n_phi {
                let p = (j as f64 + 0.5) * dp;
                let h = Vec3::new((st * p.cos()) as f32, (st * p.sin()) as f32, ct as f32);
                let wo_h = wo.dot(h);
                if wo_h <= 0.0 {
                    continue;
                }
                let wi = 2.0 * wo_h * h - wo;
                if wi.z <= 0.0 {
                    continue;
                }
                ring += brdf.eval(wi, wo).0[0] as f64 * wi.z as f64 * 4.0 * wo_h as f64;
            }
            sum += ring * st * jac;
        }
        sum * ds * dp
    }

    fn model(d: Distribution, s: Shadowing, f: Fresnel) -> MicrofacetBrdf {
        MicrofacetBrdf { distribution: d, shadowing: s, fresnel: f, tint: Rgb::ONE }
    }

    #[test]
    fn albedo_quadrature_agrees_with_sampling_and_stays_below_one() {
        // With F = 1 the albedo is E[G/G1(wo)] over visible normals: the quadrature over half vectors
        // must agree with the Monte Carlo mean of the sampler's weights (two independent routes),
        // and neither can exceed 1.
        let mut worst = 0.0f64;
        for d in [
            Distribution::Ggx(Ggx::new(0.05, 0.05)),
            Distribution::Ggx(Ggx::new(0.5, 0.5)),
            Distribution::Ggx(Ggx::new(1.0, 1.0)),
            Distribution::Beckmann(Beckmann::new(0.05, 0.05)),
            Distribution::Beckmann(Beckmann::new(0.5, 0.5)),
            Distribution::Beckmann(Beckmann::new(1.0, 1.0)),
            Distribution::Ggx(Ggx::new(0.1, 0.6)),
        ] {
            let (ax, ay) = d.alphas();
            for shadowing in [Shadowing::Separable, Shadowing::Correlated] {
                let m = model(d, shadowing, Fresnel::None);
                for deg in [0.0f32, 45.0, 75.0, 89.0] {
                    let wo = radiometry::spherical_direction(deg.to_radians(), 0.4);
                    let a = albedo(&m, wo, ax.max(ay) as f64, 2000, 256);
                    // Monte Carlo with the model's own sampler: mean weight = albedo.
                    let mut rng = rand_pcg::Pcg64::seed_from_u64(17);
                    let n = 40_000;
                    let (mut s1, mut s2) = (0.0f64, 0.0f64);
                    for _ in 0..n {
                        let w =
                            m.sample(wo, 0.5, Vec2::new(rng.gen(), rng.gen())).map_or(0.0, |s| s.weight.0[0] as f64);
                        s1 += w;
                        s2 += w * w;
                    }
                    let mean = s1 / n as f64;
                    let se = ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
                    assert!(
                        (a - mean).abs() < 4.0 * se + 2e-3,
                        "{d:?} {shadowing:?} θo={deg}: quadrature {a} vs MC {mean} ± {se}"
                    );
                    assert!(a <= 1.0 + 1e-3, "{d:?} {shadowing:?} θo={deg}: albedo {a}");
                    worst = worst.max(a);
                }
            }
        }
        println!("max single-scattering albedo with F = 1: {worst:.4}");
        // Head-on, a smooth surface with F = 1 reflects (almost) everything.
        let smooth = model(Distribution::Ggx(Ggx::new(0.01, 0.01)), Shadowing::Correlated, Fresnel::None);
        let a = albedo(&smooth, Vec3::Z, 0.01, 2000, 64);
        assert!((a - 1.0).abs() < 2e-3, "{a}");
    }

    #[test]
    fn reciprocal_and_finite_everywhere() {
        let gold =
            fresnel::from_params(&crate::Params::resolve("m", &fresnel::params("conductor"), &[]).unwrap()).unwrap();
        let mut rng = rand_pcg::Pcg64::seed_from_u64(3);
        for d in [
            Distribution::Ggx(Ggx::new(0.001, 0.001)),
            Distribution::Ggx(Ggx::new(0.3, 0.05)),
            Distribution::Beckmann(Beckmann::new(0.001, 0.001)),
            Distribution::Beckmann(Beckmann::new(1.0, 0.2)),
        ] {
            for shadowing in [Shadowing::Separable, Shadowing::Correlated] {
                let m = model(d, shadowing, gold);
                for _ in 0..20_000 {
                    let mut w = || {
                        let z: f32 = if rng.gen::<f32>() < 0.2 { rng.gen::<f32>() * 1e-6 } else { rng.gen() };
                        radiometry::spherical_direction(z.acos(), rng.gen::<f32>() * std::f32::consts::TAU)
                    };
                    let (wi, wo) = (w(), w());
                    let (a, b) = (m.eval(wi, wo), m.eval(wo, wi));
                    assert!(a.is_finite() && a.min_channel() >= 0.0, "{d:?} {wi} {wo}: {a:?}");
                    assert_eq!(a, b, "{d:?} not reciprocal at {wi}, {wo}");
                    let pdf = m.pdf(wi, wo);
                    assert!(pdf.is_finite() && pdf >= 0.0);
                    if let Some(s) = m.sample(wo, 0.3, Vec2::new(rng.gen(), rng.gen())) {
                        assert!(s.pdf > 0.0 && s.pdf.is_finite() && s.weight.is_finite() && s.wi.z > 0.0);
                        assert!(s.weight.max_channel() <= 1.0 + 1e-4, "weight F·G/G1 ≤ 1: {:?}", s.weight);
                    }
                }
                assert_eq!(m.eval(Vec3::Z, Vec3::new(0.0, 0.6, -0.8)), Rgb::ZERO);
                assert!(m.sample(Vec3::new(0.0, 0.6, -0.8), 0.5, Vec2::splat(0.5)).is_none());
            }
        }
    }

    #[test]
    fn shared_terms_give_bit_identical_results() {
        // eval_pdf and sample share work with eval and pdf; they must not change a bit: the
        // sample equals the generic completion from the model's own pdf and eval.
        let gold = Fresnel::Conductor { eta: fresnel::AU.eta, k: fresnel::AU.k };
        let mut rng = rand_pcg::Pcg64::seed_from_u64(11);
        for d in [Distribution::Ggx(Ggx::new(0.3, 0.05)), Distribution::Beckmann(Beckmann::new(0.1, 0.4))] {
            for shadowing in [Shadowing::Separable, Shadowing::Correlated] {
                let m = model(d, shadowing, gold);
                for _ in 0..20_000 {
                    let mut w = || {
                        let z: f32 = rng.gen::<f32>() * 2.0 - 0.2;
                        radiometry::spherical_direction(
                            z.clamp(-1.0, 1.0).acos(),
                            rng.gen::<f32>() * std::f32::consts::TAU,
                        )
                    };
                    let (wi, wo) = (w(), w());
                    assert_eq!(m.eval_pdf(wi, wo), (m.eval(wi, wo), m.pdf(wi, wo)), "{wi} {wo}");
                    let u = Vec2::new(rng.gen(), rng.gen());
                    let generic = if wo.z > 0.0 {
                        reflect_about_half_vector(&m, wo, m.distribution.sample_visible(wo, u))
                    } else {
                        None
                    };
                    assert_eq!(m.sample(wo, 0.5, u), generic, "{wo} {u}");
                }
            }
        }
    }

    #[test]
    fn sampler_matches_pdf() {
        let m = model(Distribution::Ggx(Ggx::new(0.3, 0.6)), Shadowing::Correlated, Fresnel::Dielectric { eta: 1.5 });
        for deg in [10.0f32, 60.0, 85.0] {
            let wo = radiometry::spherical_direction(deg.to_radians(), 1.0);
            let p = crate::microfacet::tests::chi_square_hemisphere(
                &|u| m.sample(wo, 0.5, u).map(|s| s.wi),
                &|wi| m.pdf(wi, wo) as f64,
                200_000,
                deg as u64,
            );
            assert!(p > 1e-4, "θo={deg}: p = {p}");
        }
    }

    #[test]
    fn registry_specs_build_and_check_parameters() {
        for spec in [SPEC, GGX_SPEC, BECKMANN_SPEC] {
            let b = spec.build_with(&[]).unwrap();
            assert!(b.claims().energy_conserving && b.claims().reciprocal && b.claims().isotropic);
            for set in spec.showcase {
                spec.build_with(set).unwrap();
            }
        }
        assert!(!(GGX_SPEC.params)().iter().any(|p| p.name == "distribution"));
        let aniso = SPEC.build_with(&[("alpha_u", "0.1"), ("alpha_v", "0.3")]).unwrap();
        assert!(!aniso.claims().isotropic);
        let e = SPEC.build_with(&[("alpha_u", "0.0001")]).unwrap_err().to_string();
        assert!(e.contains("alpha_u"), "{e}");
        // A diffuse lobe under a lobe whose reflectance reaches 1 cannot be claimed conserving.
        let with_diffuse = GGX_SPEC.build_with(&[("diffuse", "0.3")]).unwrap();
        assert!(!with_diffuse.claims().energy_conserving);
    }
}
