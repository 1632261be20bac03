//! A discrete distribution over indices with probabilities proportional to given weights:
//! the seed's "sum until the running sum exceeds ηI" (seed §5), with a precomputed CDF and a
//! binary search so a draw costs O(log n). Used to pick a delta line or a mixture component.

/// Probabilities ∝ weights over `0..n`, sampled by inverting a precomputed CDF.
#[derive(Clone, Debug, PartialEq)]
pub struct DiscreteDistribution {
    /// Running sums: `cdf[0] = 0`, `cdf[i+1] = cdf[i] + w[i]`.
    cdf: Vec<f64>,
    /// Index of the last entry with positive weight (guards against `u·total` rounding up).
    last_positive: usize,
}

impl DiscreteDistribution {
    /// Build from non-negative finite weights. Returns `None` when there is no positive weight or
    /// a weight is negative or not finite.
    pub fn new(weights: &[f64]) -> Option<Self> {
        if weights.iter().any(|w| !w.is_finite() || *w < 0.0) {
            return None;
        }
        let last_positive = weights.iter().rposition(|&w| w > 0.0)?;
        let mut cdf = Vec::with_capacity(weights.len() + 1);
        cdf.push(0.0);
        let mut acc = 0.0;
        for &w in weights {
            acc += w;
            cdf.push(acc);
        }
        if !acc.is_finite() {
            return None;
        }
        Some(Self { cdf, last_positive })
    }

    /// Number of entries.
    pub fn len(&self) -> usize {
        self.cdf.len() - 1
    }

    /// True when there are no entries (never, for a successfully built distribution).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sum of all weights.
    pub fn total(&self) -> f64 {
        self.cdf[self.cdf.len() - 1]
    }

    /// Probability of index `i` (0 for out-of-range indices).
    pub fn probability(&self, i: usize) -> f64 {
        if i >= self.len() {
            return 0.0;
        }
        (self.cdf[i + 1] - self.cdf[i]) / self.total()
    }

    /// Draw an index with `u ∈ [0,1)`. Returns the index, its probability, and `u` remapped to
    /// `[0,1)` within the chosen entry so the caller can reuse it for a further decision.
    /// Zero-weight entries are never returned.
    pub fn sample(&self, u: f64) -> (usize, f64, f64) {
        let target = u.clamp(0.0, 1.0) * self.total();
        // First index whose running sum exceeds the target is one past the chosen entry; a
        // zero-weight entry has cdf[i] == cdf[i+1] and so can never straddle the target.
        let i = (self.cdf.partition_point(|&c| c <= target).max(1) - 1).min(self.last_positive);
        let w = self.cdf[i + 1] - self.cdf[i];
        let remapped = ((target - self.cdf[i]) / w).clamp(0.0, 1.0 - f64::EPSILON / 2.0);
        (i, w / self.total(), remapped)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Zero-weight entries must never be chosen, even at u = 0 and u → 1 (exact check: a single
    // wrong index is a bug, not a tolerance issue).
    #[test]
    fn skips_zero_weights_at_both_ends() {
        let d = DiscreteDistribution::new(&[0.0, 1.0, 0.0, 3.0, 0.0]).unwrap();
        assert_eq!(d.sample(0.0).0, 1);
        assert_eq!(d.sample(0.2499).0, 1);
        assert_eq!(d.sample(0.25).0, 3);
        assert_eq!(d.sample(1.0).0, 3);
        assert_eq!(d.sample(0.9999999999999999).0, 3);
        assert!((d.probability(3) - 0.75).abs() < 1e-15);
        assert!(DiscreteDistribution::new(&[0.0, 0.0]).is_none());
        assert!(DiscreteDistribution::new(&[1.0, -1.0]).is_none());
    }
}
