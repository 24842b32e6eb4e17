//! Importance sampling of a tabulated isotropic BRDF: for each of `THETA_O_BINS` bands of the
//! viewing angle θo, a piecewise-constant density over the hemisphere of wi, proportional to
//! ρ·cos θi averaged over each cell, mixed with cosine sampling.
//!
//! Cells are uniform in θi (`THETA_BINS`) and in the azimuth relative to wo (`PHI_BINS`); a cell's
//! density is constant in solid angle, so a direction is placed uniformly in (cos θi, φ) within
//! it (dω = d cos θ dφ). For wo in band k the density is
//!
//!   p(wi | wo) = (1 − c) · P_k(cell) / Ω(cell) + c · cos θi / π,
//!
//! with c = `COSINE_FRACTION` (1 when the band's table is empty). The cosine part keeps every
//! direction where ρ > 0 reachable even if cell averaging missed a narrow feature. `pdf` uses the
//! same band and cell lookup as `sample`, and `sample` reports `pdf(wi, wo)` itself, so the two
//! agree exactly. Isotropy is assumed: only θo and φi − φo matter.
//!
//! A cell is drawn by inverting the band's cdf. A guide table (the cutpoint method of Chen and
//! Asau 1974) gives, for each of `GUIDE` equal intervals of u, the cell that the interval's start
//! falls in, so the search is a short forward scan from there rather than a binary search whose
//! every step misses the cache; it finds the same cell.

use radiometry::warp::{cosine_hemisphere, cosine_hemisphere_pdf};
use radiometry::{Vec2, Vec3};
use std::f64::consts::{FRAC_PI_2, TAU};

/// Bands of the viewing angle θo, uniform over [0°, 90°].
pub const THETA_O_BINS: usize = 32;
/// Cells in θi, uniform over [0°, 90°].
pub const THETA_BINS: usize = 64;
/// Cells in φi − φo, uniform over [0, 2π).
pub const PHI_BINS: usize = 128;
/// Share of directions drawn by cosine sampling.
pub const COSINE_FRACTION: f32 = 0.1;

const CELLS: usize = THETA_BINS * PHI_BINS;
/// Guide-table entries per band (a power of two, so u·GUIDE and its floor are exact).
const GUIDE: usize = 1024;

/// Per-band piecewise-constant distributions of wi.
#[derive(Clone, Debug)]
pub struct TableSampler {
    /// cos of the θi cell edges, from 1 (θ = 0) down to 0.
    cos_edges: Vec<f64>,
    /// Per band: cumulative cell probabilities, `CELLS + 1` values from 0 to 1.
    cdf: Vec<f64>,
    /// Per band and guide interval i: the cell that u = i / GUIDE falls in.
    guide: Vec<u16>,
    /// Per band and cell: probability / solid angle.
    density: Vec<f32>,
    /// Per band: the cosine share (1 when the table is empty).
    cosine: Vec<f32>,
}

/// Band of a viewing direction.
#[inline]
fn band(wo: Vec3) -> usize {
    let t = f64::from(wo.z).clamp(-1.0, 1.0).acos();
    ((t / FRAC_PI_2 * THETA_O_BINS as f64) as usize).min(THETA_O_BINS - 1)
}

/// cos and sin of φo (1, 0 at the normal).
#[inline]
fn azimuth(w: Vec3) -> (f32, f32) {
    let r = (w.x * w.x + w.y * w.y).sqrt();
    if r > 1e-12 {
        (w.x / r, w.y / r)
    } else {
        (1.0, 0.0)
    }
}

impl TableSampler {
    /// Builds the distributions from a scalar ρ (e.g. a channel sum) of an isotropic BRDF.
    pub fn build(rho: &(dyn Fn(Vec3, Vec3) -> f32 + Sync)) -> Self {
        let dtheta = FRAC_PI_2 / THETA_BINS as f64;
        let dphi = TAU / PHI_BINS as f64;
        let cos_edges: Vec<f64> = (0..=THETA_BINS).map(|i| (i as f64 * dtheta).cos()).collect();
        let mut cdf = vec![0.0f64; THETA_O_BINS * (CELLS + 1)];
        let mut density = vec![0.0f32; THETA_O_BINS * CELLS];
        let mut cosine = vec![1.0f32; THETA_O_BINS];
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).clamp(1, THETA_O_BINS);
        let per = THETA_O_BINS.div_ceil(threads);
        let cos_edges_ref = &cos_edges;
        std::thread::scope(|s| {
            let chunks =
                cdf.chunks_mut(per * (CELLS + 1)).zip(density.chunks_mut(per * CELLS)).zip(cosine.chunks_mut(per));
            for (t, ((cdf, density), cosine)) in chunks.enumerate() {
                s.spawn(move || {
                    for (j, cos_share) in cosine.iter_mut().enumerate() {
                        let k = t * per + j;
                        let theta_o = (k as f64 + 0.5) / THETA_O_BINS as f64 * FRAC_PI_2;
                        let wo = Vec3::new(theta_o.sin() as f32, 0.0, theta_o.cos() as f32);
                        let cdf = &mut cdf[j * (CELLS + 1)..(j + 1) * (CELLS + 1)];
                        let density = &mut density[j * CELLS..(j + 1) * CELLS];
                        let mut total = 0.0f64;
                        for it in 0..THETA_BINS {
                            let solid = (cos_edges_ref[it] - cos_edges_ref[it + 1]) * dphi;
                            for ip in 0..PHI_BINS {
                                // ρ cos θi at four interior points of the cell, averaged.
                                let mut g = 0.0f64;
                                for (a, b) in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)] {
                                    let th = (it as f64 + a) * dtheta;
                                    let ph = (ip as f64 + b) * dphi;
                                    let wi = Vec3::new(
                                        (th.sin() * ph.cos()) as f32,
                                        (th.sin() * ph.sin()) as f32,
                                        th.cos() as f32,
                                    );
                                    let v = f64::from(rho(wi, wo));
                                    if v.is_finite() && v > 0.0 {
                                        g += v * th.cos();
                                    }
                                }
                                let mass = 0.25 * g * solid;
                                cdf[it * PHI_BINS + ip + 1] = mass;
                                total += mass;
                            }
                        }
                        if !(total > 0.0 && total.is_finite()) {
                            continue;
                        }
                        let mut acc = 0.0;
                        for c in 0..CELLS {
                            let mass = cdf[c + 1] / total;
                            acc += mass;
                            cdf[c + 1] = acc;
                            let solid = (cos_edges_ref[c / PHI_BINS] - cos_edges_ref[c / PHI_BINS + 1]) * dphi;
                            density[c] = (mass / solid) as f32;
                        }
                        cdf[CELLS] = 1.0;
                        *cos_share = COSINE_FRACTION;
                    }
                });
            }
        });
        let guide = cdf
            .chunks_exact(CELLS + 1)
            .flat_map(|cdf| (0..GUIDE).map(|i| find_cell(cdf, i as f64 / GUIDE as f64, 0) as u16))
            .collect();
        TableSampler { cos_edges, cdf, guide, density, cosine }
    }

    /// Solid-angle density of `sample(wo, ..)` returning `wi`.
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let k = band(wo);
        let c = self.cosine[k];
        let mut p = c * cosine_hemisphere_pdf(wi.z);
        if c < 1.0 {
            let (co, so) = azimuth(wo);
            // wi's azimuth relative to wo's.
            let x = wi.x * co + wi.y * so;
            let y = -wi.x * so + wi.y * co;
            let mut phi = f64::from(y).atan2(f64::from(x));
            if phi < 0.0 {
                phi += TAU;
            }
            let ip = ((phi / TAU * PHI_BINS as f64) as usize).min(PHI_BINS - 1);
            let theta = f64::from(wi.z).min(1.0).acos();
            let it = ((theta / FRAC_PI_2 * THETA_BINS as f64) as usize).min(THETA_BINS - 1);
            p += (1.0 - c) * self.density[k * CELLS + it * PHI_BINS + ip];
        }
        p
    }

    /// [`sample`](Self::sample) as the sample of the model `brdf` these tables were built from,
    /// weighted by its ρ·cos θi / pdf.
    pub fn sample_brdf(&self, brdf: &dyn crate::Brdf, wo: Vec3, uc: f32, u: Vec2) -> Option<crate::BrdfSample> {
        let (wi, pdf) = self.sample(wo, uc, u)?;
        let weight = brdf.eval(wi, wo) * (wi.z / pdf);
        weight.is_finite().then_some(crate::BrdfSample { wi, pdf, weight, delta: false, eta: 1.0 })
    }

    /// Draws wi for `wo`: `uc` chooses cosine or table sampling, `u` places the direction.
    /// Returns wi and its density, `None` below the horizon.
    pub fn sample(&self, wo: Vec3, uc: f32, u: Vec2) -> Option<(Vec3, f32)> {
        if wo.z <= 0.0 {
            return None;
        }
        let k = band(wo);
        let wi = if uc < self.cosine[k] {
            cosine_hemisphere(u)
        } else {
            let cdf = &self.cdf[k * (CELLS + 1)..(k + 1) * (CELLS + 1)];
            let ux = f64::from(u.x);
            let start = self.guide[k * GUIDE + ((ux * GUIDE as f64) as usize).min(GUIDE - 1)];
            let cell = find_cell(cdf, ux, usize::from(start));
            let width = cdf[cell + 1] - cdf[cell];
            let t = if width > 0.0 { ((ux - cdf[cell]) / width).clamp(0.0, 1.0) } else { 0.5 };
            let (it, ip) = (cell / PHI_BINS, cell % PHI_BINS);
            let z = self.cos_edges[it] - t * (self.cos_edges[it] - self.cos_edges[it + 1]);
            let s = (1.0 - z * z).max(0.0).sqrt();
            let rel = (ip as f64 + f64::from(u.y)) / PHI_BINS as f64 * TAU;
            let (co, so) = azimuth(wo);
            let (x, y) = (s * rel.cos(), s * rel.sin());
            // Rotate back by φo.
            let (co, so) = (f64::from(co), f64::from(so));
            Vec3::new((x * co - y * so) as f32, (x * so + y * co) as f32, z as f32)
        };
        if wi.z <= 0.0 || !wi.is_finite() {
            return None;
        }
        let pdf = self.pdf(wi, wo);
        (pdf > 0.0 && pdf.is_finite()).then_some((wi, pdf))
    }

    /// Bytes held.
    pub fn memory(&self) -> usize {
        self.cdf.len() * 8
            + self.guide.len() * 2
            + self.density.len() * 4
            + self.cosine.len() * 4
            + self.cos_edges.len() * 8
    }
}

/// The last cell whose lower cdf edge is ≤ u (so empty cells are skipped), searching forward
/// from `start`, a cell at or before it.
#[inline]
fn find_cell(cdf: &[f64], u: f64, start: usize) -> usize {
    let mut cell = start;
    while cell + 1 < CELLS && cdf[cell + 1] <= u {
        cell += 1;
    }
    cell
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guided_search_finds_the_binary_search_cell() {
        // Zero over half the azimuths and near grazing, a spike at the mirror direction: runs
        // of empty cells whose edges repeat a cdf value.
        let s = TableSampler::build(&|wi: Vec3, wo: Vec3| {
            let mirror = (wi.x + wo.x).abs() + (wi.y + wo.y).abs() < 0.05;
            if wi.y < 0.0 || wi.z < 0.2 {
                0.0
            } else if mirror {
                500.0
            } else {
                1.0
            }
        });
        for k in [0, 7, THETA_O_BINS - 1] {
            let cdf = &s.cdf[k * (CELLS + 1)..(k + 1) * (CELLS + 1)];
            // Every cdf edge, the guide intervals' starts and a sweep in between.
            let us = cdf
                .iter()
                .copied()
                .chain((0..GUIDE).map(|i| i as f64 / GUIDE as f64))
                .chain((0..100_000).map(|i| f64::from((i as f32 + 0.37) / 100_000.0)))
                .filter(|u| (0.0..1.0).contains(u));
            for u in us {
                let binary = (cdf.partition_point(|&v| v <= u).max(1) - 1).min(CELLS - 1);
                let start = s.guide[k * GUIDE + ((u * GUIDE as f64) as usize).min(GUIDE - 1)];
                assert!(usize::from(start) <= binary, "band {k}, u {u}");
                assert_eq!(find_cell(cdf, u, usize::from(start)), binary, "band {k}, u {u}");
            }
        }
    }
}
