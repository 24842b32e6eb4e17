//! Random streams, test directions and the f32 comparison rules shared by the checks.

use radiometry::{Rgb, Vec2, Vec3};
use rand::Rng;
use rand_pcg::Pcg32;
use std::f64::consts::TAU;

/// A BRDF value below this (1/sr) counts as zero: it is far above f32's subnormal range,
/// so values above it still carry full relative precision, and far below anything visible.
pub(crate) const TINY: f32 = 1e-20;

/// Relative agreement expected of two f32 evaluations of the same quantity along different
/// but equally valid paths, where the result is well conditioned: ~100 roundings of 2⁻²⁴
/// (≈ 6e-6) with a safety factor.
pub(crate) const BASE_TOL: f64 = 1e-4;

/// Relative size of the input perturbation used to measure how ill-conditioned a quantity is
/// at a point: 2⁻²¹, i.e. about four units in the last place of each direction component.
const PERTURB: f64 = 1.0 / (1u64 << 21) as f64;

/// How many times the measured conditioning is allowed on top of `BASE_TOL`.
pub(crate) const SENS_FACTOR: f64 = 4.0;

/// An independent random stream: the same `(seed, stream)` always gives the same numbers.
pub(crate) fn stream(seed: u64, stream: u64) -> Pcg32 {
    Pcg32::new(seed ^ 0x9E37_79B9_7F4A_7C15, stream)
}

/// A point of [0, 1)².
pub(crate) fn u2(rng: &mut Pcg32) -> Vec2 {
    Vec2::new(rng.gen(), rng.gen())
}

/// The direction with the given cos θ and φ, computed in f64 and rounded once.
pub(crate) fn direction(cos_theta: f64, phi: f64) -> Vec3 {
    let c = cos_theta.clamp(-1.0, 1.0);
    let s = (1.0 - c * c).max(0.0).sqrt();
    Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32)
}

/// A uniformly distributed direction on the whole sphere.
pub(crate) fn uniform_sphere(rng: &mut Pcg32) -> Vec3 {
    direction(rng.gen_range(-1.0..=1.0), rng.gen::<f64>() * TAU)
}

/// A uniformly distributed direction strictly above the surface.
pub(crate) fn uniform_upper(rng: &mut Pcg32) -> Vec3 {
    loop {
        let w = direction(rng.gen::<f64>(), rng.gen::<f64>() * TAU);
        if w.z > 0.0 {
            return w;
        }
    }
}

/// A direction at a log-uniform angle between 1e-4 and 1 rad from the mirror direction of
/// `wo`, where specular lobes live and uniform directions rarely go; `None` below the surface.
pub(crate) fn near_mirror(wo: Vec3, rng: &mut Pcg32) -> Option<Vec3> {
    let w = near(Vec3::new(-wo.x, -wo.y, wo.z), rng);
    (w.z > 0.0).then_some(w)
}

/// A direction at a log-uniform angle between 1e-4 and 1 rad from `axis` (any side).
pub(crate) fn near(axis: Vec3, rng: &mut Pcg32) -> Vec3 {
    let m = [axis.x as f64, axis.y as f64, axis.z as f64];
    let len = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    let m = m.map(|c| c / len);
    // An orthonormal basis (t, b, m), as in Duff et al. 2017.
    let sign = 1f64.copysign(m[2]);
    let a = -1.0 / (sign + m[2]);
    let bb = m[0] * m[1] * a;
    let t = [1.0 + sign * m[0] * m[0] * a, sign * bb, -sign * m[0]];
    let b = [bb, sign + m[1] * m[1] * a, -m[1]];
    let angle = 10f64.powf(rng.gen_range(-4.0..0.0));
    let phi = rng.gen::<f64>() * TAU;
    let (st, ct) = angle.sin_cos();
    let (sp, cp) = phi.sin_cos();
    let w: [f64; 3] = std::array::from_fn(|i| st * cp * t[i] + st * sp * b[i] + ct * m[i]);
    Vec3::new(w[0] as f32, w[1] as f32, w[2] as f32)
}

/// The direction refracted from `wo` through a smooth interface of relative index `eta`
/// (below over above), or the mirror direction under total internal reflection: where a
/// transmitted lobe is centred.
pub(crate) fn refracted(wo: Vec3, eta: f32) -> Vec3 {
    let eta_t = crate::dielectric::eta_seen_from(eta, wo.z);
    crate::model::refract(wo, Vec3::Z, eta_t).unwrap_or(Vec3::new(-wo.x, -wo.y, wo.z))
}

/// Rotation of `w` by `angle` about the normal, in f64 and rounded once.
pub(crate) fn rotate_z(w: Vec3, angle: f64) -> Vec3 {
    let (s, c) = angle.sin_cos();
    let (x, y) = (w.x as f64, w.y as f64);
    Vec3::new((c * x - s * y) as f32, (s * x + c * y) as f32, w.z)
}

/// `w` with every component scaled by 1 + e, |e| ≤ 2⁻²¹: a few ulps, keeping signs.
pub(crate) fn perturb(w: Vec3, rng: &mut Pcg32) -> Vec3 {
    let mut c = |v: f32| (v as f64 * (1.0 + PERTURB * rng.gen_range(-1.0..=1.0))) as f32;
    Vec3::new(c(w.x), c(w.y), c(w.z))
}

/// Largest relative difference |a − b| / max(|a|, |b|) over the channels where either is not
/// negligible; `None` when every channel of both is below `TINY`.
pub(crate) fn rel_diff(a: Rgb, b: Rgb) -> Option<f64> {
    let mut worst: Option<f64> = None;
    for (x, y) in a.0.iter().zip(b.0.iter()) {
        if let Some(d) = rel_diff1(*x, *y) {
            worst = Some(worst.map_or(d, |w| w.max(d)));
        }
    }
    worst
}

/// `rel_diff` for one number.
pub(crate) fn rel_diff1(a: f32, b: f32) -> Option<f64> {
    let (a, b) = (a as f64, b as f64);
    let m = a.abs().max(b.abs());
    if !m.is_finite() {
        return Some(f64::INFINITY);
    }
    (m >= TINY as f64).then(|| (a - b).abs() / m)
}

/// How much `f(wi, wo)` moves, relatively, when both inputs move by a few ulps: the best
/// agreement f32 can promise there between two evaluation paths (largest of two trials).
pub(crate) fn sensitivity(f: impl Fn(Vec3, Vec3) -> Rgb, wi: Vec3, wo: Vec3, rng: &mut Pcg32) -> f64 {
    let v = f(wi, wo);
    (0..2).map(|_| rel_diff(f(perturb(wi, rng), perturb(wo, rng)), v).unwrap_or(0.0)).fold(0.0, f64::max)
}

/// The tolerance for a difference between two evaluation paths at a point of given sensitivity.
pub(crate) fn tolerance(sens: f64) -> f64 {
    BASE_TOL + SENS_FACTOR * sens
}

/// Per-test significance for `tests` independent tests at family-wise level `alpha` (Šidák).
pub(crate) fn sidak(alpha: f64, tests: usize) -> f64 {
    let n = tests.max(1) as f64;
    // 1 − (1 − α)^(1/n), written with ln_1p/exp_m1 so that tiny levels keep their digits.
    -((1.0 - alpha).ln() / n).exp_m1()
}

/// θ in degrees of a direction, for reports.
pub(crate) fn theta_deg(w: Vec3) -> f64 {
    (w.z as f64).clamp(-1.0, 1.0).acos().to_degrees()
}

/// φ in degrees in [0, 360) of a direction, for reports.
pub(crate) fn phi_deg(w: Vec3) -> f64 {
    let p = (w.y as f64).atan2(w.x as f64).to_degrees();
    if p < 0.0 {
        p + 360.0
    } else {
        p
    }
}

/// A direction written as (θ, φ) in degrees.
pub(crate) fn fmt_dir(w: Vec3) -> String {
    format!("(θ {:.2}°, φ {:.1}°)", theta_deg(w), phi_deg(w))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sidak_matches_its_definition() {
        let a = sidak(0.01, 40);
        assert!(((1.0 - a).powi(40) - 0.99).abs() < 1e-12, "{a}");
        assert!((sidak(0.01, 1) - 0.01).abs() < 1e-15);
    }

    #[test]
    fn near_mirror_stays_near_the_mirror() {
        let mut rng = stream(1, 2);
        let wo = direction(0.5, 1.0);
        let m = Vec3::new(-wo.x, -wo.y, wo.z);
        for _ in 0..1000 {
            if let Some(w) = near_mirror(wo, &mut rng) {
                assert!((w.length() - 1.0).abs() < 1e-6);
                assert!(w.dot(m) >= 1.0f32.cos() - 1e-6);
            }
        }
    }
}
