//! A wavelength-sampling table made from any non-negative density on a wavelength range: the
//! path tracer's observer × emission importance ([`crate::integrator::wavelengths::groups`]).
//!
//! Like the visible-importance table of [`super::wavelength_sampling`], it is a piecewise-constant
//! density on [`WAVELENGTH_TABLE_SEGMENTS`] segments of equal probability: knot `k` is the
//! target density's inverse CDF at `u = k/N` and segment `k` has the constant density
//! `1/(N·(knots[k+1] − knots[k]))`. Drawing a wavelength is a multiply, a table read and a
//! linear interpolation; the pdf a lane stores is exactly the density it was drawn from (the
//! table's, which follows the target density up to the segment width).
//!
//! | quantity | unit | meaning |
//! |---|---|---|
//! | `range` | nm | support of the table: the density is 0 outside it |
//! | `knots` | nm | `N + 1` segment ends, strictly increasing, `knots[0]` and `knots[N]` the range's ends |
//! | `pdf` | 1/nm | `N` segment densities |
//! | [`INTEGRATION_STEP_NM`] | nm | cell width of the midpoint rule that finds the knots |

use super::wavelength_sampling::rotated;
use super::{SampledWavelengths, LANES};

/// Segments of a [`WavelengthTable`] (equal probability each).
pub const WAVELENGTH_TABLE_SEGMENTS: usize = 1024;

/// Cell width (nm) of the midpoint rule that integrates the target density to place the knots.
/// Within a cell the target is taken as constant, so a knot is where the target's CDF at this
/// resolution reaches `k/N`.
pub const INTEGRATION_STEP_NM: f64 = 0.05;

/// An equal-probability piecewise-constant wavelength density (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct WavelengthTable {
    knots: Vec<f64>,
    pdf: Vec<f64>,
}

impl WavelengthTable {
    /// The table following `density` (any scale, ≥ 0) on `range` (nm). An error when the range
    /// is empty or not finite, when the density is negative or not finite somewhere on it, or
    /// when it integrates to 0. A segment of zero width cannot arise: every segment holds
    /// probability `1/N` > 0 of a finite density.
    pub fn from_density(range: (f64, f64), density: impl Fn(f64) -> f64) -> Result<Self, String> {
        Self::from_mixture(range, &[(1.0, &density)])
    }

    /// The table following the mixture `Σ wᵢ·dᵢ(λ)/∫dᵢ` of the components `(wᵢ, dᵢ)` (weights
    /// summing to 1, each density of any scale, ≥ 0) on `range` (nm): each component is
    /// normalised on the range first, so the weights are the components' probabilities. Errors
    /// as for [`from_density`](Self::from_density), also when a component with a positive weight
    /// integrates to 0 or a weight is negative.
    pub fn from_mixture(
        range: (f64, f64),
        components: &[(f64, &dyn Fn(f64) -> f64)],
    ) -> Result<Self, String> {
        let (lo, hi) = range;
        if !(lo.is_finite() && hi.is_finite() && hi > lo) {
            return Err(format!("wavelength table: empty range {lo}–{hi} nm"));
        }
        let cells = ((hi - lo) / INTEGRATION_STEP_NM).ceil().max(1.0) as usize;
        let h = (hi - lo) / cells as f64;
        let mut mass = vec![0.0f64; cells];
        for (c, (w, density)) in components.iter().enumerate() {
            if !(*w >= 0.0 && w.is_finite()) {
                return Err(format!("wavelength table: component {c} has weight {w}"));
            }
            if *w == 0.0 {
                continue;
            }
            let values = (0..cells)
                .map(|j| {
                    let l = lo + (j as f64 + 0.5) * h;
                    let d = density(l);
                    if d >= 0.0 && d.is_finite() {
                        Ok(d)
                    } else {
                        Err(format!("wavelength table: density {d} at {l:.2} nm"))
                    }
                })
                .collect::<Result<Vec<f64>, String>>()?;
            let total: f64 = values.iter().sum();
            if !(total > 0.0) {
                return Err(format!("wavelength table: density is 0 on {lo}–{hi} nm"));
            }
            for (m, v) in mass.iter_mut().zip(values) {
                *m += w * v / total;
            }
        }
        let mut cdf = Vec::with_capacity(cells + 1);
        cdf.push(0.0f64);
        let mut acc = 0.0f64;
        for m in &mass {
            acc += m;
            cdf.push(acc);
        }
        if !(acc > 0.0) {
            return Err(format!("wavelength table: density is 0 on {lo}–{hi} nm"));
        }
        let n = WAVELENGTH_TABLE_SEGMENTS;
        let mut knots = Vec::with_capacity(n + 1);
        knots.push(lo);
        let mut j = 0usize;
        for k in 1..n {
            let t = acc * k as f64 / n as f64;
            // Last cell whose start lies below t; t lies inside it (its mass is positive).
            while j + 1 < cells && cdf[j + 1] < t {
                j += 1;
            }
            let mass = cdf[j + 1] - cdf[j];
            let f = if mass > 0.0 {
                ((t - cdf[j]) / mass).clamp(0.0, 1.0)
            } else {
                0.5
            };
            knots.push(lo + (j as f64 + f) * h);
        }
        knots.push(hi);
        let mut pdf = Vec::with_capacity(n);
        for k in 0..n {
            let w = knots[k + 1] - knots[k];
            if !(w > 0.0) {
                return Err(format!(
                    "wavelength table: segment {k} at {:.3} nm has no width (density too peaked for {n} segments)",
                    knots[k]
                ));
            }
            pdf.push(1.0 / (n as f64 * w));
        }
        Ok(Self { knots, pdf })
    }

    /// Support (nm): the density is 0 outside it.
    pub fn range(&self) -> (f64, f64) {
        (self.knots[0], self.knots[WAVELENGTH_TABLE_SEGMENTS])
    }

    /// Density (1/nm) at `lambda_nm`; 0 outside [`range`](Self::range).
    pub fn pdf(&self, lambda_nm: f64) -> f64 {
        let (lo, hi) = self.range();
        if !(lambda_nm >= lo && lambda_nm <= hi) {
            return 0.0;
        }
        let k = self.knots.partition_point(|&x| x <= lambda_nm);
        self.pdf[k.clamp(1, WAVELENGTH_TABLE_SEGMENTS) - 1]
    }

    /// Inverse CDF at `u ∈ [0, 1]` and the segment it falls in.
    #[inline]
    fn invert(&self, u: f64) -> (f64, usize) {
        let x = u.clamp(0.0, 1.0) * WAVELENGTH_TABLE_SEGMENTS as f64;
        // x ∈ [0, segments]: `as i32` floors it with one conversion (a float → usize
        // conversion saturates, which costs more instructions).
        let k = (x as i32 as usize).min(WAVELENGTH_TABLE_SEGMENTS - 1);
        let (a, b) = (self.knots[k], self.knots[k + 1]);
        (a + (x - k as f64) * (b - a), k)
    }

    /// Inverse CDF: the wavelength (nm) drawn by `u ∈ [0, 1]`.
    pub fn sample(&self, u: f64) -> f64 {
        self.invert(u).0
    }

    /// [`pdf`](Self::pdf) of `lambda_nm` known to lie in or next to segment `k` (as after
    /// rounding a draw of segment `k` to f32): a neighbour check instead of a search.
    #[inline]
    fn pdf_near(&self, lambda_nm: f64, k: usize) -> f64 {
        if lambda_nm < self.knots[k] || lambda_nm >= self.knots[k + 1] {
            return self.pdf(lambda_nm);
        }
        self.pdf[k]
    }

    /// Four lanes from one uniform: lane `i` is the inverse CDF at `frac(u + i/LANES)` and
    /// stores the density of its (f32) wavelength, its marginal density.
    pub fn sample_lanes(&self, u: f64) -> SampledWavelengths {
        SampledWavelengths::from_lanes(|i| {
            let (l, k) = self.invert(rotated(u, i, LANES));
            let l = l as f32;
            (l, self.pdf_near(l as f64, k) as f32)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // A triangle-shaped target on 400–700 nm: the table integrates to 1 (midpoint rule at
    // 0.01 nm; the density is piecewise constant, so the rule errs only in the cells holding a
    // knot, each by at most 0.01 nm × the largest density jump, < 1e-4 in all; tolerance 1e-3),
    // the inverse CDF is consistent with the density (d λ(u)/du · p(λ(u)) = 1 inside a segment,
    // 1e-6 for rounding at h = 1e-7), and the table follows the target: at 300 points away from
    // the peak and the ends, within 2% of the normalised triangle (the segments there are
    // < 0.6 nm wide and the triangle's relative slope is < 1/100 per nm near its middle, < 3%
    // per segment near the ends, which are left out).
    #[test]
    fn follows_its_target_and_is_normalised() {
        let tri = |l: f64| 150.0 - (l - 550.0).abs();
        let t = WavelengthTable::from_density((400.0, 700.0), tri).unwrap();
        let n = 30_000;
        let h = 300.0 / n as f64;
        let sum: f64 = (0..n)
            .map(|i| t.pdf(400.0 + (i as f64 + 0.5) * h) * h)
            .sum();
        assert!((sum - 1.0).abs() < 1e-3, "{sum}");
        for k in 1..20 {
            let u = ((k as f64 / 20.0 * 1024.0).floor() + 0.5) / 1024.0;
            let d = 1e-7;
            let dl = (t.sample(u + d) - t.sample(u - d)) / (2.0 * d);
            assert!((dl * t.pdf(t.sample(u)) - 1.0).abs() < 1e-6, "u = {u}");
        }
        let norm = 150.0 * 150.0; // area of the triangle
        for i in 0..300 {
            let l = 450.0 + 200.0 * (i as f64 + 0.5) / 300.0;
            if (l - 550.0).abs() < 2.0 {
                continue;
            }
            let ratio = t.pdf(l) / (tri(l) / norm);
            assert!((ratio - 1.0).abs() < 0.02, "{l}: {ratio}");
        }
        assert_eq!(t.pdf(399.9), 0.0);
        assert_eq!(t.pdf(700.1), 0.0);
        assert_eq!(t.sample(0.0), 400.0);
        assert_eq!(t.sample(1.0), 700.0);
    }

    // Each lane stores the density of its own f32 wavelength (exact equality: the same f64
    // value), over many u including segment ends.
    #[test]
    fn lanes_carry_their_own_pdf() {
        let t = WavelengthTable::from_density((360.0, 830.0), |l| 1.0 + (l / 40.0).sin().abs())
            .unwrap();
        for k in 0..=4096 {
            let w = t.sample_lanes(k as f64 / 4096.0);
            for i in 0..LANES {
                assert_eq!(
                    w.pdf[i],
                    t.pdf(w.lambda[i] as f64) as f32,
                    "u {k}, lane {i}"
                );
                assert!(w.pdf[i] > 0.0);
            }
        }
    }

    // Bad targets are errors naming the problem, not panics.
    #[test]
    fn bad_targets_are_errors() {
        let e = WavelengthTable::from_density((500.0, 400.0), |_| 1.0).unwrap_err();
        assert!(e.contains("range"), "{e}");
        let e = WavelengthTable::from_density((400.0, 500.0), |_| 0.0).unwrap_err();
        assert!(e.contains("is 0"), "{e}");
        let e = WavelengthTable::from_density((400.0, 500.0), |l| 450.0 - l).unwrap_err();
        assert!(e.contains("density -"), "{e}");
        let e = WavelengthTable::from_density((400.0, 500.0), |_| f64::NAN).unwrap_err();
        assert!(e.contains("NaN"), "{e}");
    }
}
