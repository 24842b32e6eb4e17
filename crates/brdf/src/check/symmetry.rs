//! Helmholtz reciprocity and isotropy: two symmetries measured the same way, by comparing ρ at
//! a pair of directions with ρ at its transformed pair.
//!
//! Tolerance. Two f32 evaluations of a symmetric function along different rounding paths agree
//! to `BASE_TOL` (1e-4) where ρ is well conditioned. Where it is not (a sharp lobe, the rim of a
//! lobe, a grazing half vector) rounding legitimately moves ρ further, so each pair that differs
//! by more than `BASE_TOL` is allowed `BASE_TOL + 4 s`, with `s` the relative change of ρ measured
//! when both inputs are moved by ~4 ulps. A genuine asymmetry (raw Phong's 1/cos θi, an
//! anisotropic lobe) is of order one and far outside this.
//!
//! Models with a back side are measured on pairs over the whole sphere: both directions on one
//! side, or, for a model that transmits, on opposite sides too, where reciprocity takes its
//! generalised form ρ(wi, wo) n_i² = ρ(wo, wi) n_o² (n the index on each direction's side:
//! 1 above the surface, the model's `eta` below).

use super::util::{
    self, fmt_dir, near_mirror, rel_diff, rotate_z, sensitivity, tolerance, uniform_sphere, uniform_upper,
};
use super::{Config, Finding, Property};
use crate::Brdf;
use radiometry::{Rgb, Vec3};
use rand::Rng;
use std::f64::consts::TAU;

/// Direction pairs per symmetry check: half uniform over the hemisphere, half near the mirror
/// direction, where glossy lobes (and their asymmetries) are.
pub const PAIRS: usize = 8192;

/// Measures the largest asymmetry of `brdf` under `transform` (applied to a pair `(wi, wo)`).
struct Asymmetry {
    worst: f64,
    worst_at: Option<(Vec3, Vec3)>,
    over: usize,
    excess_at: Option<(Vec3, Vec3, f64, f64)>,
    compared: usize,
}

/// Pair `i` of the measurement: (wi, wo).
fn pair(brdf: &dyn Brdf, i: usize, rng: &mut rand_pcg::Pcg32) -> (Vec3, Vec3) {
    if !brdf.back_side() {
        let wo = uniform_upper(rng);
        let wi = if i.is_multiple_of(2) { uniform_upper(rng) } else { near_mirror(wo, rng).unwrap_or(wo) };
        return (wo, wi);
    }
    let wo = uniform_upper(rng);
    let wo = if i % 4 < 2 { wo } else { Vec3::new(wo.x, wo.y, -wo.z) };
    let wi = match (i % 2, brdf.transmits()) {
        (0, true) => uniform_sphere(rng),
        (0, false) => {
            let w = uniform_upper(rng);
            Vec3::new(w.x, w.y, w.z.copysign(wo.z))
        }
        // Near the refracted direction every other time, where a transmitted lobe is.
        (_, true) if i % 8 >= 4 => util::near(util::refracted(wo, brdf.eta()), rng),
        _ => util::near(Vec3::new(-wo.x, -wo.y, wo.z), rng),
    };
    (wo, wi)
}

fn measure(
    brdf: &dyn Brdf,
    seed: u64,
    stream: u64,
    eval: impl Fn(Vec3, Vec3) -> Rgb,
    transform: impl Fn(Vec3, Vec3, f64) -> (Vec3, Vec3),
) -> Asymmetry {
    let mut rng = util::stream(seed, stream);
    let mut a = Asymmetry { worst: 0.0, worst_at: None, over: 0, excess_at: None, compared: 0 };
    let eval = &eval;
    for i in 0..PAIRS {
        let (wo, wi) = pair(brdf, i, &mut rng);
        let t = rng.gen::<f64>();
        let (ti, to) = transform(wi, wo, t);
        let Some(d) = rel_diff(eval(wi, wo), eval(ti, to)) else { continue };
        a.compared += 1;
        if d > a.worst {
            a.worst = d;
            a.worst_at = Some((wi, wo));
        }
        if d > util::BASE_TOL {
            let s = sensitivity(eval, wi, wo, &mut rng).max(sensitivity(eval, ti, to, &mut rng));
            let tol = tolerance(s);
            if d > tol {
                a.over += 1;
                if !matches!(a.excess_at, Some((_, _, d0, t0)) if d - tol <= d0 - t0) {
                    a.excess_at = Some((wi, wo, d, tol));
                }
            }
        }
    }
    a
}

fn finding(property: Property, claimed: bool, a: Asymmetry, what: &str) -> Finding {
    let passed = a.over == 0;
    let detail = if a.compared == 0 {
        format!("ρ is zero at all {PAIRS} pairs tried: nothing to compare")
    } else {
        let mut s = format!(
            "max relative {what} {:.2e} over {} pairs with ρ > 0 (tolerance {:.0e}, more where ρ is ill-conditioned in f32)",
            a.worst, a.compared, util::BASE_TOL
        );
        if let Some((wi, wo)) = a.worst_at {
            s += &format!(", worst at wi {} wo {}", fmt_dir(wi), fmt_dir(wo));
        }
        if let Some((wi, wo, d, tol)) = a.excess_at {
            s += &format!(
                "; {} pairs beyond tolerance, e.g. {:.3e} > {:.1e} at wi {} wo {}",
                a.over,
                d,
                tol,
                fmt_dir(wi),
                fmt_dir(wo)
            );
        }
        s
    };
    Finding { property, claimed, passed, value: a.worst, detail }
}

/// Helmholtz reciprocity: max over pairs of |ρ(wi, wo) − ρ(wo, wi)| / max of the two; for a
/// model that transmits, of ρ(wi, wo) n_i² against ρ(wo, wi) n_o².
pub fn reciprocity(brdf: &dyn Brdf, cfg: &Config) -> Finding {
    if brdf.transmits() {
        let eta2 = brdf.eta() * brdf.eta();
        let n2 = |w: Vec3| if w.z < 0.0 { eta2 } else { 1.0 };
        let a = measure(brdf, cfg.seed, 0x2EC1, |wi, wo| brdf.eval(wi, wo) * n2(wi), |wi, wo, _| (wo, wi));
        return finding(
            Property::Reciprocity,
            brdf.claims().reciprocal,
            a,
            "error |ρ(wi,wo) n_i² − ρ(wo,wi) n_o²|/(ρ n²) (generalised reciprocity)",
        );
    }
    let a = measure(brdf, cfg.seed, 0x2EC1, |wi, wo| brdf.eval(wi, wo), |wi, wo, _| (wo, wi));
    finding(Property::Reciprocity, brdf.claims().reciprocal, a, "error |ρ(wi,wo) − ρ(wo,wi)|/ρ")
}

/// Isotropy: max over pairs of the relative change of ρ under a common random rotation about z.
pub fn isotropy(brdf: &dyn Brdf, cfg: &Config) -> Finding {
    let eval = |wi: Vec3, wo: Vec3| brdf.eval(wi, wo);
    let a = measure(brdf, cfg.seed, 0x1507, eval, |wi, wo, t| (rotate_z(wi, t * TAU), rotate_z(wo, t * TAU)));
    finding(Property::Isotropy, brdf.claims().isotropic, a, "change under rotation about z")
}
