//! A virtual gonio-reflectometer over an explicit micro-surface: a periodic Gaussian height field
//! (`heightfield`) whose facets reflect by a mirror or any `Brdf`, lit by a beam and seen by
//! detectors, with multiple bounces between facets.
//!
//! Estimator. A beam of irradiance E (per unit area of the mean plane) from direction wi is
//! modelled by N rays starting at uniform points of one period of the mean plane (above the
//! highest point), each carrying flux Φ/N. The flux leaving the period into a detector bin B is
//! Φ_B = ∫_B L_o(w) cos θ A dω, and the macro-surface BRDF is ρ = dL_o/dE, so for ρ nearly constant
//! over B
//!   ρ̂(wi, B) = (Φ_B / Φ) / Ω⊥(B),   Ω⊥(B) = ∫_B cos θ dω = Δφ (sin²θ₁ − sin²θ₀)/2,
//! i.e. the fraction of the beam's flux reaching B over B's projected solid angle. Its standard
//! error follows from the per-ray contributions X (the ray's weight if it lands in B, else 0):
//! √(Var X / N) / Ω⊥(B).
//!
//! With `Beam::Bin` the incident directions are also spread over a bin A around wi, with density
//! ∝ cos θi (a uniform-radiance source over A); the estimate is then
//!   ρ̂(A, B) = ∫_A ∫_B ρ cos θi cos θo dωi dωo / (Ω⊥(A) Ω⊥(B)),
//! which is symmetric in A and B exactly when ρ is reciprocal: the right quantity for a
//! reciprocity test free of bin-averaging bias.
//!
//! Facets: a mirror reflects d ↦ d − 2(d·n)n; a `Brdf` facet samples the new direction in the
//! facet's frame with `sample(wo = −d)` and multiplies the ray's weight by ρ cos / pdf (valid for
//! reciprocal facet models, which is what light tracing with that sampler assumes).
//!
//! Theory to check against: for mirror facets the single-scattering part is the microfacet BRDF
//! D(h) G / (4 cos θi cos θo) with D the distribution of facet normals, here Beckmann with m the
//! RMS slope (Beckmann & Spizzichino 1963; Torrance & Sparrow 1967; Walter et al. 2007); the
//! multiply scattered rest is what Heitz et al. 2016, "Multiple-Scattering Microfacet BSDFs with
//! the Smith Model", compute stochastically; this tracer measures it on one explicit surface.

use super::heightfield::{Cast, HeightField};
use super::tabulated::Tabulated;
use crate::Brdf;
use radiometry::{DVec3, Frame, Vec2};
use rand::Rng;
use rand_pcg::Pcg32;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// How the facets reflect.
#[derive(Debug)]
pub enum Facet {
    /// An ideal mirror (a microfacet surface).
    Mirror,
    /// Any model, sampled in the facet's local frame.
    Model(Box<dyn Brdf>),
}

/// How the incident light arrives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Beam {
    /// A collimated beam exactly from each grid direction wi.
    Collimated,
    /// A uniform-radiance source filling the incident grid cell around wi (for reciprocity tests).
    Bin,
}

/// Measurement settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeasureOptions {
    /// Rays per incident direction.
    pub rays: usize,
    /// Seed of the ray streams; the result does not depend on the thread count.
    pub seed: u64,
    /// The incident light.
    pub beam: Beam,
    /// Worker threads (0: the machine's cores).
    pub threads: usize,
}

impl Default for MeasureOptions {
    fn default() -> Self {
        MeasureOptions { rays: 200_000, seed: 1, beam: Beam::Collimated, threads: 0 }
    }
}

/// Where the flux of one incident direction went, as fractions of the beam's flux.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FluxBalance {
    /// Left the surface upwards (binned or not), per channel.
    pub escaped: [f64; 3],
    /// Left the surface beyond the detector grid's θ range (included in `escaped`), per channel.
    pub unbinned: [f64; 3],
    /// Still bouncing when the bounce limit stopped it, per channel.
    pub truncated: [f64; 3],
    /// Lost numerically (through a crack, or grazing without resolving), per channel.
    pub lost: [f64; 3],
    /// Mean number of facet hits of an escaping ray.
    pub mean_bounces: f64,
}

/// A measured table with its statistical errors and flux balance.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// ρ̂ on the θi × φi × θo × φo grid.
    pub table: Tabulated,
    /// The standard error of each entry of `table`, per channel.
    pub std_err: Vec<[f32; 3]>,
    /// Where the flux went, per incident direction (index iθi · nφi + iφi).
    pub balance: Vec<FluxBalance>,
    /// Rays traced per incident direction.
    pub rays: usize,
}

/// A micro-surface and how its facets reflect.
#[derive(Debug)]
pub struct Microsurface {
    /// The surface.
    pub field: HeightField,
    /// The facets' reflection.
    pub facet: Facet,
    /// Facet hits after which a ray is given up (counted in `truncated`).
    pub max_bounces: u32,
}

/// Cell edges (degrees) around each value of a sorted θ axis, within [0, 90].
fn theta_edges(axis: &[f64]) -> Vec<(f64, f64)> {
    let n = axis.len();
    (0..n)
        .map(|k| {
            let lo = if k > 0 {
                0.5 * (axis[k - 1] + axis[k])
            } else if n > 1 {
                axis[0] - 0.5 * (axis[1] - axis[0])
            } else {
                0.0
            };
            let hi = if k + 1 < n {
                0.5 * (axis[k] + axis[k + 1])
            } else if n > 1 {
                axis[k] + 0.5 * (axis[k] - axis[k - 1])
            } else {
                90.0
            };
            (lo.clamp(0.0, 90.0), hi.clamp(0.0, 90.0))
        })
        .collect()
}

/// Cell edges (degrees) around each value of a sorted periodic φ axis (a single value: the circle).
fn phi_edges(axis: &[f64]) -> Vec<(f64, f64)> {
    let n = axis.len();
    (0..n)
        .map(|k| {
            if n == 1 {
                return (axis[0] - 180.0, axis[0] + 180.0);
            }
            let prev = if k == 0 { axis[n - 1] - 360.0 } else { axis[k - 1] };
            let next = if k + 1 == n { axis[0] + 360.0 } else { axis[k + 1] };
            (0.5 * (prev + axis[k]), 0.5 * (axis[k] + next))
        })
        .collect()
}

/// The index of the θ cell holding `t` (degrees), if any.
fn theta_bin(edges: &[(f64, f64)], t: f64) -> Option<usize> {
    let k = edges.partition_point(|e| e.1 <= t);
    (k < edges.len() && t >= edges[k].0).then_some(k)
}

/// The index of the φ cell holding `p` (degrees): the circularly nearest axis value.
fn phi_bin(axis: &[f64], p: f64) -> usize {
    let n = axis.len();
    if n == 1 {
        return 0;
    }
    let p = p.rem_euclid(360.0);
    let hi = axis.partition_point(|&v| v <= p);
    let (a, b) = ((hi + n - 1) % n, hi % n);
    let dist = |v: f64| {
        let d = (p - v).rem_euclid(360.0);
        d.min(360.0 - d)
    };
    if dist(axis[a]) <= dist(axis[b]) {
        a
    } else {
        b
    }
}

/// Projected solid angle ∫ cos θ dω of a cell (degrees).
fn projected_solid_angle(t: (f64, f64), p: (f64, f64)) -> f64 {
    let s2 = |d: f64| d.to_radians().sin().powi(2);
    0.5 * (s2(t.1) - s2(t.0)) * (p.1 - p.0).to_radians()
}

fn direction(theta_deg: f64, phi_deg: f64) -> DVec3 {
    let (st, ct) = theta_deg.to_radians().sin_cos();
    let (sp, cp) = phi_deg.to_radians().sin_cos();
    DVec3::new(st * cp, st * sp, ct)
}

/// Per-job sums over one chunk of rays.
struct Chunk {
    sum: Vec<[f64; 3]>,
    sum2: Vec<[f64; 3]>,
    balance: FluxBalance,
    bounces: f64,
    escaped_rays: f64,
}

/// Rays per job: small enough to balance threads, large enough that merging is cheap.
const CHUNK: usize = 16_384;

impl Microsurface {
    /// A Gaussian micro-surface of RMS slope `rms_slope` on a `grid`² height field with correlation
    /// kernel `corr_cells` cells.
    pub fn gaussian(rms_slope: f64, grid: usize, corr_cells: f64, seed: u64, facet: Facet) -> Self {
        Microsurface { field: HeightField::gaussian(grid, corr_cells, rms_slope, seed), facet, max_bounces: 100 }
    }

    /// Traces one ray arriving along `d` (pointing down) at the top of the period, at (x, y);
    /// returns (its final direction if it escaped, its weight, hits, outcome code).
    fn trace(&self, x: f64, y: f64, d: DVec3, rng: &mut Pcg32) -> (DVec3, [f64; 3], u32, Outcome) {
        let n = self.field.size() as f64;
        let mut o = DVec3::new(x, y, self.field.max_height() + 1e-6);
        let mut d = d;
        let mut w = [1.0f64; 3];
        for bounce in 0..=self.max_bounces {
            match self.field.cast(o, d) {
                Cast::Escaped => return (d, w, bounce, Outcome::Escaped),
                Cast::Lost => return (d, w, bounce, Outcome::Lost),
                Cast::Hit(hit) => {
                    if bounce == self.max_bounces {
                        return (d, w, bounce, Outcome::Truncated);
                    }
                    // Keep the origin within one period so positions stay precise.
                    o = DVec3::new(hit.p.x.rem_euclid(n), hit.p.y.rem_euclid(n), hit.p.z);
                    match &self.facet {
                        Facet::Mirror => d = d - 2.0 * d.dot(hit.n) * hit.n,
                        Facet::Model(m) => {
                            let frame = Frame::from_normal(hit.n.as_vec3());
                            let wo = frame.to_local((-d).as_vec3()).normalize();
                            let u = Vec2::new(rng.gen(), rng.gen());
                            let Some(s) = m.sample(wo, rng.gen(), u) else {
                                return (d, [0.0; 3], bounce, Outcome::Absorbed);
                            };
                            if !(s.weight.is_finite() && s.wi.z > 0.0) {
                                return (d, [0.0; 3], bounce, Outcome::Absorbed);
                            }
                            for (c, wc) in w.iter_mut().enumerate() {
                                *wc *= f64::from(s.weight.0[c]);
                            }
                            d = frame.to_world(s.wi).as_dvec3().normalize();
                            if w.iter().all(|&v| v == 0.0) {
                                return (d, w, bounce, Outcome::Absorbed);
                            }
                        }
                    }
                }
            }
        }
        (d, w, self.max_bounces, Outcome::Truncated)
    }

    /// Measures ρ̂ on the grid θi × φi × θo × φo (degrees; see the module doc for the estimator
    /// and `tabulated` for the grid's meaning). Each θo, φo value is the centre of a detector cell
    /// reaching halfway to its neighbours.
    pub fn measure(
        &self,
        theta_i: Vec<f64>,
        phi_i: Vec<f64>,
        theta_o: Vec<f64>,
        phi_o: Vec<f64>,
        opts: &MeasureOptions,
    ) -> Measurement {
        let (te_o, pe_o) = (theta_edges(&theta_o), phi_edges(&phi_o));
        let (te_i, pe_i) = (theta_edges(&theta_i), phi_edges(&phi_i));
        let n_bins = theta_o.len() * phi_o.len();
        let n_dirs = theta_i.len() * phi_i.len();
        let rays = opts.rays.max(1);
        let chunks_per_dir = rays.div_ceil(CHUNK);
        let jobs = n_dirs * chunks_per_dir;
        let results: Mutex<Vec<Option<Chunk>>> = Mutex::new((0..jobs).map(|_| None).collect());
        let next = AtomicUsize::new(0);
        let threads =
            if opts.threads == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { opts.threads }
                .clamp(1, jobs.max(1));
        let period = self.field.size() as f64;
        let run = || loop {
            let job = next.fetch_add(1, Ordering::Relaxed);
            if job >= jobs {
                break;
            }
            let (dir, chunk) = (job / chunks_per_dir, job % chunks_per_dir);
            let (a, b) = (dir / phi_i.len(), dir % phi_i.len());
            let count = CHUNK.min(rays - chunk * CHUNK);
            let mut rng = Pcg32::new(opts.seed ^ (dir as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15), job as u64);
            let mut c = Chunk {
                sum: vec![[0.0; 3]; n_bins],
                sum2: vec![[0.0; 3]; n_bins],
                balance: FluxBalance::default(),
                bounces: 0.0,
                escaped_rays: 0.0,
            };
            for _ in 0..count {
                let wi = match opts.beam {
                    Beam::Collimated => direction(theta_i[a], phi_i[b]),
                    Beam::Bin => {
                        // Density ∝ cos θ: sin²θ uniform over the cell, φ uniform.
                        let s2 = |d: f64| d.to_radians().sin().powi(2);
                        let (t0, t1) = te_i[a];
                        let st = (s2(t0) + rng.gen::<f64>() * (s2(t1) - s2(t0))).sqrt().min(1.0);
                        let p = pe_i[b].0 + rng.gen::<f64>() * (pe_i[b].1 - pe_i[b].0);
                        direction(st.asin().to_degrees(), p)
                    }
                };
                let (x, y) = (rng.gen::<f64>() * period, rng.gen::<f64>() * period);
                let (d, w, hits, outcome) = self.trace(x, y, -wi, &mut rng);
                let add = |acc: &mut [f64; 3]| {
                    for k in 0..3 {
                        acc[k] += w[k];
                    }
                };
                match outcome {
                    Outcome::Escaped => {
                        add(&mut c.balance.escaped);
                        c.bounces += f64::from(hits);
                        c.escaped_rays += 1.0;
                        let t = d.z.clamp(-1.0, 1.0).acos().to_degrees();
                        let p = d.y.atan2(d.x).to_degrees();
                        match theta_bin(&te_o, t) {
                            Some(ti) => {
                                let bin = ti * phi_o.len() + phi_bin(&phi_o, p);
                                for (k, wk) in w.iter().enumerate() {
                                    c.sum[bin][k] += wk;
                                    c.sum2[bin][k] += wk * wk;
                                }
                            }
                            None => add(&mut c.balance.unbinned),
                        }
                    }
                    Outcome::Truncated => add(&mut c.balance.truncated),
                    Outcome::Lost => add(&mut c.balance.lost),
                    Outcome::Absorbed => {}
                }
            }
            results.lock().unwrap_or_else(|e| e.into_inner())[job] = Some(c);
        };
        std::thread::scope(|s| {
            for _ in 0..threads {
                s.spawn(run);
            }
        });
        let results = results.into_inner().unwrap_or_else(|e| e.into_inner());
        let mut values = Vec::with_capacity(n_dirs * n_bins);
        let mut std_err = Vec::with_capacity(n_dirs * n_bins);
        let mut balance = Vec::with_capacity(n_dirs);
        let nr = rays as f64;
        for chunks in results.chunks(chunks_per_dir) {
            let mut sum = vec![[0.0f64; 3]; n_bins];
            let mut sum2 = vec![[0.0f64; 3]; n_bins];
            let mut bal = FluxBalance::default();
            let (mut bounces, mut escaped_rays) = (0.0, 0.0);
            // Merged in chunk order, so the sums do not depend on which thread ran what.
            for c in chunks.iter().map(|c| c.as_ref().expect("every job ran")) {
                for k in 0..n_bins {
                    for ch in 0..3 {
                        sum[k][ch] += c.sum[k][ch];
                        sum2[k][ch] += c.sum2[k][ch];
                    }
                }
                for ch in 0..3 {
                    bal.escaped[ch] += c.balance.escaped[ch] / nr;
                    bal.unbinned[ch] += c.balance.unbinned[ch] / nr;
                    bal.truncated[ch] += c.balance.truncated[ch] / nr;
                    bal.lost[ch] += c.balance.lost[ch] / nr;
                }
                bounces += c.bounces;
                escaped_rays += c.escaped_rays;
            }
            bal.mean_bounces = if escaped_rays > 0.0 { bounces / escaped_rays } else { 0.0 };
            balance.push(bal);
            for (ti, te) in te_o.iter().enumerate() {
                for (pi, pe) in pe_o.iter().enumerate() {
                    let k = ti * phi_o.len() + pi;
                    let omega = projected_solid_angle(*te, *pe);
                    if omega <= 0.0 {
                        values.push([-1.0; 3]);
                        std_err.push([0.0; 3]);
                        continue;
                    }
                    let mean: [f64; 3] = std::array::from_fn(|ch| sum[k][ch] / nr);
                    values.push(mean.map(|m| (m / omega) as f32));
                    std_err.push(std::array::from_fn(|ch| {
                        let var = (sum2[k][ch] / nr - mean[ch] * mean[ch]).max(0.0);
                        ((var / nr).sqrt() / omega) as f32
                    }));
                }
            }
        }
        Measurement { table: Tabulated { theta_i, phi_i, theta_o, phi_o, values }, std_err, balance, rays }
    }
}

/// How a traced ray ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Outcome {
    Escaped,
    Truncated,
    Lost,
    Absorbed,
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn cells_tile_the_hemisphere_and_bins_find_them() {
        let t = crate::measured::tabulated::uniform_theta(18);
        let p = crate::measured::tabulated::uniform_phi(72);
        let (te, pe) = (theta_edges(&t), phi_edges(&p));
        let total: f64 = te.iter().flat_map(|a| pe.iter().map(move |b| projected_solid_angle(*a, *b))).sum();
        // Everything but the ring beyond the last cell's upper edge (87.5°).
        let missing = PI * (1.0 - 87.5f64.to_radians().sin().powi(2));
        assert!((total + missing - PI).abs() < 1e-12, "{total}");
        assert_eq!(theta_bin(&te, 0.0), Some(0));
        assert_eq!(theta_bin(&te, 2.6), Some(1));
        assert_eq!(theta_bin(&te, 88.0), None);
        assert_eq!(phi_bin(&p, 358.0), 0);
        assert_eq!(phi_bin(&p, -7.0), 71);
        assert_eq!(phi_bin(&p, 182.4), 36);
    }
}
