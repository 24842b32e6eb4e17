//! Non-negativity and finiteness everywhere, and agreement of `sample` with `pdf` and `eval`.

use super::util::{
    self, direction, fmt_dir, rel_diff, rel_diff1, sensitivity, tolerance, u2, uniform_sphere, uniform_upper,
};
use super::{Config, Finding, Property};
use crate::{Brdf, BrdfSample};
use radiometry::{Rgb, Vec2, Vec3};
use rand::Rng;

/// cos θ values that break careless code: below the horizon, exactly on it, within 1e-6 of
/// it on either side, and at or within 1e-6 of the normal.
const SPECIAL_COS: [f64; 14] =
    [-1.0, -0.5, -1e-6, -1e-7, 0.0, 1e-7, 1e-6, 1e-4, 1e-2, 0.5, 0.9, 1.0 - 1e-6, 1.0 - 1e-7, 1.0];

/// Azimuths for the special directions, including the axes.
const SPECIAL_PHI: [f64; 4] = [0.0, 0.7, std::f64::consts::FRAC_PI_2, 4.1];

/// The special directions: every `SPECIAL_COS` at every `SPECIAL_PHI`.
pub(crate) fn special_directions() -> Vec<Vec3> {
    SPECIAL_COS.iter().flat_map(|&c| SPECIAL_PHI.iter().map(move |&p| direction(c, p))).collect()
}

/// Random direction pairs over the whole sphere in the non-negativity check.
pub const RANDOM_PAIRS: usize = 16384;

/// Sample arguments at the corners and middle of [0, 1)³ (1 − 2⁻²⁴ is the largest f32 below 1).
fn corner_inputs() -> Vec<(f32, Vec2)> {
    let v = [0.0f32, 0.5, 1.0 - f32::EPSILON / 2.0];
    let mut out = Vec::new();
    for &a in &v {
        for &b in &v {
            for &c in &v {
                out.push((a, Vec2::new(b, c)));
            }
        }
    }
    out
}

/// Why a returned sample is malformed, if it is (non-finite, negative, zero density).
fn sample_defect(s: &BrdfSample) -> Option<&'static str> {
    if !(s.wi.is_finite() && s.pdf.is_finite() && s.weight.is_finite()) {
        Some("non-finite sample")
    } else if s.pdf <= 0.0 {
        Some("sample with pdf ≤ 0")
    } else if s.weight.min_channel() < 0.0 {
        Some("negative sample weight")
    } else {
        None
    }
}

/// Records violations, keeping the first for the report.
#[derive(Default)]
struct Tally {
    count: usize,
    first: Option<String>,
}

impl Tally {
    fn add(&mut self, what: impl FnOnce() -> String) {
        self.count += 1;
        if self.first.is_none() {
            self.first = Some(what());
        }
    }
}

/// Checks that eval and pdf are finite and ≥ 0 at every pair of the special directions and at
/// random pairs over the whole sphere, and that `sample` returns only finite values.
pub fn non_negative(brdf: &dyn Brdf, cfg: &Config) -> Finding {
    let mut rng = util::stream(cfg.seed, 0x4E4E);
    let special = special_directions();
    let mut bad = Tally::default();
    let mut evals = 0usize;
    let mut test_pair = |wi: Vec3, wo: Vec3, bad: &mut Tally| {
        evals += 1;
        let f = brdf.eval(wi, wo);
        if !f.is_finite() || f.min_channel() < 0.0 {
            bad.add(|| format!("eval(wi {wi:?}, wo {wo:?}) = {:?}", f.0));
        }
        let p = brdf.pdf(wi, wo);
        if !p.is_finite() || p < 0.0 {
            bad.add(|| format!("pdf(wi {wi:?}, wo {wo:?}) = {p}"));
        }
    };
    for &wi in &special {
        for &wo in &special {
            test_pair(wi, wo, &mut bad);
        }
    }
    for _ in 0..RANDOM_PAIRS {
        let (wi, wo) = (uniform_sphere(&mut rng), uniform_sphere(&mut rng));
        test_pair(wi, wo, &mut bad);
    }
    let corners = corner_inputs();
    let mut samples = 0usize;
    let wos: Vec<Vec3> = special.iter().copied().chain((0..1024).map(|_| uniform_sphere(&mut rng))).collect();
    for wo in wos {
        let randoms: Vec<(f32, Vec2)> = (0..8).map(|_| (rng.gen(), u2(&mut rng))).collect();
        for &(uc, u) in corners.iter().chain(randoms.iter()) {
            samples += 1;
            if let Some(s) = brdf.sample(wo, uc, u) {
                if let Some(why) = sample_defect(&s) {
                    bad.add(|| format!("{why}: sample(wo {wo:?}, uc {uc}, u {u:?}) = {s:?}"));
                }
            }
        }
    }
    let detail = match &bad.first {
        None => format!("eval and pdf finite and ≥ 0 at {evals} pairs (grazing and below-horizon included), {samples} samples finite"),
        Some(first) => format!("{} violations in {evals} pairs and {samples} samples; first: {first}", bad.count),
    };
    Finding { property: Property::NonNegative, claimed: true, passed: bad.count == 0, value: bad.count as f64, detail }
}

/// Outgoing directions in the sampling check, plus `GRAZING_WO`.
pub const SAMPLING_WO: usize = 128;
/// Samples drawn per outgoing direction in the sampling check.
pub const SAMPLES_PER_WO: usize = 128;
/// Grazing and normal outgoing directions always included.
const GRAZING_WO: [f64; 5] = [1.0, 0.999, 0.02, 2e-3, 1e-4];

/// A sampled or coverage defect is reported when ρ cos θi exceeds this (1/sr) where pdf = 0:
/// a part of the lobe the sampler never reaches, so every estimate through it is biased.
const COVERAGE_MIN: f32 = 1e-6;

/// True when a sample `wi` for `wo` lies where the model may send light: above the surface for
/// a reflection model; on `wo`'s side for one with a back side; anywhere off the plane for one
/// that transmits.
fn allowed(brdf: &dyn Brdf, wi: Vec3, wo: Vec3) -> bool {
    if brdf.transmits() {
        wi.z != 0.0
    } else if brdf.back_side() {
        wi.z * wo.z > 0.0
    } else {
        wi.z > 0.0
    }
}

/// Checks every sample against the model: finite, unit `wi` where the model may send light
/// (`allowed`), `s.pdf` equal to `pdf(wi, wo)` and `s.weight` equal to
/// `eval(wi, wo) |cos θi| / s.pdf` within the f32 tolerance (see `symmetry.rs`), `s.eta` 1 for
/// a reflection and the model's index ratio for a transmission, and non-zero pdf wherever
/// ρ |cos θi| is not negligible. A model with a back side is tested from below as well.
pub fn sampling(brdf: &dyn Brdf, cfg: &Config) -> Finding {
    let mut rng = util::stream(cfg.seed, 0x5A3F);
    let mut bad = Tally::default();
    let (mut drawn, mut returned, mut deltas, mut compared) = (0usize, 0usize, 0usize, 0usize);
    let mut worst = 0.0f64;
    let mut wos: Vec<Vec3> = GRAZING_WO.iter().map(|&c| direction(c, 2.0)).collect();
    wos.extend((0..SAMPLING_WO).map(|_| uniform_upper(&mut rng)));
    if brdf.back_side() {
        let below: Vec<Vec3> = wos.iter().map(|w| Vec3::new(w.x, -w.y, -w.z)).collect();
        wos.extend(below);
    }
    let eta = brdf.eta();
    let eval = |wi: Vec3, wo: Vec3| brdf.eval(wi, wo);
    let pdf = |wi: Vec3, wo: Vec3| Rgb::splat(brdf.pdf(wi, wo));
    for &wo in &wos {
        for _ in 0..SAMPLES_PER_WO {
            drawn += 1;
            let (uc, u) = (rng.gen::<f32>(), u2(&mut rng));
            let Some(s) = brdf.sample(wo, uc, u) else { continue };
            returned += 1;
            let at = || format!("wo {}, uc {uc}, u ({}, {}): wi {}", fmt_dir(wo), u.x, u.y, fmt_dir(s.wi));
            if let Some(why) = sample_defect(&s) {
                bad.add(|| format!("{why} ({})", at()));
                continue;
            }
            if (s.wi.length() - 1.0).abs() > 1e-4 {
                bad.add(|| format!("|wi| = {} ({})", s.wi.length(), at()));
            }
            if !allowed(brdf, s.wi, wo) {
                bad.add(|| format!("wi where the model sends no light, z = {:e} ({})", s.wi.z, at()));
                continue;
            }
            let want_eta = if s.wi.z * wo.z < 0.0 { crate::dielectric::eta_seen_from(eta, wo.z) } else { 1.0 };
            if rel_diff1(s.eta, want_eta).unwrap_or(0.0) > util::BASE_TOL {
                bad.add(|| format!("sample eta {} but the sides crossed give {want_eta} ({})", s.eta, at()));
            }
            if s.delta {
                deltas += 1;
                continue;
            }
            compared += 1;
            let p = brdf.pdf(s.wi, wo);
            let d_pdf = rel_diff1(s.pdf, p).unwrap_or(0.0);
            let want = brdf.eval(s.wi, wo) * (s.wi.z.abs() / s.pdf);
            let d_w = rel_diff(s.weight, want).unwrap_or(0.0);
            worst = worst.max(d_pdf).max(d_w);
            if d_pdf.max(d_w) > util::BASE_TOL {
                let sp = sensitivity(pdf, s.wi, wo, &mut rng);
                if d_pdf > tolerance(sp) {
                    bad.add(|| format!("sample pdf {} but pdf() {} ({})", s.pdf, p, at()));
                }
                if d_w > util::BASE_TOL {
                    let se = sensitivity(eval, s.wi, wo, &mut rng);
                    if d_w > tolerance(sp + se) {
                        bad.add(|| format!("weight {:?} but eval·cos/pdf {:?} ({})", s.weight.0, want.0, at()));
                    }
                }
            }
        }
        for _ in 0..SAMPLES_PER_WO / 2 {
            let wi = if brdf.back_side() { uniform_sphere(&mut rng) } else { uniform_upper(&mut rng) };
            let f = brdf.eval(wi, wo);
            if f.max_channel() * wi.z.abs() > COVERAGE_MIN && brdf.pdf(wi, wo) == 0.0 {
                bad.add(|| format!("pdf = 0 where ρ = {:?} (wi {} wo {})", f.0, fmt_dir(wi), fmt_dir(wo)));
            }
        }
    }
    let summary = format!(
        "max relative mismatch {worst:.2e} of pdf/weight over {compared} non-delta samples \
         ({returned} of {drawn} draws returned, {deltas} delta; tolerance {:.0e}, more where ill-conditioned)",
        util::BASE_TOL
    );
    let detail = match &bad.first {
        None => summary,
        Some(first) => format!("{} defects; first: {first}; {summary}", bad.count),
    };
    Finding { property: Property::Sampling, claimed: true, passed: bad.count == 0, value: worst, detail }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_directions_are_unit_and_include_the_horizon() {
        let d = special_directions();
        assert!(d.iter().all(|w| (w.length() - 1.0).abs() < 1e-6));
        assert!(d.iter().any(|w| w.z == 0.0) && d.iter().any(|w| w.z == 1.0) && d.iter().any(|w| w.z < 0.0));
    }
}
