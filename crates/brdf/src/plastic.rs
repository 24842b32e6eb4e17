//! Mitsuba 3's plastic models (`roughplastic`, `plastic`): a diffuse base under a dielectric coat.
//!
//! Rough coat (`roughplastic`), with η = int_ior / ext_ior, h = (wi + wo)/|wi + wo|:
//!   ρ = k_s F(wi·h; η) D(h) G1(wi) G1(wo) / (4 cos θi cos θo)
//!     + ρ_d / (1 − F_int) · t(cos θi) t(cos θo) / (π η²),
//! where D is Beckmann or GGX, G1 Smith's masking (for Beckmann, Walter et al.'s rational
//! approximation, as Mitsuba uses), t(μ) the rough coat's transmittance into the material for
//! light arriving at cos θ = μ, and F_int the cosine-weighted internal reflectance of the coat
//! seen from inside (relative index 1/η). With `nonlinear` the base term is ρ_d / (1 − ρ_d F_int):
//! the colour shift of light bouncing between base and coat.
//!   t(μ)   = E_{m∼D_w}[(1 − F(w·m; η)) G1(w_t, m)],   w = (√(1−μ²), 0, μ), w_t refracted,
//!   R_i(μ) = E_{m∼D_w}[F(w·m; 1/η) G1(w_r, m)],       w_r reflected (zero below the surface),
//! both expectations over the normals visible from w, each one integral over the unit square
//! (Gauss–Legendre). As in Mitsuba, t is tabulated at 64 cosines μ_k = max(10⁻⁶, k/63) and read
//! by linear interpolation, and F_int = 2 · mean_k R_i(μ_k) μ_k (the plain mean of the 64 values,
//! endpoints included: Mitsuba's estimate, reproduced rather than improved so that images match).
//!
//! Smooth coat (`plastic`): a delta lobe of weight k_s F(cos θo; η) in the mirror direction, and
//!   ρ = ρ_d / (1 − F_dr) · (1 − F(cos θi; η)) (1 − F(cos θo; η)) / (π η²),
//! with F_dr the internal diffuse Fresnel reflectance from the fits Mitsuba uses: Egan & Hilgeman
//! for a relative index e < 1 (here e = 1/η), d'Eon & Irving's polynomial in 1/e otherwise.
//!
//! Sampling (ours, not Mitsuba's): the coat lobe with probability
//! P_s = (1 − t_o) w / ((1 − t_o) w + t_o (1 − w)), w = mean(k_s) / (mean(k_s) + mean(ρ_d)),
//! t_o the transmittance at θo (smooth: 1 − F(cos θo)); visible normals for the rough coat, the
//! cosine for the base; the rough model's pdf is the mixture of both densities.
//! Both are reciprocal. Energy: the coat's reflectance and transmittance add to at most 1, and
//! the base adds max(ρ_d) c t_o with c = 2∫t(μ)μ dμ / (η²(1 − F_int)) (c ≈ 1): claimed when
//! max(ρ_d) c ≤ 1 and k_s ≤ 1.
//! Sources: Mitsuba 3 documentation and source, `roughplastic` and `plastic` (W. Jakob et al.);
//! B. Walter, S. Marschner, H. Li, K. Torrance, "Microfacet Models for Refraction through Rough
//! Surfaces", EGSR 2007; C. Kelemen, L. Szirmay-Kalos, "A Microfacet Based Coupled
//! Specular-Matte BRDF Model with Importance Sampling", Eurographics 2001; W. G. Egan,
//! T. W. Hilgeman, *Optical Properties of Inhomogeneous Materials*, 1979; E. d'Eon, G. Irving,
//! "A Quantized-Diffusion Model for Rendering Translucent Materials", SIGGRAPH 2011.

use crate::fresnel;
use crate::fresnel::Fresnel;
use crate::microfacet::{Distribution, Ndf};
use crate::model::{reflect, reflect_z, same_upper_hemisphere, sample_from_pdf, Brdf, BrdfSample, Claims};
use crate::params::{ParamError, ParamSource, ParamSpec};
use crate::registry::{by_value, ModelSpec};
use crate::roughness::ALPHA_MIN;
use radiometry::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use radiometry::{Rgb, Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// Number of tabulated cosines of the rough coat's transmittance (Mitsuba's resolution).
pub const TABLE_SIZE: usize = 64;

/// Smith masking G1(w) of the distribution, in Mitsuba's form: the exact term for GGX and
/// Walter et al.'s rational approximation (< 0.35 % off) for Beckmann; zero when w sees the back
/// of the facet m. Only |w.z| enters the slope, so it serves directions below the surface too.
fn smith_g1(beckmann: bool, alpha: f32, w: Vec3, m: Vec3) -> f32 {
    if w.dot(m) * w.z <= 0.0 {
        return 0.0;
    }
    let xy = alpha * alpha * (w.x * w.x + w.y * w.y);
    if xy <= 0.0 {
        return 1.0;
    }
    let t2 = xy / (w.z * w.z);
    if beckmann {
        let a = 1.0 / t2.sqrt();
        if a >= 1.6 {
            1.0
        } else {
            (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
        }
    } else {
        2.0 / (1.0 + (1.0 + t2).sqrt())
    }
}

/// The coat tables of (distribution, α, η), computed once per process: a textured material
/// builds its model at every hit, and the tables depend only on parameters that cannot vary.
/// Each thread keeps the tables it used last, so a hit takes no lock.
fn cached_coat_tables(dist: &Distribution, beckmann: bool, alpha: f32, eta: f32) -> CoatTables {
    type Key = (bool, u32, u32);
    /// More distinct coats than this are computed without being kept.
    const KEPT: usize = 256;
    static ALL: std::sync::RwLock<Vec<(Key, CoatTables)>> = std::sync::RwLock::new(Vec::new());
    thread_local!(static LAST: std::cell::Cell<Option<(Key, CoatTables)>> = const { std::cell::Cell::new(None) });
    let key = (beckmann, alpha.to_bits(), eta.to_bits());
    if let Some((k, t)) = LAST.get() {
        if k == key {
            return t;
        }
    }
    let found = ALL.read().ok().and_then(|all| all.iter().find(|(k, _)| *k == key).map(|e| e.1));
    let tables = found.unwrap_or_else(|| {
        let t = coat_tables(dist, beckmann, alpha, eta);
        if let Ok(mut all) = ALL.write() {
            if all.len() < KEPT && !all.iter().any(|(k, _)| *k == key) {
                all.push((key, t));
            }
        }
        t
    });
    LAST.set(Some((key, tables)));
    tables
}

/// What a rough coat of given (distribution, α, η) needs, whatever the base under it.
#[derive(Clone, Copy, Debug)]
struct CoatTables {
    /// t(μ_k), the coat's transmittance at cosine μ_k = k/(TABLE_SIZE − 1).
    t: [f32; TABLE_SIZE],
    /// F_int, the cosine-weighted internal reflectance.
    f_int: f32,
}

/// The rough coat's tables: t(μ_k) and F_int, integrated over visible normals. The cosines
/// are shared among the cores (the integrals are 327 680 visible-normal samples, 0.1 s on one
/// core, at every load of a scene with a rough coat); F_int sums them in order, as one core did.
fn coat_tables(dist: &Distribution, beckmann: bool, alpha: f32, eta: f32) -> CoatTables {
    // The transmittance integrand is smooth; the internal reflectance jumps at the critical
    // angle, so it gets a finer rule.
    let rules = (radiometry::integrate::gauss_legendre01(32), radiometry::integrate::gauss_legendre01(64));
    let mut rows = [(0.0f32, 0.0f64); TABLE_SIZE];
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).clamp(1, 8);
    let per = TABLE_SIZE.div_ceil(threads);
    std::thread::scope(|scope| {
        for (c, chunk) in rows.chunks_mut(per).enumerate() {
            let rules = &rules;
            scope.spawn(move || {
                for (j, row) in chunk.iter_mut().enumerate() {
                    *row = coat_row(dist, (beckmann, alpha, eta), rules, c * per + j);
                }
            });
        }
    });
    let mut t = [0.0f32; TABLE_SIZE];
    let mut r_mean = 0.0f64;
    for (tk, &(trans, refl_mu)) in t.iter_mut().zip(&rows) {
        *tk = trans;
        r_mean += refl_mu / TABLE_SIZE as f64;
    }
    CoatTables { t, f_int: (2.0 * r_mean) as f32 }
}

/// A quadrature rule on [0, 1]: (node, weight) pairs.
type Rule = Vec<(f64, f64)>;

/// Row `k` of the coat's tables, t(μ_k) and R_i(μ_k) μ_k, with the (coarse, fine) quadrature
/// rules `rules`.
fn coat_row(
    dist: &Distribution,
    (beckmann, alpha, eta): (bool, f32, f32),
    rules: &(Rule, Rule),
    k: usize,
) -> (f32, f64) {
    let (coarse, fine) = rules;
    let mu = (k as f32 / (TABLE_SIZE - 1) as f32).max(1e-6);
    let w = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
    let mut trans = 0.0f64;
    for &(x, wx) in coarse {
        for &(y, wy) in coarse {
            let m = dist.sample_visible(w, Vec2::new(x as f32, y as f32));
            let c = w.dot(m);
            let sin2_t = (1.0 - c * c).max(0.0) / (eta * eta);
            if c <= 0.0 || sin2_t >= 1.0 {
                continue;
            }
            let cos_t = (1.0 - sin2_t).sqrt();
            let wt = (-w / eta + (c / eta - cos_t) * m).normalize_or_zero();
            if wt.z >= 0.0 {
                continue;
            }
            let f = fresnel::dielectric(c, eta);
            trans += wx * wy * ((1.0 - f) * smith_g1(beckmann, alpha, wt, m)) as f64;
        }
    }
    let mut refl = 0.0f64;
    for &(x, wx) in fine {
        for &(y, wy) in fine {
            let m = dist.sample_visible(w, Vec2::new(x as f32, y as f32));
            let wr = reflect(w, m);
            if wr.z <= 0.0 {
                continue;
            }
            let f = fresnel::dielectric(w.dot(m), 1.0 / eta);
            refl += wx * wy * (f * smith_g1(beckmann, alpha, wr, m)) as f64;
        }
    }
    (trans as f32, refl * mu as f64)
}

/// What a coated model claims: always reciprocal and isotropic; energy conserving while the coat
/// tint and the base's albedo bound `energy_bound` stay within 1.
fn coat_claims(specular: Rgb, energy_bound: f32) -> Claims {
    Claims {
        reciprocal: true,
        energy_conserving: specular.max_channel() <= 1.0 && energy_bound <= 1.0,
        isotropic: true,
    }
}

/// Linear interpolation in the table at cosine `mu` ∈ [0, 1] (Mitsuba's `lerp_gather`).
#[inline]
fn lerp_table(table: &[f32; TABLE_SIZE], mu: f32) -> f32 {
    let x = mu.clamp(0.0, 1.0) * (TABLE_SIZE - 1) as f32;
    let i = (x as usize).min(TABLE_SIZE - 2);
    let f = x - i as f32;
    (1.0 - f) * table[i] + f * table[i + 1]
}

/// Mitsuba's internal diffuse Fresnel reflectance F_dr(e) for a relative index e (fits).
pub fn fresnel_diffuse_reflectance(e: f32) -> f32 {
    if e < 1.0 {
        // Egan & Hilgeman (1979).
        -1.4399 * e * e + 0.7099 * e + 0.6681 + 0.0636 / e
    } else {
        // d'Eon & Irving (2011), a polynomial in 1/e.
        let x = 1.0 / e;
        let c = [0.919317f32, -3.4793, 6.75335, -7.80989, 4.98554, -1.36881];
        c.iter().rev().fold(0.0, |acc, &k| acc * x + k)
    }
}

/// Mitsuba's lobe weight w = mean(k_s) / (mean(k_s) + mean(ρ_d)), and the coat probability
/// P_s from it and the coat's transmittance at θo.
#[inline]
fn coat_probability(weight: f32, t_o: f32) -> f32 {
    let s = (1.0 - t_o).max(0.0) * weight;
    let d = t_o.max(0.0) * (1.0 - weight);
    if s + d > 0.0 {
        s / (s + d)
    } else {
        0.5
    }
}

fn sampling_weight(specular: Rgb, diffuse: Rgb) -> f32 {
    let (s, d) = (specular.mean().max(0.0), diffuse.mean().max(0.0));
    if s + d > 0.0 {
        s / (s + d)
    } else {
        0.5
    }
}

/// The base's factor ρ_d / (1 − F_int) (or ρ_d / (1 − ρ_d F_int) when `nonlinear`) / (π η²).
fn base_factor(diffuse: Rgb, f_int: f32, nonlinear: bool, eta: f32) -> Rgb {
    let scale = FRAC_1_PI / (eta * eta);
    diffuse.map(|d| {
        let denom = 1.0 - if nonlinear { d * f_int } else { f_int };
        if denom > 0.0 {
            d / denom * scale
        } else {
            0.0
        }
    })
}

/// Mitsuba's `roughplastic`: a rough dielectric coat over a diffuse base.
#[derive(Clone, Debug, PartialEq)]
pub struct RoughPlastic {
    dist: Distribution,
    beckmann: bool,
    alpha: f32,
    eta: f32,
    specular: Rgb,
    base: Rgb,
    transmittance: [f32; TABLE_SIZE],
    internal_reflectance: f32,
    weight: f32,
}

impl RoughPlastic {
    /// The model for `distribution` ("beckmann" or "ggx"), roughness `alpha`, relative index
    /// `eta` = int_ior/ext_ior, base ρ_d `diffuse` and coat tint k_s `specular`.
    pub fn new(distribution: &str, alpha: f32, eta: f32, diffuse: Rgb, specular: Rgb, nonlinear: bool) -> Option<Self> {
        let dist = Distribution::named(distribution, alpha, alpha)?;
        let beckmann = distribution == "beckmann";
        // Mitsuba's own floor on α.
        let alpha = alpha.max(1e-4);
        let CoatTables { t: transmittance, f_int: internal_reflectance } =
            cached_coat_tables(&dist, beckmann, alpha, eta);
        let base = base_factor(diffuse, internal_reflectance, nonlinear, eta);
        Some(RoughPlastic {
            dist,
            beckmann,
            alpha,
            eta,
            specular,
            base,
            transmittance,
            internal_reflectance,
            weight: sampling_weight(specular, diffuse),
        })
    }

    /// The base's albedo bound ρ̂ π 2∫t(μ)μ dμ, the integral of the interpolated table by
    /// Simpson's rule on each linear piece (t μ is quadratic there). Computed where a check
    /// asks, not at each build: a textured base rebuilds the model at every hit, and this
    /// integral had been 56 % of such a render.
    fn energy_bound(&self) -> f32 {
        let n = (TABLE_SIZE - 1) as f64;
        let mut t_bar = 0.0f64;
        for k in 0..TABLE_SIZE - 1 {
            let (m0, m1) = (k as f64 / n, (k + 1) as f64 / n);
            let f = |mu: f64| lerp_table(&self.transmittance, mu as f32) as f64 * mu;
            t_bar += (m1 - m0) / 6.0 * (f(m0) + 4.0 * f(0.5 * (m0 + m1)) + f(m1));
        }
        (self.base.max_channel() as f64 * std::f64::consts::PI * 2.0 * t_bar) as f32
    }

    /// The coat's transmittance t(μ) (interpolated table).
    pub fn transmittance(&self, mu: f32) -> f32 {
        lerp_table(&self.transmittance, mu)
    }

    /// The coat's cosine-weighted internal reflectance F_int.
    pub fn internal_reflectance(&self) -> f32 {
        self.internal_reflectance
    }

    /// The coat lobe alone, k_s F D G / (4 cos θi cos θo), for h = (wi + wo)/|wi + wo| with
    /// h.z > 0 and d = D(h).
    #[inline]
    fn coat(&self, wi: Vec3, wo: Vec3, h: Vec3, d: f32) -> Rgb {
        // Symmetric in wi and wo so that ρ is exactly reciprocal in f32.
        let cos_d = 0.5 * (wi.dot(h) + wo.dot(h));
        let g = smith_g1(self.beckmann, self.alpha, wi, h) * smith_g1(self.beckmann, self.alpha, wo, h);
        let denom = 4.0 * (wi.z * wo.z);
        if g <= 0.0 || denom <= 0.0 {
            return Rgb::ZERO;
        }
        let v = fresnel::dielectric(cos_d, self.eta) * d * g / denom;
        if v.is_finite() {
            self.specular * v
        } else {
            Rgb::ZERO
        }
    }

    /// ρ given h, D(h) (when h.z > 0) and t(cos θo).
    #[inline]
    fn rho(&self, wi: Vec3, wo: Vec3, hd: Option<(Vec3, f32)>, t_o: f32) -> Rgb {
        let coat = hd.map_or(Rgb::ZERO, |(h, d)| self.coat(wi, wo, h, d));
        coat + self.base * (self.transmittance(wi.z) * t_o)
    }

    /// The sampling density given h, D(h) (when h.z > 0) and t(cos θo).
    #[inline]
    fn density(&self, wi: Vec3, wo: Vec3, hd: Option<(Vec3, f32)>, t_o: f32) -> f32 {
        let p = coat_probability(self.weight, t_o);
        // Visible normals reflected about h: G1(wo) D(h) / (4 cos θo), with our sampler's exact G1.
        let coat = match hd {
            Some((h, d)) if wo.dot(h) > 0.0 => self.dist.g1(wo) * d / (4.0 * wo.z),
            _ => 0.0,
        };
        let v = p * coat + (1.0 - p) * cosine_hemisphere_pdf(wi.z);
        if v.is_finite() {
            v
        } else {
            0.0
        }
    }

    /// The half vector and D there, when h.z > 0.
    #[inline]
    fn half(&self, wi: Vec3, wo: Vec3) -> Option<(Vec3, f32)> {
        let h = (wi + wo).normalize_or_zero();
        (h.z > 0.0).then(|| (h, self.dist.d(h)))
    }
}

impl Brdf for RoughPlastic {
    fn fresnel(&self) -> Option<Fresnel> {
        Some(Fresnel::Dielectric { eta: self.eta })
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        self.rho(wi, wo, self.half(wi, wo), self.transmittance(wo.z))
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !same_upper_hemisphere(wi, wo) {
            return 0.0;
        }
        self.density(wi, wo, self.half(wi, wo), self.transmittance(wo.z))
    }

    /// Sharing h, D(h) and t(cos θo): bit for bit what each returns.
    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        if !same_upper_hemisphere(wi, wo) {
            return (Rgb::ZERO, 0.0);
        }
        let (hd, t_o) = (self.half(wi, wo), self.transmittance(wo.z));
        (self.rho(wi, wo, hd, t_o), self.density(wi, wo, hd, t_o))
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let p = coat_probability(self.weight, self.transmittance(wo.z));
        let wi = if uc < p {
            let h = self.dist.sample_visible(wo, u);
            if wo.dot(h) <= 0.0 {
                return None;
            }
            reflect(wo, h).normalize()
        } else {
            cosine_hemisphere(u)
        };
        sample_from_pdf(self, wi, wo)
    }

    fn claims(&self) -> Claims {
        coat_claims(self.specular, self.energy_bound())
    }
}

/// Mitsuba's `plastic`: a smooth dielectric coat (a delta lobe) over a diffuse base.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    eta: f32,
    specular: Rgb,
    base: Rgb,
    weight: f32,
}

impl Plastic {
    /// The model for relative index `eta`, base ρ_d `diffuse` and coat tint k_s `specular`.
    pub fn new(eta: f32, diffuse: Rgb, specular: Rgb, nonlinear: bool) -> Self {
        let f_dr = fresnel_diffuse_reflectance(1.0 / eta);
        let base = base_factor(diffuse, f_dr, nonlinear, eta);
        Plastic { eta, specular, base, weight: sampling_weight(specular, diffuse) }
    }

    /// The base's albedo bound ρ̂ π 2∫(1 − F(μ))μ dμ, by the midpoint rule (F is smooth; 4096
    /// steps are far below f32). Computed where a check asks, not at each build, which a
    /// textured base makes at every hit.
    fn energy_bound(&self) -> f32 {
        let n = 4096;
        let t_bar: f64 = (0..n)
            .map(|i| {
                let mu = (i as f64 + 0.5) / n as f64;
                (1.0 - fresnel::dielectric(mu as f32, self.eta) as f64) * mu
            })
            .sum::<f64>()
            * 2.0
            / n as f64;
        (self.base.max_channel() as f64 * std::f64::consts::PI * t_bar) as f32
    }

    /// Probability of drawing the delta lobe for viewer cosine `cos_o`.
    fn coat_probability(&self, cos_o: f32) -> f32 {
        coat_probability(self.weight, 1.0 - fresnel::dielectric(cos_o, self.eta))
    }
}

impl Brdf for Plastic {
    fn fresnel(&self) -> Option<Fresnel> {
        Some(Fresnel::Dielectric { eta: self.eta })
    }

    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if !same_upper_hemisphere(wi, wo) {
            return Rgb::ZERO;
        }
        let t = (1.0 - fresnel::dielectric(wi.z, self.eta)) * (1.0 - fresnel::dielectric(wo.z, self.eta));
        self.base * t
    }

    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if !same_upper_hemisphere(wi, wo) {
            return 0.0;
        }
        (1.0 - self.coat_probability(wo.z)) * cosine_hemisphere_pdf(wi.z)
    }

    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let p = self.coat_probability(wo.z);
        if uc < p {
            let weight = self.specular * (fresnel::dielectric(wo.z, self.eta) / p);
            return Some(BrdfSample { wi: reflect_z(wo), pdf: p, weight, delta: true, eta: 1.0 });
        }
        let wi = cosine_hemisphere(u);
        sample_from_pdf(self, wi, wo)
    }

    fn claims(&self) -> Claims {
        coat_claims(self.specular, self.energy_bound())
    }

    fn has_delta(&self) -> bool {
        true
    }
}

fn common_params() -> Vec<ParamSpec> {
    vec![
        ParamSpec::rgb("diffuse_reflectance", 0.0, 1.0, 0.5, "reflectance ρ_d of the diffuse base under the coat"),
        ParamSpec::rgb("specular_reflectance", 0.0, 1.0, 1.0, "tint k_s of the coat's reflection (1 is physical)"),
        crate::ior::param("int_ior", 1.49, "index of refraction of the coat (polypropylene 1.49)"),
        crate::ior::param("ext_ior", 1.000277, "index of refraction outside (air 1.000277)"),
        ParamSpec::boolean(
            "nonlinear",
            false,
            "base ρ_d/(1 − ρ_d F_int) (colour shift of inner bounces) instead of ρ_d/(1 − F_int)",
        ),
    ]
}

fn rough_params() -> Vec<ParamSpec> {
    let mut v = vec![
        ParamSpec::choice("distribution", &["beckmann", "ggx"], "beckmann", "distribution of facet normals D"),
        ParamSpec::float("alpha", ALPHA_MIN, 1.0, 0.1, "roughness α of the coat").fixed(),
    ];
    v.extend(common_params());
    v
}

fn eta_of(p: &dyn ParamSource) -> Result<f32, ParamError> {
    let (int, ext) = (p.float("int_ior"), p.float("ext_ior"));
    if int == ext {
        return Err(ParamError::Inconsistent(format!(
            "int_ior and ext_ior are both {int}: the coat must differ from its surroundings"
        )));
    }
    Ok(int / ext)
}

fn make_rough(p: &dyn ParamSource) -> Result<RoughPlastic, ParamError> {
    let m = RoughPlastic::new(
        p.choice("distribution"),
        p.float("alpha"),
        eta_of(p)?,
        p.rgb("diffuse_reflectance"),
        p.rgb("specular_reflectance"),
        p.flag("nonlinear"),
    )
    .expect("distribution choice list matches Distribution::named");
    Ok(m)
}

fn make_smooth(p: &dyn ParamSource) -> Result<Plastic, ParamError> {
    Ok(Plastic::new(eta_of(p)?, p.rgb("diffuse_reflectance"), p.rgb("specular_reflectance"), p.flag("nonlinear")))
}

/// Registry entry for `roughplastic`.
pub const ROUGH_SPEC: ModelSpec = ModelSpec {
    name: "roughplastic",
    summary: "Mitsuba 3's rough plastic: a rough dielectric coat (Beckmann/GGX) over a diffuse base",
    reference: "Mitsuba 3 roughplastic; Walter et al. 2007; Kelemen & Szirmay-Kalos 2001",
    params: rough_params,
    build: by_value!(make_rough),
    showcase: &[
        &[
            ("distribution", "ggx"),
            ("alpha", "0.15"),
            ("int_ior", "1.5"),
            ("ext_ior", "1"),
            ("diffuse_reflectance", "0.7,0.25,0.08"),
        ],
        &[("alpha", "0.5"), ("diffuse_reflectance", "0.9"), ("nonlinear", "true")],
    ],
};

/// Registry entry for `plastic`.
pub const SMOOTH_SPEC: ModelSpec = ModelSpec {
    name: "plastic",
    summary: "Mitsuba 3's smooth plastic: a mirror-like dielectric coat (delta lobe) over a diffuse base",
    reference: "Mitsuba 3 plastic; Egan & Hilgeman 1979 and d'Eon & Irving 2011 for F_dr",
    params: common_params,
    build: by_value!(make_smooth),
    showcase: &[&[("int_ior", "1.5"), ("ext_ior", "1"), ("diffuse_reflectance", "0.9,0.5,0.1")]],
};

#[cfg(test)]
mod tests {
    use super::*;
    use radiometry::spherical_direction;

    fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
        spherical_direction(theta_deg.to_radians(), phi_deg.to_radians())
    }

    /// (θi, φi), (θo, φo) in degrees, wi towards the light, wo towards the viewer.
    const PAIRS: [((f32, f32), (f32, f32)); 6] = [
        ((10.0, 0.0), (20.0, 180.0)),
        ((45.0, 30.0), (45.0, 210.0)),
        ((60.0, 0.0), (30.0, 90.0)),
        ((80.0, 10.0), (5.0, 0.0)),
        ((0.0, 0.0), (0.0, 0.0)),
        ((89.0, 0.0), (70.0, 180.0)),
    ];

    /// ρ from Mitsuba 3.9.1 (`scalar_rgb`, `BSDF.eval` divided by cos θi, si.wi = our wo) at
    /// `PAIRS`, first channel; the parameter sets are those of the `build_with` calls below.
    type Args = &'static [(&'static str, &'static str)];
    const MITSUBA: [(Args, [f32; 6]); 4] = [
        (
            &[
                ("distribution", "ggx"),
                ("alpha", "0.15"),
                ("int_ior", "1.5"),
                ("ext_ior", "1"),
                ("diffuse_reflectance", "0.7,0.25,0.08"),
            ],
            [0.2761836, 0.5351761, 0.1795239, 0.1456268, 0.33143, 9.29031],
        ),
        (
            &[
                ("distribution", "beckmann"),
                ("alpha", "0.3"),
                ("int_ior", "1.5"),
                ("ext_ior", "1"),
                ("diffuse_reflectance", "0.5"),
            ],
            [0.174146, 0.2226511, 0.1302007, 0.1112055, 0.1739951, 7.97267],
        ),
        (
            &[("distribution", "ggx"), ("alpha", "0.5"), ("nonlinear", "true"), ("diffuse_reflectance", "0.9")],
            [0.165445, 0.167453, 0.1412383, 0.1179637, 0.1662455, 0.9129141],
        ),
        (
            &[("int_ior", "1.5"), ("ext_ior", "1"), ("diffuse_reflectance", "0.7,0.25,0.08")],
            [0.2262935, 0.2215567, 0.2144215, 0.144374, 0.2263599, 0.01950847],
        ),
    ];

    #[test]
    fn values_match_mitsuba() {
        for (i, (args, want)) in MITSUBA.iter().enumerate() {
            let spec = if i < 3 { &ROUGH_SPEC } else { &SMOOTH_SPEC };
            let m = spec.build_with(args).unwrap();
            // The smooth model is closed-form: f32 rounding only, which 1 − F near grazing
            // (1 − F(89°) ≈ 0.08) amplifies to ε/0.08 ≈ 10⁻⁶ per factor. The rough one integrates the
            // coat's transmittance; Mitsuba does so with 32×32 Gauss–Legendre nodes, which leaves
            // its t(μ) up to 4·10⁻⁴ above the converged value (ours converges to 10⁻⁶ from 48 to
            // 256 nodes), so t_i t_o, and the base term, may differ by up to 10⁻³ relative.
            let tol = if i < 3 { 1e-3 } else { 1e-5 };
            for (&((a, b), (c, d)), &w) in PAIRS.iter().zip(want) {
                let got = m.eval(dir(a, b), dir(c, d)).0[0];
                assert!(
                    (got - w).abs() <= tol * w,
                    "{} {args:?} at {a},{b} / {c},{d}: {got} vs Mitsuba {w}",
                    spec.name
                );
            }
        }
    }

    #[test]
    fn shared_terms_give_bit_identical_results() {
        // eval_pdf and sample share h, D(h) and t(cos θo) with eval and pdf: not a bit may change,
        // and a sample is the generic completion from the model's own pdf and eval.
        let mut state = 7u64;
        let mut next = || {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((state >> 40) as f32) / (1u64 << 24) as f32
        };
        for (dist, alpha) in [("ggx", 0.15f32), ("beckmann", 0.3)] {
            let m = RoughPlastic::new(dist, alpha, 1.5, Rgb::new(0.7, 0.25, 0.08), Rgb::ONE, false).unwrap();
            for _ in 0..20_000 {
                let mut w = || {
                    spherical_direction((next() * 2.0 - 0.2).clamp(-1.0, 1.0).acos(), next() * std::f32::consts::TAU)
                };
                let (wi, wo) = (w(), w());
                assert_eq!(m.eval_pdf(wi, wo), (m.eval(wi, wo), m.pdf(wi, wo)), "{wi} {wo}");
                let (uc, u) = (next(), Vec2::new(next(), next()));
                if let Some(s) = m.sample(wo, uc, u) {
                    assert_eq!(Some(s), sample_from_pdf(&m, s.wi, wo));
                }
            }
        }
    }

    #[test]
    fn smooth_coat_limit_reflects_the_normal_incidence_fresnel_term() {
        // ρ_d = 0 and α = 0.001: the albedo seen head-on is the coat's, F(0) = ((η−1)/(η+1))²,
        // up to the variation of F over a lobe of width α (F is flat to O(θ²) there).
        // Monte Carlo over the sampler: the weights' own spread gives the 4σ bound.
        let m = RoughPlastic::new("ggx", 0.001, 1.5, Rgb::ZERO, Rgb::ONE, false).unwrap();
        let f0 = (0.5f64 / 2.5).powi(2);
        let n = 20_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        let mut rng = 12345u64;
        let mut next = || {
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((rng >> 40) as f32) / (1u64 << 24) as f32
        };
        for _ in 0..n {
            let w = m.sample(Vec3::Z, next(), Vec2::new(next(), next())).map_or(0.0, |s| s.weight.0[0] as f64);
            s += w;
            s2 += w * w;
        }
        let mean = s / n as f64;
        let sigma = ((s2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
        assert!((mean - f0).abs() <= 4.0 * sigma + 1e-4, "albedo {mean} vs F(0) = {f0} (σ = {sigma:.1e})");
        // And the smooth model's delta lobe carries exactly F(0) head-on.
        let p = Plastic::new(1.5, Rgb::ZERO, Rgb::ONE, false);
        let d = p.sample(Vec3::Z, 0.0, Vec2::ZERO).unwrap();
        assert!(d.delta && (d.weight.0[0] * d.pdf - f0 as f32).abs() < 1e-6, "{d:?}");
    }

    #[test]
    fn smooth_base_albedo_is_rho_d_times_the_coat_transmittance() {
        // Specular off: albedo(wo) = ρ_d (1 − F(θo)) · 2∫(1 − F(μ))μ dμ / (η² (1 − F_dr)). By the
        // reciprocity of Fresnel transmission, 2∫(1 − F(μ; η))μ dμ = η² (1 − F̄_int) exactly, so
        // the albedo is ρ_d (1 − F(θo)) (1 − F̄_int)/(1 − F_dr): ρ_d (1 − F(θo)) up to the error of
        // the F_dr fit (Egan & Hilgeman: 0.1 % of F_dr for η ≤ 1.5), i.e. 10⁻³ F_dr/(1 − F_dr).
        let eta = 1.5f32;
        let rho_d = 0.8f32;
        let m = Plastic::new(eta, Rgb::splat(rho_d), Rgb::ZERO, false);
        let f_dr = fresnel_diffuse_reflectance(1.0 / eta) as f64;
        let tol = 1e-3 * f_dr / (1.0 - f_dr) + 1e-5;
        for theta in [0.0f32, 30.0, 60.0, 85.0] {
            let wo = dir(theta, 40.0);
            let a = radiometry::integrate::irradiance_quadrature(|w| m.eval(w.as_vec3(), wo).0[0] as f64, 1024, 16);
            let want = rho_d as f64 * (1.0 - fresnel::dielectric(wo.z, eta) as f64);
            assert!((a / want - 1.0).abs() <= tol, "θo = {theta}: albedo {a} vs {want} (tolerance {tol:.1e})");
        }
    }

    #[test]
    fn rough_tables_tend_to_the_smooth_fresnel_terms() {
        // As α → 0 the visible normals collapse onto +z: t(μ) → 1 − F(μ), and F_int → Mitsuba's
        // 64-point mean of the smooth internal reflectance.
        let eta = 1.5f32;
        let m = RoughPlastic::new("beckmann", 0.001, eta, Rgb::ONE, Rgb::ONE, false).unwrap();
        for k in [8usize, 32, 63] {
            let mu = k as f32 / 63.0;
            let want = 1.0 - fresnel::dielectric(mu, eta);
            assert!((m.transmittance(mu) - want).abs() < 2e-3, "t({mu}) = {} vs {want}", m.transmittance(mu));
        }
        let mean: f32 = (0..TABLE_SIZE)
            .map(|k| (k as f32 / 63.0).max(1e-6))
            .map(|mu| fresnel::dielectric(mu, 1.0 / eta) * mu)
            .sum::<f32>()
            * 2.0
            / TABLE_SIZE as f32;
        assert!((m.internal_reflectance() - mean).abs() < 2e-3, "{} vs {mean}", m.internal_reflectance());
    }

    #[test]
    fn extreme_inputs_stay_finite() {
        let models: Vec<Box<dyn Brdf>> = vec![
            Box::new(RoughPlastic::new("ggx", 0.001, 1.5, Rgb::ONE, Rgb::ONE, true).unwrap()),
            Box::new(RoughPlastic::new("beckmann", 1.0, 10.0, Rgb::ONE, Rgb::ONE, false).unwrap()),
            Box::new(RoughPlastic::new("ggx", 0.3, 1.0 / 1.5, Rgb::ZERO, Rgb::ZERO, false).unwrap()),
            Box::new(Plastic::new(1.5, Rgb::ONE, Rgb::ONE, true)),
            Box::new(Plastic::new(10.0, Rgb::ZERO, Rgb::ZERO, false)),
        ];
        let dirs =
            [Vec3::Z, Vec3::new(1.0, 0.0, 1e-7).normalize(), Vec3::new(0.0, 0.6, 0.8), Vec3::new(0.6, 0.0, 1e-30)];
        for m in &models {
            for &wo in &dirs {
                for &wi in &dirs {
                    assert!(m.eval(wi, wo).is_finite() && m.pdf(wi, wo).is_finite(), "{m:?} {wi} {wo}");
                }
                for uc in [0.0f32, 0.5, 0.999_999_9] {
                    for u in [Vec2::ZERO, Vec2::splat(0.999_999_9), Vec2::new(0.5, 1e-7)] {
                        if let Some(s) = m.sample(wo, uc, u) {
                            assert!(s.weight.is_finite() && s.pdf > 0.0 && s.pdf.is_finite(), "{m:?} {wo}: {s:?}");
                        }
                    }
                }
            }
        }
    }
}
