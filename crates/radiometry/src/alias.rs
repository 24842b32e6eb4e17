//! Walker's alias method: a discrete distribution sampled in constant time with one table
//! lookup (Walker, "An efficient method for generating discrete random variables with general
//! distributions", ACM TOMS 1977; built by Vose's stable O(n) construction, "A linear algorithm
//! for generating random numbers with a given distribution", IEEE TSE 1991). Entry k keeps
//! itself with probability q_k and otherwise gives its alias a_k; the table is exact up to
//! the rounding of the q_k to f32.

/// An alias table over n ≥ 1 outcomes.
#[derive(Clone, Debug)]
pub struct AliasTable {
    /// (q_k, a_k): keep k when the coin is below q_k, else take a_k.
    entries: Vec<(f32, u32)>,
    /// The sum of the weights.
    total: f64,
}

impl AliasTable {
    /// The entry `sample(u_index, …)` reads.
    #[inline]
    fn slot(&self, u_index: f32) -> usize {
        let n = self.entries.len();
        ((u_index * n as f32) as usize).min(n - 1)
    }

    /// Starts loading the entry that `sample(u_index, …)` will read.
    #[inline]
    pub fn prefetch(&self, u_index: f32) {
        crate::prefetch::prefetch(&self.entries[self.slot(u_index)]);
    }

    /// From non-negative weights (others count as zero). None when there is none, more than
    /// 2³² of them, or they sum to zero.
    pub fn new(weights: &[f32]) -> Option<Self> {
        let n = weights.len();
        if n == 0 || u32::try_from(n).is_err() {
            return None;
        }
        let w = |x: f32| if x.is_finite() && x > 0.0 { x as f64 } else { 0.0 };
        let total: f64 = weights.iter().map(|&x| w(x)).sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        // Scaled so that the mean is 1; the "small" ones borrow from the "large" ones.
        let mut scaled: Vec<f64> = weights.iter().map(|&x| w(x) * n as f64 / total).collect();
        let mut entries = vec![(1.0f32, 0u32); n];
        let (mut small, mut large): (Vec<u32>, Vec<u32>) = (0..n as u32).partition(|&k| scaled[k as usize] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            entries[s as usize] = (scaled[s as usize] as f32, l);
            scaled[l as usize] -= 1.0 - scaled[s as usize];
            if scaled[l as usize] < 1.0 {
                large.pop();
                small.push(l);
            }
        }
        // What is left has scaled weight 1 up to rounding: it keeps itself.
        for k in small.into_iter().chain(large) {
            entries[k as usize] = (1.0, k);
        }
        Some(AliasTable { entries, total })
    }

    /// The number of outcomes.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Never: a table has at least one outcome.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The sum of the weights it was built from.
    pub fn total(&self) -> f64 {
        self.total
    }

    /// The outcome for uniform numbers `u_index` (which entry) and `u_coin` (which of its two
    /// outcomes), with `u_coin` rescaled to a fresh uniform number in [0, 1).
    #[inline]
    pub fn sample(&self, u_index: f32, u_coin: f32) -> (usize, f32) {
        let k = self.slot(u_index);
        let (q, alias) = self.entries[k];
        let below_one = 1.0 - f32::EPSILON / 2.0;
        if u_coin < q {
            (k, (u_coin / q).min(below_one))
        } else {
            (alias as usize, ((u_coin - q) / (1.0 - q)).clamp(0.0, below_one))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outcome_probabilities_are_the_weights() {
        // Exact probabilities from a sweep over the entries and the coin: each entry covers
        // 1/n of u_index, and within it the coin splits q : 1 − q.
        let weights = [0.0f32, 3.0, 1.0, 0.5, 7.5, 0.0, 2.0, f32::NAN, -1.0];
        let t = AliasTable::new(&weights).unwrap();
        assert_eq!(t.total(), 14.0);
        let mut p = vec![0.0f64; weights.len()];
        for (k, &(q, a)) in t.entries.iter().enumerate() {
            p[k] += q as f64 / weights.len() as f64;
            p[a as usize] += (1.0 - q as f64) / weights.len() as f64;
        }
        for (k, &w) in weights.iter().enumerate() {
            let want = if w > 0.0 { w as f64 / 14.0 } else { 0.0 };
            assert!((p[k] - want).abs() < 1e-7, "outcome {k}: {} vs {want}", p[k]);
        }
        // Sampling: zero-weight outcomes never come out, the rescaled coin stays in [0, 1).
        for i in 0..1000 {
            for c in [0.0, 0.25, 0.999_999_9] {
                let (k, r) = t.sample(i as f32 / 1000.0, c);
                assert!(weights[k] > 0.0 && (0.0..1.0).contains(&r), "{i} {c}: {k} {r}");
            }
        }
        assert!(AliasTable::new(&[]).is_none() && AliasTable::new(&[0.0, 0.0]).is_none());
        assert_eq!(AliasTable::new(&[2.0]).unwrap().sample(0.7, 0.3), (0, 0.3));
    }
}
