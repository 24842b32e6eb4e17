//! An equirectangular environment map, with Mitsuba 3's lookup: direction d (world, +Y up)
//! maps to u = atan2(d.x, −d.z)/2π (mod 1), v = acos(d.y)/π; texel (i, j) is centred at
//! u = (i + ½)/W, v = j/(H − 1); radiance is bilinear between texel centres, periodic in u.
//! The angles come from one polynomial atan2 (`crate::atan`), v as atan2(√(x² + z²), y).
//!
//! Importance sampling follows Mitsuba 3's `envmap` (its density exactly, by another warp):
//! on the grid of texel centres (W + 1 columns, the last repeating the first; H rows) take
//! f(i, j) = luminance(i, j) · sin θj with θj = πj/(H − 1), and sample x = u − ½/W (mod 1),
//! y = v from the density p(x, y) ∝ the bilinear interpolant of f (`warp2d::Bilinear2D`).
//! Since dω = 2π² sin θ du dv, the solid-angle density is
//!     pdf(d) = p(x, y) / (2π² sin θ),
//! the density Mitsuba samples. Within a cell it is the bilinear luminance times
//! (interpolated sin θ)/sin θ (within (Δθ)²/8 of 1) plus a term fy(1 − fy)·ΔL·Δ(sin θ)/sin θ
//! that is small wherever sin θ changes little across the cell (away from the poles), so
//! L/pdf stays near constant even in a cell whose corners differ 1000×. The density is
//! continuous, and positive wherever a cell's corners carry light; at the poles, where p and
//! sin θ both vanish, it takes their ratio's limit.
//! A map with no light to sample by (all black, or only 2 rows, whose sin θj are both 0)
//! is sampled uniformly.
//!
//! Light samples that MIS combines with BSDF samples may use the *compensated* density
//! instead (Karlík, Šik, Vévoda, Skřivan & Křivánek, "MIS compensation", 2019; pbrt-v4 does
//! the same): f from the radiance less its mean over the sphere, clamped at 0. Where the map is
//! dimmer than its mean the BSDF samples find its light (their MIS weight there is 1), and the
//! light samples go where the map is bright. Without a BSDF strategy beside it, a light sample
//! must use the full density.

use crate::error::{Error, Result};
use crate::image::Image;
use crate::light::LightSample;
use glam::{Vec2, Vec3};
use radiometry::trig::sin_cos_pi;
use radiometry::warp::{uniform_sphere, uniform_sphere_pdf};
use radiometry::warp2d::{bilerp, Bilinear2D};
use radiometry::Rgb;
use std::f32::consts::PI;

mod packet;

/// An environment map light.
#[derive(Clone, Debug)]
pub struct EnvMap {
    width: usize,
    height: usize,
    /// Radiance per texel (already multiplied by the scale), W + 1 per row: the last column
    /// repeats the first, so the lookup never wraps.
    texels: Vec<Rgb>,
    /// The sampling density over (u − ½/W, v); None when there is no light to sample by.
    warp: Option<Bilinear2D>,
    /// The compensated density; None where nothing exceeds the mean (a constant map).
    warp_mis: Option<Bilinear2D>,
    /// False: sample the sphere uniformly instead (for tests and comparisons).
    pub importance: bool,
    /// The map's rotation into the world (Mitsuba's `to_world`); None for the identity.
    to_world: Option<glam::Mat3>,
}

/// Where a direction falls on an environment map: the direction in the map's frame and its
/// cell (i, j) with the place f in it. Found once before a ray's query, it serves both the
/// prefetch and, where the ray escapes, the lookup (the angles cost as much as the lookup).
#[derive(Clone, Copy, Debug)]
pub struct EnvLookup {
    m: Vec3,
    i: usize,
    j: usize,
    f: Vec2,
}

/// A direction drawn from an environment map (world frame), with the radiance arriving along
/// it and its solid-angle density.
#[derive(Clone, Copy, Debug)]
pub struct EnvDirection {
    /// The unit direction.
    pub wi: Vec3,
    /// The radiance.
    pub li: Rgb,
    /// The density (possibly 0 or not finite: no sample).
    pub pdf: f32,
}

/// The solid-angle density of a sample of grid density `pdf` where sin θ = `sin_t` (> 0):
/// dω = 2π² sin θ du dv.
#[inline(always)]
fn solid_angle_pdf(pdf: f32, sin_t: f32) -> f32 {
    pdf / (2.0 * PI * PI * sin_t)
}

/// Which density an environment map's light samples follow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EnvDensity {
    /// By radiance (× sin θ): what light sampling alone needs.
    Radiance,
    /// By radiance less its mean, for light samples that MIS combines with BSDF samples.
    Compensated,
}

/// The (u, v) of Mitsuba's lookup for a direction (unit, or any length).
#[inline(always)]
pub fn direction_to_uv(d: Vec3) -> Vec2 {
    let u = crate::atan::atan2(d.x, -d.z) * (0.5 / PI);
    let v = crate::atan::atan2((d.x * d.x + d.z * d.z).sqrt(), d.y) * (1.0 / PI);
    Vec2::new(if u < 0.0 { u + 1.0 } else { u }, v)
}

/// The unit direction with lookup coordinates (u, v).
#[inline]
pub fn uv_to_direction(uv: Vec2) -> Vec3 {
    let (sin_t, cos_t) = sin_cos_pi(uv.y);
    let (sin_p, cos_p) = sin_cos_pi(2.0 * uv.x);
    Vec3::new(sin_t * sin_p, cos_t, -sin_t * cos_p)
}

impl EnvMap {
    /// From an image (at least 1×2 texels) and a radiance scale.
    pub fn new(image: &Image, scale: f32) -> Result<Self> {
        let (w, h) = (image.width as usize, image.height as usize);
        if w < 1 || h < 2 {
            return Err(Error::Invalid(format!("environment map of {w}x{h} texels: need at least 1x2")));
        }
        // The lookup indexes texels with i32 (see `cell`).
        if w.max(h) > i32::MAX as usize {
            return Err(Error::Invalid(format!("environment map of {w}x{h} texels: at most {} per side", i32::MAX)));
        }
        if let Some(i) = image.pixels.iter().position(|p| !p.is_finite()) {
            return Err(Error::Invalid(format!("environment map texel ({}, {}) is not finite", i % w, i / w)));
        }
        let texels: Vec<Rgb> = (0..h)
            .flat_map(|j| (0..=w).map(move |i| (j, i % w)))
            .map(|(j, i)| image.pixels[j * w + i] * scale)
            .collect();
        // sin θj from the nearer pole, so that both pole rows are exactly 0.
        let sin_theta = |j: usize| (std::f64::consts::PI * j.min(h - 1 - j) as f64 / (h - 1) as f64).sin() as f32;
        let lum: Vec<f32> = texels.iter().map(|t| t.luminance().max(0.0)).collect();
        let f: Vec<f32> = lum.iter().enumerate().map(|(k, l)| l * sin_theta(k / (w + 1))).collect();
        // The mean over the sphere, each texel weighted by its sin θ (the repeated column left out).
        let (mut sum, mut weight) = (0.0f64, 0.0f64);
        for (k, l) in lum.iter().enumerate().filter(|(k, _)| k % (w + 1) != w) {
            let s = sin_theta(k / (w + 1)) as f64;
            sum += *l as f64 * s;
            weight += s;
        }
        let mean = if weight > 0.0 { (sum / weight) as f32 } else { 0.0 };
        let f_mis: Vec<f32> =
            lum.iter().enumerate().map(|(k, l)| (l - mean).max(0.0) * sin_theta(k / (w + 1))).collect();
        Ok(EnvMap {
            width: w,
            height: h,
            texels,
            warp: Bilinear2D::new(&f, w + 1, h),
            warp_mis: Bilinear2D::new(&f_mis, w + 1, h),
            importance: true,
            to_world: None,
        })
    }

    /// The map with its radiance multiplied by `s` > 0, sharing the sampling density (which a
    /// uniform scale leaves as it is) instead of building it again.
    pub fn scaled(&self, s: f32) -> Self {
        let mut m = self.clone();
        m.texels.iter_mut().for_each(|t| *t *= s);
        m
    }

    /// The map turned by the rotation `r` (world = r · map direction), or mirrored by it. None
    /// when `r` is not orthonormal (to 1e-4): other maps would not keep the density normalised.
    pub fn with_rotation(mut self, r: glam::Mat3) -> Option<Self> {
        let err = (r.transpose() * r - glam::Mat3::IDENTITY).to_cols_array().iter().fold(0.0f32, |a, x| a.max(x.abs()));
        if !(err < 1e-4 && (r.determinant().abs() - 1.0).abs() < 1e-4) {
            return None;
        }
        self.to_world = (r != glam::Mat3::IDENTITY).then_some(r);
        Some(self)
    }

    /// A world direction in the map's frame.
    #[inline(always)]
    fn to_map(&self, d: Vec3) -> Vec3 {
        match &self.to_world {
            Some(r) => r.transpose() * d,
            None => d,
        }
    }

    /// Texel (column i, row j).
    #[inline]
    pub fn texel(&self, i: usize, j: usize) -> Rgb {
        self.texels[j * (self.width + 1) + i]
    }

    /// The grid cell (its lower texel column and row) holding lookup coordinates `uv`, and
    /// the place within it: x = uW − ½ wrapped into [0, W), y = v(H − 1).
    #[inline(always)]
    fn cell(&self, uv: Vec2) -> (usize, usize, Vec2) {
        let mut x = uv.x * self.width as f32 - 0.5;
        if x < 0.0 {
            x += self.width as f32;
        }
        let y = (uv.y * (self.height - 1) as f32).max(0.0);
        // Truncation is the floor here (x, y ≥ 0), and cheaper than floor(); to i32, which
        // vector code converts to in one instruction (x ≤ W and y ≤ H − 1 fit, and NaN gives 0
        // either way).
        let (i, j) = ((x as i32).min(self.width as i32 - 1), (y as i32).min(self.height as i32 - 2));
        (i as usize, j as usize, Vec2::new((x - i as f32).min(1.0), (y - j as f32).min(1.0)))
    }

    /// The bilinear radiance at place `f` of cell (i, j).
    #[inline(always)]
    fn radiance(&self, i: usize, j: usize, f: Vec2) -> Rgb {
        let k = j * (self.width + 1) + i;
        let t = &self.texels;
        let top = t[k] * (1.0 - f.x) + t[k + 1] * f.x;
        let bottom = t[k + self.width + 1] * (1.0 - f.x) + t[k + self.width + 2] * f.x;
        top * (1.0 - f.y) + bottom * f.y
    }

    /// Radiance arriving from direction `d` (unit, pointing away from the scene).
    pub fn eval(&self, d: Vec3) -> Rgb {
        self.eval_at(&self.lookup(d))
    }

    /// [`eval`](Self::eval) where the direction's [`lookup`](Self::lookup) is `l`.
    #[inline]
    pub fn eval_at(&self, l: &EnvLookup) -> Rgb {
        self.radiance(l.i, l.j, l.f)
    }

    /// The solid-angle density at place `f` of cell (i, j), where sin θ = `sin_t`.
    #[inline]
    fn density(&self, warp: &Bilinear2D, i: usize, j: usize, f: Vec2, sin_t: f32) -> f32 {
        let c = warp.corners(i, j);
        // (The threshold is the one `sample` uses.)
        let p_over_sin = if sin_t > 1e-18 {
            bilerp(c, f) / sin_t
        } else {
            // At a pole f's row is 0, and p/sin θ tends to its slope in θ = (j + fy)·π/(H − 1).
            ((c[2] - c[0]) + (c[3] - c[2] - c[1] + c[0]) * f.x).abs() * ((self.height - 1) as f32 / PI)
        };
        warp.cell_scale(i, j) * p_over_sin * (0.5 / (PI * PI))
    }

    /// The density `d` samples by; None for uniform sampling.
    #[inline]
    fn warp(&self, d: EnvDensity) -> Option<&Bilinear2D> {
        if !self.importance {
            return None;
        }
        match d {
            EnvDensity::Compensated => self.warp_mis.as_ref().or(self.warp.as_ref()),
            EnvDensity::Radiance => self.warp.as_ref(),
        }
    }

    /// Starts loading what `sample(_, uc, _)` reads first, the cell choice's table entry: called
    /// well before `sample`, its cache miss overlaps other work.
    #[inline]
    pub fn prefetch_sample(&self, uc: f32, d: EnvDensity) {
        if let Some(warp) = self.warp(d) {
            warp.prefetch_cell_choice(uc);
        }
    }

    /// Once that entry is loaded, starts loading the cell's corners and texels that
    /// `sample(_, uc, u)` reads next.
    #[inline]
    pub fn prefetch_sample_cell(&self, uc: f32, u: Vec2, d: EnvDensity) {
        if let Some(warp) = self.warp(d) {
            let (i, j) = warp.prefetch_cell(uc, u.y);
            self.prefetch_texels(i, j);
        }
    }

    /// Where direction `d` falls on the map, for [`eval_pdf_at`](Self::eval_pdf_at).
    #[inline]
    pub fn lookup(&self, d: Vec3) -> EnvLookup {
        let m = self.to_map(d);
        let (i, j, f) = self.cell(direction_to_uv(m));
        EnvLookup { m, i, j, f }
    }

    /// Starts loading what [`eval_pdf_at`](Self::eval_pdf_at)`(l, density)` reads: the texels
    /// and density corners of l's cell.
    #[inline]
    pub fn prefetch_eval(&self, l: &EnvLookup, density: EnvDensity) {
        self.prefetch_texels(l.i, l.j);
        if let Some(warp) = self.warp(density) {
            warp.prefetch_corners(l.i, l.j);
        }
    }

    /// Starts loading the two texel rows of cell (i, j).
    #[inline]
    fn prefetch_texels(&self, i: usize, j: usize) {
        let k = j * (self.width + 1) + i;
        radiometry::prefetch::prefetch(&self.texels[k]);
        radiometry::prefetch::prefetch(&self.texels[k + self.width + 1]);
    }

    /// A direction towards the environment with its solid-angle density and radiance, from
    /// uniform numbers `uc` and `u`.
    pub fn sample(&self, p: Vec3, uc: f32, u: Vec2) -> Option<LightSample> {
        self.sample_by(p, uc, u, EnvDensity::Radiance)
    }

    /// [`sample`](Self::sample) by density `d`.
    pub fn sample_by(&self, p: Vec3, uc: f32, u: Vec2, d: EnvDensity) -> Option<LightSample> {
        self.light_sample(p, &self.sample_direction(uc, u, d))
    }

    /// What [`sample_by`](Self::sample_by) draws before it knows the reference point: it
    /// depends on the numbers alone.
    #[inline]
    pub fn sample_direction(&self, uc: f32, u: Vec2, d: EnvDensity) -> EnvDirection {
        let (wi, li, pdf) = match self.warp(d) {
            Some(warp) => {
                let s = warp.sample(uc, u);
                let (wi, sin_t) = self.cell_direction(s.i, s.j, s.frac);
                let pdf = if sin_t > 1e-18 {
                    solid_angle_pdf(s.pdf, sin_t)
                } else {
                    self.density(warp, s.i, s.j, s.frac, sin_t)
                };
                (wi, self.radiance(s.i, s.j, s.frac), pdf)
            }
            None => {
                let wi = uniform_sphere(u);
                let (i, j, f) = self.cell(direction_to_uv(wi));
                (wi, self.radiance(i, j, f), uniform_sphere_pdf())
            }
        };
        EnvDirection { wi: self.map_to_world(wi), li, pdf }
    }

    /// The light sample from `p` of direction `s` (None where its density is not positive
    /// and finite).
    #[inline]
    pub fn light_sample(&self, p: Vec3, s: &EnvDirection) -> Option<LightSample> {
        (s.pdf > 0.0 && s.pdf.is_finite()).then_some(LightSample {
            wi: s.wi,
            dist: f32::INFINITY,
            p: p + s.wi,
            li: s.li,
            pdf: s.pdf,
            delta: false,
            shape: None,
        })
    }

    /// The direction (map frame) at place `f` of cell (i, j) of the sampling grid, whose
    /// cells are offset by half a texel in u, and its sin θ (≥ 0).
    #[inline(always)]
    fn cell_direction(&self, i: usize, j: usize, f: Vec2) -> (Vec3, f32) {
        let mut uu = (i as f32 + 0.5 + f.x) / self.width as f32;
        if uu >= 1.0 {
            uu -= 1.0;
        }
        let v = (j as f32 + f.y) / (self.height - 1) as f32;
        let (sin_t, cos_t) = sin_cos_pi(v);
        let (sin_p, cos_p) = sin_cos_pi(2.0 * uu);
        let sin_t = sin_t.max(0.0);
        (Vec3::new(sin_t * sin_p, cos_t, -sin_t * cos_p), sin_t)
    }

    /// A map-frame direction in the world.
    #[inline(always)]
    fn map_to_world(&self, d: Vec3) -> Vec3 {
        match &self.to_world {
            Some(r) => *r * d,
            None => d,
        }
    }

    /// `eval` and `pdf` together, sharing the direction's cell: bit for bit what each returns.
    pub fn eval_pdf(&self, d: Vec3) -> (Rgb, f32) {
        self.eval_pdf_by(d, EnvDensity::Radiance)
    }

    /// [`eval_pdf`](Self::eval_pdf) with the density `density`.
    pub fn eval_pdf_by(&self, d: Vec3, density: EnvDensity) -> (Rgb, f32) {
        self.eval_pdf_at(&self.lookup(d), density)
    }

    /// [`eval_pdf_by`](Self::eval_pdf_by) where the direction's [`lookup`](Self::lookup) is `l`.
    #[inline]
    pub fn eval_pdf_at(&self, l: &EnvLookup, density: EnvDensity) -> (Rgb, f32) {
        (self.radiance(l.i, l.j, l.f), self.pdf_at(l, density))
    }

    /// The density of `sample` for direction `d`.
    pub fn pdf(&self, d: Vec3) -> f32 {
        self.pdf_by(d, EnvDensity::Radiance)
    }

    /// The density of `sample_by(…, density)` for direction `d`.
    pub fn pdf_by(&self, d: Vec3, density: EnvDensity) -> f32 {
        self.pdf_at(&self.lookup(d), density)
    }

    /// The density `density` for the direction whose [`lookup`](Self::lookup) is `l`.
    #[inline]
    fn pdf_at(&self, l: &EnvLookup, density: EnvDensity) -> f32 {
        let Some(warp) = self.warp(density) else {
            return uniform_sphere_pdf();
        };
        let m = l.m;
        let pdf = self.density(warp, l.i, l.j, l.f, (m.x * m.x + m.z * m.z).sqrt());
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
    fn eval_pdf_is_eval_and_pdf_bit_for_bit() {
        let plain = EnvMap::new(&test_map(16, 9), 1.0).unwrap();
        let rotated = plain.clone().with_rotation(glam::Mat3::from_rotation_x(0.7)).unwrap();
        let mut rng = Sampler::new(7, 0, 0);
        for env in [&plain, &rotated] {
            for i in 0..20_000 {
                // Poles and the seam included.
                let d = match i % 100 {
                    0 => Vec3::Y,
                    1 => -Vec3::Y,
                    2 => Vec3::new(0.0, 0.3, -1.0).normalize(),
                    _ => uniform_sphere(rng.next_2d()),
                };
                let (le, pdf) = env.eval_pdf(d);
                assert_eq!((le, pdf.to_bits()), (env.eval(d), env.pdf(d).to_bits()), "{d}");
            }
        }
    }

    #[test]
    fn compensated_density_skips_what_is_dimmer_than_the_mean() {
        let env = EnvMap::new(&test_map(16, 9), 1.0).unwrap();
        let c = EnvDensity::Compensated;
        // Normalised: the same midpoint rule as below, exact on the bilinear cells.
        let mut integral = 0.0f64;
        for j in 0..8 {
            let v = (j as f32 + 0.5) / 8.0;
            for i in 0..16 {
                let d = uv_to_direction(Vec2::new((i as f32 + 1.0) / 16.0, v));
                integral += (env.pdf_by(d, c) * 2.0 * PI * PI * (v * PI).sin()) as f64 / (16 * 8) as f64;
            }
        }
        assert!((integral - 1.0).abs() < 1e-5, "{integral}");
        // The dim texels (about 0.2 against a mean near 4) get nothing; the bright spot all.
        let dim = uv_to_direction(Vec2::new(12.5 / 16.0, 2.0 / 8.0));
        let spot = uv_to_direction(Vec2::new(6.5 / 16.0, 4.5 / 8.0));
        assert_eq!(env.pdf_by(dim, c), 0.0);
        assert!(env.pdf(dim) > 0.0 && env.pdf_by(spot, c) > env.pdf(spot));
        // Samples follow the density they report, and land only where it is positive.
        let mut rng = Sampler::new(5, 0, 0);
        for _ in 0..20_000 {
            let s = env.sample_by(Vec3::ZERO, rng.next_1d(), rng.next_2d(), c).unwrap();
            let pdf = env.pdf_by(s.wi, c);
            assert!(pdf > 0.0 && ((pdf - s.pdf) / s.pdf).abs() < 1e-2, "{pdf} against {}", s.pdf);
        }
        // A constant map has nothing above its mean: it keeps the full density.
        let mut img = Image::new(8, 5);
        img.pixels.iter_mut().for_each(|p| *p = Rgb::splat(0.5));
        let flat = EnvMap::new(&img, 1.0).unwrap();
        let d = Vec3::new(0.3, 0.4, -0.5).normalize();
        assert_eq!(flat.pdf_by(d, c), flat.pdf(d));
    }

    #[test]
    fn sampling_density_is_normalised_and_matches_samples() {
        let env = EnvMap::new(&test_map(16, 9), 1.0).unwrap();
        // ∫ pdf dω = ∫∫ pdf · 2π² sin θ du dv, whose integrand is bilinear over each cell of
        // the grid of texel centres: the midpoint rule is exact there.
        let mut integral = 0.0f64;
        for j in 0..8 {
            let v = (j as f32 + 0.5) / 8.0;
            for i in 0..16 {
                let d = uv_to_direction(Vec2::new((i as f32 + 1.0) / 16.0, v));
                integral += (env.pdf(d) * 2.0 * PI * PI * (v * PI).sin()) as f64 / (16 * 8) as f64;
            }
        }
        assert!((integral - 1.0).abs() < 1e-5, "{integral}");
        // sample() agrees with pdf() and eval(), and E[L/pdf] = ∫ L dω within 4σ.
        let mut rng = Sampler::new(3, 0, 0);
        let (n, mut sum, mut sum2) = (200_000, 0.0f64, 0.0f64);
        let (mut worst_pdf, mut worst_li) = (0.0f32, 0.0f32);
        for _ in 0..n {
            let s = env.sample(Vec3::ZERO, rng.next_1d(), rng.next_2d()).unwrap();
            worst_pdf = worst_pdf.max(((env.pdf(s.wi) - s.pdf) / s.pdf).abs());
            worst_li = worst_li.max(((env.eval(s.wi) - s.li) / s.li).max_channel().abs());
            let x = (s.li.luminance() / s.pdf) as f64;
            sum += x;
            sum2 += x * x;
        }
        // The round trip direction → (u, v) moves x = uW by a few ulp of u times W (say
        // 2·2⁻²³·16), and within a cell ln(density) and ln(L) change by at most 1/(the
        // smallest corner / the largest) ≈ 2000 per unit of x.
        let tol = 2.0 * 2f32.powi(-23) * 16.0 * 2000.0;
        assert!(worst_pdf < tol && worst_li < tol, "sample vs lookup: pdf {worst_pdf}, radiance {worst_li}");
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
