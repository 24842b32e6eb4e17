//! Pixel reconstruction filters (Mitsuba 3's `rfilter`s), all separable, f(x, y) = f(x) f(y),
//! x in pixels from the pixel centre. The box filter is the pixel's square: each sample counts
//! in its own pixel. Every other filter is splatted: each sample adds f·L and f to every pixel
//! it reaches and a pixel is Σ f·L / Σ f (`film.rs`), as Mitsuba's `hdrfilm` does.
//!
//! - `box`: f = 1 on [−½, ½].
//! - `gaussian`: f(x) = max(0, exp(−x²/2σ²) − exp(−r²/2σ²)), r = 4σ, σ = 0.5 px by default.
//! - `tent`: f(x) = max(0, 1 − |x|/r), r = 1 by default.
//! - `mitchell` (B, C = ⅓, ⅓ by default) and `catmullrom` (B = 0, C = ½): the cubics of
//!   Mitchell & Netravali, "Reconstruction filters in computer graphics", SIGGRAPH 1988, r = 2.
//! - `lanczos` (L = 3 lobes by default): sinc(x) sinc(x/L) for |x| ≤ L.
//!
//! The Gaussian can also be importance sampled (Ernst et al., "Filter Importance Sampling",
//! RT 2006), the estimator splatting is measured against.

use glam::Vec2;
use radiometry::distribution::Distribution1D;
use std::f32::consts::PI;

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
    /// The triangle of half-width `radius` px.
    Tent {
        /// Half-width in pixels.
        radius: f32,
    },
    /// Mitchell–Netravali's cubic (Catmull–Rom for B = 0, C = ½).
    Mitchell {
        /// The B parameter.
        b: f32,
        /// The C parameter.
        c: f32,
    },
    /// The windowed sinc with `lobes` lobes.
    Lanczos {
        /// Lobes (the radius in pixels).
        lobes: u32,
    },
}

impl Filter {
    /// Mitsuba's `gaussian` with standard deviation `stddev` pixels (None unless finite and > 0).
    pub fn gaussian(stddev: f32) -> Option<Filter> {
        Gaussian::new(stddev).map(Filter::Gaussian)
    }

    /// The separable 1D factor at offset `x` pixels (unnormalised: the splatting film divides
    /// by the summed weights).
    #[inline]
    pub fn eval_1d(&self, x: f32) -> f32 {
        match *self {
            Filter::Box => (x.abs() <= 0.5) as u8 as f32,
            Filter::Gaussian(ref g) => g.eval(x),
            Filter::Tent { radius } => (1.0 - x.abs() / radius).max(0.0),
            Filter::Mitchell { b, c } => {
                let x = x.abs();
                let x2 = x * x;
                let v = if x < 1.0 {
                    (12.0 - 9.0 * b - 6.0 * c) * x2 * x + (-18.0 + 12.0 * b + 6.0 * c) * x2 + (6.0 - 2.0 * b)
                } else if x < 2.0 {
                    (-b - 6.0 * c) * x2 * x
                        + (6.0 * b + 30.0 * c) * x2
                        + (-12.0 * b - 48.0 * c) * x
                        + (8.0 * b + 24.0 * c)
                } else {
                    0.0
                };
                v / 6.0
            }
            Filter::Lanczos { lobes } => {
                let (x, l) = (x.abs(), lobes as f32);
                if x < 1e-6 {
                    1.0
                } else if x > l {
                    0.0
                } else {
                    let (a, b) = (PI * x, PI * x / l);
                    a.sin() * b.sin() / (a * b)
                }
            }
        }
    }

    /// The filter's radius in pixels.
    pub fn radius(&self) -> f32 {
        match *self {
            Filter::Box => 0.5,
            Filter::Gaussian(ref g) => g.radius,
            Filter::Tent { radius } => radius,
            Filter::Mitchell { .. } => 2.0,
            Filter::Lanczos { lobes } => lobes as f32,
        }
    }
}

/// The windowed Gaussian, tabulated for sampling.
#[derive(Clone, PartialEq)]
pub struct Gaussian {
    /// Standard deviation in pixels.
    pub stddev: f32,
    /// Support radius, 4σ.
    pub radius: f32,
    table: Distribution1D,
    /// ∫ f over [−r, r].
    integral: f64,
    /// −1/2σ², and the window exp(−r²/2σ²) subtracted: computed once, not per splat.
    a: f32,
    window: f32,
}

impl std::fmt::Debug for Gaussian {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Gaussian").field("stddev", &self.stddev).field("radius", &self.radius).finish()
    }
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
        // The window as `eval` computes it at x = r, so that the filter ends at exactly 0 there.
        let a = (-0.5 / (stddev as f64 * stddev as f64)) as f32;
        let window = (a * radius * radius).exp();
        Some(Gaussian { stddev, radius, table, integral, a, window })
    }

    fn eval_with(stddev: f64, radius: f64, x: f64) -> f64 {
        let a = -0.5 / (stddev * stddev);
        ((a * x * x).exp() - (a * radius * radius).exp()).max(0.0)
    }

    /// The 1D filter value at offset `x` pixels (in single precision: the film evaluates it
    /// some ten times per sample).
    #[inline]
    pub fn eval(&self, x: f32) -> f32 {
        ((self.a * x * x).exp() - self.window).max(0.0)
    }

    /// An offset from the pixel centre drawn ∝ the filter (in pixels) and the sample's weight,
    /// of mean 1: filter importance sampling.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (x, wx) = self.sample_1d(u.x);
        let (y, wy) = self.sample_1d(u.y);
        (Vec2::new(x, y), wx * wy)
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
#[allow(clippy::excessive_precision)] // Mitsuba's reference numbers, as it prints them
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
    }

    #[test]
    fn filters_match_mitsuba() {
        // Mitsuba 3.9.1's exact (JIT-variant) filter values.
        let cases: [(Filter, &[(f32, f32)]); 4] = [
            (Filter::Tent { radius: 1.0 }, &[(0.1, 0.9), (0.5, 0.5), (0.75, 0.25)]),
            (
                Filter::Mitchell { b: 1.0 / 3.0, c: 1.0 / 3.0 },
                &[(0.0, 0.88888896), (0.5, 0.53472227), (1.0, 0.055555623), (1.25, -0.023437422), (1.5, -0.034721967)],
            ),
            (
                Filter::Mitchell { b: 0.0, c: 0.5 },
                &[(0.0, 1.0), (0.25, 0.8671875), (0.5, 0.5625), (1.0, 0.0), (1.25, -0.0703125), (1.5, -0.0625)],
            ),
            (
                Filter::Lanczos { lobes: 3 },
                &[(0.5, 0.60792708), (1.25, -0.13287102), (1.5, -0.13509491), (2.5, 0.024317075)],
            ),
        ];
        for (f, values) in cases {
            for &(x, want) in values {
                assert!((f.eval_1d(x) - want).abs() < 2e-6, "{f:?} at {x}: {} vs {want}", f.eval_1d(x));
                assert_eq!(f.eval_1d(-x), f.eval_1d(x));
            }
            assert_eq!(f.eval_1d(f.radius() + 0.01), 0.0);
        }
        assert!((Filter::Lanczos { lobes: 2 }.eval_1d(0.5) - 0.57315916).abs() < 2e-6);
    }
}
