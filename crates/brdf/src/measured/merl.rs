//! The MERL BRDF database's binary format (Matusik, Pfister, Brand & McMillan 2003), read and
//! written byte for byte as its reference reader (`BRDFRead.cpp`) defines it:
//!
//! - a header of three little-endian int32: 90 (θh), 90 (θd), 180 (φd);
//! - 3 × 1,458,000 little-endian float64, one channel after another (all red, then green, then
//!   blue), each entry index = (iθh · 90 + iθd) · 180 + iφd, stored scaled: ρ = raw × s with
//!   s = 1/1500, 1.15/1500, 1.66/1500 for red, green, blue;
//! - negative raw values mean "not measured" (e.g. a direction below the horizon).
//!
//! A full file is 12 + 3 · 1,458,000 · 8 = 34,992,012 bytes.
//!
//! Coordinates are Rusinkiewicz's half/difference angles (Rusinkiewicz 1998, "A new change of
//! variables for efficient BRDF representation"): h = (wi + wo)/|wi + wo| with polar angles
//! (θh, φh); d is wi expressed in the frame where h is the pole, with polar angles (θd, φd).
//! Swapping wi and wo turns φd into φd + π, so by reciprocity φd is folded into [0, π).
//! Indices: iθh = √(θh / (π/2)) · 90 (dense near the specular peak), iθd = θd / (π/2) · 90,
//! iφd = φd / π · 180, each truncated and clamped to the table.
//!
//! Sample positions: entry i of an axis holds the value at that axis' coordinate i (θh = (i/90)²
//! · 90°, θd = i°, φd = i°); the reference reader's truncating lookup reads it for the whole
//! interval [i, i + 1). `lookup` interpolates trilinearly between those nodes instead (φd wraps
//! around, since φd = π is φd = 0); `lookup_nearest` reproduces the reference reader. Both depend
//! on (wi, wo) only through a fold that maps (wi, wo) and (wo, wi) to bitwise the same
//! coordinates, so reciprocity holds exactly.

use super::error::MeasuredError;
use crate::Brdf;
use radiometry::{DVec3, Rgb, Vec3};
use std::f64::consts::{FRAC_PI_2, PI};
use std::path::Path;

/// Entries along θh.
pub const THETA_H_RES: usize = 90;
/// Entries along θd.
pub const THETA_D_RES: usize = 90;
/// Entries along φd (over [0, π)).
pub const PHI_D_RES: usize = 180;
/// Entries per channel: 90 · 90 · 180.
pub const ENTRIES: usize = THETA_H_RES * THETA_D_RES * PHI_D_RES;
/// Bytes of a full MERL file: the 12-byte header and 3 channels of float64.
pub const FILE_BYTES: u64 = 12 + 3 * ENTRIES as u64 * 8;
/// Raw value × scale = ρ in 1/sr, per channel (red, green, blue).
pub const SCALE: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];
const CHANNELS: [&str; 3] = ["red", "green", "blue"];

/// Rusinkiewicz's half/difference angles, in radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfDiff {
    /// Polar angle of the half vector, [0, π/2].
    pub theta_h: f64,
    /// Polar angle of wi about the half vector, [0, π/2] for directions above the surface.
    pub theta_d: f64,
    /// Azimuth of wi about the half vector, folded into [0, π).
    pub phi_d: f64,
}

/// Rotates `v` so that the direction with polar angles (θ, φ) becomes the pole, given cos and
/// sin of θ and φ: Rot_y(−θ) · Rot_z(−φ) · v.
#[inline]
fn to_half_frame(v: DVec3, ct: f64, st: f64, cp: f64, sp: f64) -> DVec3 {
    let x = v.x * cp + v.y * sp;
    let y = -v.x * sp + v.y * cp;
    DVec3::new(x * ct - v.z * st, y, x * st + v.z * ct)
}

/// The half/difference angles of a direction pair; symmetric in `wi` and `wo` bit for bit.
pub fn half_diff(wi: Vec3, wo: Vec3) -> HalfDiff {
    let (a, b) = (wi.as_dvec3(), wo.as_dvec3());
    // a + b is the same sum whichever is first: h (and its frame) is exactly symmetric.
    let sum = a + b;
    let len = sum.length();
    let h = if len > 1e-12 { sum / len } else { DVec3::Z };
    let theta_h = h.z.clamp(-1.0, 1.0).acos();
    let r = (h.x * h.x + h.y * h.y).sqrt();
    let (cp, sp) = if r > 1e-15 { (h.x / r, h.y / r) } else { (1.0, 0.0) };
    let (ct, st) = (h.z, r);
    let di = to_half_frame(a, ct, st, cp, sp);
    let dono = to_half_frame(b, ct, st, cp, sp);
    // wo is wi reflected about h, i.e. (−x, −y, z) in the half frame. Averaging the two
    // estimates this way makes the swapped pair give exactly (−x, −y, z).
    let mut d = DVec3::new(0.5 * (di.x - dono.x), 0.5 * (di.y - dono.y), 0.5 * (di.z + dono.z));
    let dl = d.length();
    if dl > 1e-300 {
        d /= dl;
    }
    let theta_d = d.z.clamp(-1.0, 1.0).acos();
    // Fold (x, y) and (−x, −y) onto one vector before the atan2, so both orders agree exactly.
    let (mut x, mut y) = (d.x, d.y);
    if y < 0.0 || (y == 0.0 && x < 0.0) {
        x = -x;
        y = -y;
    }
    let mut phi_d = y.atan2(x);
    if !(0.0..PI).contains(&phi_d) {
        phi_d = 0.0;
    }
    HalfDiff { theta_h, theta_d, phi_d }
}

/// The direction pair with half vector at (θh, φh = 0) and difference angles (θd, φd).
pub fn from_half_diff(theta_h: f64, theta_d: f64, phi_d: f64) -> (Vec3, Vec3) {
    let (st, ct) = theta_d.sin_cos();
    let (sp, cp) = phi_d.sin_cos();
    let d = DVec3::new(st * cp, st * sp, ct);
    let (sh, ch) = theta_h.sin_cos();
    let rot = |v: DVec3| DVec3::new(v.x * ch + v.z * sh, v.y, -v.x * sh + v.z * ch);
    let wi = rot(d);
    let wo = rot(DVec3::new(-d.x, -d.y, d.z));
    (wi.as_vec3().normalize_or_zero(), wo.as_vec3().normalize_or_zero())
}

/// Continuous table coordinates (iθh, iθd, iφd) of a direction pair; entry i sits at i.
#[inline]
pub fn table_coords(hd: &HalfDiff) -> [f64; 3] {
    [
        (hd.theta_h.max(0.0) / FRAC_PI_2).sqrt() * THETA_H_RES as f64,
        hd.theta_d.max(0.0) / FRAC_PI_2 * THETA_D_RES as f64,
        hd.phi_d.max(0.0) / PI * PHI_D_RES as f64,
    ]
}

/// The angles of table entry (iθh, iθd, iφd).
pub fn entry_angles(ih: usize, id: usize, ip: usize) -> HalfDiff {
    let t = ih as f64 / THETA_H_RES as f64;
    HalfDiff {
        theta_h: t * t * FRAC_PI_2,
        theta_d: id as f64 / THETA_D_RES as f64 * FRAC_PI_2,
        phi_d: ip as f64 / PHI_D_RES as f64 * PI,
    }
}

/// Index of entry (iθh, iθd, iφd) within one channel.
#[inline]
pub fn entry_index(ih: usize, id: usize, ip: usize) -> usize {
    (ih * THETA_D_RES + id) * PHI_D_RES + ip
}

/// A full MERL table, held as ρ in 1/sr (scales applied), RGB per entry; a negative channel
/// means "not measured".
#[derive(Clone, PartialEq)]
pub struct MerlTable {
    rgb: Vec<[f32; 3]>,
}

impl std::fmt::Debug for MerlTable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let measured = self.rgb.iter().filter(|c| c.iter().all(|&v| v >= 0.0)).count();
        write!(f, "MerlTable {{ {ENTRIES} entries, {measured} measured }}")
    }
}

impl MerlTable {
    /// A table from ρ per entry, in `entry_index` order (negative = not measured).
    pub fn from_entries(rgb: Vec<[f32; 3]>) -> Option<Self> {
        (rgb.len() == ENTRIES && rgb.iter().flatten().all(|v| v.is_finite())).then_some(MerlTable { rgb })
    }

    /// ρ per entry in `entry_index` order, in 1/sr (negative = not measured).
    pub fn entries(&self) -> &[[f32; 3]] {
        &self.rgb
    }

    /// Tabulates `f(wi, wo)` at every entry (on all cores); entries with a direction below the
    /// horizon are written "not measured", as a gonio-reflectometer cannot see them.
    pub fn tabulate(f: &(dyn Fn(Vec3, Vec3) -> Rgb + Sync)) -> Self {
        let mut rgb = vec![[0.0f32; 3]; ENTRIES];
        let per_h = THETA_D_RES * PHI_D_RES;
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()).clamp(1, THETA_H_RES);
        let rows_per = THETA_H_RES.div_ceil(threads);
        std::thread::scope(|s| {
            for (t, chunk) in rgb.chunks_mut(rows_per * per_h).enumerate() {
                s.spawn(move || {
                    for (k, out) in chunk.iter_mut().enumerate() {
                        let ih = t * rows_per + k / per_h;
                        let (id, ip) = ((k % per_h) / PHI_D_RES, k % PHI_D_RES);
                        let a = entry_angles(ih, id, ip);
                        let (wi, wo) = from_half_diff(a.theta_h, a.theta_d, a.phi_d);
                        *out = if wi.z > 0.0 && wo.z > 0.0 {
                            let v = f(wi, wo);
                            v.0.map(|c| if c.is_finite() { c.max(0.0) } else { -1.0 })
                        } else {
                            [-1.0; 3]
                        };
                    }
                });
            }
        });
        MerlTable { rgb }
    }

    /// Tabulates a model, as a virtual gonio-reflectometer would measure it.
    pub fn from_brdf(brdf: &dyn Brdf) -> Self {
        Self::tabulate(&|wi, wo| brdf.eval(wi, wo))
    }

    /// Reads a MERL file; `path` names it in errors.
    pub fn read(path: &Path) -> Result<Self, MeasuredError> {
        let bytes = std::fs::read(path).map_err(|e| MeasuredError::io(path, e))?;
        Self::parse(&bytes, path)
    }

    /// Parses the bytes of a MERL file; `path` names it in errors.
    pub fn parse(bytes: &[u8], path: &Path) -> Result<Self, MeasuredError> {
        let dims_text = format!("{THETA_H_RES} × {THETA_D_RES} × {PHI_D_RES}");
        let size_err = |what, expected| MeasuredError::Size {
            path: path.to_path_buf(),
            what,
            expected,
            found: bytes.len() as u64,
            dims: dims_text.clone(),
        };
        if bytes.len() < 12 {
            return Err(size_err("truncated header", FILE_BYTES));
        }
        let word = |k: usize| -> [u8; 4] { bytes[4 * k..4 * k + 4].try_into().expect("4 bytes") };
        let le = [0, 1, 2].map(|k| i32::from_le_bytes(word(k)));
        let be = [0, 1, 2].map(|k| i32::from_be_bytes(word(k)));
        let want = [THETA_H_RES as i32, THETA_D_RES as i32, PHI_D_RES as i32];
        if le != want {
            return Err(if be == want {
                MeasuredError::Endianness { path: path.to_path_buf() }
            } else {
                MeasuredError::Dimensions { path: path.to_path_buf(), dims: le.map(i64::from) }
            });
        }
        match (bytes.len() as u64).cmp(&FILE_BYTES) {
            std::cmp::Ordering::Less => return Err(size_err("truncated", FILE_BYTES)),
            std::cmp::Ordering::Greater => return Err(size_err("trailing bytes", FILE_BYTES)),
            std::cmp::Ordering::Equal => {}
        }
        let mut rgb = vec![[0.0f32; 3]; ENTRIES];
        for (c, chunk) in bytes[12..].chunks_exact(ENTRIES * 8).enumerate() {
            for (k, raw) in chunk.chunks_exact(8).enumerate() {
                let v = f64::from_le_bytes(raw.try_into().expect("8 bytes"));
                let rho = (v * SCALE[c]) as f32;
                if !v.is_finite() || !rho.is_finite() {
                    let (ih, rest) = (k / (THETA_D_RES * PHI_D_RES), k % (THETA_D_RES * PHI_D_RES));
                    return Err(MeasuredError::NotFinite {
                        path: path.to_path_buf(),
                        value: v,
                        channel: CHANNELS[c],
                        theta_h: ih,
                        theta_d: rest / PHI_D_RES,
                        phi_d: rest % PHI_D_RES,
                    });
                }
                rgb[k][c] = if v < 0.0 { -1.0 } else { rho };
            }
        }
        Ok(MerlTable { rgb })
    }

    /// The file's bytes: header, then each channel's raw (unscaled) float64 values.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(FILE_BYTES as usize);
        for d in [THETA_H_RES, THETA_D_RES, PHI_D_RES] {
            out.extend_from_slice(&(d as i32).to_le_bytes());
        }
        for (c, scale) in SCALE.iter().enumerate() {
            for e in &self.rgb {
                let raw = if e[c] < 0.0 { -1.0 } else { f64::from(e[c]) / scale };
                out.extend_from_slice(&raw.to_le_bytes());
            }
        }
        out
    }

    /// Writes the table to `path` (through a temporary file and a rename, so a reader never
    /// sees half a file).
    pub fn write(&self, path: &Path) -> Result<(), MeasuredError> {
        super::write_atomic(path, &self.to_bytes())
    }

    /// ρ at entry (iθh, iθd, iφd); negative channels are "not measured".
    #[inline]
    pub fn entry(&self, ih: usize, id: usize, ip: usize) -> [f32; 3] {
        self.rgb[entry_index(ih, id, ip)]
    }

    /// The reference reader's lookup: the entry whose interval holds the coordinates, with
    /// unmeasured channels read as 0.
    pub fn lookup_nearest(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::ZERO;
        }
        let u = table_coords(&half_diff(wi, wo));
        let idx = |x: f64, n: usize| (x as usize).min(n - 1);
        let e = self.entry(idx(u[0], THETA_H_RES), idx(u[1], THETA_D_RES), idx(u[2], PHI_D_RES));
        Rgb::new(e[0].max(0.0), e[1].max(0.0), e[2].max(0.0))
    }

    /// Trilinear interpolation between entries (φd wrapping around, θ axes held at their last
    /// entry); unmeasured entries are left out and the remaining weights renormalised, and where
    /// no neighbouring entry is measured the value is 0.
    pub fn lookup(&self, wi: Vec3, wo: Vec3) -> Rgb {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Rgb::ZERO;
        }
        let u = table_coords(&half_diff(wi, wo));
        let axis = |x: f64, n: usize| -> ([usize; 2], f32) {
            let x = x.clamp(0.0, (n - 1) as f64);
            let i0 = (x as usize).min(n - 1);
            let i1 = (i0 + 1).min(n - 1);
            ([i0, i1], (x - i0 as f64) as f32)
        };
        let (h, fh) = axis(u[0], THETA_H_RES);
        let (d, fd) = axis(u[1], THETA_D_RES);
        let p0 = (u[2] as usize).min(PHI_D_RES - 1);
        let fp = (u[2] - p0 as f64).clamp(0.0, 1.0) as f32;
        let p = [p0, (p0 + 1) % PHI_D_RES];
        let mut sum = [0.0f32; 3];
        let mut wsum = [0.0f32; 3];
        for (a, wa) in [(h[0], 1.0 - fh), (h[1], fh)] {
            for (b, wb) in [(d[0], 1.0 - fd), (d[1], fd)] {
                for (c, wc) in [(p[0], 1.0 - fp), (p[1], fp)] {
                    let w = wa * wb * wc;
                    if w <= 0.0 {
                        continue;
                    }
                    let e = self.entry(a, b, c);
                    for k in 0..3 {
                        if e[k] >= 0.0 {
                            sum[k] += w * e[k];
                            wsum[k] += w;
                        }
                    }
                }
            }
        }
        let ch = |k: usize| if wsum[k] > 1e-6 { (sum[k] / wsum[k]).max(0.0) } else { 0.0 };
        Rgb::new(ch(0), ch(1), ch(2))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_diff_round_trips_and_is_reciprocal_bit_for_bit() {
        for &(th, td, pd) in &[(0.3, 0.5, 0.2), (0.01, 1.2, 2.9), (1.0, 0.1, 1.5), (0.6, 0.7, 3.0)] {
            let (wi, wo) = from_half_diff(th, td, pd);
            let a = half_diff(wi, wo);
            assert!((a.theta_h - th).abs() < 1e-6 && (a.theta_d - td).abs() < 1e-6, "{a:?}");
            assert!((a.phi_d - pd).abs() < 1e-5, "{a:?} vs {pd}");
            // Swapping: the same coordinates exactly (φd folds by π).
            assert_eq!(half_diff(wo, wi), a);
        }
        // The specular configuration: h at the normal, θd = θi.
        let wi = Vec3::new(0.6, 0.0, 0.8);
        let a = half_diff(wi, Vec3::new(-0.6, 0.0, 0.8));
        assert!(a.theta_h.abs() < 1e-6 && (a.theta_d - 0.8f64.acos()).abs() < 1e-6, "{a:?}");
    }

    #[test]
    fn index_formulas_match_the_reference_reader() {
        // θh index = √(θh/(π/2))·90: θh = 22.5° is a quarter of the range, index 45.
        let hd = HalfDiff { theta_h: FRAC_PI_2 / 4.0, theta_d: 30f64.to_radians(), phi_d: 90f64.to_radians() };
        let u = table_coords(&hd);
        assert!((u[0] - 45.0).abs() < 1e-9 && (u[1] - 30.0).abs() < 1e-9 && (u[2] - 90.0).abs() < 1e-9, "{u:?}");
        assert_eq!(FILE_BYTES, 34_992_012);
        assert_eq!(entry_index(1, 0, 0), 16_200);
    }
}
