//! Pieces shared by `principled` and `principledthin` (Mitsuba 3.9.1's principled BSDFs), each
//! written as Mitsuba evaluates it, in f32.
//!
//! - Dielectric Fresnel with Mitsuba's special cases: F = 0 when η = 1, F = 1 at c = 0; it also
//!   returns the refracted cosine and the relative indices seen from the side of c.
//! - schlick_weight(x) = clamp(1 − x, 0, 1)⁵, R0(η) = ((η − 1)/(η + 1))², and
//!   calc_schlick(R0, c, η) = R0 + (1 − R0)·w with w = schlick_weight(|c|) when light meets the
//!   denser medium (η_it > 1), else schlick_weight(cos θt).
//! - α from roughness r and anisotropic a: aspect = √(1 − 0.9 a), α_x = max(0.001, r²/aspect),
//!   α_y = max(0.001, r²·aspect) (a = 0 gives α_x = α_y = max(0.001, r²)).
//! - GGX with separable Smith masking G = G1(a, m) G1(b, m), G1(v, m) = 2/(1 + √(1 + α(v)² tan²θv))
//!   and zero unless (v·m) v_z > 0; D cut to zero unless D m_z > 1e-20; the visible-normal density
//!   D(m) G1(v, m) |v·m| / v_z. D, Λ and the visible-normal sampler are gonio's `Ggx`, which has
//!   the same density as Mitsuba's warp (the directions drawn for given numbers differ).
//! - The "macro/micro compatibility" test: both directions on the side of m that the first one's
//!   hemisphere picks (reflection), or the second on the opposite side (refraction).
//! - The Disney diffuse shape (Burley 2012) in Mitsuba's split form: with F_a, F_b the Schlick
//!   weights of the two cosines, cd the cosine between the half vector and a direction and
//!   R_r = 2 r cd², f_diff = (1 − F_a/2)(1 − F_b/2), f_retro = R_r (F_a + F_b + F_a F_b (R_r − 1)),
//!   and with flatness the Hanrahan-Krueger-like f_ss = 1.25 (F_ss (1/(|c_a| + |c_b|) − 0.5) + 0.5),
//!   F_ss = lerp(1, R_r/2, F_a) lerp(1, R_r/2, F_b), blended as lerp(f_diff + f_retro, f_ss, flatness).
//!
//! Sources: Mitsuba 3, `src/bsdfs/principledhelpers.h`, `include/mitsuba/render/fresnel.h` and
//! `microfacet.h` (behaviour, read for the conventions); B. Burley, "Physically Based Shading at
//! Disney", SIGGRAPH 2012 course notes; B. Burley, "Extending the Disney BRDF to a BSDF with
//! Integrated Subsurface Scattering", SIGGRAPH 2015 course notes.

use crate::microfacet::{Ggx, Ndf};
use crate::params::ParamSource;
use radiometry::{Rgb, Vec2, Vec3};

/// Mitsuba's "has" flag of a parameter: given, and not 0 (a 0 reads as the parameter absent).
pub(crate) fn has(p: &dyn ParamSource, name: &'static str) -> bool {
    p.was_given(name) && p.float(name) != 0.0
}

/// a(1 − t) + b t.
#[inline]
pub(crate) fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a * (1.0 - t) + b * t
}

/// Per channel a(1 − t) + b t.
#[inline]
pub(crate) fn lerp_rgb(a: Rgb, b: Rgb, t: f32) -> Rgb {
    a * (1.0 - t) + b * t
}

/// Luminance with Mitsuba's RGB weights (they differ from `Rgb::luminance` in the 4th digit).
#[inline]
pub(crate) fn luminance(c: Rgb) -> f32 {
    0.212_671 * c.0[0] + 0.715_160 * c.0[1] + 0.072_169 * c.0[2]
}

/// The tint colour C / lum(C), white where the luminance is not positive.
#[inline]
pub(crate) fn tint(c: Rgb) -> Rgb {
    let lum = luminance(c);
    if lum > 0.0 {
        c * (1.0 / lum)
    } else {
        Rgb::ONE
    }
}

/// clamp(1 − x, 0, 1)⁵.
#[inline]
pub(crate) fn schlick_weight(x: f32) -> f32 {
    let m = (1.0 - x).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// ((η − 1)/(η + 1))².
#[inline]
pub(crate) fn schlick_r0(eta: f32) -> f32 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// Schlick's Fresnel from `r0` at facet cosine `c`: R0 + (1 − R0)·w, where the weight uses |c|
/// when the far side is denser and the refracted cosine otherwise (so it reaches 1 under total
/// internal reflection).
#[inline]
pub(crate) fn calc_schlick(r0: Rgb, c: f32, eta: f32) -> Rgb {
    let eta_it = if c >= 0.0 { eta } else { 1.0 / eta };
    let eta_ti = 1.0 / eta_it;
    let cos_t = (1.0 - (1.0 - c * c) * eta_ti * eta_ti).max(0.0).sqrt();
    let w = if eta_it > 1.0 { schlick_weight(c.abs()) } else { schlick_weight(cos_t) };
    r0 + (Rgb::ONE - r0) * w
}

/// The dielectric Fresnel term at one facet cosine, with what refraction through it needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Fresnel {
    /// Unpolarised reflectance.
    pub f: f32,
    /// Cosine of the refracted direction, on the far side (sign opposite to c).
    pub cos_t: f32,
    /// Index of the far side over that of c's side.
    pub eta_it: f32,
    /// Its reciprocal.
    pub eta_ti: f32,
}

/// Exact dielectric Fresnel at cosine `c` for relative index `eta` (below over above; c < 0
/// means the light is below). Total internal reflection gives F = 1 through cos θt = 0.
#[inline]
pub(crate) fn fresnel(c: f32, eta: f32) -> Fresnel {
    let (eta_it, eta_ti) = if c >= 0.0 { (eta, 1.0 / eta) } else { (1.0 / eta, eta) };
    let cos2_t = 1.0 - (1.0 - c * c) * (eta_ti * eta_ti);
    let ct = cos2_t.max(0.0).sqrt();
    let ci = c.abs();
    let f = if eta == 1.0 {
        0.0
    } else if ci == 0.0 {
        1.0
    } else {
        let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
        let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
        0.5 * (a_s * a_s + a_p * a_p)
    };
    Fresnel { f, cos_t: if c >= 0.0 { -ct } else { ct }, eta_it, eta_ti }
}

/// (α_x, α_y) from roughness and anisotropy: α = roughness², stretched by √(1 − 0.9 a) along
/// the tangent and squeezed along the bitangent, never below 0.001.
#[inline]
pub(crate) fn alphas(roughness: f32, anisotropic: f32) -> (f32, f32) {
    let r2 = roughness * roughness;
    let aspect = (1.0 - 0.9 * anisotropic).sqrt();
    ((r2 / aspect).max(0.001), (r2 * aspect).max(0.001))
}

/// True when `a` and `b` see facet `m` from the sides the macro-surface allows: for a
/// reflection both on the side of m that sign(c) picks, for a refraction `b` on the other.
#[inline]
pub(crate) fn compatible(m: Vec3, a: Vec3, b: Vec3, c: f32, reflection: bool) -> bool {
    let sm = if c >= 0.0 { m } else { -m };
    a.dot(sm) > 0.0 && if reflection { b.dot(sm) > 0.0 } else { b.dot(-sm) > 0.0 }
}

/// GGX as Mitsuba's `MicrofacetDistribution(GGX, α_x, α_y)` with separable Smith masking.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SmithGgx {
    /// gonio's distribution: D, Λ and the visible-normal sampler.
    pub ggx: Ggx,
}

impl SmithGgx {
    /// The distribution with roughnesses (α_x, α_y) (floored at 1e-4 by `Ggx`).
    pub fn new(alpha_x: f32, alpha_y: f32) -> Self {
        SmithGgx { ggx: Ggx::new(alpha_x, alpha_y) }
    }

    /// D(m), zero unless D m_z > 1e-20.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        let d = self.ggx.d(m);
        if d * m.z > 1e-20 {
            d
        } else {
            0.0
        }
    }

    /// G1(v, m): zero unless v sees m from its own side of the macro-surface.
    #[inline]
    pub fn g1(&self, v: Vec3, m: Vec3) -> f32 {
        if v.dot(m) * v.z <= 0.0 {
            return 0.0;
        }
        // Λ depends on v_z² only; gonio's wants the upper copy.
        self.ggx.g1(Vec3::new(v.x, v.y, v.z.abs()))
    }

    /// Separable shadowing-masking G1(a, m) G1(b, m).
    #[inline]
    pub fn g(&self, a: Vec3, b: Vec3, m: Vec3) -> f32 {
        self.g1(a, m) * self.g1(b, m)
    }

    /// Density of `sample` seen from `v` (v_z > 0): D(m) G1(v, m) |v·m| / v_z.
    #[inline]
    pub fn pdf(&self, v: Vec3, m: Vec3) -> f32 {
        if v.z <= 0.0 {
            return 0.0;
        }
        self.d(m) * self.g1(v, m) * v.dot(m).abs() / v.z
    }

    /// A facet normal visible from `v` (v_z > 0).
    #[inline]
    pub fn sample(&self, v: Vec3, u: Vec2) -> Vec3 {
        self.ggx.sample_visible(v, u)
    }

    /// True when α_x = α_y.
    pub fn is_isotropic(&self) -> bool {
        self.ggx.is_isotropic()
    }
}

/// The Disney diffuse shape (without C/π): retro-reflection from `roughness` and `cd`, Schlick
/// weights of the cosines `ca`, `cb`, and with `flatness` the fake-subsurface blend.
#[inline]
pub(crate) fn diffuse_shape(roughness: f32, cd: f32, ca: f32, cb: f32, flatness: Option<f32>) -> f32 {
    let (fa, fb) = (schlick_weight(ca.abs()), schlick_weight(cb.abs()));
    let f_diff = (1.0 - 0.5 * fa) * (1.0 - 0.5 * fb);
    let rr = 2.0 * roughness * cd * cd;
    let f_retro = rr * (fa + fb + fa * fb * (rr - 1.0));
    match flatness {
        Some(t) => {
            let fss90 = 0.5 * rr;
            let fss = lerp(1.0, fss90, fa) * lerp(1.0, fss90, fb);
            let f_ss = 1.25 * (fss * (1.0 / (ca.abs() + cb.abs()) - 0.5) + 0.5);
            lerp(f_diff + f_retro, f_ss, t)
        }
        None => f_diff + f_retro,
    }
}

/// Picks lobe `k` from `probs` (normalised weights in order) with `uc` ∈ [0, 1): the first whose
/// cumulative interval holds `uc`; `None` past the last (rounding at the top end).
#[inline]
pub(crate) fn pick(probs: &[f32], uc: f32) -> Option<usize> {
    let mut cum = 0.0;
    for (k, &p) in probs.iter().enumerate() {
        cum += p;
        if uc < cum {
            return Some(k);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_special_cases_and_closed_forms() {
        // Normal incidence: R0; index matched: 0; grazing: 1; total internal reflection: 1.
        assert!((fresnel(1.0, 1.5).f - 0.04).abs() < 1e-7);
        assert!((fresnel(-1.0, 1.5).f - 0.04).abs() < 1e-7);
        assert_eq!(fresnel(0.3, 1.0).f, 0.0);
        assert_eq!(fresnel(0.0, 1.5).f, 1.0);
        let tir = fresnel(-0.5, 1.5);
        assert_eq!((tir.f, tir.cos_t), (1.0, 0.0));
        // Against gonio's own exact dielectric Fresnel.
        for c in [0.05f32, 0.3, 0.7, 0.99, -0.8, -0.95] {
            let f = fresnel(c, 1.33);
            assert!((f.f - crate::fresnel::dielectric(c, 1.33)).abs() < 1e-6, "{c}");
            // Snell: sin²θt = sin²θi / η_it².
            assert!(((1.0 - f.cos_t * f.cos_t) - (1.0 - c * c) * f.eta_ti * f.eta_ti).abs() < 1e-6);
            assert!(f.cos_t * c <= 0.0);
        }
    }

    #[test]
    fn schlick_pieces() {
        assert_eq!(schlick_weight(1.0), 0.0);
        assert_eq!(schlick_weight(-1.0), 1.0);
        assert!((schlick_weight(0.5) - 0.03125).abs() < 1e-9);
        assert!((schlick_r0(1.5) - 0.04).abs() < 1e-7);
        // From the denser side beyond the critical angle the weight is 1: F = 1.
        assert_eq!(calc_schlick(Rgb::splat(0.04), -0.3, 1.5), Rgb::ONE);
        assert!((calc_schlick(Rgb::splat(0.04), 1.0, 1.5).0[0] - 0.04).abs() < 1e-7);
    }

    #[test]
    fn alphas_match_the_notes() {
        let (ax, ay) = alphas(0.3, 0.5);
        assert!((ax - 0.121_355_97).abs() < 1e-7 && (ay - 0.066_745_795).abs() < 1e-7, "{ax} {ay}");
        assert_eq!(alphas(0.5, 0.0), (0.25, 0.25));
        assert_eq!(alphas(0.0, 0.0), (0.001, 0.001));
    }

    #[test]
    fn visible_normal_density_integrates_to_one() {
        let g = SmithGgx::new(0.3, 0.1);
        for v in [Vec3::Z, radiometry::spherical_direction(1.1, 0.4)] {
            let i = radiometry::integrate::hemisphere_integral(|m| g.pdf(v, m.as_vec3()) as f64, 1500, 96);
            assert!((i - 1.0).abs() < 2e-3, "{v}: {i}");
        }
    }

    #[test]
    fn pick_follows_cumulative_intervals() {
        let p = [0.25, 0.0, 0.5, 0.25];
        assert_eq!(pick(&p, 0.0), Some(0));
        assert_eq!(pick(&p, 0.25), Some(2));
        assert_eq!(pick(&p, 0.8), Some(3));
        assert_eq!(pick(&[0.5, 0.5 - 1e-7], 0.999_999_9), None);
    }
}
