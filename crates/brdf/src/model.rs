//! The `Brdf` trait every scattering model implements, in a z-up local frame.
//!
//! Most models only reflect: both directions above the surface (z > 0). A model may also
//! scatter on its back side (`back_side`: a two-sided wrapper, a dielectric) or transmit
//! (`transmits`: `wi` and `wo` on opposite sides, e.g. refraction into glass). For those,
//! "cos θ" in `eval`'s and `sample`'s conventions is |w.z|, and a sample across the surface
//! carries the relative index η = n(wi side) / n(wo side) it crossed, since radiance scales
//! by 1/η² across an interface (Veach 1997, §5.2): ρ(wi, wo) / n_wo² = ρ(wo, wi) / n_wi²
//! replaces Helmholtz reciprocity, and a path tracer undoes the scaling (multiplies by η²)
//! before it judges a path's weight for Russian roulette, as Mitsuba 3 does.

use radiometry::{Rgb, Vec2, Vec3};

/// One importance sample of an incident direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrdfSample {
    /// The sampled incident direction (towards the light), local frame.
    pub wi: Vec3,
    /// Its density in solid angle; for a delta lobe, the probability of choosing that lobe.
    pub pdf: f32,
    /// ρ(wi, wo) · |cos θi| / pdf.
    pub weight: Rgb,
    /// True when `wi` came from a delta (perfectly specular) lobe.
    pub delta: bool,
    /// Relative index n(wi side) / n(wo side) crossed: 1 for a reflection.
    pub eta: f32,
}

impl BrdfSample {
    /// A reflected sample (η = 1).
    #[inline]
    pub fn reflected(wi: Vec3, pdf: f32, weight: Rgb, delta: bool) -> Self {
        BrdfSample { wi, pdf, weight, delta, eta: 1.0 }
    }
}

/// The properties a model claims for its current parameters; `check` measures them all
/// and fails only on claimed ones.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Claims {
    /// Helmholtz reciprocity ρ(wi, wo) = ρ(wo, wi).
    pub reciprocal: bool,
    /// Directional albedo ∫ ρ cos θi dωi ≤ 1 for every wo.
    pub energy_conserving: bool,
    /// Invariance under a common rotation of wi and wo about the normal.
    pub isotropic: bool,
}

impl Claims {
    /// A physically plausible isotropic model: reciprocal, energy conserving, isotropic.
    pub const PLAUSIBLE: Claims = Claims { reciprocal: true, energy_conserving: true, isotropic: true };
}

/// A scattering model (the name stays `Brdf`: most models only reflect). `wi` points towards
/// the light, `wo` towards the viewer; both point away from the surface and are unit vectors
/// in the local frame (normal = +z). See the module doc for models that transmit.
pub trait Brdf: Send + Sync + std::fmt::Debug {
    /// ρ(wi, wo) in 1/sr, without the cosine; zero for delta lobes. A reflection-only model
    /// returns zero when either direction is below the surface; one that `transmits` may
    /// return non-zero for directions on opposite sides, one with a `back_side` for both below.
    fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb;

    /// Solid-angle density with which `sample(wo, ..)` returns `wi` (delta lobes excluded).
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32;

    /// `eval` and `pdf` together, bit for bit what each returns; models whose two share
    /// work (half vector, D, Fresnel) override it, since a renderer's light sample needs both.
    #[inline]
    fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
        (self.eval(wi, wo), self.pdf(wi, wo))
    }

    /// Draws `wi` for a given `wo`: `uc` picks a lobe, `u` places the direction.
    /// `None` when no direction can be produced (e.g. `wo` below the surface).
    fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample>;

    /// The properties this model, with these parameters, claims.
    fn claims(&self) -> Claims;

    /// True when the model has a delta lobe (an ideal mirror component).
    fn has_delta(&self) -> bool {
        false
    }

    /// True when every lobe is a delta: `eval` is zero for every pair of directions, so a
    /// renderer's light samples can add nothing here and need not be drawn.
    fn delta_only(&self) -> bool {
        false
    }

    /// True when light may cross the surface: `wi` and `wo` on opposite sides.
    fn transmits(&self) -> bool {
        false
    }

    /// True when the model scatters light arriving on its back side too (`wo.z < 0`); a
    /// renderer may skip a one-sided model's back faces.
    fn back_side(&self) -> bool {
        self.transmits()
    }

    /// Index of the medium below the surface over the one above, n(z < 0) / n(z > 0); 1 for
    /// a model that does not transmit.
    fn eta(&self) -> f32 {
        1.0
    }

    /// The Fresnel term of the model's specular interface, for models that have one (plots
    /// of Rs, Rp and Schlick against the exact term use it).
    fn fresnel(&self) -> Option<crate::fresnel::Fresnel> {
        None
    }

    /// The lecture's Phong coefficients, for models that are written in them (the `phong`
    /// integrator uses ρ·cos θ for the others).
    fn phong_terms(&self) -> Option<PhongTerms> {
        None
    }

    /// The albedo when this is Lambert's model (ρ = albedo/π), so that an integrator may shade
    /// it many points at a time.
    fn lambertian(&self) -> Option<Rgb> {
        None
    }
}

/// A model of any kind, owned.
pub type BoxedBrdf = Box<dyn Brdf>;

/// Forwards every method to the pointee: a model behind a `Box`, an `Arc` or a reference is
/// the same model.
macro_rules! forward_brdf {
    ($($ptr:ty),*) => {$(
        impl<T: Brdf + ?Sized> Brdf for $ptr {
            #[inline]
            fn eval(&self, wi: Vec3, wo: Vec3) -> Rgb {
                (**self).eval(wi, wo)
            }
            #[inline]
            fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
                (**self).pdf(wi, wo)
            }
            #[inline]
            fn eval_pdf(&self, wi: Vec3, wo: Vec3) -> (Rgb, f32) {
                (**self).eval_pdf(wi, wo)
            }
            #[inline]
            fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<BrdfSample> {
                (**self).sample(wo, uc, u)
            }
            fn claims(&self) -> Claims {
                (**self).claims()
            }
            fn has_delta(&self) -> bool {
                (**self).has_delta()
            }
            fn delta_only(&self) -> bool {
                (**self).delta_only()
            }
            fn transmits(&self) -> bool {
                (**self).transmits()
            }
            fn back_side(&self) -> bool {
                (**self).back_side()
            }
            fn eta(&self) -> f32 {
                (**self).eta()
            }
            fn fresnel(&self) -> Option<crate::fresnel::Fresnel> {
                (**self).fresnel()
            }
            fn phong_terms(&self) -> Option<PhongTerms> {
                (**self).phong_terms()
            }
            fn lambertian(&self) -> Option<Rgb> {
                (**self).lambertian()
            }
        }
    )*};
}

forward_brdf!(Box<T>, std::sync::Arc<T>, &T);

/// The lecture's Phong illumination coefficients, L = k_a L_a + Σ L_l [k_d (I·N) + k_s (R·V)^k_e],
/// of a model that has them (Lambert, Phong, Blinn-Phong and those with a diffuse lobe).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhongTerms {
    /// Ambient reflectance k_a (unitless): the diffuse albedo, exact for an unshadowed Lambert
    /// surface under constant light.
    pub ka: Rgb,
    /// Diffuse coefficient k_d, 1/sr (albedo/π).
    pub kd: Rgb,
    /// Specular coefficient k_s, 1/sr.
    pub ks: Rgb,
    /// Specular exponent k_e.
    pub ke: f32,
    /// Blinn's half-vector form, (N·H)^k_e, instead of (R·V)^k_e.
    pub half_vector: bool,
}

impl PhongTerms {
    /// The terms of a Lambert surface of albedo `a`: k_a = a, k_d = a/π, no specular.
    pub fn diffuse(a: Rgb) -> Self {
        PhongTerms { ka: a, kd: a * std::f32::consts::FRAC_1_PI, ks: Rgb::ZERO, ke: 1.0, half_vector: false }
    }
}

/// Mirror reflection of `w` about the normal +z.
#[inline]
pub fn reflect_z(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

/// Mirror reflection of `w` about the unit vector `n`: 2(w·n)n − w.
#[inline]
pub fn reflect(w: Vec3, n: Vec3) -> Vec3 {
    2.0 * w.dot(n) * n - w
}

/// Refraction of the unit vector `w` through a surface of unit normal `n` (either side), η_t
/// the index of the far side over that of `w`'s side: −w/η_t + (c/η_t − sgn(c) cos θt) n with
/// c = w·n, cos²θt = 1 − (1 − c²)/η_t². None under total internal reflection.
#[inline]
pub fn refract(w: Vec3, n: Vec3, eta_t: f32) -> Option<Vec3> {
    let c = w.dot(n);
    let sin2_t = (1.0 - c * c).max(0.0) / (eta_t * eta_t);
    if sin2_t.is_nan() || sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some(-w / eta_t + (c / eta_t - cos_t.copysign(c)) * n)
}

/// True when both directions are strictly above the surface.
#[inline]
pub fn same_upper_hemisphere(wi: Vec3, wo: Vec3) -> bool {
    wi.z > 0.0 && wo.z > 0.0
}

/// Completes a sample of `wi`: the pdf and weight come from the model's own `eval_pdf`, so
/// that the three agree exactly. `None` when `wi` is below the surface or has no density.
pub fn sample_from_pdf(brdf: &impl Brdf, wi: Vec3, wo: Vec3) -> Option<BrdfSample> {
    if wi.z <= 0.0 {
        return None;
    }
    let (rho, pdf) = brdf.eval_pdf(wi, wo);
    if !(pdf > 0.0 && pdf.is_finite()) {
        return None;
    }
    let weight = rho * (wi.z / pdf);
    weight.is_finite().then_some(BrdfSample::reflected(wi, pdf, weight, false))
}

/// Completes a half-vector sample: reflects `wo` about the sampled facet normal `h` and takes
/// pdf and weight from the model (`sample_from_pdf`). `None` when `h` faces away from `wo`.
pub fn reflect_about_half_vector(brdf: &impl Brdf, wo: Vec3, h: Vec3) -> Option<BrdfSample> {
    let wo_h = wo.dot(h);
    if wo_h <= 0.0 {
        return None;
    }
    sample_from_pdf(brdf, (2.0 * wo_h * h - wo).normalize(), wo)
}
