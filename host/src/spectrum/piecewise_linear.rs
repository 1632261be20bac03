//! Sampling a piecewise-linear density by exact inversion of its CDF (seed §5, "replacing gaps
//! with a linear function"), with the segment integrals precomputed. The segment holding a
//! wavelength or a CDF value is found through a [`GuideTable`] (expected O(1), the same segment
//! as a binary search): wavelength sampling evaluates and samples light spectra for every
//! lane of every BDPT sample, where the binary searches were about half of the cost.
//!
//! Inside a segment with end values `a`, `b` and area fraction `t ∈ [0,1)`, the position
//! `s ∈ [0,1]` solves `(b−a)s² + 2as − t(a+b) = 0`. The textbook root `(√(a²+t(b²−a²)) − a)/(b−a)`
//! loses all precision when `b ≈ a`; we use the algebraically equal, cancellation-free form
//! `s = t(a+b) / (a + √((1−t)a² + tb²))`, which is exact for `a = b` (gives `s = t`) and for
//! `a = 0` (gives `s = √t`). Values are rescaled by `max(a,b)` first so 1e±30 data cannot
//! overflow the squares.

use super::guide_table::GuideTable;

/// A density on `[x₀, x_{n−1}]` proportional to the linear interpolation of `(x_i, f_i)`.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseLinear1D {
    x: Vec<f64>,
    f: Vec<f64>,
    /// `cdf[i]` = unnormalized integral from `x₀` to `x_i`.
    cdf: Vec<f64>,
    /// Index of the last segment with positive area.
    last_positive: usize,
    /// Search guides for `x` and `cdf`.
    x_guide: GuideTable,
    cdf_guide: GuideTable,
}

impl PiecewiseLinear1D {
    /// Build from strictly increasing finite `x` and finite non-negative `f` of the same length
    /// (≥ 2). Returns `None` if the inputs break those rules or the total area is zero or infinite.
    pub fn new(x: &[f64], f: &[f64]) -> Option<Self> {
        if x.len() < 2 || x.len() != f.len() {
            return None;
        }
        if x.iter().any(|v| !v.is_finite()) || f.iter().any(|v| !v.is_finite() || *v < 0.0) {
            return None;
        }
        if x.windows(2).any(|w| w[1] <= w[0]) {
            return None;
        }
        let mut cdf = Vec::with_capacity(x.len());
        cdf.push(0.0);
        let mut acc = 0.0;
        let mut last_positive = None;
        for i in 0..x.len() - 1 {
            // Halve before adding so two 1e308 values cannot overflow.
            let area = (0.5 * f[i] + 0.5 * f[i + 1]) * (x[i + 1] - x[i]);
            if area > 0.0 {
                last_positive = Some(i);
            }
            acc += area;
            cdf.push(acc);
        }
        if !(acc.is_finite() && acc > 0.0) {
            return None;
        }
        Some(Self {
            x_guide: GuideTable::new(x),
            cdf_guide: GuideTable::new(&cdf),
            x: x.to_vec(),
            f: f.to_vec(),
            cdf,
            last_positive: last_positive?,
        })
    }

    /// The node positions.
    pub fn x(&self) -> &[f64] {
        &self.x
    }

    /// The node values (unnormalized).
    pub fn f(&self) -> &[f64] {
        &self.f
    }

    /// `[x₀, x_{n−1}]`.
    pub fn range(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// Integral of the unnormalized function over its range.
    pub fn integral(&self) -> f64 {
        self.cdf[self.cdf.len() - 1]
    }

    /// Linearly interpolated unnormalized value at `x`, 0 outside the range.
    pub fn value(&self, x: f64) -> f64 {
        // `tabulation::interpolate` with the guided search (the same segment, the same value).
        let (xs, f, n) = (&self.x, &self.f, self.x.len());
        if !(x >= xs[0] && x <= xs[n - 1]) {
            return 0.0;
        }
        let i = (self.x_guide.partition_point(xs, x).max(1) - 1).min(n - 2);
        let s = (x - xs[i]) / (xs[i + 1] - xs[i]);
        (1.0 - s) * f[i] + s * f[i + 1]
    }

    /// Normalized density at `x` (1/unit of x).
    pub fn pdf(&self, x: f64) -> f64 {
        self.value(x) / self.integral()
    }

    /// Draw `x` with `u ∈ [0,1)`; returns `(x, pdf(x))`. The pdf is always finite and positive:
    /// zero-area segments are skipped and a draw never lands exactly on a zero end of a segment.
    pub fn sample(&self, u: f64) -> (f64, f64) {
        let total = self.integral();
        let target = u.clamp(0.0, 1.0) * total;
        let i =
            (self.cdf_guide.partition_point(&self.cdf, target).max(1) - 1).min(self.last_positive);
        let area = self.cdf[i + 1] - self.cdf[i];
        // Keep t strictly inside (0,1) so a zero-valued segment end is never returned.
        let t = ((target - self.cdf[i]) / area).clamp(f64::EPSILON, 1.0 - f64::EPSILON);
        let (a, b) = (self.f[i], self.f[i + 1]);
        let s = linear_segment_inverse(a, b, t);
        let (x0, x1) = (self.x[i], self.x[i + 1]);
        let x = (x0 + s * (x1 - x0)).clamp(x0, x1);
        // Evaluate at the returned x (so the pdf is exactly pdf(x), even next to a zero end
        // where rounding x matters), but on the chosen segment (so a shared node with a zero
        // neighbour cannot report the neighbour's value). Should x round onto a zero end of a
        // microscopically short segment, fall back to the value at s, which is positive.
        let s_x = (x - x0) / (x1 - x0);
        let mut v = (1.0 - s_x) * a + s_x * b;
        if v <= 0.0 {
            v = (1.0 - s) * a + s * b;
        }
        (x, v / total)
    }
}

/// Position `s ∈ [0,1]` inside a segment with end values `a`, `b ≥ 0` (not both 0) at which the
/// area fraction reaches `t ∈ [0,1]`; the cancellation-free root described in the module docs.
pub fn linear_segment_inverse(a: f64, b: f64, t: f64) -> f64 {
    let m = a.max(b);
    if m <= 0.0 {
        return t;
    }
    let (a, b) = (a / m, b / m);
    let denom = a + ((1.0 - t) * a * a + t * b * b).sqrt();
    if denom <= 0.0 {
        return 0.0;
    }
    (t * (a + b) / denom).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    // The inverse must reproduce the area fraction: ∫₀ˢ((1−σ)a+σb)dσ / ((a+b)/2) = t. Tolerance
    // 1e-14 because the closed form has only a handful of roundings (no cancellation).
    #[test]
    fn segment_inverse_reproduces_area_fraction() {
        for &(a, b) in &[
            (1.0, 1.0),
            (0.0, 1.0),
            (1.0, 0.0),
            (1.0, 1.0 + 1e-13),
            (3.0, 7.0),
            (1e-30, 1e30),
        ] {
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                let s = linear_segment_inverse(a, b, t);
                let m: f64 = f64::max(a, b);
                let (an, bn) = (a / m, b / m);
                let frac = (an * s + 0.5 * (bn - an) * s * s) / (0.5 * (an + bn));
                assert!(
                    (frac - t).abs() < 1e-14,
                    "a={a} b={b} t={t} s={s} frac={frac}"
                );
            }
        }
    }

    // A flat segment must map t to s = t exactly (the case the textbook form gets wrong).
    /// Quantity: `value` (guided search) against `tabulation::interpolate` (binary search) on
    /// an uneven table at 20 000 points in and around its range, and `sample`'s wavelength
    /// against a binary search of the CDF for the segment. Tolerance: bit equality, since both
    /// find the same segment and then do the same arithmetic.
    #[test]
    fn guided_lookups_equal_binary_search() {
        let x: Vec<f64> = (0..300)
            .map(|i| 380.0 + i as f64 + 0.003 * (i * i) as f64)
            .collect();
        let f: Vec<f64> = (0..300)
            .map(|i| {
                if (40..60).contains(&i) {
                    0.0
                } else {
                    1.0 + (i % 7) as f64
                }
            })
            .collect();
        let d = PiecewiseLinear1D::new(&x, &f).unwrap();
        let (lo, hi) = d.range();
        for k in 0..20_000 {
            let l = lo - 5.0 + (hi - lo + 10.0) * k as f64 / 19_999.0;
            assert_eq!(
                d.value(l).to_bits(),
                super::super::tabulation::interpolate(&x, &f, l).to_bits(),
                "{l}"
            );
            let u = k as f64 / 20_000.0;
            let target = u * d.integral();
            let i = (d.cdf.partition_point(|&c| c <= target).max(1) - 1).min(d.last_positive);
            let (l, _) = d.sample(u);
            assert!(
                l >= x[i] && l <= x[i + 1],
                "u = {u}: {l} outside segment {i}"
            );
        }
    }

    #[test]
    fn flat_segment_is_exact() {
        for k in 0..100 {
            let t = k as f64 / 100.0;
            assert_eq!(linear_segment_inverse(2.5, 2.5, t), t);
        }
    }

    // Zero stretches are never sampled and the pdf stays positive at both range ends
    // (exact checks: any violation is a logic error).
    #[test]
    fn never_samples_zero_stretch_and_ends_are_positive() {
        let d =
            PiecewiseLinear1D::new(&[0.0, 1.0, 2.0, 3.0, 4.0], &[0.0, 0.0, 1.0, 0.0, 0.0]).unwrap();
        for k in 0..=1000 {
            let (x, p) = d.sample(k as f64 / 1000.0);
            assert!(x > 1.0 && x < 3.0, "x={x}");
            assert!(p > 0.0 && p.is_finite());
        }
        let (x, p) = d.sample(0.0);
        assert!(x > 1.0 && p > 0.0);
    }
}
