//! Fitting analytic models to measured reflectance (`gonio fit`).
//!
//! Model: ρ(wi, wo) = k_d/π + k_s S(wi, wo; p) per channel (see `models`), with k_d, k_s ≥ 0 per
//! channel and one shape parameter p shared by the channels.
//!
//! Error: the cosine-weighted one of Ngan, Durand & Matusik,
//!   E = √( Σ_k w_k cos²θi (ρ_data − ρ_model)² / Σ_k w_k ),
//! i.e. ρ·cos θi compared in a least-squares sense over the sampled pairs, w_k the solid-angle
//! measure dωi dωo the sample stands for (so E approximates the L2 norm over both hemispheres;
//! per channel, then the root mean square of the three). We use this linear variant, not their
//! log or cube-root ones, so that k_d and k_s stay linear. Pairs with θi or θo beyond 80° are
//! left out: grazing measurements are the least reliable and matter least after the cosine.
//!
//! Search (variable projection, Golub & Pereyra 1973): for a given p the six k's are the
//! nonnegative least-squares solution of a 2 × 2 problem per channel, solved in closed form, and
//! LM (`lm`) minimises the resulting residual over p alone, from several starts.
//! Uncertainties: the sandwich (heteroscedasticity-robust) covariance
//! (JᵀJ)⁻¹ (Σ_k J_kᵀ r_k² J_k) (JᵀJ)⁻¹ of all seven parameters at the minimum.
//!
//! Source: A. Ngan, F. Durand, W. Matusik, "Experimental Analysis of BRDF Models", EGSR 2005;
//! G. H. Golub, V. Pereyra, SIAM J. Numer. Anal. 10(2), 1973.

pub mod lm;
pub mod models;
pub mod report;

pub use models::FitModel;

use crate::measured::merl::{entry_angles, entry_index, from_half_diff, PHI_D_RES, THETA_D_RES, THETA_H_RES};
use crate::measured::{MerlTable, Tabulated};
use radiometry::Vec3;
use rand::Rng;
use rand_pcg::Pcg32;
use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, PI};

/// Largest θi, θo fitted (degrees).
pub const MAX_THETA_DEG: f64 = 80.0;

/// One measurement: a direction pair, ρ per channel (1/sr) and the measure it stands for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sample {
    /// Towards the light.
    pub wi: Vec3,
    /// Towards the viewer.
    pub wo: Vec3,
    /// Measured ρ, RGB.
    pub rho: [f64; 3],
    /// The solid-angle measure dωi dωo this sample stands for (any common scale).
    pub weight: f64,
}

/// Whether a pair is inside the fitted range.
fn in_range(wi: Vec3, wo: Vec3) -> bool {
    let c = (MAX_THETA_DEG.to_radians().cos()) as f32;
    wi.z >= c && wo.z >= c
}

/// `n` distinct entries of the MERL grid (θi, θo ≤ 80°, measured channels only), drawn uniformly
/// by index with seed `seed`: the √θh spacing crowds entries near the specular peak, and each
/// sample's weight is its cell's exact measure 4 cos θd sin θd sin θh dθh dθd dφd (dφh
/// integrated out), so weighted sums still approximate integrals over direction pairs.
/// `value(index, wi, wo)` gives the entry's ρ, or `None` when it is not measured.
pub fn merl_grid_samples(n: usize, seed: u64, value: &dyn Fn(usize, Vec3, Vec3) -> Option<[f64; 3]>) -> Vec<Sample> {
    let mut rng = Pcg32::new(seed ^ 0x6A09_E667_F3BC_C908, 0xF17);
    let mut seen = std::collections::HashSet::new();
    let mut out = Vec::with_capacity(n);
    let mut tries = 0usize;
    while out.len() < n && tries < 50 * n.max(1) {
        tries += 1;
        let (ih, id, ip) = (rng.gen_range(0..THETA_H_RES), rng.gen_range(0..THETA_D_RES), rng.gen_range(0..PHI_D_RES));
        let idx = entry_index(ih, id, ip);
        if !seen.insert(idx) {
            continue;
        }
        let a = entry_angles(ih, id, ip);
        let (wi, wo) = from_half_diff(a.theta_h, a.theta_d, a.phi_d);
        if !in_range(wi, wo) {
            continue;
        }
        let Some(rho) = value(idx, wi, wo) else { continue };
        // Cell edges half an index either side, clamped to the axes' ends.
        let th = |x: f64| (x.clamp(0.0, THETA_H_RES as f64) / THETA_H_RES as f64).powi(2) * FRAC_PI_2;
        let td = |x: f64| x.clamp(0.0, THETA_D_RES as f64) / THETA_D_RES as f64 * FRAC_PI_2;
        let (h0, h1) = (th(ih as f64 - 0.5), th(ih as f64 + 0.5));
        let (d0, d1) = (td(id as f64 - 0.5), td(id as f64 + 0.5));
        let m_h = h0.cos() - h1.cos();
        let m_d = 0.5 * (d1.sin().powi(2) - d0.sin().powi(2));
        let weight = 4.0 * m_h * m_d * (PI / PHI_D_RES as f64);
        if weight > 0.0 {
            out.push(Sample { wi, wo, rho, weight });
        }
    }
    out
}

/// Samples from a MERL table (see `merl_grid_samples`).
pub fn merl_samples(table: &MerlTable, n: usize, seed: u64) -> Vec<Sample> {
    let e = table.entries();
    merl_grid_samples(n, seed, &|idx, _, _| {
        let c = e[idx];
        c.iter().all(|v| *v >= 0.0).then(|| c.map(|v| v as f64))
    })
}

/// Every measured point of a tabulated grid within 80°, weighted by its cell's measure
/// (Δcos θ Δφ for each direction; a single φi counts as the whole circle, as an isotropic
/// surface measured in one plane stands for every plane).
pub fn tabulated_samples(t: &Tabulated) -> Vec<Sample> {
    fn theta_cells(axis: &[f64]) -> Vec<f64> {
        (0..axis.len())
            .map(|k| {
                let lo = if k == 0 { 0.0 } else { 0.5 * (axis[k - 1] + axis[k]) };
                let hi = if k + 1 == axis.len() { 90.0 } else { 0.5 * (axis[k] + axis[k + 1]) };
                (lo.to_radians().cos() - hi.to_radians().cos()).max(0.0)
            })
            .collect()
    }
    let phi_cell = |axis: &[f64]| 2.0 * PI / axis.len().max(1) as f64;
    let dir = |theta: f64, phi: f64| {
        let (st, ct) = theta.to_radians().sin_cos();
        let (sp, cp) = phi.to_radians().sin_cos();
        Vec3::new((st * cp) as f32, (st * sp) as f32, ct as f32)
    };
    let (wti, wto) = (theta_cells(&t.theta_i), theta_cells(&t.theta_o));
    let (dpi, dpo) = (phi_cell(&t.phi_i), phi_cell(&t.phi_o));
    let mut out = Vec::new();
    let mut k = 0;
    for (a, &ti) in t.theta_i.iter().enumerate() {
        for &pi in &t.phi_i {
            for (c, &to) in t.theta_o.iter().enumerate() {
                for &po in &t.phi_o {
                    let v = t.values[k];
                    k += 1;
                    let (wi, wo) = (dir(ti, pi), dir(to, po));
                    let weight = wti[a] * dpi * wto[c] * dpo;
                    if v.iter().all(|x| *x >= 0.0) && in_range(wi, wo) && weight > 0.0 {
                        out.push(Sample { wi, wo, rho: v.map(|x| x as f64), weight });
                    }
                }
            }
        }
    }
    out
}

/// A fitted model.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    /// Which model.
    pub model: FitModel,
    /// The shape parameter (α, m or k_e).
    pub shape: f64,
    /// Diffuse albedo a = π k_d per channel (the registry's `diffuse`).
    pub diffuse: [f64; 3],
    /// Specular scale k_s per channel.
    pub ks: [f64; 3],
    /// Standard errors of (shape, diffuse r g b, ks r g b), from the sandwich covariance.
    pub std_err: [f64; 7],
    /// Ngan et al.'s error E (1/sr), RMS over the channels.
    pub error: f64,
    /// E divided by the same norm of the data: a relative error.
    pub relative_error: f64,
    /// LM iterations, summed over the starts.
    pub iterations: usize,
    /// Whether the best start's LM run met a tolerance.
    pub converged: bool,
}

impl Fit {
    /// ρ of the fitted model, RGB, in f64.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> [f64; 3] {
        let s = self.model.lobe(self.shape).eval(wi, wo);
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return [0.0; 3];
        }
        std::array::from_fn(|c| self.diffuse[c] * FRAC_1_PI + self.ks[c] * s.0[c] as f64)
    }
}

/// The unit-scale lobe values of every sample at shape `p`.
fn lobe_values(model: FitModel, p: f64, data: &[Sample]) -> Vec<f64> {
    let lobe = model.lobe(p);
    data.iter().map(|s| lobe.eval(s.wi, s.wo).0[0] as f64).collect()
}

/// Per channel, the nonnegative (a, k_s) minimising Σ q_k (y − a/π − k_s S)², q = w cos²θi, with
/// a the diffuse albedo.
fn solve_linear(data: &[Sample], lobe: &[f64]) -> ([f64; 3], [f64; 3]) {
    let (mut aa, mut ab, mut bb) = (0.0, 0.0, 0.0);
    let (mut ay, mut by) = ([0.0; 3], [0.0; 3]);
    for (s, &l) in data.iter().zip(lobe) {
        let q = s.weight * (s.wi.z as f64).powi(2);
        let a = FRAC_1_PI;
        aa += q * a * a;
        ab += q * a * l;
        bb += q * l * l;
        for c in 0..3 {
            ay[c] += q * a * s.rho[c];
            by[c] += q * l * s.rho[c];
        }
    }
    let mut kd = [0.0; 3];
    let mut ks = [0.0; 3];
    for c in 0..3 {
        let det = aa * bb - ab * ab;
        let (mut d, mut k) = if det > 1e-12 * aa * bb {
            ((bb * ay[c] - ab * by[c]) / det, (aa * by[c] - ab * ay[c]) / det)
        } else {
            (-1.0, -1.0)
        };
        if !(d >= 0.0 && k >= 0.0) {
            // The unconstrained optimum leaves the orthant: the best of the two edges (each a
            // one-variable problem) and the origin.
            let cost = |d: f64, k: f64| aa * d * d + 2.0 * ab * d * k + bb * k * k - 2.0 * (d * ay[c] + k * by[c]);
            let d_only = if aa > 0.0 { (ay[c] / aa).max(0.0) } else { 0.0 };
            let k_only = if bb > 0.0 { (by[c] / bb).max(0.0) } else { 0.0 };
            (d, k) = if cost(d_only, 0.0) <= cost(0.0, k_only) { (d_only, 0.0) } else { (0.0, k_only) };
        }
        kd[c] = d;
        ks[c] = k;
    }
    (kd, ks)
}

/// Residuals √q (y − ρ) for all samples and channels (3 per sample).
fn residuals(data: &[Sample], lobe: &[f64], kd: &[f64; 3], ks: &[f64; 3], r: &mut [f64]) {
    for (k, (s, &l)) in data.iter().zip(lobe).enumerate() {
        let sq = s.weight.sqrt() * s.wi.z as f64;
        for c in 0..3 {
            r[3 * k + c] = sq * (s.rho[c] - (kd[c] * FRAC_1_PI + ks[c] * l));
        }
    }
}

/// Fits `model` to `data` by LM over the shape parameter with the k's projected out.
pub fn fit(model: FitModel, data: &[Sample]) -> Fit {
    let m = 3 * data.len();
    let total_w: f64 = data.iter().map(|s| s.weight).sum::<f64>().max(f64::MIN_POSITIVE);
    let projected = |t: &[f64], r: &mut [f64]| {
        let lobe = lobe_values(model, model.shape_from_free(t[0]), data);
        let (kd, ks) = solve_linear(data, &lobe);
        residuals(data, &lobe, &kd, &ks, r);
    };
    // The lobe is evaluated in f32: a step of 1e-3 in t keeps the central difference's rounding
    // error near 1e-7/1e-3 relative, and its truncation error (∝ step²) near 1e-6.
    let opts = lm::LmOptions { fd_step: 1e-3, cost_tolerance: 1e-10, step_tolerance: 1e-7, ..Default::default() };
    let mut best: Option<lm::LmResult> = None;
    let mut iterations = 0;
    for &p0 in model.starts() {
        let res = lm::minimize(projected, &[model.free_from_shape(p0)], m, &opts);
        iterations += res.iterations;
        if best.as_ref().is_none_or(|b| res.cost < b.cost) {
            best = Some(res);
        }
    }
    let best = best.expect("at least one start");
    let shape = model.shape_from_free(best.x[0]);
    let lobe = lobe_values(model, shape, data);
    let (kd, ks) = solve_linear(data, &lobe);
    let mut r = vec![0.0; m];
    residuals(data, &lobe, &kd, &ks, &mut r);
    let error = (r.iter().map(|v| v * v).sum::<f64>() / (3.0 * total_w)).sqrt();
    let norm = (data
        .iter()
        .map(|s| s.weight * (s.wi.z as f64).powi(2) * s.rho.iter().map(|v| v * v).sum::<f64>())
        .sum::<f64>()
        / (3.0 * total_w))
        .sqrt();
    let std_err = std_errors(model, data, shape, &lobe, &ks, &r);
    Fit {
        model,
        shape,
        diffuse: kd,
        ks,
        std_err,
        error,
        relative_error: if norm > 0.0 { error / norm } else { 0.0 },
        iterations,
        converged: best.converged,
    }
}

/// Sandwich standard errors of (shape, a_r, a_g, a_b, ks_r, ks_g, ks_b) at the fit.
fn std_errors(model: FitModel, data: &[Sample], shape: f64, lobe: &[f64], ks: &[f64; 3], r: &[f64]) -> [f64; 7] {
    // ∂S/∂p by a central difference in log p (f32 lobe: see `fit`).
    let h: f64 = 1e-3;
    let dp = shape * (h.exp() - (-h).exp());
    let (lp, lm_) = (lobe_values(model, shape * h.exp(), data), lobe_values(model, shape * (-h).exp(), data));
    let mut jtj = [0.0; 49];
    let mut meat = [0.0; 49];
    for (k, s) in data.iter().enumerate() {
        let sq = s.weight.sqrt() * s.wi.z as f64;
        let ds = (lp[k] - lm_[k]) / dp;
        for c in 0..3 {
            // Residual y − ρ: derivatives of −ρ, with ∂ρ/∂a = 1/π.
            let mut g = [0.0; 7];
            g[0] = -sq * ks[c] * ds;
            g[1 + c] = -sq * FRAC_1_PI;
            g[4 + c] = -sq * lobe[k];
            let r2 = r[3 * k + c] * r[3 * k + c];
            for a in 0..7 {
                for b in 0..7 {
                    jtj[a * 7 + b] += g[a] * g[b];
                    meat[a * 7 + b] += g[a] * g[b] * r2;
                }
            }
        }
    }
    // Columns of (JᵀJ)⁻¹ one at a time; a parameter with no influence (e.g. k_s = 0 makes the
    // shape invisible) makes JᵀJ singular: report infinite errors then.
    let mut inv = [0.0; 49];
    for j in 0..7 {
        let mut e = [0.0; 7];
        e[j] = 1.0;
        match lm::cholesky_solve(&jtj, &e) {
            Some(col) => {
                for i in 0..7 {
                    inv[i * 7 + j] = col[i];
                }
            }
            None => return [f64::INFINITY; 7],
        }
    }
    std::array::from_fn(|a| {
        let mut v = 0.0;
        for i in 0..7 {
            for j in 0..7 {
                v += inv[a * 7 + i] * meat[i * 7 + j] * inv[j * 7 + a];
            }
        }
        v.max(0.0).sqrt()
    })
}

/// Fits every model and returns them best first (lowest error).
pub fn fit_all(data: &[Sample]) -> Vec<Fit> {
    let mut fits: Vec<Fit> = FitModel::ALL.iter().map(|&m| fit(m, data)).collect();
    fits.sort_by(|a, b| a.error.total_cmp(&b.error));
    fits
}
