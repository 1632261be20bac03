//! Wavelength sampling: property tests on random tables and chi-square goodness of fit.

use proptest::prelude::*;
use spectrace::spectrum::wavelength_sampling::{visible_pdf, visible_sample};
use spectrace::spectrum::{Interpolation, Spd, TabulatedSpd};

/// SplitMix64: a tiny, well-distributed deterministic generator for the chi-square runs.
struct SplitMix(u64);
impl SplitMix {
    fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Random table: strictly increasing wavelengths from 300 nm with gaps of 0.1–50 nm; values are
/// exactly 0 (zero stretches) a third of the time, otherwise m·10^e with e ∈ [−30, 30].
fn table() -> impl Strategy<Value = (Vec<f64>, Vec<f64>)> {
    let value = prop_oneof![
        1 => Just(0.0),
        2 => (1.0f64..10.0, -30i32..=30).prop_map(|(m, e)| m * 10f64.powi(e)),
    ];
    (2usize..40)
        .prop_flat_map(move |n| {
            (
                proptest::collection::vec(0.1f64..50.0, n),
                proptest::collection::vec(value.clone(), n),
                0..n,
            )
        })
        .prop_map(|(gaps, mut values, forced)| {
            let mut x = 300.0;
            let lambda = gaps
                .iter()
                .map(|g| {
                    x += g;
                    x
                })
                .collect::<Vec<_>>();
            // At least one positive node so the table can be normalized; for step interpolation
            // the last node carries no bin, so also make sure an earlier one is positive.
            let last_bin = values.len() - 2;
            values[forced.min(last_bin)] = 1.0;
            (lambda, values)
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, .. ProptestConfig::default() })]

    // For both interpolations: every draw lies in the range, has a finite positive pdf equal
    // (to 1e-9 relative, rounding of one re-evaluation) to pdf(λ), and lands where the value
    // is positive; pdf > 0 wherever value > 0 on a probe grid; everything finite.
    #[test]
    fn samples_are_in_range_with_positive_finite_pdf(
        (lambda, values) in table(),
        us in proptest::collection::vec(0.0f64..1.0, 64),
    ) {
        for interp in [Interpolation::Linear, Interpolation::Step] {
            let spd = TabulatedSpd::new("prop", &lambda, &values, interp).unwrap();
            let (lo, hi) = spd.range();
            let mut all_u = us.clone();
            all_u.extend([0.0, 1.0 - f64::EPSILON, 0.5]);
            for &u in &all_u {
                let s = spd.sample(u);
                prop_assert!(s.lambda >= lo && s.lambda <= hi, "{} not in {lo}..{hi}", s.lambda);
                prop_assert!(s.pdf.is_finite() && s.pdf > 0.0, "pdf {} at {}", s.pdf, s.lambda);
                prop_assert!(!s.is_delta);
                let p = spd.pdf(s.lambda);
                prop_assert!(p.is_finite() && p > 0.0, "pdf(λ) {p} at {}", s.lambda);
                prop_assert!((p - s.pdf).abs() <= 1e-9 * s.pdf, "{p} vs {}", s.pdf);
            }
            for k in 0..=200 {
                let l = lo + (hi - lo) * k as f64 / 200.0;
                let v = spd.value(l);
                prop_assert!(v.is_finite() && v >= 0.0);
                if v > 0.0 {
                    prop_assert!(spd.pdf(l) > 0.0);
                }
            }
        }
    }
}

/// Chi-square of `n` draws of `sample` against the exact bin probabilities `prob` over the
/// equal-width bins of `[lo, hi]`. Bins with zero probability must receive no draws; bins with
/// expected count < 5 are pooled into one, as the test's asymptotics require.
fn chi_square(
    n: usize,
    lo: f64,
    hi: f64,
    bins: usize,
    prob: &dyn Fn(f64, f64) -> f64,
    sample: &mut dyn FnMut() -> f64,
) -> (f64, usize) {
    let mut counts = vec![0usize; bins];
    for _ in 0..n {
        let l = sample();
        let b = (((l - lo) / (hi - lo)) * bins as f64).floor() as usize;
        counts[b.min(bins - 1)] += 1;
    }
    let mut stat = 0.0;
    let mut used = 0;
    let (mut pooled_e, mut pooled_o) = (0.0, 0.0);
    for (b, &count) in counts.iter().enumerate() {
        let a = lo + (hi - lo) * b as f64 / bins as f64;
        let c = lo + (hi - lo) * (b + 1) as f64 / bins as f64;
        let e = prob(a, c) * n as f64;
        if e == 0.0 {
            assert_eq!(count, 0, "draws in a zero-probability bin {a}..{c}");
        } else if e < 5.0 {
            pooled_e += e;
            pooled_o += count as f64;
        } else {
            stat += (count as f64 - e).powi(2) / e;
            used += 1;
        }
    }
    if pooled_e > 0.0 {
        stat += (pooled_o - pooled_e).powi(2) / pooled_e;
        used += 1;
    }
    (stat, used - 1)
}

/// Upper α = 0.001 critical value of χ² with `df` degrees of freedom (Wilson–Hilferty cube
/// approximation, z₀.₉₉₉ = 3.0902; accurate to < 0.5 % for df ≥ 10).
fn critical_0001(df: usize) -> f64 {
    let d = df as f64;
    let q = 2.0 / (9.0 * d);
    d * (1.0 - q + 3.0902 * q.sqrt()).powi(3)
}

/// Exact integral of the linear interpolation of `(x, f)` over `[a, c]` (trapezoid on the merged
/// grid is exact for a piecewise-linear function), computed independently of the library.
fn linear_integral(x: &[f64], f: &[f64], a: f64, c: f64) -> f64 {
    let interp = |l: f64| -> f64 {
        if l < x[0] || l > x[x.len() - 1] {
            return 0.0;
        }
        for i in 0..x.len() - 1 {
            if l <= x[i + 1] {
                let s = (l - x[i]) / (x[i + 1] - x[i]);
                return f[i] + s * (f[i + 1] - f[i]);
            }
        }
        0.0
    };
    let mut pts = vec![a, c];
    pts.extend(x.iter().copied().filter(|&v| v > a && v < c));
    pts.sort_by(|p, q| p.partial_cmp(q).unwrap());
    pts.windows(2)
        .map(|w| 0.5 * (interp(w[0]) + interp(w[1])) * (w[1] - w[0]))
        .sum()
}

// 10⁶ draws from a table with a zero stretch, a steep ramp from 0, a flat top and values
// spanning 6 decades, binned into 200 equal bins (which do not align with the nodes). The test
// fails at significance α = 0.001 (a correct sampler fails one seed in a thousand; the seed is
// fixed, so the outcome is deterministic). Zero-probability bins must stay empty.
#[test]
fn chi_square_piecewise_linear() {
    let x = [
        380.0, 400.0, 430.0, 431.0, 500.0, 520.0, 600.0, 700.0, 780.0,
    ];
    let f = [0.0, 0.0, 5.0, 1e-3, 1e-3, 3.0, 3.0, 1e-6, 0.5];
    let spd = TabulatedSpd::new("chi", &x, &f, Interpolation::Linear).unwrap();
    let total = linear_integral(&x, &f, 380.0, 780.0);
    let mut rng = SplitMix(1);
    let (stat, df) = chi_square(
        1_000_000,
        380.0,
        780.0,
        200,
        &|a, c| linear_integral(&x, &f, a, c) / total,
        &mut || spd.sample(rng.next_f64()).lambda,
    );
    assert!(
        stat < critical_0001(df),
        "χ² = {stat} with {df} dof (critical {})",
        critical_0001(df)
    );
}

// Same for step interpolation: bin probabilities are exact sums of value × overlap.
#[test]
fn chi_square_piecewise_constant() {
    let x = [
        380.0, 400.0, 430.0, 431.0, 500.0, 520.0, 600.0, 700.0, 780.0,
    ];
    let f = [0.0, 2.0, 50.0, 0.0, 1.0, 3.0, 1e-4, 0.5, 0.0];
    let spd = TabulatedSpd::new("chi", &x, &f, Interpolation::Step).unwrap();
    let mass = |a: f64, c: f64| -> f64 {
        (0..x.len() - 1)
            .map(|i| f[i] * (x[i + 1].min(c) - x[i].max(a)).max(0.0))
            .sum()
    };
    let total = mass(380.0, 780.0);
    let mut rng = SplitMix(2);
    let (stat, df) = chi_square(
        1_000_000,
        380.0,
        780.0,
        200,
        &|a, c| mass(a, c) / total,
        &mut || spd.sample(rng.next_f64()).lambda,
    );
    assert!(
        stat < critical_0001(df),
        "χ² = {stat} with {df} dof (critical {})",
        critical_0001(df)
    );
}

// Visible-importance sampling against its analytic pdf: bin probabilities by Simpson's rule
// with 64 panels per bin (the density is constant between its table's knots, so the rule errs
// only in panels holding a knot, by at most a panel width times a ≈1% density jump: < 1e-6 of a
// bin's probability), α = 0.001 as above.
#[test]
fn chi_square_visible() {
    let bin_prob = |a: f64, c: f64| -> f64 {
        let n = 64;
        let h = (c - a) / n as f64;
        let s: f64 = (0..=n)
            .map(|i| {
                let w = if i == 0 || i == n {
                    1.0
                } else if i % 2 == 1 {
                    4.0
                } else {
                    2.0
                };
                w * visible_pdf(a + i as f64 * h)
            })
            .sum();
        s * h / 3.0
    };
    let mut rng = SplitMix(3);
    let (stat, df) = chi_square(1_000_000, 360.0, 830.0, 100, &bin_prob, &mut || {
        visible_sample(rng.next_f64())
    });
    assert!(
        stat < critical_0001(df),
        "χ² = {stat} with {df} dof (critical {})",
        critical_0001(df)
    );
}

// A sum of a continuous SPD and a delta line: the line is drawn with its power fraction
// (binomial, 10⁵ draws: 5σ = 5·√(p(1−p)/n) ≈ 0.0068 for p = 0.3) and reported as delta with
// pdf = 0.3 exactly; continuous draws report pdf = value.
#[test]
fn delta_line_is_drawn_with_its_weight() {
    let spd = spectrace::spectrum::parse_spd_spec("0.7*gaussian:600:30 + 0.3*line:532").unwrap();
    let mut rng = SplitMix(4);
    let n = 100_000;
    let mut hits = 0;
    for _ in 0..n {
        let s = spd.sample(rng.next_f64());
        if s.is_delta {
            assert_eq!(s.lambda, 532.0);
            assert!((s.pdf - 0.3).abs() < 1e-12);
            hits += 1;
        } else {
            assert!((s.pdf - spd.value(s.lambda)).abs() <= 1e-12 * s.pdf);
        }
    }
    let frac = hits as f64 / n as f64;
    assert!((frac - 0.3).abs() < 0.0068, "{frac}");
}

// Each lane's stored pdf must be that lane's actual marginal density. For lanes 1..LANES of
// visible-importance and light-SPD (D65) sampling, 2·10⁵ draws of the lane's wavelength are
// binned and tested against the density the lane reports (bin probabilities by Simpson's rule
// on `pdf`, 16 panels per bin; error ≪ 1e-6 for these smooth densities), at α = 0.001.
#[test]
fn every_lane_has_its_own_marginal_pdf() {
    use spectrace::spectrum::{parse_spd_spec, SampledWavelengths, LANES};
    let d65 = parse_spd_spec("d65").unwrap();
    type Case<'a> = (
        &'a str,
        f64,
        f64,
        Box<dyn Fn(f64) -> f64 + 'a>,
        Box<dyn Fn(f32) -> SampledWavelengths + 'a>,
    );
    let cases: Vec<Case> = vec![
        (
            "visible",
            360.0,
            830.0,
            Box::new(visible_pdf),
            Box::new(SampledWavelengths::sample_visible),
        ),
        (
            "d65",
            300.0,
            780.0,
            Box::new(|l| d65.pdf(l)),
            Box::new(|u| SampledWavelengths::sample_spd(&d65, u)),
        ),
    ];
    for (name, lo, hi, pdf, draw) in &cases {
        let simpson = |a: f64, c: f64| -> f64 {
            let n = 16;
            let h = (c - a) / n as f64;
            let s: f64 = (0..=n)
                .map(|i| {
                    let w = if i == 0 || i == n {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    w * pdf(a + i as f64 * h)
                })
                .sum();
            s * h / 3.0
        };
        for lane in 1..LANES {
            let mut rng = SplitMix(10 + lane as u64);
            let (stat, df) = chi_square(200_000, *lo, *hi, 96, &simpson, &mut || {
                let w = draw(rng.next_f64() as f32);
                // The stored pdf must be the density at the stored wavelength (1e-5 relative:
                // f32 storage of λ and pdf).
                let p = pdf(w.lambda[lane] as f64);
                assert!(
                    (w.pdf[lane] as f64 - p).abs() <= 1e-5 * p,
                    "{name} lane {lane}"
                );
                w.lambda[lane] as f64
            });
            assert!(
                stat < critical_0001(df),
                "{name} lane {lane}: χ² = {stat} with {df} dof"
            );
        }
    }
}
