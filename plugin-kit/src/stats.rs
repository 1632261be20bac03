//! The statistics of the kit: Pearson's chi-square test of samples against a density (over the
//! sphere of directions, or over an interval of wavelengths), with the binning of Mitsuba 3's
//! `chi2` tests, and the chi-square distribution's tail.
//!
//! Written by hand: the one special function needed (the regularised upper incomplete gamma
//! function, for the p-value) is forty lines, while the statistics crates that offer it pull in
//! a linear-algebra stack that every plugin author would then compile for a dev-dependency.
//!
//! # The test
//!
//! Samples are counted in cells; each cell's expected count is the density integrated over the
//! cell (composite Simpson rule, [`SUBDIVISIONS`] intervals per cell side; cells the edge of
//! the density's support or a steep lobe crosses by the midpoint rule on a [`REFINE`]² grid),
//! scaled so that the
//! expected counts add up to the observed ones: the test compares the *shape* of the sampled
//! distribution with the density's, and the kit checks the mass separately (`pdf_integral`,
//! `lines`), so that each defect is caught by one check. Cells whose expected count is below
//! [`MIN_EXPECTED`] are pooled, smallest first, until each pool reaches it (Pearson's
//! approximation of the statistic's distribution by χ² needs about five per cell). Samples in
//! cells where the density is zero at every quadrature node fail the test outright when there
//! are more than [`ZERO_CELL_TOLERANCE`] of them (a quadrature node grid can miss a sliver of
//! support at a cell's edge, so one stray sample is not proof).

/// Intervals of the Simpson rule along each side of a cell (even).
pub const SUBDIVISIONS: usize = 6;
/// Smallest expected count of a cell (or pool of cells).
pub const MIN_EXPECTED: f64 = 5.0;
/// Samples tolerated in cells of zero expected count before the test fails outright.
pub const ZERO_CELL_TOLERANCE: u64 = 5;

/// Overall significance level of a check's chi-square tests: a correct plugin fails a check
/// with probability at most 1 % (over the check's test cases, see [`per_test_level`]). The kit's
/// seeds are fixed, so a given plugin always gets the same verdict.
pub const SIGNIFICANCE: f64 = 0.01;

/// Šidák's form of the Bonferroni correction (as Mitsuba's tests): the level each of `tests`
/// independent tests must reach so that all of them pass a correct plugin with probability
/// `1 − SIGNIFICANCE`.
pub fn per_test_level(tests: usize) -> f64 {
    1.0 - (1.0 - SIGNIFICANCE).powf(1.0 / tests.max(1) as f64)
}

/// Outcome of one chi-square test.
#[derive(Clone, Debug, Default)]
pub struct Chi2 {
    /// Pearson's statistic.
    pub statistic: f64,
    /// Degrees of freedom (cells after pooling, minus one).
    pub dof: usize,
    /// Probability of a statistic at least this large under the null hypothesis.
    pub p_value: f64,
    /// Samples counted.
    pub observed: u64,
    /// Samples in cells of zero expected count.
    pub in_zero_cells: u64,
    /// The density integrated over the whole domain (before scaling).
    pub mass: f64,
}

/// Pearson's test of `observed` counts against `expected` densities integrated per cell (any
/// scale: they are scaled to the observed total).
pub fn pearson(observed: &[u64], integrals: &[f64]) -> Chi2 {
    let mass: f64 = integrals.iter().sum();
    let total: u64 = observed.iter().sum();
    let mut out = Chi2 {
        observed: total,
        mass,
        ..Chi2::default()
    };
    if total == 0 || !(mass > 0.0) {
        out.p_value = if total == 0 { 1.0 } else { 0.0 };
        out.in_zero_cells = total;
        return out;
    }
    let scale = total as f64 / mass;
    let mut cells: Vec<(f64, u64)> = Vec::with_capacity(observed.len());
    for (&o, &e) in observed.iter().zip(integrals) {
        if e > 0.0 {
            cells.push((e * scale, o));
        } else {
            out.in_zero_cells += o;
        }
    }
    cells.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut pooled: Vec<(f64, f64)> = Vec::new();
    let (mut pe, mut po) = (0.0, 0.0);
    for (e, o) in cells {
        if e < MIN_EXPECTED || pe > 0.0 && pe < MIN_EXPECTED {
            pe += e;
            po += o as f64;
            if pe >= MIN_EXPECTED {
                pooled.push((pe, po));
                pe = 0.0;
                po = 0.0;
            }
        } else {
            pooled.push((e, o as f64));
        }
    }
    if pe > 0.0 {
        // The last pool fell short: merge it into the smallest cell kept.
        match pooled.first_mut() {
            Some(first) => {
                first.0 += pe;
                first.1 += po;
            }
            None => pooled.push((pe, po)),
        }
    }
    out.statistic = pooled.iter().map(|(e, o)| (o - e) * (o - e) / e).sum();
    out.dof = pooled.len().saturating_sub(1);
    out.p_value = if out.in_zero_cells > ZERO_CELL_TOLERANCE {
        0.0
    } else if out.dof == 0 {
        1.0
    } else {
        chi2_upper_tail(out.statistic, out.dof as f64)
    };
    out
}

/// Cells over the sphere: `rows` bands of equal height in cos θ (so of equal solid angle) by
/// `cols` sectors in φ, as Mitsuba's spherical domain (which bins in cos θ and φ).
#[derive(Clone, Copy, Debug)]
pub struct SphereGrid {
    /// Bands in cos θ over [−1, 1].
    pub rows: usize,
    /// Sectors in φ over [−π, π].
    pub cols: usize,
}

impl SphereGrid {
    /// The grid the kit uses: 16 × 32 = 512 cells of π/128 sr each, fine enough to see a lobe
    /// a few degrees off and coarse enough for 10⁵ samples to fill the cells of a diffuse lobe
    /// with ≈ 400 each.
    pub const DEFAULT: Self = Self { rows: 16, cols: 32 };

    /// The cell of a direction (any length).
    pub fn cell(&self, d: [f64; 3]) -> Option<usize> {
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        if !(len > 0.0) || !len.is_finite() {
            return None;
        }
        let z = (d[2] / len).clamp(-1.0, 1.0);
        let phi = d[1].atan2(d[0]);
        let r = (((z + 1.0) * 0.5 * self.rows as f64) as usize).min(self.rows - 1);
        let c = (((phi + std::f64::consts::PI) / (2.0 * std::f64::consts::PI) * self.cols as f64)
            as usize)
            .min(self.cols - 1);
        Some(r * self.cols + c)
    }

    /// The density (1/sr) integrated over each cell: ∫∫ pdf dcosθ dφ (dω = dcosθ dφ exactly).
    /// A non-finite or negative density counts as 0 here (the `finite` checks report it).
    pub fn integrate(&self, pdf: &mut dyn FnMut([f64; 3]) -> f64) -> Vec<f64> {
        let n = SUBDIVISIONS;
        let dz = 2.0 / self.rows as f64;
        let dp = 2.0 * std::f64::consts::PI / self.cols as f64;
        let w = simpson_weights(n);
        let mut out = vec![0.0; self.rows * self.cols];
        for r in 0..self.rows {
            for c in 0..self.cols {
                let mut sum = 0.0;
                let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
                for (i, wi) in w.iter().enumerate() {
                    let z = -1.0 + dz * (r as f64 + i as f64 / n as f64);
                    let s = (1.0 - z * z).max(0.0).sqrt();
                    for (j, wj) in w.iter().enumerate() {
                        let phi = -std::f64::consts::PI + dp * (c as f64 + j as f64 / n as f64);
                        let v = clean(pdf([s * phi.cos(), s * phi.sin(), z]));
                        sum += wi * wj * v;
                        lo = lo.min(v);
                        hi = hi.max(v);
                    }
                }
                out[r * self.cols + c] = if hi > 0.0 && hi > REFINE_RATIO * lo {
                    // An edge of the density's support, or a steep lobe, crosses the cell:
                    // Simpson's rule assumes smoothness, so integrate by the midpoint rule on
                    // a fine grid instead (error O(h) at a jump, h = 1/REFINE of the cell).
                    let mut sum = 0.0;
                    for i in 0..REFINE {
                        let z = -1.0 + dz * (r as f64 + (i as f64 + 0.5) / REFINE as f64);
                        let s = (1.0 - z * z).max(0.0).sqrt();
                        for j in 0..REFINE {
                            let phi = -std::f64::consts::PI
                                + dp * (c as f64 + (j as f64 + 0.5) / REFINE as f64);
                            sum += clean(pdf([s * phi.cos(), s * phi.sin(), z]));
                        }
                    }
                    sum * dz * dp / (REFINE * REFINE) as f64
                } else {
                    sum * (dz / n as f64 / 3.0) * (dp / n as f64 / 3.0)
                };
            }
        }
        out
    }
}

/// Cells whose density varies by more than this factor between quadrature nodes (or is 0 at
/// some) are integrated on the fine grid of [`REFINE`]² points instead.
pub const REFINE_RATIO: f64 = 20.0;
/// Points per side of the fine grid.
pub const REFINE: usize = 96;

/// A density value usable in a sum: NaN, infinite or negative values count as 0 (the `finite`
/// checks report them).
fn clean(v: f64) -> f64 {
    if v.is_finite() && v > 0.0 {
        v
    } else {
        0.0
    }
}

/// Composite Simpson weights for `n` (even) intervals, without the h/3 factor.
fn simpson_weights(n: usize) -> Vec<f64> {
    (0..=n)
        .map(|i| {
            if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            }
        })
        .collect()
}

/// ∫ f over [a, b] by the composite Simpson rule with `n` (even) intervals.
pub fn simpson(a: f64, b: f64, n: usize, f: &mut dyn FnMut(f64) -> f64) -> f64 {
    let n = n + n % 2;
    let h = (b - a) / n as f64;
    let w = simpson_weights(n);
    w.iter()
        .enumerate()
        .map(|(i, wi)| wi * f(a + h * i as f64))
        .sum::<f64>()
        * h
        / 3.0
}

/// Counts of `samples` (wavelengths, nm) in `bins` equal bins over [a, b] and the density
/// integrated over each bin (Simpson, [`SUBDIVISIONS`] intervals a bin), for [`pearson`].
/// Samples outside [a, b] are returned as the third value.
pub fn interval_cells(
    samples: &[f64],
    a: f64,
    b: f64,
    bins: usize,
    pdf: &mut dyn FnMut(f64) -> f64,
) -> (Vec<u64>, Vec<f64>, u64) {
    let mut counts = vec![0u64; bins];
    let mut outside = 0;
    let width = (b - a) / bins as f64;
    for &x in samples {
        if !(x >= a && x <= b) {
            outside += 1;
            continue;
        }
        let i = (((x - a) / width) as usize).min(bins - 1);
        counts[i] += 1;
    }
    let integrals = (0..bins)
        .map(|i| {
            let lo = a + width * i as f64;
            simpson(lo, lo + width, SUBDIVISIONS, &mut |x| {
                let v = pdf(x);
                if v.is_finite() && v > 0.0 {
                    v
                } else {
                    0.0
                }
            })
        })
        .collect();
    (counts, integrals, outside)
}

/// P(X ≥ x) for X ~ χ²(k): the regularised upper incomplete gamma function Q(k/2, x/2).
pub fn chi2_upper_tail(x: f64, k: f64) -> f64 {
    if !(x > 0.0) {
        return 1.0;
    }
    upper_gamma_q(0.5 * k, 0.5 * x)
}

/// Q(a, x) = Γ(a, x)/Γ(a): the power series of P for x < a + 1, else the continued fraction of
/// Q (modified Lentz), both to double precision.
fn upper_gamma_q(a: f64, x: f64) -> f64 {
    let ln_prefactor = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut ap) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            ap += 1.0;
            term *= x / ap;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * ln_prefactor.exp()).clamp(0.0, 1.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (h * ln_prefactor.exp()).clamp(0.0, 1.0)
    }
}

/// ln Γ(x) for x > 0: Lanczos' approximation (g = 7, nine coefficients), |error| < 1e-13.
fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // Reflection: Γ(x)Γ(1−x) = π / sin(πx).
        return (std::f64::consts::PI / (std::f64::consts::PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut a = C[0];
    let t = x + G + 0.5;
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// Mean and standard error of the mean.
pub fn mean_se(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    if values.is_empty() {
        return (0.0, 0.0);
    }
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, (var / n).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tail probabilities against tabulated values of the χ² distribution (Abramowitz & Stegun
    /// table 26.8 / any statistics table): χ²(10) exceeds 18.307 with probability 0.05 and
    /// 23.209 with 0.01; χ²(1) exceeds 3.841 with 0.05; χ²(100) exceeds 124.342 with 0.05.
    /// Tolerance 2e-4 absolute: the tables give the quantiles to three decimals.
    #[test]
    fn the_tail_matches_tables() {
        for (x, k, p) in [
            (18.307, 10.0, 0.05),
            (23.209, 10.0, 0.01),
            (3.841, 1.0, 0.05),
            (124.342, 100.0, 0.05),
            (2.0, 2.0, (-1.0f64).exp()),
        ] {
            let q = chi2_upper_tail(x, k);
            assert!((q - p).abs() < 2e-4, "Q({x}; {k}) = {q}, table {p}");
        }
    }

    /// Uniform samples against a uniform density pass; against a linear density they fail
    /// with a p-value far below any threshold. Fixed seed.
    #[test]
    fn pearson_separates_right_from_wrong() {
        let mut rng = crate::rng::Rng::new(1);
        let samples: Vec<f64> = (0..20_000).map(|_| rng.f64()).collect();
        let (c, e, out) = interval_cells(&samples, 0.0, 1.0, 50, &mut |_| 1.0);
        assert_eq!(out, 0);
        let good = pearson(&c, &e);
        assert!(good.p_value > 1e-3, "{good:?}");
        let (c, e, _) = interval_cells(&samples, 0.0, 1.0, 50, &mut |x| 2.0 * x);
        let bad = pearson(&c, &e);
        assert!(bad.p_value < 1e-12, "{bad:?}");
    }

    /// The sphere grid integrates the uniform density 1/(4π) to 1 and the cosine density of
    /// the upper hemisphere to 1 (Simpson on smooth functions: error < 1e-6 here).
    #[test]
    fn the_sphere_grid_integrates_densities() {
        let g = SphereGrid::DEFAULT;
        let u: f64 = g
            .integrate(&mut |_| 1.0 / (4.0 * std::f64::consts::PI))
            .iter()
            .sum();
        assert!((u - 1.0).abs() < 1e-9, "{u}");
        let c: f64 = g
            .integrate(&mut |d| d[2].max(0.0) / std::f64::consts::PI)
            .iter()
            .sum();
        assert!((c - 1.0).abs() < 1e-6, "{c}");
    }
}
