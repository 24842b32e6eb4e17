//! Fresnel reflectance: the fraction of light a smooth interface reflects.
//!
//! Dielectric, relative index η = n_t / n_i, cos θi = c, cos θt = c_t from Snell's law
//! (sin²θt = (1 − c²)/η²; total internal reflection when that exceeds 1):
//!   R_s = ((c − η c_t) / (c + η c_t))²,  R_p = ((η c − c_t) / (η c + c_t))²,  F = (R_s + R_p)/2.
//! Conductor, complex relative index η + ik, with a² + b² = √((η² − k² − s²)² + 4η²k²),
//! a = √((a² + b² + η² − k² − s²)/2), s = sin θi:
//!   R_s = (a²+b² − 2ac + c²) / (a²+b² + 2ac + c²),
//!   R_p = R_s (c²(a²+b²) − 2acs² + s⁴) / (c²(a²+b²) + 2acs² + s⁴),  F = (R_s + R_p)/2,
//! exact for unpolarised light; at normal incidence F = ((η−1)² + k²) / ((η+1)² + k²).
//! Schlick's approximation: F ≈ R0 + (1 − R0)(1 − c)⁵, R0 = ((n − 1)/(n + 1))².
//! Sources: M. Born & E. Wolf, *Principles of Optics*, §1.5 and §14.2; C. Schlick, "An
//! Inexpensive BRDF Model for Physically-based Rendering", Computer Graphics Forum 13(3), 1994.
//!
//! Named conductors: Au, Cu and Al carry the RGB η/k that Mitsuba 3.9.1 uses for
//! `material=<name>` (copied from `shared/bench/scenes/materials.json`). Ag, absent there,
//! is reduced here from the luxpop.com spectral optical constants Mitsuba ships
//! (`data/ior/Ag.{eta,k}.spd`) by the same CIE 1931 → linear sRGB reduction; the test in
//! `fresnel/spectral.rs` shows that reduction reproduces Au, Cu and Al to 1e-6 (f32 rounding).

use crate::params::{ParamError, ParamSource, ParamSpec};
use glam::Vec3A;
use radiometry::Rgb;

mod metals;
#[cfg(test)]
mod spectral;

/// Reflectances of an interface for s- (perpendicular) and p- (parallel) polarised light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polarized {
    /// Perpendicular (s) reflectance.
    pub s: f32,
    /// Parallel (p) reflectance.
    pub p: f32,
}

impl Polarized {
    /// Reflectance of unpolarised light: the mean of s and p.
    #[inline]
    pub fn mean(self) -> f32 {
        0.5 * (self.s + self.p)
    }
}

/// Exact s/p reflectance of a dielectric interface with relative index `eta` = n_t/n_i.
/// A negative `cos_theta_i` means light arrives from the other (n_t) side: η is inverted.
/// Total internal reflection gives 1 for both.
pub fn dielectric_polarized(cos_theta_i: f32, eta: f32) -> Polarized {
    let (c, eta) = if cos_theta_i < 0.0 { (-cos_theta_i, 1.0 / eta) } else { (cos_theta_i, eta) };
    let c = c.min(1.0);
    let sin2_t = (1.0 - c * c).max(0.0) / (eta * eta);
    if sin2_t.is_nan() || sin2_t >= 1.0 {
        return Polarized { s: 1.0, p: 1.0 };
    }
    let ct = (1.0 - sin2_t).sqrt();
    let (ds, dp) = (c + eta * ct, eta * c + ct);
    // Both sums vanish only at grazing incidence into an index-matched medium; the limit there is 1.
    if ds <= 0.0 || dp <= 0.0 {
        return Polarized { s: 1.0, p: 1.0 };
    }
    let rs = (c - eta * ct) / ds;
    let rp = (eta * c - ct) / dp;
    Polarized { s: rs * rs, p: rp * rp }
}

/// Exact unpolarised reflectance of a dielectric interface (mean of s and p).
#[inline]
pub fn dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    dielectric_polarized(cos_theta_i, eta).mean()
}

/// Exact s/p reflectance of a conductor with complex relative index `eta` + i`k`
/// (only |cos θi| matters: light cannot arrive from inside a metal).
pub fn conductor_polarized(cos_theta_i: f32, eta: f32, k: f32) -> Polarized {
    // f64 here: a²+b² − 2ac + c² cancels badly in f32 for large k near normal incidence.
    let c = (cos_theta_i.abs().min(1.0)) as f64;
    let (eta, k) = (eta as f64, k as f64);
    let c2 = c * c;
    let s2 = 1.0 - c2;
    let t0 = eta * eta - k * k - s2;
    let a2b2 = (t0 * t0 + 4.0 * eta * eta * k * k).sqrt();
    let a = (0.5 * (a2b2 + t0)).max(0.0).sqrt();
    let ds = a2b2 + c2 + 2.0 * a * c;
    if ds <= 0.0 {
        return Polarized { s: 1.0, p: 1.0 };
    }
    let rs = (a2b2 + c2 - 2.0 * a * c) / ds;
    let (num_p, den_p) = (c2 * a2b2 + s2 * s2 - 2.0 * a * c * s2, c2 * a2b2 + s2 * s2 + 2.0 * a * c * s2);
    let rp = if den_p > 0.0 { rs * num_p / den_p } else { rs };
    Polarized { s: rs.clamp(0.0, 1.0) as f32, p: rp.clamp(0.0, 1.0) as f32 }
}

/// Exact unpolarised conductor reflectance (mean of s and p).
#[inline]
pub fn conductor(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    conductor_polarized(cos_theta_i, eta, k).mean()
}

/// Exact unpolarised conductor reflectance per RGB channel: `conductor` for the three channels
/// at once, in f32 lanes, equal to it within a few f32 roundings.
///
/// With (a + ib)² = η² − k² − s² + 2iηk, R_s = ((a − c)² + b²)/((a + c)² + b²) and
/// R_p/R_s = ((ac − s²)² + b²c²)/((ac + s²)² + b²c²), so F = N_s (D_p + N_p) / (2 D_s D_p): one
/// division. a² = (|n²| + t)/2 and b² = (|n²| − t)/2, t = η² − k² − s², each cancel on one side of
/// t = 0; since ab = ηk, only the stable one is taken square root of, r, and the other enters
/// through ηk/r, with both quotients scaled by r² (t ≥ 0, r = a) or b² (t < 0, r = b) to clear it.
#[inline]
pub fn conductor_rgb(cos_theta_i: f32, eta: Rgb, k: Rgb) -> Rgb {
    let c = cos_theta_i.abs().min(1.0);
    let s2 = (1.0 - c) * (1.0 + c);
    let (eta, k) = (Vec3A::from_array(eta.0), Vec3A::from_array(k.0));
    let (cv, s2v) = (Vec3A::splat(c), Vec3A::splat(s2));
    let ek = eta * k;
    let t = eta * eta - k * k - s2v;
    let n2 = sqrt3(t * t + 4.0 * ek * ek);
    let t_pos = t.cmpge(Vec3A::ZERO);
    let r = sqrt3(0.5 * Vec3A::select(t_pos, n2 + t, n2 - t));
    let rc = r * cv;
    let ekc = ek * cv;
    // t ≥ 0: r = a, b = ηk/r, everything times r². t < 0: r = b, a = ηk/r, everything times r².
    let (xs_m, xs_p, ys) = (
        Vec3A::select(t_pos, (r - cv) * r, ek - rc),
        Vec3A::select(t_pos, (r + cv) * r, ek + rc),
        Vec3A::select(t_pos, ek, r * r),
    );
    let (xp_m, xp_p, yp) = (
        Vec3A::select(t_pos, (rc - s2v) * r, ekc - s2v * r),
        Vec3A::select(t_pos, (rc + s2v) * r, ekc + s2v * r),
        Vec3A::select(t_pos, ekc, r * rc),
    );
    let (ys2, yp2) = (ys * ys, yp * yp);
    let (ns, ds) = (xs_m * xs_m + ys2, xs_p * xs_p + ys2);
    let (np, dp) = (xp_m * xp_m + yp2, xp_p * xp_p + yp2);
    let num = ns * (dp + np);
    let den = 2.0 * ds * dp;
    // den = 0 only for k = 0 and η = sin θi (a = b = 0), where R_s = R_p = 1.
    let f = Vec3A::select(den.cmpgt(Vec3A::ZERO), num / den, Vec3A::ONE);
    Rgb(f.clamp(Vec3A::ZERO, Vec3A::ONE).to_array())
}

/// Lane-wise square root.
#[inline]
fn sqrt3(v: Vec3A) -> Vec3A {
    Vec3A::from_array(v.to_array().map(f32::sqrt))
}

/// Normal-incidence reflectance of a dielectric of index `n` (against vacuum): ((n−1)/(n+1))².
#[inline]
pub fn schlick_r0(n: f32) -> f32 {
    let r = (n - 1.0) / (n + 1.0);
    r * r
}

/// Normal-incidence reflectance of a conductor: ((η−1)² + k²) / ((η+1)² + k²); k = 0 gives
/// the dielectric R0.
#[inline]
pub fn normal_reflectance(eta: f32, k: f32) -> f32 {
    let k2 = k * k;
    ((eta - 1.0) * (eta - 1.0) + k2) / ((eta + 1.0) * (eta + 1.0) + k2)
}

/// Schlick's approximation R0 + (1 − R0)(1 − |cos θ|)⁵.
#[inline]
pub fn schlick(cos_theta_i: f32, r0: f32) -> f32 {
    let m = (1.0 - cos_theta_i.abs().min(1.0)).max(0.0);
    let m2 = m * m;
    r0 + (1.0 - r0) * m2 * m2 * m
}

/// A named conductor's RGB optical constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metal {
    /// Its chemical symbol, as `material` takes it.
    pub name: &'static str,
    /// Real part of the relative index, per RGB channel.
    pub eta: Rgb,
    /// Extinction coefficient, per RGB channel.
    pub k: Rgb,
}

/// Gold (Mitsuba 3.9.1 `material=Au`).
#[allow(clippy::excessive_precision)] // the digits materials.json gives
pub const AU: Metal = Metal {
    name: "Au",
    eta: Rgb::new(0.14303597807884216, 0.3753070831298828, 1.4420453310012817),
    k: Rgb::new(3.982996940612793, 2.38555645942688, 1.6033592224121094),
};
/// Silver, reduced from luxpop.com spectral data (see the module doc and `fresnel/spectral.rs`).
pub const AG: Metal = Metal {
    name: "Ag",
    eta: Rgb::new(0.15527629, 0.11672802, 0.13838771),
    k: Rgb::new(4.828357, 3.1222239, 2.1469023),
};
/// Copper (Mitsuba 3.9.1 `material=Cu`).
#[allow(clippy::excessive_precision)] // the digits materials.json gives
pub const CU: Metal = Metal {
    name: "Cu",
    eta: Rgb::new(0.2010054737329483, 0.9237495064735413, 1.1022154092788696),
    k: Rgb::new(3.913262128829956, 2.453045129776001, 2.14208984375),
};
/// Aluminium (Mitsuba 3.9.1 `material=Al`).
#[allow(clippy::excessive_precision)] // the digits materials.json gives
pub const AL: Metal = Metal {
    name: "Al",
    eta: Rgb::new(1.6575008630752563, 0.8804047107696533, 0.521244466304779),
    k: Rgb::new(9.223811149597168, 6.26950216293335, 4.8370041847229),
};

/// Every named conductor.
pub const METALS: [Metal; 4] = [AU, AG, CU, AL];

/// The named conductor `name` (case-insensitive), if there is one: Au, Ag, Cu, Al, or any of
/// Mitsuba's other named conductors (`metals.rs`).
pub fn metal(name: &str) -> Option<Metal> {
    METALS.iter().chain(metals::MORE_METALS).copied().find(|m| m.name.eq_ignore_ascii_case(name))
}

/// A Fresnel term: how much of the light reaching a microfacet it reflects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Fresnel {
    /// F = 1: every facet is a perfect mirror.
    None,
    /// Schlick's approximation with per-channel normal reflectance `r0`.
    Schlick { r0: Rgb },
    /// Exact dielectric with relative index `eta`.
    Dielectric { eta: f32 },
    /// Exact conductor with complex index `eta` + i`k` per channel.
    Conductor { eta: Rgb, k: Rgb },
}

impl Fresnel {
    /// Reflectance at incidence cosine `cos_theta_i` (negative: from inside, dielectric only).
    #[inline]
    pub fn eval(&self, cos_theta_i: f32) -> Rgb {
        match *self {
            Fresnel::None => Rgb::ONE,
            Fresnel::Schlick { r0 } => r0.map(|r| schlick(cos_theta_i, r)),
            Fresnel::Dielectric { eta } => Rgb::splat(dielectric(cos_theta_i, eta)),
            Fresnel::Conductor { eta, k } => conductor_rgb(cos_theta_i, eta, k),
        }
    }

    /// The largest reflectance over all angles and channels: 1 for every term here, since each
    /// reaches 1 at grazing incidence; an upper bound for energy claims.
    pub fn max_reflectance(&self) -> f32 {
        1.0
    }
}

/// The `fresnel` modes, as the parameter lists them.
pub const MODES: &[&str] = &["none", "schlick", "dielectric", "conductor"];
/// The `material` choices: `custom` (use `eta` and `k`), `none` (a perfect reflector, F = 1,
/// Mitsuba's default conductor) and the named conductors.
pub use metals::MATERIALS;

/// Default `eta` when the default mode is not `conductor`: crown glass.
pub const DEFAULT_DIELECTRIC_ETA: f32 = 1.5;

/// The Fresnel parameters shared by every model that takes a Fresnel term, with
/// `default_mode` (one of [`MODES`]) as the default `fresnel`. With `conductor` as the
/// default, `eta` and `k` default to gold's values; otherwise to 1.5 and 0.
///
/// How they combine ([`from_params`]): `none` ignores the rest; `dielectric` uses the mean of
/// the three `eta` channels and ignores `k`; `schlick` uses R0 = ((η−1)² + k²)/((η+1)² + k²)
/// per channel (the dielectric ((n−1)/(n+1))² when k = 0); `conductor` uses `eta` and `k`
/// per channel. A named `material` implies a conductor and supplies η and k; `material=none`
/// is a perfect reflector (F = 1) unless `eta` or `k` is given with it left at its default.
pub fn params(default_mode: &str) -> Vec<ParamSpec> {
    assert!(MODES.contains(&default_mode), "unknown Fresnel mode '{default_mode}'");
    let (eta, k) =
        if default_mode == "conductor" { (AU.eta, AU.k) } else { (Rgb::splat(DEFAULT_DIELECTRIC_ETA), Rgb::ZERO) };
    let rgb = |c: Rgb| crate::params::Value::Rgb(c.0.map(|v| v as f64));
    vec![
        ParamSpec::choice("fresnel", MODES, default_mode, "Fresnel term: none (F=1), schlick, dielectric or conductor"),
        ParamSpec::rgb(
            "eta",
            0.01,
            10.0,
            0.0,
            "relative index of refraction η (dielectric: mean of the channels; schlick and conductor: per channel)",
        )
        .with_default(rgb(eta)),
        ParamSpec::rgb("k", 0.0, 20.0, 0.0, "extinction coefficient k of a conductor (ignored by dielectric)")
            .with_default(rgb(k)),
        ParamSpec::choice(
            "material",
            MATERIALS,
            "custom",
            "a named conductor (implies fresnel=conductor and sets eta, k); none: F = 1; custom uses eta and k",
        ),
    ]
}

/// Builds the Fresnel term from resolved [`params`].
pub fn from_params(p: &dyn ParamSource) -> Result<Fresnel, ParamError> {
    let mode = p.choice("fresnel");
    let material = p.choice("material");
    let (eta, k) = (p.rgb("eta"), p.rgb("k"));
    let eta_or_k = p.was_given("eta") || p.was_given("k");
    if let Some(m) = metal(material) {
        if mode == "none" {
            return Err(ParamError::Inconsistent(format!(
                "parameters 'material' and 'fresnel': material={material} needs a Fresnel term, but fresnel=none"
            )));
        }
        if eta_or_k {
            return Err(ParamError::Inconsistent(format!(
                "parameters 'material', 'eta' and 'k': material={material} sets eta and k; \
                 use material=custom to give them yourself"
            )));
        }
        if mode == "schlick" {
            return Ok(Fresnel::Schlick { r0: m.eta.zip(m.k, normal_reflectance) });
        }
        return Ok(Fresnel::Conductor { eta: m.eta, k: m.k });
    }
    if material == "none" {
        if !eta_or_k {
            return Ok(Fresnel::None);
        }
        if p.was_given("material") {
            return Err(ParamError::Inconsistent(
                "parameters 'material', 'eta' and 'k': material=none is a perfect reflector and takes no eta or k"
                    .into(),
            ));
        }
    }
    Ok(match mode {
        "none" => Fresnel::None,
        "schlick" => Fresnel::Schlick { r0: eta.zip(k, normal_reflectance) },
        "dielectric" => Fresnel::Dielectric { eta: eta.mean() },
        "conductor" => Fresnel::Conductor { eta, k },
        other => unreachable!("fresnel mode '{other}' passed the choice check"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::FRAC_PI_2;

    fn close(a: f32, b: f32, tol: f32) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn normal_incidence_is_r0() {
        for n in [1.1f32, 1.33, 1.5, 2.4, 0.7] {
            let r0 = schlick_r0(n);
            assert!(close(dielectric(1.0, n), r0, 1e-6), "n={n}");
            let pol = dielectric_polarized(1.0, n);
            assert!(close(pol.s, pol.p, 1e-6));
            assert!(close(schlick(1.0, r0), r0, 1e-7));
        }
        for (eta, k) in [(0.2f32, 3.9f32), (1.66, 9.22), (1.5, 0.0), (0.05, 0.5)] {
            let r0 = ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k);
            assert!(close(conductor(1.0, eta, k), r0, 1e-6), "η={eta} k={k}");
            assert!(close(normal_reflectance(eta, k), r0, 1e-6));
        }
        // A conductor with k = 0 is a dielectric at every angle.
        for c in [0.05f32, 0.3, 0.7, 1.0] {
            assert!(close(conductor(c, 1.5, 0.0), dielectric(c, 1.5), 1e-6), "cos {c}");
        }
    }

    #[test]
    fn grazing_incidence_reflects_everything() {
        let c = 0.0;
        for n in [1.01f32, 1.5, 3.0, 0.8] {
            assert_eq!(dielectric(c, n), 1.0, "n={n}");
        }
        for (eta, k) in [(0.2f32, 3.9f32), (1.5, 0.0), (AL.eta.0[0], AL.k.0[0])] {
            assert!(close(conductor(c, eta, k), 1.0, 1e-6));
        }
        assert_eq!(schlick(0.0, 0.04), 1.0);
        for f in [
            Fresnel::None,
            Fresnel::Schlick { r0: Rgb::splat(0.5) },
            Fresnel::Dielectric { eta: 1.5 },
            Fresnel::Conductor { eta: AU.eta, k: AU.k },
        ] {
            assert!(f.eval(0.0).0.iter().all(|&v| close(v, 1.0, 1e-6)), "{f:?}");
        }
    }

    #[test]
    fn brewster_angle_kills_p() {
        for n in [1.33f32, 1.5, 2.4] {
            let tb = n.atan();
            let pol = dielectric_polarized(tb.cos(), n);
            assert!(pol.p < 1e-10, "Rp at Brewster = {}", pol.p);
            assert!(pol.s > 0.01);
            // Either side of Brewster p is nonzero.
            assert!(dielectric_polarized((tb - 0.1).cos(), n).p > 1e-5);
            assert!(dielectric_polarized((tb + 0.1).cos(), n).p > 1e-5);
        }
    }

    #[test]
    fn total_internal_reflection_from_inside() {
        let n = 1.5f32;
        let critical = (1.0 / n).asin();
        // From inside (negative cosine): beyond the critical angle everything is reflected.
        let beyond = -(critical + 0.05).cos();
        assert_eq!(dielectric(beyond, n), 1.0);
        // Just inside the critical angle some light escapes.
        let before = -(critical - 0.05).cos();
        assert!(dielectric(before, n) < 1.0);
        // The same interface seen from either side has the same normal reflectance.
        assert!(close(dielectric(-1.0, n), dielectric(1.0, n), 1e-7));
        // Reciprocity of the interface: R(θ, η) from outside = R(θt, 1/η) from inside.
        let ci = 0.6f32;
        let ct = (1.0 - (1.0 - ci * ci) / (n * n)).sqrt();
        assert!(close(dielectric(ci, n), dielectric(-ct, n), 1e-6));
    }

    #[test]
    fn reflectance_is_a_fraction() {
        let mut worst = 0.0f32;
        for i in 0..=1000 {
            let c = -1.0 + 2.0 * i as f32 / 1000.0;
            for n in [0.5f32, 1.0, 1.0001, 1.5, 4.0, 10.0] {
                let pol = dielectric_polarized(c, n);
                for v in [pol.s, pol.p] {
                    assert!((0.0..=1.0).contains(&v), "dielectric n={n} cos={c}: {v}");
                }
            }
            for m in METALS {
                for ch in 0..3 {
                    let pol = conductor_polarized(c, m.eta.0[ch], m.k.0[ch]);
                    assert!((0.0..=1.0).contains(&pol.s) && (0.0..=1.0).contains(&pol.p), "{}", m.name);
                    worst = worst.max(pol.s).max(pol.p);
                }
            }
            for (eta, k) in [(0.01f32, 0.0f32), (10.0, 20.0), (0.01, 20.0), (10.0, 0.0)] {
                let v = conductor(c, eta, k);
                assert!((0.0..=1.0).contains(&v) && v.is_finite());
            }
        }
        assert!(worst <= 1.0);
    }

    #[test]
    fn schlick_error_against_exact_dielectric() {
        // For n = 1.5 Schlick's curve overshoots the exact one most near 85°. By hand at 85°:
        // sin θt = sin 85°/1.5 = 0.6641, cos θt = 0.7476, R_s = 0.7323, R_p = 0.4933, F = 0.6128,
        // while Schlick gives 0.04 + 0.96 (1 − cos 85°)⁵ = 0.6483: an error of 0.0355. The measured
        // maximum must be that peak: between 0.034 and 0.037, within 2° of 85°.
        let n = 1.5f32;
        let r0 = schlick_r0(n);
        let (mut worst, mut at) = (0.0f32, 0.0f32);
        for i in 0..=9000 {
            let t = FRAC_PI_2 * i as f32 / 9000.0;
            let e = (schlick(t.cos(), r0) - dielectric(t.cos(), n)).abs();
            if e > worst {
                worst = e;
                at = t.to_degrees();
            }
        }
        println!("Schlick vs exact, n = 1.5: max |ΔF| = {worst:.4} at θ = {at:.1}°");
        assert!((0.034..0.037).contains(&worst) && (at - 85.0).abs() < 2.0, "max error {worst} at {at}°");
        // It undershoots in between: at 60°, by hand, R_s = 0.1766, R_p = 0.0018, F = 0.0892 against
        // Schlick's 0.04 + 0.96/32 = 0.07.
        let c60 = 60f32.to_radians().cos();
        let d60 = schlick(c60, r0) - dielectric(c60, n);
        assert!((d60 + 0.0192).abs() < 2e-4, "{d60}");
        // Up to 30° the two agree to 0.002.
        let early = (0..=300)
            .map(|i| (i as f32 / 10.0).to_radians().cos())
            .map(|c| (schlick(c, r0) - dielectric(c, n)).abs())
            .fold(0.0f32, f32::max);
        assert!(early < 0.002, "{early}");
    }

    fn resolve(default_mode: &str, given: &[(&str, &str)]) -> Result<Fresnel, ParamError> {
        from_params(&crate::params::Params::resolve("m", &params(default_mode), given)?)
    }

    #[test]
    fn parameters_build_the_right_term() {
        assert_eq!(resolve("conductor", &[]).unwrap(), Fresnel::Conductor { eta: AU.eta, k: AU.k });
        assert_eq!(resolve("dielectric", &[]).unwrap(), Fresnel::Dielectric { eta: 1.5 });
        assert_eq!(resolve("dielectric", &[("eta", "1.2,1.5,1.8")]).unwrap(), Fresnel::Dielectric { eta: 1.5 });
        assert_eq!(resolve("conductor", &[("fresnel", "none")]).unwrap(), Fresnel::None);
        assert_eq!(resolve("conductor", &[("material", "Cu")]).unwrap(), Fresnel::Conductor { eta: CU.eta, k: CU.k });
        // A named material implies a conductor even where the default mode is dielectric.
        assert_eq!(resolve("dielectric", &[("material", "Al")]).unwrap(), Fresnel::Conductor { eta: AL.eta, k: AL.k });
        match resolve("dielectric", &[("fresnel", "schlick")]).unwrap() {
            Fresnel::Schlick { r0 } => assert!(close(r0.0[1], 0.04, 1e-6)),
            other => panic!("{other:?}"),
        }
        match resolve("dielectric", &[("fresnel", "schlick"), ("material", "Au")]).unwrap() {
            Fresnel::Schlick { r0 } => assert!(close(r0.0[0], conductor(1.0, AU.eta.0[0], AU.k.0[0]), 1e-6)),
            other => panic!("{other:?}"),
        }
        assert_eq!(
            resolve("conductor", &[("eta", "0.2"), ("k", "3")]).unwrap(),
            Fresnel::Conductor { eta: Rgb::splat(0.2), k: Rgb::splat(3.0) }
        );
    }

    #[test]
    fn inconsistent_parameters_are_named() {
        let e = resolve("conductor", &[("material", "Au"), ("fresnel", "none")]).unwrap_err().to_string();
        assert!(e.contains("'material'") && e.contains("'fresnel'"), "{e}");
        let e = resolve("conductor", &[("material", "Ag"), ("eta", "0.3")]).unwrap_err().to_string();
        assert!(e.contains("'material'") && e.contains("'eta'"), "{e}");
        let e = resolve("dielectric", &[("material", "Cu"), ("k", "2")]).unwrap_err().to_string();
        assert!(e.contains("'k'"), "{e}");
        assert!(resolve("conductor", &[("material", "Pt")]).is_err());
        // Mitsuba's conductor: material none is F = 1, unless eta and k are given instead.
        assert_eq!(resolve("conductor", &[("material", "none")]).unwrap(), Fresnel::None);
        let e = resolve("conductor", &[("material", "none"), ("k", "2")]).unwrap_err().to_string();
        assert!(e.contains("none"), "{e}");
        let spec: Vec<ParamSpec> = params("conductor")
            .into_iter()
            .map(|s| if s.name == "material" { s.with_default(crate::Value::Choice("none".into())) } else { s })
            .collect();
        let p = crate::params::Params::resolve("m", &spec, &[("eta", "0.2"), ("k", "3")]).unwrap();
        assert_eq!(from_params(&p).unwrap(), Fresnel::Conductor { eta: Rgb::splat(0.2), k: Rgb::splat(3.0) });
    }

    #[test]
    fn rgb_conductor_matches_the_f64_reference() {
        // Backward stability: the f32 result is the exact reflectance (the f64 reference) of
        // inputs within 4 ulp of the given ones, to within 16 ε of output rounding (a handful of
        // f32 operations, none cancelling in a term that dominates). Near the critical angle of
        // an η < 1, k = 0 interface F is ill-conditioned in cos θi, and no f32 evaluation can
        // do better than the perturbed inputs' spread; elsewhere that spread is a few ε.
        let eps = f32::EPSILON / 2.0;
        let mut cases: Vec<(f32, f32)> = METALS.iter().flat_map(|m| (0..3).map(|c| (m.eta.0[c], m.k.0[c]))).collect();
        cases.extend([
            (0.01, 0.0),
            (0.01, 20.0),
            (10.0, 0.0),
            (10.0, 20.0),
            (1.5, 0.0),
            (0.7, 0.0),
            (1.0, 0.0),
            (1.0, 1e-3),
        ]);
        cases.extend([(0.05, 0.5), (3.0, 0.01), (0.9, 0.2), (2.0, 5.0)]);
        let mut worst_metal = 0.0f32;
        for i in 0..=4000 {
            let c = -1.0 + 2.0 * i as f32 / 4000.0;
            for &(eta, k) in &cases {
                let got = conductor_rgb(c, Rgb::splat(eta), Rgb::splat(k)).0;
                assert!(got[0] == got[1] && got[1] == got[2], "lanes differ: {got:?}");
                let want = conductor(c, eta, k);
                let (mut lo, mut hi) = (want, want);
                for dc in [-4.0, 4.0] {
                    for de in [-4.0, 4.0] {
                        for dk in [-4.0, 4.0] {
                            let v = conductor(c * (1.0 + dc * eps), eta * (1.0 + de * eps), k * (1.0 + dk * eps));
                            lo = lo.min(v);
                            hi = hi.max(v);
                        }
                    }
                }
                let slack = 16.0 * eps * want + eps;
                assert!(
                    got[0] >= lo - slack && got[0] <= hi + slack,
                    "cos {c}, η {eta}, k {k}: {} outside [{lo}, {hi}] ± {slack:.1e}",
                    got[0]
                );
                if k > 1.0 {
                    worst_metal = worst_metal.max((got[0] - want).abs() / (want * eps));
                }
            }
        }
        // The named metals and other k > 1 conductors are well-conditioned: a few ε outright.
        assert!(worst_metal <= 16.0, "{worst_metal} ε");
        // η = sin θi with k = 0: a = b = 0, where every term of the one quotient vanishes.
        let c = 0.6f32;
        let s = (1.0 - c * c).sqrt();
        assert!(conductor_rgb(c, Rgb::splat(s), Rgb::ZERO).0.iter().all(|v| v.is_finite() && (0.0..=1.0).contains(v)));
        println!("conductor_rgb vs f64: max error {worst_metal:.1} ε for k > 1");
    }

    #[test]
    fn named_metals_look_like_themselves() {
        let r0 = |m: Metal| conductor_rgb(1.0, m.eta, m.k);
        let (au, ag, cu, al) = (r0(AU), r0(AG), r0(CU), r0(AL));
        // Gold and copper are red-yellow (R > G > B), silver and aluminium nearly neutral and bright.
        assert!(au.0[0] > au.0[1] && au.0[1] > au.0[2], "{au:?}");
        assert!(cu.0[0] > cu.0[1] && cu.0[1] > cu.0[2], "{cu:?}");
        assert!(ag.min_channel() > 0.85 && ag.max_channel() - ag.min_channel() < 0.1, "{ag:?}");
        assert!(al.min_channel() > 0.85 && al.max_channel() - al.min_channel() < 0.05, "{al:?}");
        assert_eq!(metal("ag"), Some(AG));
        // Every named choice is a conductor with finite constants (Mitsuba's names, case-insensitive).
        for name in MATERIALS.iter().filter(|n| !["custom", "none"].contains(n)) {
            let m = metal(name).unwrap_or_else(|| panic!("{name}"));
            assert!(m.eta.is_finite() && m.k.is_finite() && m.k.min_channel() >= 0.0, "{name}");
        }
        // Chromium is grey and strongly absorbing: R0 ≈ 0.55–0.65 in every channel.
        let cr = metal("cr").unwrap();
        let r0 = conductor_rgb(1.0, cr.eta, cr.k);
        assert!(r0.min_channel() > 0.5 && r0.max_channel() < 0.7, "{r0:?}");
    }
}
