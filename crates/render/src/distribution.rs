//! A piecewise-constant 1D distribution over n cells: sampling proportional to given
//! non-negative weights by inverting the cumulative sum (binary search).

/// Discrete/piecewise-constant distribution over `n` equal-width cells of [0, 1).
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1D {
    /// Normalised cumulative weights: cdf[0] = 0, cdf[n] = 1.
    cdf: Vec<f32>,
    /// Sum of the weights before normalisation.
    total: f64,
}

impl Distribution1D {
    /// From weights (negative or non-finite ones count as zero). With all weights zero,
    /// every cell gets the same probability, so sampling still works; `total` then reads 0.
    pub fn new(weights: &[f32]) -> Self {
        let clean = |w: f32| if w.is_finite() && w > 0.0 { w as f64 } else { 0.0 };
        let total: f64 = weights.iter().map(|&w| clean(w)).sum();
        let n = weights.len();
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0);
        let mut acc = 0.0f64;
        for (i, &w) in weights.iter().enumerate() {
            acc += if total > 0.0 { clean(w) / total } else { 1.0 / n as f64 };
            // The last entry is exactly 1 so that u < 1 always finds a cell.
            cdf.push(if i + 1 == n { 1.0 } else { acc as f32 });
        }
        Distribution1D { cdf, total }
    }

    /// The number of cells.
    pub fn len(&self) -> usize {
        self.cdf.len() - 1
    }

    /// True when there are no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The sum of the weights.
    pub fn total(&self) -> f64 {
        self.total
    }

    /// The probability of cell `i`.
    #[inline]
    pub fn prob(&self, i: usize) -> f32 {
        self.cdf[i + 1] - self.cdf[i]
    }

    /// Picks a cell for `u` in [0, 1); returns it, its probability, and `u` rescaled to
    /// [0, 1) within the cell (reusable as a fresh uniform number).
    #[inline]
    pub fn sample(&self, u: f32) -> (usize, f32, f32) {
        // The last cell whose cdf start is ≤ u, skipping zero-probability cells.
        let i = self.cdf.partition_point(|&c| c <= u).saturating_sub(1).min(self.len() - 1);
        let p = self.prob(i);
        let rest = if p > 0.0 { ((u - self.cdf[i]) / p).clamp(0.0, 1.0 - f32::EPSILON / 2.0) } else { 0.5 };
        (i, p, rest)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probabilities_follow_weights_and_zero_cells_are_never_picked() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0, 0.0]);
        assert_eq!(d.total(), 4.0);
        assert!((d.prob(0) - 0.25).abs() < 1e-7 && d.prob(1) == 0.0 && (d.prob(2) - 0.75).abs() < 1e-7);
        for k in 0..1000 {
            let u = k as f32 / 1000.0;
            let (i, p, rest) = d.sample(u);
            assert!(i == 0 || i == 2, "u {u} gave cell {i}");
            assert!(p > 0.0 && (0.0..1.0).contains(&rest));
        }
        assert_eq!(d.sample(0.0).0, 0);
        assert_eq!(d.sample(0.25).0, 2);
        assert_eq!(d.sample(1.0 - f32::EPSILON).0, 2);
        let z = Distribution1D::new(&[0.0, 0.0]);
        assert_eq!(z.prob(0), 0.5);
    }
}
