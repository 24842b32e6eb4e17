//! Microfacet theory: distributions of facet normals D(h), Smith masking-shadowing, and the
//! two ways of sampling facet normals.
//!
//! D is normalised so that the facets' projected area is the macro-surface's:
//! ∫ D(h) cos θh dω_h = 1. Smith's masking of a direction w is G1(w) = 1 / (1 + Λ(w)), with Λ
//! from the distribution; shadowing-masking is either separable, G = G1(wi) G1(wo), or
//! height-correlated, G = 1 / (1 + Λ(wi) + Λ(wo)) (E. Heitz, "Understanding the
//! Masking-Shadowing Function in Microfacet-Based BRDFs", JCGT 3(2), 2014).
//! Visible normals seen from wo are distributed as D_wo(h) = G1(wo) max(0, wo·h) D(h) / cos θo,
//! which integrates to 1 over the hemisphere because Λ is defined to make it so.
//! Both distributions here are stretch-invariant: anisotropy is the α = 1 case with slopes
//! scaled by (α_x, α_y), which is how they are sampled.

pub mod beckmann;
pub mod erf;
pub mod ggx;

pub use beckmann::Beckmann;
pub use ggx::Ggx;

use radiometry::{Vec2, Vec3};

/// Roughness floor: below it D's peak 1/(πα²) and the f32 half-vector resolution part ways.
pub const MIN_ALPHA: f32 = 1e-4;

/// α(w)² tan²θ = (w_x² α_x² + w_y² α_y²) / w_z², the argument of Λ; infinite at or below the horizon.
#[inline]
pub(crate) fn stretched_tan2(w: Vec3, ax: f32, ay: f32) -> f32 {
    if w.z <= 0.0 {
        return f32::INFINITY;
    }
    let num = (w.x * ax) * (w.x * ax) + (w.y * ay) * (w.y * ay);
    num / (w.z * w.z)
}

/// The unit facet normal with slopes (x̃, ỹ): normalize(−x̃, −ỹ, 1).
#[inline]
pub(crate) fn normal_from_slopes(x: f32, y: f32) -> Vec3 {
    Vec3::new(-x, -y, 1.0).normalize()
}

/// Which Smith shadowing-masking term a model uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shadowing {
    /// G1(wi) G1(wo): masking and shadowing independent.
    Separable,
    /// 1 / (1 + Λ(wi) + Λ(wo)): a facet high on the surface is both less masked and less shadowed.
    Correlated,
}

impl Shadowing {
    /// The shadowing-masking term from Λ(wi) and Λ(wo), for callers that reuse the Λs;
    /// bit for bit what [`Ndf::g`] returns.
    #[inline]
    pub fn from_lambdas(self, lambda_i: f32, lambda_o: f32) -> f32 {
        match self {
            Shadowing::Separable => g1_from_lambda(lambda_i) * g1_from_lambda(lambda_o),
            // Summing the Λs first keeps G exactly symmetric in wi and wo.
            Shadowing::Correlated => 1.0 / (1.0 + (lambda_i + lambda_o)),
        }
    }
}

/// Smith masking G1 = 1 / (1 + Λ) from Λ.
#[inline]
pub fn g1_from_lambda(lambda: f32) -> f32 {
    1.0 / (1.0 + lambda)
}

/// A microfacet normal distribution: D, Smith's Λ, and samplers for D cos θh and D_wo.
pub trait Ndf {
    /// D(h) in 1/sr; zero for h below the surface.
    fn d(&self, h: Vec3) -> f32;

    /// Smith's Λ(w); infinite for w at or below the horizon.
    fn lambda(&self, w: Vec3) -> f32;

    /// The roughnesses (α_x, α_y).
    fn alphas(&self) -> (f32, f32);

    /// A facet normal with density D(h) cos θh.
    fn sample_normal(&self, u: Vec2) -> Vec3;

    /// A facet normal visible from `wo` (`wo.z > 0`), with density D_wo(h).
    fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3;

    /// True when D is invariant under rotation about the normal.
    fn is_isotropic(&self) -> bool {
        let (ax, ay) = self.alphas();
        ax == ay
    }

    /// Smith masking G1(w) = 1 / (1 + Λ(w)); zero at or below the horizon.
    #[inline]
    fn g1(&self, w: Vec3) -> f32 {
        g1_from_lambda(self.lambda(w))
    }

    /// Separable shadowing-masking G1(wi) G1(wo).
    #[inline]
    fn g_separable(&self, wi: Vec3, wo: Vec3) -> f32 {
        Shadowing::Separable.from_lambdas(self.lambda(wi), self.lambda(wo))
    }

    /// Height-correlated shadowing-masking 1 / (1 + Λ(wi) + Λ(wo)).
    #[inline]
    fn g_correlated(&self, wi: Vec3, wo: Vec3) -> f32 {
        Shadowing::Correlated.from_lambdas(self.lambda(wi), self.lambda(wo))
    }

    /// The shadowing-masking term of kind `s`.
    #[inline]
    fn g(&self, s: Shadowing, wi: Vec3, wo: Vec3) -> f32 {
        s.from_lambdas(self.lambda(wi), self.lambda(wo))
    }

    /// Density of `sample_normal`: D(h) cos θh.
    #[inline]
    fn pdf_normal(&self, h: Vec3) -> f32 {
        if h.z <= 0.0 {
            return 0.0;
        }
        self.d(h) * h.z
    }

    /// Density of `sample_visible`: D_wo(h) = G1(wo) max(0, wo·h) D(h) / cos θo.
    #[inline]
    fn pdf_visible(&self, wo: Vec3, h: Vec3) -> f32 {
        let cos_o = wo.z;
        let wo_h = wo.dot(h);
        if cos_o <= 0.0 || wo_h <= 0.0 {
            return 0.0;
        }
        visible_density(self.g1(wo), wo_h, self.d(h), cos_o)
    }
}

/// D_wo(h) = G1(wo) (wo·h) D(h) / cos θo from its factors (wo·h > 0, cos θo > 0): what
/// [`Ndf::pdf_visible`] returns, for a model that already has G1(wo) and D(h).
#[inline]
pub fn visible_density(g1_wo: f32, wo_h: f32, d: f32, cos_o: f32) -> f32 {
    g1_wo * wo_h * d / cos_o
}

/// A distribution chosen at run time: Beckmann or GGX.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Distribution {
    /// Gaussian slopes.
    Beckmann(Beckmann),
    /// Trowbridge-Reitz: longer tails.
    Ggx(Ggx),
}

impl Distribution {
    /// The distribution called `name` ("beckmann" or "ggx") with roughnesses α_x, α_y.
    pub fn named(name: &str, alpha_x: f32, alpha_y: f32) -> Option<Self> {
        match name {
            "beckmann" => Some(Distribution::Beckmann(Beckmann::new(alpha_x, alpha_y))),
            "ggx" => Some(Distribution::Ggx(Ggx::new(alpha_x, alpha_y))),
            _ => None,
        }
    }
}

impl Ndf for Distribution {
    #[inline]
    fn d(&self, h: Vec3) -> f32 {
        match self {
            Distribution::Beckmann(b) => b.d(h),
            Distribution::Ggx(g) => g.d(h),
        }
    }
    #[inline]
    fn lambda(&self, w: Vec3) -> f32 {
        match self {
            Distribution::Beckmann(b) => b.lambda(w),
            Distribution::Ggx(g) => g.lambda(w),
        }
    }
    #[inline]
    fn alphas(&self) -> (f32, f32) {
        match self {
            Distribution::Beckmann(b) => b.alphas(),
            Distribution::Ggx(g) => g.alphas(),
        }
    }
    fn sample_normal(&self, u: Vec2) -> Vec3 {
        match self {
            Distribution::Beckmann(b) => b.sample_normal(u),
            Distribution::Ggx(g) => g.sample_normal(u),
        }
    }
    fn sample_visible(&self, wo: Vec3, u: Vec2) -> Vec3 {
        match self {
            Distribution::Beckmann(b) => b.sample_visible(wo, u),
            Distribution::Ggx(g) => g.sample_visible(wo, u),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use statrs::distribution::{ChiSquared, ContinuousCDF};
    use std::f64::consts::PI;

    /// Midpoint rule over the hemisphere in (θ, φ) of f(direction) sin θ.
    pub(crate) fn hemisphere(f: &dyn Fn(Vec3) -> f64, n_theta: usize, n_phi: usize) -> f64 {
        radiometry::integrate::hemisphere_integral(|w| f(w.as_vec3()), n_theta, n_phi)
    }

    /// The integral at two resolutions; the quadrature's error is bounded by their difference
    /// (the midpoint rule's error falls 4× per doubling, so |I_2n − I| ≈ |I_2n − I_n|/3),
    /// plus 1e-5 for evaluating the integrand in f32.
    fn integral_with_error(f: &dyn Fn(Vec3) -> f64, n_theta: usize, n_phi: usize) -> (f64, f64) {
        let coarse = hemisphere(f, n_theta, n_phi);
        let fine = hemisphere(f, 2 * n_theta, 2 * n_phi);
        (fine, (fine - coarse).abs() + 1e-5)
    }

    pub(crate) fn distributions() -> Vec<Distribution> {
        let mut v = Vec::new();
        for &(ax, ay) in &[(0.05, 0.05), (0.2, 0.2), (0.5, 0.5), (1.0, 1.0), (0.1, 0.4), (0.7, 0.15)] {
            v.push(Distribution::Beckmann(Beckmann::new(ax, ay)));
            v.push(Distribution::Ggx(Ggx::new(ax, ay)));
        }
        v
    }

    #[test]
    fn projected_area_is_one() {
        for dist in distributions() {
            let f = |h: Vec3| dist.d(h) as f64 * h.z as f64;
            let (i, err) = integral_with_error(&f, 1500, 96);
            println!("{dist:?}: ∫ D cos = {i:.6} ± {err:.1e}");
            assert!((i - 1.0).abs() < err, "{dist:?}: ∫ D cos θ = {i} (tolerance {err})");
            assert!(err < 2e-3, "quadrature too coarse for {dist:?}: {err}");
        }
    }

    fn directions() -> Vec<Vec3> {
        [0.0f32, 30.0, 60.0, 80.0, 89.0].iter().map(|&t| radiometry::spherical_direction(t.to_radians(), 0.7)).collect()
    }

    #[test]
    fn visible_normals_are_normalised() {
        // ∫ D_wo = 1 holds only if Λ is the right one for D: a test of Λ against D.
        for dist in distributions() {
            for wo in directions() {
                let f = |h: Vec3| dist.pdf_visible(wo, h) as f64;
                let (i, err) = integral_with_error(&f, 1500, 96);
                assert!((i - 1.0).abs() < err, "{dist:?} wo={wo}: ∫ D_wo = {i} (tolerance {err})");
                assert!(err < 3e-3, "quadrature too coarse for {dist:?}, wo={wo}: {err}");
            }
        }
    }

    #[test]
    fn masking_and_shadowing_limits() {
        for dist in distributions() {
            // No masking head-on; full masking at the horizon; correlated G ≥ separable G.
            assert!((dist.g1(Vec3::Z) - 1.0).abs() < 1e-6);
            assert_eq!(dist.g1(Vec3::X), 0.0);
            assert_eq!(dist.g1(Vec3::new(0.6, 0.0, -0.8)), 0.0);
            for (a, b) in [(0.3f32, 1.2f32), (1.0, 1.5), (0.1, 0.2)] {
                let wi = radiometry::spherical_direction(a, 0.3);
                let wo = radiometry::spherical_direction(b, 2.0);
                let (sep, cor) = (dist.g_separable(wi, wo), dist.g_correlated(wi, wo));
                assert!(cor >= sep - 1e-6 && cor <= 1.0 && sep >= 0.0, "{dist:?}: {sep} {cor}");
                assert_eq!(dist.g_correlated(wi, wo), dist.g_correlated(wo, wi));
            }
        }
        // GGX closed form: α tan θ = 1 gives Λ = (√2 − 1)/2.
        let g = Ggx::new(0.5, 0.5);
        let w = radiometry::spherical_direction(2f32.atan(), 1.0);
        assert!((g.lambda(w) - (2f32.sqrt() - 1.0) / 2.0).abs() < 1e-6);
    }

    /// χ² goodness of fit of `sample` against `pdf` over the hemisphere, binned in θ × φ;
    /// expected counts from a 12×12 midpoint rule per cell, cells expecting < 5 pooled.
    /// Returns the p-value.
    pub(crate) fn chi_square_hemisphere(
        sample: &dyn Fn(Vec2) -> Option<Vec3>,
        pdf: &dyn Fn(Vec3) -> f64,
        n: usize,
        seed: u64,
    ) -> f64 {
        let (nt, np, sub) = (24usize, 24usize, 12usize);
        let (dt, dp) = (0.5 * PI / nt as f64, 2.0 * PI / np as f64);
        let mut expected = vec![0.0f64; nt * np];
        for i in 0..nt {
            for j in 0..np {
                let mut s = 0.0;
                for a in 0..sub {
                    let t = (i as f64 + (a as f64 + 0.5) / sub as f64) * dt;
                    for b in 0..sub {
                        let p = (j as f64 + (b as f64 + 0.5) / sub as f64) * dp;
                        let w = Vec3::new((t.sin() * p.cos()) as f32, (t.sin() * p.sin()) as f32, t.cos() as f32);
                        s += pdf(w) * t.sin();
                    }
                }
                expected[i * np + j] = s * dt * dp / (sub * sub) as f64 * n as f64;
            }
        }
        let mut observed = vec![0.0f64; nt * np];
        let mut rng = rand_pcg::Pcg64::seed_from_u64(seed);
        for _ in 0..n {
            let Some(w) = sample(Vec2::new(rng.gen(), rng.gen())) else { continue };
            assert!(w.is_finite() && (w.length() - 1.0).abs() < 1e-4, "{w}");
            let t = (w.z.clamp(-1.0, 1.0) as f64).acos();
            let i = ((t / dt) as usize).min(nt - 1);
            let j = ((radiometry::phi(w) as f64 / dp) as usize).min(np - 1);
            observed[i * np + j] += 1.0;
        }
        // Pool small cells together, and the mass the grid misses (below the horizon, None).
        let (mut chi2, mut cells) = (0.0, 0usize);
        let (mut pool_o, mut pool_e) = (0.0, 0.0);
        for k in 0..nt * np {
            if expected[k] < 5.0 {
                pool_o += observed[k];
                pool_e += expected[k];
            } else {
                chi2 += (observed[k] - expected[k]).powi(2) / expected[k];
                cells += 1;
            }
        }
        // The quadrature can overshoot n by a little; only a shortfall is mass outside the grid.
        pool_o += n as f64 - observed.iter().sum::<f64>();
        pool_e += (n as f64 - expected.iter().sum::<f64>()).max(0.0);
        if pool_e >= 5.0 {
            chi2 += (pool_o - pool_e).powi(2) / pool_e;
            cells += 1;
        } else {
            assert!(pool_o < 5.0 + 5.0 * pool_e.max(1.0).sqrt(), "{pool_o} samples where {pool_e} expected");
        }
        ChiSquared::new((cells - 1) as f64).unwrap().sf(chi2)
    }

    #[test]
    fn samplers_follow_their_densities() {
        // 30 tests at a 1e-4 level each: a family-wise false-alarm rate below 0.3%.
        let dists = [
            Distribution::Beckmann(Beckmann::new(0.3, 0.3)),
            Distribution::Ggx(Ggx::new(0.3, 0.3)),
            Distribution::Beckmann(Beckmann::new(0.2, 0.6)),
            Distribution::Ggx(Ggx::new(0.6, 0.2)),
            Distribution::Ggx(Ggx::new(1.0, 1.0)),
        ];
        let mut seed = 1;
        for dist in dists {
            seed += 1;
            let p =
                chi_square_hemisphere(&|u| Some(dist.sample_normal(u)), &|h| dist.pdf_normal(h) as f64, 200_000, seed);
            assert!(p > 1e-4, "{dist:?} D cos sampling: p = {p}");
            for wo in [0.0f32, 40.0, 70.0, 87.0].map(|t| radiometry::spherical_direction(t.to_radians(), 2.2)) {
                seed += 1;
                let p = chi_square_hemisphere(
                    &|u| Some(dist.sample_visible(wo, u)),
                    &|h| dist.pdf_visible(wo, h) as f64,
                    200_000,
                    seed,
                );
                println!("{dist:?} wo.z={:.3}: p = {p:.3}", wo.z);
                assert!(p > 1e-4, "{dist:?} visible-normal sampling from {wo}: p = {p}");
            }
        }
    }

    #[test]
    fn extreme_inputs_stay_finite() {
        for dist in [
            Distribution::Beckmann(Beckmann::new(MIN_ALPHA, MIN_ALPHA)),
            Distribution::Ggx(Ggx::new(MIN_ALPHA, 1.0)),
            Distribution::Beckmann(Beckmann::new(1.0, 1.0)),
            Distribution::Ggx(Ggx::new(0.0, 0.0)),
        ] {
            for wo in [Vec3::Z, Vec3::new(1.0, 0.0, 1e-7).normalize(), Vec3::new(0.0, 0.6, 0.8)] {
                for u in [Vec2::ZERO, Vec2::new(0.999_999_9, 0.999_999_9), Vec2::new(0.5, 0.0), Vec2::new(1e-7, 0.5)] {
                    for h in [dist.sample_visible(wo, u), dist.sample_normal(u)] {
                        assert!(h.is_finite() && h.z >= 0.0, "{dist:?} {wo} {u}: {h}");
                        assert!(dist.d(h).is_finite() && dist.pdf_visible(wo, h).is_finite());
                    }
                }
                assert!(dist.lambda(wo).is_finite() && dist.g1(wo).is_finite());
            }
            for h in [Vec3::X, Vec3::new(1.0, 0.0, 1e-20).normalize(), Vec3::new(0.0, 1.0, 1e-3).normalize()] {
                assert!(dist.d(h).is_finite() && dist.d(h) >= 0.0, "{dist:?} D({h})");
            }
        }
    }
}
