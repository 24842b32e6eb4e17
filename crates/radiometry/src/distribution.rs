//! A piecewise-constant 1D distribution over n cells: sampling proportional to given
//! non-negative weights by inverting the cumulative sum. A guide table (Chen & Asau 1974,
//! "On generating random variates from an empirical distribution") maps ⌊u·G⌋ to the
//! first cell that u can fall in, so a lookup searches a few cells instead of all n, and
//! the result is the same cell the full inversion gives.

/// Discrete/piecewise-constant distribution over `n` equal-width cells of [0, 1).
#[derive(Clone, Debug, PartialEq)]
pub struct Distribution1D {
    /// Normalised cumulative weights: cdf[0] = 0, cdf[n] = 1.
    cdf: Vec<f32>,
    /// guide[k]: the cell of the smallest u with ⌊u·G⌋ = k, for k = 0..G; guide[G] = n − 1.
    guide: Vec<u32>,
    /// G as f32.
    guide_scale: f32,
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
        for &w in weights {
            acc += if total > 0.0 { clean(w) / total } else { 1.0 / n as f64 };
            cdf.push(acc as f32);
        }
        // The end is exactly 1, trailing empty cells included, so that u < 1 never lands
        // in a cell of probability zero.
        let last = if total > 0.0 { weights.iter().rposition(|&w| clean(w) > 0.0).unwrap_or(0) } else { n };
        for c in cdf.iter_mut().skip(last + 1) {
            *c = 1.0;
        }
        // One sweep: the cells of increasing u are increasing.
        let mut guide = Vec::with_capacity(n + 1);
        let mut i = 0;
        for k in 0..n {
            let u = first_u(k, n);
            while i + 1 < n && cdf[i + 1] <= u {
                i += 1;
            }
            guide.push(i as u32);
        }
        guide.push(n.saturating_sub(1) as u32);
        Distribution1D { cdf, guide, guide_scale: n as f32, total }
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
        let i = self.cell(u);
        let p = self.prob(i);
        let rest = if p > 0.0 { ((u - self.cdf[i]) / p).clamp(0.0, 1.0 - f32::EPSILON / 2.0) } else { 0.5 };
        (i, p, rest)
    }

    /// The cell [`sample`](Self::sample) picks for `u`, without its probability and rescaled
    /// number (a caller that needs only the cell skips their division).
    #[inline]
    pub fn cell(&self, u: f32) -> usize {
        let k = ((u * self.guide_scale) as u32 as usize).min(self.guide.len() - 2);
        // The cell is between the guides of k and k + 1: count the cell starts ≤ u there.
        let (lo, hi) = (self.guide[k] as usize, self.guide[k + 1] as usize);
        lo + self.cdf[lo + 1..=hi].partition_point(|&c| c <= u)
    }
}

/// The smallest u ≥ 0 with ⌊u·g⌋ ≥ k as `sample` computes it in f32: the guide entries are
/// taken there, so rounding in u·g can never send a u below its guide.
fn first_u(k: usize, g: usize) -> f32 {
    let slot = |u: f32| (u * g as f32) as u32 as usize;
    let mut u = k as f32 / g as f32;
    while u > 0.0 && slot(f32::from_bits(u.to_bits() - 1)) >= k {
        u = f32::from_bits(u.to_bits() - 1);
    }
    while slot(u) < k {
        u = f32::from_bits(u.to_bits() + 1);
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn probabilities_follow_weights_and_zero_cells_are_never_picked() {
        let d = Distribution1D::new(&[1.0, 0.0, 3.0, 0.0]);
        assert_eq!(d.total(), 4.0);
        assert!((d.prob(0) - 0.25).abs() < 1e-7 && d.prob(1) == 0.0 && (d.prob(2) - 0.75).abs() < 1e-7);
        assert_eq!(d.prob(3), 0.0);
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
        assert_eq!(z.sample(0.75).0, 1);
    }

    /// The cell holding `u` by a search over all cells: the last one whose start is ≤ u
    /// (so cells of probability zero are skipped).
    fn find(d: &Distribution1D, u: f32) -> usize {
        d.cdf.partition_point(|&c| c <= u).saturating_sub(1).min(d.len() - 1)
    }

    #[test]
    fn guided_lookup_is_the_full_inversion() {
        // Weights spanning ten decades with runs of empty cells: guide intervals then hold
        // many cells or cut through one, and every u must still find the inversion's cell.
        let mut weights = Vec::new();
        let mut x = 12345u32;
        for i in 0..3000 {
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let w = if (x >> 28) < 3 { 0.0 } else { 10f32.powi(((x >> 8) % 11) as i32 - 5) };
            weights.push(if i % 500 == 7 { 1e6 } else { w });
        }
        let d = Distribution1D::new(&weights);
        // A sweep, then the f32 values around every guide boundary and every cell start.
        let mut us: Vec<f32> = (0..100_000).map(|k| k as f32 / 100_000.0).collect();
        us.extend((0..=3000).map(|k| first_u(k, 3000)));
        us.extend_from_slice(&d.cdf);
        for u in us {
            for k in -3..=3i32 {
                let v = f32::from_bits((u.to_bits() as i32 + k).max(0) as u32);
                if v < 1.0 {
                    let (i, p, rest) = d.sample(v);
                    assert_eq!(i, find(&d, v), "u {v}");
                    assert_eq!(d.cell(v), find(&d, v), "cell, u {v}");
                    assert!(p > 0.0 && (0.0..1.0).contains(&rest), "u {v}: p {p}, rest {rest}");
                }
            }
        }
    }
}
