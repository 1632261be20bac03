//! The figures a lighting report gives for a calculation grid (EN 12464-1 §4, CIE 171 §2):
//! minimum, average and maximum illuminance, the uniformity U₀ = E_min/Ē and the diversity
//! E_min/E_max, each with a standard error from the points' own Monte Carlo errors.
//!
//! Standard errors: Ē's is the reading's [`SensorReading::mean_stderr`]; E_min's and E_max's
//! are those of the point that attains them; the ratios' follow by first-order error
//! propagation, `σ(x/y)/(x/y) = √((σx/x)² + (σy/y)²)`, treating the two as independent (for a
//! ratio whose numerator is one of the denominator's points this overstates the error a
//! little). The minimum of noisy values is biased low (and the maximum high) by about one
//! standard error of the points near it: the error shown is of the point's value, not that
//! bias; more samples shrink both.

use super::estimate::SensorReading;
use serde::Serialize;

/// A value with its standard error.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct WithError {
    /// The value.
    pub value: f64,
    /// Its standard error (same unit).
    pub stderr: f64,
}

/// Grid statistics (see the module docs). Illuminances in lx.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GridStatistics {
    /// Number of points.
    pub points: usize,
    /// Smallest point value.
    pub e_min: WithError,
    /// Mean over the points.
    pub e_mean: WithError,
    /// Largest point value.
    pub e_max: WithError,
    /// E_min / Ē.
    pub u0: WithError,
    /// E_min / E_max.
    pub min_over_max: WithError,
    /// Index of the smallest point (row-major).
    pub min_index: usize,
    /// Index of the largest point.
    pub max_index: usize,
}

fn ratio(x: WithError, y: WithError) -> WithError {
    if !(y.value != 0.0 && x.value.is_finite() && y.value.is_finite()) {
        return WithError {
            value: 0.0,
            stderr: 0.0,
        };
    }
    let r = x.value / y.value;
    let rel_x = if x.value != 0.0 {
        x.stderr / x.value
    } else {
        0.0
    };
    let rel_y = y.stderr / y.value;
    WithError {
        value: r,
        stderr: r.abs() * (rel_x * rel_x + rel_y * rel_y).sqrt(),
    }
}

/// Statistics of `values` (one per point) with standard errors `stderr`, the mean's own
/// standard error `mean_stderr`. An error for an empty grid.
pub fn statistics(
    values: &[f64],
    stderr: &[f64],
    mean_stderr: f64,
) -> Result<GridStatistics, String> {
    if values.is_empty() || values.len() != stderr.len() {
        return Err(format!(
            "a grid needs at least one point with a value and an error (got {} values, {} errors)",
            values.len(),
            stderr.len()
        ));
    }
    let (mut lo, mut hi) = (0usize, 0usize);
    for (k, v) in values.iter().enumerate() {
        if *v < values[lo] {
            lo = k;
        }
        if *v > values[hi] {
            hi = k;
        }
    }
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let e_min = WithError {
        value: values[lo],
        stderr: stderr[lo],
    };
    let e_max = WithError {
        value: values[hi],
        stderr: stderr[hi],
    };
    let e_mean = WithError {
        value: mean,
        stderr: mean_stderr,
    };
    Ok(GridStatistics {
        points: values.len(),
        e_min,
        e_mean,
        e_max,
        u0: ratio(e_min, e_mean),
        min_over_max: ratio(e_min, e_max),
        min_index: lo,
        max_index: hi,
    })
}

/// The statistics of a sensor reading in lux.
pub fn of_reading(r: &SensorReading) -> Result<GridStatistics, String> {
    statistics(&r.lux, &r.stderr, r.mean_stderr)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hand-computed: values 100, 200, 300 (errors 1, 2, 3; mean error 1.2): U₀ = 0.5 with
    /// 0.5·√(0.01² + 0.006²) = 0.005831; min/max = 1/3 with (1/3)·√(0.01² + 0.01²) = 0.004714.
    #[test]
    fn hand_computed() {
        let s = statistics(&[200.0, 100.0, 300.0], &[2.0, 1.0, 3.0], 1.2).unwrap();
        assert_eq!((s.min_index, s.max_index), (1, 2));
        assert_eq!(s.e_mean.value, 200.0);
        assert!((s.u0.value - 0.5).abs() < 1e-15);
        assert!((s.u0.stderr - 0.5 * (0.01f64.powi(2) + 0.006f64.powi(2)).sqrt()).abs() < 1e-12);
        assert!((s.min_over_max.value - 1.0 / 3.0).abs() < 1e-15);
        assert!((s.min_over_max.stderr - (2.0f64).sqrt() * 0.01 / 3.0).abs() < 1e-12);
        assert!(statistics(&[], &[], 0.0)
            .unwrap_err()
            .contains("at least one point"));
    }
}
