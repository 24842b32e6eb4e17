//! An equirectangular environment map, with Mitsuba 3's lookup: direction d (world, +Y up)
//! maps to u = atan2(d.x, −d.z)/2π (mod 1), v = acos(d.y)/π; texel (i, j) is centred at
//! u = (i + ½)/W, v = j/(H − 1); radiance is bilinear between texel centres, periodic in u.
//!
//! Importance sampling: the sphere is cut into cells whose corners are four neighbouring
//! texel centres (W columns, H − 1 rows). Cell (i, j) is chosen with probability ∝ its mean
//! corner luminance × its solid angle Δφ·(cos θj − cos θj+1) (that is, luminance × sin θ
//! integrated over the cell), then a direction is drawn uniformly in solid angle within it.
//! The bilinear radiance is zero over a cell only when all four corners are, so every
//! direction that carries light has a positive density.

use crate::distribution::Distribution1D;
use crate::error::{Error, Result};
use crate::image::Image;
use crate::light::LightSample;
use glam::{Vec2, Vec3};
use radiometry::warp::{uniform_sphere, uniform_sphere_pdf};
use radiometry::Rgb;
use std::f32::consts::{PI, TAU};

/// An environment map light.
#[derive(Clone, Debug)]
pub struct EnvMap {
    width: usize,
    height: usize,
    /// Radiance per texel (already multiplied by the scale).
    texels: Vec<Rgb>,
    /// Picks a cell row.
    rows: Distribution1D,
    /// Picks a cell column within each row.
    columns: Vec<Distribution1D>,
    /// cos θ at each texel row (the cell row boundaries), j = 0..H.
    cos_theta: Vec<f32>,
    /// False: sample the sphere uniformly instead (for tests and comparisons).
    pub importance: bool,
    /// The map's rotation into the world (Mitsuba's `to_world`); None for the identity.
    to_world: Option<glam::Mat3>,
}

/// The (u, v) of Mitsuba's lookup for a unit direction.
#[inline]
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let u = d.x.atan2(-d.z) * (0.5 / PI);
    Vec2::new(if u < 0.0 { u + 1.0 } else { u }, d.y.clamp(-1.0, 1.0).acos() * (1.0 / PI))
}

/// The unit direction with lookup coordinates (u, v).
#[inline]
pub fn uv_to_direction(uv: Vec2) -> Vec3 {
    let (sin_t, cos_t) = (uv.y * PI).sin_cos();
    let (sin_p, cos_p) = (uv.x * TAU).sin_cos();
    Vec3::new(sin_t * sin_p, cos_t, -sin_t * cos_p)
}

impl EnvMap {
    /// From an image (at least 1×2 texels) and a radiance scale.
    pub fn new(image: &Image, scale: f32) -> Result<Self> {
        let (w, h) = (image.width as usize, image.height as usize);
        if w < 1 || h < 2 {
            return Err(Error::Invalid(format!("environment map of {w}x{h} texels: need at least 1x2")));
        }
        if let Some(i) = image.pixels.iter().position(|p| !p.is_finite()) {
            return Err(Error::Invalid(format!("environment map texel ({}, {}) is not finite", i % w, i / w)));
        }
        let texels: Vec<Rgb> = image.pixels.iter().map(|&p| p * scale).collect();
        let cos_theta: Vec<f32> = (0..h).map(|j| (PI * j as f32 / (h - 1) as f32).cos()).collect();
        let lum = |i: usize, j: usize| texels[j * w + i % w].luminance().max(0.0);
        let dphi = TAU / w as f32;
        let mut row_weights = Vec::with_capacity(h - 1);
        let mut columns = Vec::with_capacity(h - 1);
        for j in 0..h - 1 {
            let omega = dphi * (cos_theta[j] - cos_theta[j + 1]).max(0.0);
            let weights: Vec<f32> = (0..w)
                .map(|i| 0.25 * (lum(i, j) + lum(i + 1, j) + lum(i, j + 1) + lum(i + 1, j + 1)) * omega)
                .collect();
            let d = Distribution1D::new(&weights);
            row_weights.push(d.total() as f32);
            columns.push(d);
        }
        Ok(EnvMap {
            width: w,
            height: h,
            texels,
            rows: Distribution1D::new(&row_weights),
            columns,
            cos_theta,
            importance: true,
            to_world: None,
        })
    }

    /// The map turned by the rotation `r` (world = r · map direction). None when `r` is not
    /// a rotation (orthonormal with determinant 1, to 1e-4): other maps would not keep the
    /// density normalised.
    pub fn with_rotation(mut self, r: glam::Mat3) -> Option<Self> {
        let err = (r.transpose() * r - glam::Mat3::IDENTITY).to_cols_array().iter().fold(0.0f32, |a, x| a.max(x.abs()));
        if !(err < 1e-4 && (r.determinant() - 1.0).abs() < 1e-4) {
            return None;
        }
        self.to_world = (r != glam::Mat3::IDENTITY).then_some(r);
        Some(self)
    }

    /// A world direction in the map's frame.
    #[inline]
    fn to_map(&self, d: Vec3) -> Vec3 {
        match &self.to_world {
            Some(r) => r.transpose() * d,
            None => d,
        }
    }

    /// Texel (column i, row j).
    #[inline]
    pub fn texel(&self, i: usize, j: usize) -> Rgb {
        self.texels[j * self.width + i]
    }

    /// Radiance arriving from direction `d` (unit, pointing away from the scene).
    pub fn eval(&self, d: Vec3) -> Rgb {
        let uv = direction_to_uv(self.to_map(d));
        let x = uv.x * self.width as f32 - 0.5;
        let y = uv.y * (self.height - 1) as f32;
        let i0 = x.floor();
        let fx = x - i0;
        let i0 = (i0 as i64).rem_euclid(self.width as i64) as usize;
        let i1 = (i0 + 1) % self.width;
        let j0 = (y.floor().max(0.0) as usize).min(self.height - 2);
        let fy = (y - j0 as f32).clamp(0.0, 1.0);
        let top = self.texel(i0, j0) * (1.0 - fx) + self.texel(i1, j0) * fx;
        let bottom = self.texel(i0, j0 + 1) * (1.0 - fx) + self.texel(i1, j0 + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// The cell (column, row) holding direction `d`.
    #[inline]
    fn cell(&self, d: Vec3) -> (usize, usize) {
        let uv = direction_to_uv(d);
        let x = (uv.x * self.width as f32 - 0.5).floor() as i64;
        let i = x.rem_euclid(self.width as i64) as usize;
        let j = ((uv.y * (self.height - 1) as f32).floor().max(0.0) as usize).min(self.height - 2);
        (i, j)
    }

    /// A direction towards the environment with its solid-angle density and radiance.
    pub fn sample(&self, p: Vec3, u: Vec2) -> Option<LightSample> {
        let (wi, pdf) = if self.importance {
            let (j, pj, ry) = self.rows.sample(u.y);
            let (i, pi, rx) = self.columns[j].sample(u.x);
            let uu = (i as f32 + 0.5 + rx) / self.width as f32;
            let uu = if uu >= 1.0 { uu - 1.0 } else { uu };
            let (c0, c1) = (self.cos_theta[j], self.cos_theta[j + 1]);
            let cos_t = c0 + (c1 - c0) * ry;
            let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
            let (sin_p, cos_p) = (uu * TAU).sin_cos();
            let wi = Vec3::new(sin_t * sin_p, cos_t, -sin_t * cos_p);
            (wi, pj * pi / ((TAU / self.width as f32) * (c0 - c1)))
        } else {
            (uniform_sphere(u), uniform_sphere_pdf())
        };
        let wi = match &self.to_world {
            Some(r) => *r * wi,
            None => wi,
        };
        let li = self.eval(wi);
        (pdf > 0.0 && pdf.is_finite()).then_some(LightSample {
            wi,
            dist: f32::INFINITY,
            p: p + wi,
            li,
            pdf,
            delta: false,
            shape: None,
        })
    }

    /// The density of `sample` for direction `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        if !self.importance {
            return uniform_sphere_pdf();
        }
        let (i, j) = self.cell(self.to_map(d));
        let omega = (TAU / self.width as f32) * (self.cos_theta[j] - self.cos_theta[j + 1]);
        let pdf = self.rows.prob(j) * self.columns[j].prob(i) / omega;
        if pdf.is_finite() {
            pdf
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::Sampler;

    /// A map whose texel (i, j) holds (i, j, 1) × 0.01 + 0.1, plus a bright 3×2 spot.
    fn test_map(w: u32, h: u32) -> Image {
        let mut img = Image::new(w, h);
        for j in 0..h {
            for i in 0..w {
                img.set(i, j, Rgb::new(i as f32 * 0.01 + 0.1, j as f32 * 0.01 + 0.1, 0.11));
            }
        }
        for (i, j) in [(5, 4), (6, 4), (7, 4), (5, 5), (6, 5), (7, 5)] {
            img.set(i, j, Rgb::splat(200.0));
        }
        img
    }

    #[test]
    fn lookup_follows_mitsubas_convention() {
        let img = test_map(16, 9);
        let env = EnvMap::new(&img, 1.0).unwrap();
        // Texel centres come back exactly (the poles are single directions: rows 0 and 8 are
        // each seen at u = 0 only).
        for j in 1..8 {
            for i in 0..16 {
                let uv = Vec2::new((i as f32 + 0.5) / 16.0, j as f32 / 8.0);
                let got = env.eval(uv_to_direction(uv));
                assert!((got - img.get(i, j)).max_channel().abs() < 1e-3, "texel ({i},{j})");
            }
        }
        // Hand-computed directions: −z is u = 0 (halfway between the last and first columns),
        // v = ½ (the equator, row 4 of 0..8); +x is u = ¼; +y is the top row.
        let mean = |a: Rgb, b: Rgb| (a + b) * 0.5;
        assert!((env.eval(-Vec3::Z) - mean(img.get(15, 4), img.get(0, 4))).max_channel().abs() < 1e-5);
        assert!((direction_to_uv(Vec3::X) - Vec2::new(0.25, 0.5)).length() < 1e-6);
        assert!((direction_to_uv(Vec3::Z) - Vec2::new(0.5, 0.5)).length() < 1e-6);
        // u = ¼ lies between texel centres 3.5/16 and 4.5/16: the mean of columns 3 and 4.
        assert!((env.eval(Vec3::X) - mean(img.get(3, 4), img.get(4, 4))).max_channel().abs() < 1e-5);
        assert!((env.eval(Vec3::Y).0[1] - 0.1).abs() < 1e-6 && (env.eval(-Vec3::Y).0[1] - 0.18).abs() < 1e-6);
        assert!(EnvMap::new(&Image::new(4, 1), 1.0).is_err());
    }

    #[test]
    fn sampling_density_is_normalised_and_matches_samples() {
        let env = EnvMap::new(&test_map(16, 9), 1.0).unwrap();
        // ∫ pdf dω = 1: the pdf is constant over each cell, so sum pdf(cell centre) × Ω(cell).
        let mut integral = 0.0f64;
        for j in 0..8 {
            let (c0, c1) = ((PI * j as f32 / 8.0).cos(), (PI * (j + 1) as f32 / 8.0).cos());
            let v = (0.5 * (c0 + c1)).acos() / PI;
            for i in 0..16 {
                let d = uv_to_direction(Vec2::new((i as f32 + 1.0) / 16.0, v));
                integral += (env.pdf(d) * (TAU / 16.0) * (c0 - c1)) as f64;
            }
        }
        assert!((integral - 1.0).abs() < 1e-5, "{integral}");
        // sample() and pdf() agree, and E[L/pdf] = ∫ L dω within 4σ of the estimator.
        let mut rng = Sampler::new(3, 0, 0);
        let (n, mut sum, mut sum2) = (200_000, 0.0f64, 0.0f64);
        let mut disagree = 0;
        for _ in 0..n {
            let s = env.sample(Vec3::ZERO, rng.next_2d()).unwrap();
            if ((env.pdf(s.wi) - s.pdf) / s.pdf).abs() > 1e-3 {
                disagree += 1; // a sample on a cell edge may round into the neighbour
            }
            let x = (s.li.luminance() / s.pdf) as f64;
            sum += x;
            sum2 += x * x;
        }
        assert!(disagree < n / 1000, "{disagree} samples with pdf ≠ pdf(wi)");
        let mean = sum / n as f64;
        let sigma = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
        let exact = {
            let (nu, nv) = (1024, 1024);
            let mut s = 0.0f64;
            for a in 0..nu {
                for b in 0..nv {
                    let u = (a as f32 + 0.5) / nu as f32;
                    let cos_t = 1.0 - 2.0 * (b as f32 + 0.5) / nv as f32;
                    s += env.eval(uv_to_direction(Vec2::new(u, cos_t.acos() / PI))).luminance() as f64;
                }
            }
            s * 4.0 * std::f64::consts::PI / (nu * nv) as f64
        };
        assert!((mean - exact).abs() < 4.0 * sigma + 2e-3 * exact, "{mean} ± {sigma} vs {exact}");
    }
}
