//! Energy conservation: the directional albedo a(wo) = ∫ ρ(wi, wo) cos θi dωi ≤ 1, and the
//! fraction of light arriving from a direction that is reflected, r(wi) = ∫ ρ(wi, wo) cos θo dωo ≤ 1.
//! The two agree for a reciprocal model; for the lecture's raw Phong (ρ ∝ 1/cos θi) only r(wi)
//! shows the energy gained at grazing incidence, so both are measured.
//!
//! A model that transmits is held to the same bound in the power sense, over the whole sphere
//! and with |cos θ|: radiance refracted into a denser medium grows by η² while the power does
//! not, so each sample weight is multiplied by its η² (the index ratio it crossed) before it
//! is averaged. By generalised reciprocity, ρ(wi, wo) η² = ρ(wo, wi), the mean over incident
//! directions is then the fraction of the power arriving from wo that is reflected or
//! transmitted, as r(wo) is. Models with a back side are measured from below the surface too.
//!
//! a(wo) is estimated with the model's own sampler as the mean of the sample weights
//! ρ cos θi / pdf (delta lobes contribute through theirs, draws that return `None` contribute 0),
//! with its standard error. The check passes when every channel at every wo satisfies
//! mean ≤ 1 + z·se + 1e-5, with z the normal quantile that keeps the family-wise false-alarm rate
//! of a model whose albedo is exactly 1 at `cfg.alpha` (Šidák over all comparisons of the run),
//! and 1e-5 the bias f32 rounding of the weights can add (~100 roundings of 2⁻²⁴).

use super::util::{self, sidak};
use super::{Config, Finding, Property};
use crate::Brdf;
use radiometry::{Rgb, Vec3};
use rand::Rng;
use statrs::distribution::{ContinuousCDF, Normal};

/// Outgoing polar angles (degrees) at which the albedo is measured, up to grazing.
pub const ENERGY_THETAS: [f64; 13] = [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 85.0, 89.0, 89.9, 89.99];
/// Outgoing azimuths (radians): two, a quarter turn apart, for anisotropic lobes.
pub const ENERGY_PHIS: [f64; 2] = [0.3, 0.3 + std::f64::consts::FRAC_PI_2];
/// Samples per albedo estimate.
pub const ALBEDO_SAMPLES: usize = 16384;
/// Bias f32 rounding can add to a mean of weights.
const F32_MARGIN: f64 = 1e-5;

/// Which hemispherical integral of ρ an albedo estimate is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Integral {
    /// a(wo) = ∫ ρ(wi, wo) cos θi dωi: light reaching the viewer at `wo` from a uniform sky.
    OverIncident,
    /// r(wi) = ∫ ρ(wi, wo) cos θo dωo: the fraction of a beam from `wi` that is reflected.
    OverOutgoing,
}

/// Directional albedo at `wo` with its standard error, per channel, in f64.
pub fn albedo_f64(brdf: &dyn Brdf, wo: Vec3, samples: usize, seed: u64) -> ([f64; 3], [f64; 3]) {
    albedo_integral(brdf, Integral::OverIncident, wo, samples, seed)
}

/// The hemispherical integral `which` of ρ with the other direction fixed at `w`, with its
/// standard error, per channel. Over outgoing directions the model's sampler, called with `w`,
/// proposes the directions and each is weighted by ρ(w, wo) cos θo / pdf: unbiased wherever the
/// sampler covers ρ's support, whether or not the model is reciprocal.
pub fn albedo_integral(brdf: &dyn Brdf, which: Integral, w: Vec3, samples: usize, seed: u64) -> ([f64; 3], [f64; 3]) {
    let mut rng = util::stream(seed, 0xA1BE);
    let (mut sum, mut sum2) = ([0f64; 3], [0f64; 3]);
    for _ in 0..samples {
        let (uc, u) = (rng.gen::<f32>(), util::u2(&mut rng));
        let Some(mut s) = brdf.sample(w, uc, u) else { continue };
        if which == Integral::OverOutgoing && !s.delta {
            s.weight = if s.pdf > 0.0 { brdf.eval(w, s.wi) * (s.wi.z.abs() / s.pdf) } else { Rgb::ZERO };
        } else if s.eta != 1.0 {
            // Radiance to power across an interface.
            s.weight *= s.eta * s.eta;
        }
        if !s.weight.is_finite() {
            // Non-finite weights are the non-negativity check's finding; keep this one readable.
            continue;
        }
        for c in 0..3 {
            let w = s.weight.0[c] as f64;
            sum[c] += w;
            sum2[c] += w * w;
        }
    }
    let n = samples.max(1) as f64;
    let mean = sum.map(|s| s / n);
    let se = std::array::from_fn(|c| {
        let var = (sum2[c] / n - mean[c] * mean[c]).max(0.0) * n / (n - 1.0).max(1.0);
        (var / n).sqrt()
    });
    (mean, se)
}

/// Directional albedo ∫ ρ cos θi dωi at `wo` estimated from `samples` draws of the model's
/// sampler: (mean, standard error) per channel.
pub fn albedo(brdf: &dyn Brdf, wo: Vec3, samples: usize, seed: u64) -> (Rgb, Rgb) {
    let (m, se) = albedo_f64(brdf, wo, samples, seed);
    (Rgb(m.map(|v| v as f32)), Rgb(se.map(|v| v as f32)))
}

/// The polar angles (degrees) at which a model is measured: `ENERGY_THETAS`, and their
/// mirror images below the surface for a model with a back side.
pub fn energy_thetas(brdf: &dyn Brdf) -> Vec<f64> {
    let below = brdf.back_side().then(|| ENERGY_THETAS.iter().map(|t| 180.0 - t));
    ENERGY_THETAS.iter().copied().chain(below.into_iter().flatten()).collect()
}

/// The energy check: the largest of a(wo) and r(wi) over the θ × φ grid.
pub fn energy(brdf: &dyn Brdf, cfg: &Config) -> Finding {
    let integrals = [Integral::OverIncident, Integral::OverOutgoing];
    let thetas = energy_thetas(brdf);
    let comparisons = integrals.len() * thetas.len() * ENERGY_PHIS.len() * 3 * cfg.chi2_tests.max(1);
    let a = sidak(cfg.alpha, comparisons);
    let z = Normal::new(0.0, 1.0).map(|n| n.inverse_cdf(1.0 - a)).unwrap_or(4.0);
    // mean, se, channel, θ, φ, integral
    let mut worst = (f64::NEG_INFINITY, 0.0, 0usize, 0.0, 0.0, Integral::OverIncident);
    let mut excess: Option<(f64, f64, usize, f64, f64, Integral)> = None;
    let mut k = 0u64;
    for which in integrals {
        for &theta in &thetas {
            for &phi in &ENERGY_PHIS {
                let w = util::direction(theta.to_radians().cos(), phi);
                let (mean, se) = albedo_integral(brdf, which, w, ALBEDO_SAMPLES, cfg.seed.wrapping_add(k));
                k += 1;
                for c in 0..3 {
                    if mean[c] > worst.0 {
                        worst = (mean[c], se[c], c, theta, phi, which);
                    }
                    let over = mean[c] - (1.0 + z * se[c] + F32_MARGIN);
                    if over > 0.0 && !matches!(excess, Some(e) if over <= e.0 - (1.0 + z * e.1 + F32_MARGIN)) {
                        excess = Some((mean[c], se[c], c, theta, phi, which));
                    }
                }
            }
        }
    }
    let ch = |c: usize| ["r", "g", "b"][c];
    let at = |which: Integral, t: f64, p: f64| match which {
        Integral::OverIncident => format!("albedo ∫ρ cosθi dωi at θo = {t}°, φo = {:.0}°", p.to_degrees()),
        Integral::OverOutgoing => format!("reflected fraction ∫ρ cosθo dωo at θi = {t}°, φi = {:.0}°", p.to_degrees()),
    };
    let (m, se, c, t, p, which) = worst;
    let limit = format!(
        "limit 1 + {z:.2}σ + {F32_MARGIN:.0e}; 2 × {} directions × {ALBEDO_SAMPLES} samples",
        thetas.len() * ENERGY_PHIS.len()
    );
    let detail = match excess {
        Some((m, se, c, t, p, which)) => {
            format!("{} = {m:.4} ± {se:.1e} (channel {}) exceeds 1; {limit}", at(which, t, p), ch(c))
        }
        None => format!("max {} = {m:.4} ± {se:.1e} (channel {}); {limit}", at(which, t, p), ch(c)),
    };
    Finding {
        property: Property::Energy,
        claimed: brdf.claims().energy_conserving,
        passed: excess.is_none(),
        value: m,
        detail,
    }
}
