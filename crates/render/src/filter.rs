//! Pixel reconstruction filters, applied by filter importance sampling: each camera sample
//! lands at an offset from the pixel centre drawn ∝ the filter, so the plain mean of the
//! samples' radiance (times a weight that is 1 for exact sampling) estimates the filtered
//! image ∫ f(x) L(x) dx / ∫ f (Ernst et al., "Filter Importance Sampling", RT 2006).
//! Mitsuba splats every sample into all pixels its filter reaches and divides by the summed
//! weights; the two estimate the same image away from its edges, with different noise. The
//! renderer splats (`film.rs`, ~4× less variance for the Gaussian) for every filter but the
//! box; `Camera::film_sample` keeps the importance-sampled estimate.
//!
//! `box`: the pixel's square, f = 1 on [−½, ½]². `gaussian` (Mitsuba's): separable,
//! f(x) = max(0, exp(−x²/2σ²) − exp(−r²/2σ²)) per axis with r = 4σ, σ = 0.5 px by default.

use crate::distribution::Distribution1D;
use glam::Vec2;

/// Cells of the tabulated 1D Gaussian: its sampling density is piecewise constant over them,
/// and the weight f/(pdf·∫f) corrects the rest exactly.
const CELLS: usize = 256;

/// A reconstruction filter.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum Filter {
    /// The pixel's square (radius ½ px).
    #[default]
    Box,
    /// Mitsuba's windowed Gaussian.
    Gaussian(Gaussian),
}

impl Filter {
    /// Mitsuba's `gaussian` with standard deviation `stddev` pixels (None unless finite and > 0).
    pub fn gaussian(stddev: f32) -> Option<Filter> {
        Gaussian::new(stddev).map(Filter::Gaussian)
    }

    /// An offset from the pixel centre (in pixels) and the sample's weight.
    #[inline]
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        match self {
            Filter::Box => (u - Vec2::splat(0.5), 1.0),
            Filter::Gaussian(g) => {
                let (x, wx) = g.sample_1d(u.x);
                let (y, wy) = g.sample_1d(u.y);
                (Vec2::new(x, y), wx * wy)
            }
        }
    }

    /// The separable 1D factor at offset `x` pixels (unnormalised: the splatting film divides
    /// by the summed weights).
    #[inline]
    pub fn eval_1d(&self, x: f32) -> f32 {
        match self {
            Filter::Box => (x.abs() <= 0.5) as u8 as f32,
            Filter::Gaussian(g) => g.eval(x),
        }
    }

    /// The filter's radius in pixels.
    pub fn radius(&self) -> f32 {
        match self {
            Filter::Box => 0.5,
            Filter::Gaussian(g) => g.radius,
        }
    }
}

/// The windowed Gaussian, tabulated for sampling.
#[derive(Clone, Debug, PartialEq)]
pub struct Gaussian {
    /// Standard deviation in pixels.
    pub stddev: f32,
    /// Support radius, 4σ.
    pub radius: f32,
    table: Distribution1D,
    /// ∫ f over [−r, r].
    integral: f64,
}

impl Gaussian {
    /// The filter of standard deviation `stddev` pixels.
    pub fn new(stddev: f32) -> Option<Self> {
        if !(stddev.is_finite() && stddev > 0.0) {
            return None;
        }
        let radius = 4.0 * stddev;
        let g = |x: f64| Self::eval_with(stddev as f64, radius as f64, x);
        let cell = 2.0 * radius as f64 / CELLS as f64;
        // Each cell's weight is its integral (fine midpoint rule), so the table matches f closely.
        let sub = 64;
        let weights: Vec<f64> = (0..CELLS)
            .map(|i| {
                let x0 = -(radius as f64) + i as f64 * cell;
                (0..sub).map(|k| g(x0 + (k as f64 + 0.5) * cell / sub as f64)).sum::<f64>() * cell / sub as f64
            })
            .collect();
        let integral = weights.iter().sum();
        let table = Distribution1D::new(&weights.iter().map(|&w| w as f32).collect::<Vec<_>>());
        Some(Gaussian { stddev, radius, table, integral })
    }

    fn eval_with(stddev: f64, radius: f64, x: f64) -> f64 {
        let a = -0.5 / (stddev * stddev);
        ((a * x * x).exp() - (a * radius * radius).exp()).max(0.0)
    }

    /// The 1D filter value at offset `x` pixels.
    pub fn eval(&self, x: f32) -> f32 {
        Self::eval_with(self.stddev as f64, self.radius as f64, x as f64) as f32
    }

    /// An offset drawn from the table and its weight f(x)/(pdf(x) ∫f), of mean 1.
    fn sample_1d(&self, u: f32) -> (f32, f32) {
        let (i, p, rest) = self.table.sample(u);
        let cell = 2.0 * self.radius / CELLS as f32;
        let x = -self.radius + (i as f32 + rest) * cell;
        let pdf = p as f64 / cell as f64;
        let w = if pdf > 0.0 { self.eval(x) as f64 / (pdf * self.integral) } else { 0.0 };
        (x, w as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaussian_matches_mitsuba_and_weights_average_to_one() {
        let Filter::Gaussian(g) = Filter::gaussian(0.5).unwrap() else { unreachable!() };
        assert_eq!(g.radius, 2.0);
        assert_eq!(g.eval(2.0), 0.0);
        assert!((g.eval(0.0) - (1.0 - (-8.0f32).exp())).abs() < 1e-6);
        // ∫ f = σ√(2π)·erf(r/(σ√2)) − 2r·e^{−r²/2σ²}; erf(2√2) = 0.99993666.
        let exact = 0.5 * (2.0 * std::f64::consts::PI).sqrt() * 0.999_936_657_516_334 - 4.0 * (-8.0f64).exp();
        assert!((g.integral - exact).abs() < 1e-6, "{} vs {exact}", g.integral);
        // E[w] = 1 and E[w x²] = ∫ x² f / ∫ f: a stratified sweep of u integrates both.
        let n = 100_000;
        let (mut sw, mut sx2) = (0.0f64, 0.0f64);
        for k in 0..n {
            let (x, w) = g.sample_1d((k as f32 + 0.5) / n as f32);
            assert!(x.abs() <= 2.0 && w.is_finite() && w >= 0.0);
            sw += w as f64;
            sx2 += (w * x * x) as f64;
        }
        assert!((sw / n as f64 - 1.0).abs() < 1e-3, "{}", sw / n as f64);
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for k in 0..200_000 {
            let x = -2.0 + 4.0 * (k as f64 + 0.5) / 200_000.0;
            let f = Gaussian::eval_with(0.5, 2.0, x);
            num += x * x * f;
            den += f;
        }
        assert!((sx2 / n as f64 - num / den).abs() < 2e-3, "{} vs {}", sx2 / n as f64, num / den);
        assert!(Filter::gaussian(0.0).is_none() && Filter::gaussian(f32::NAN).is_none());
        assert_eq!(Filter::Box.sample(Vec2::new(0.25, 0.75)), (Vec2::new(-0.25, 0.25), 1.0));
    }
}
