//! An observer known only every `k` nm and linearly interpolated in between: what a renderer
//! that stores 5 or 10 nm colour-matching-function tables integrates with. Used to measure the
//! observer's representation error against the 1 nm CIE tables.

use super::observer::Observer;
use std::sync::Arc;

/// `inner`'s x̄ȳz̄ sampled at `lo, lo + k, lo + 2k, …` (and at the range's end), linear between
/// those nodes and 0 outside the range. With the CIE tables (integer-nm ranges) every node is on
/// an integer nm, so the film's 1 nm copy of this observer reproduces it exactly.
#[derive(Debug, Clone)]
pub struct ResampledObserver {
    name: String,
    /// Node wavelengths in nm, strictly increasing; the first and last are the range ends.
    nodes: Vec<f64>,
    /// `[x̄, ȳ, z̄]` of the inner observer at each node.
    values: Vec<[f64; 3]>,
    /// `Σ ȳ` of this (interpolated) curve over the 1 nm integration grid.
    integral_y: f64,
}

/// Why an observer cannot be resampled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ResampleError {
    /// The step is 0.
    #[error("observer step must be at least 1 nm, got {0} nm")]
    ZeroStep(u32),
    /// The observer's range is not a finite interval of at least one step.
    #[error(
        "observer `{name}` has range {lo}..{hi} nm, which cannot be resampled every {step} nm"
    )]
    BadRange {
        /// Observer name.
        name: String,
        /// Range start, nm.
        lo: f64,
        /// Range end, nm.
        hi: f64,
        /// Requested step, nm.
        step: u32,
    },
}

impl ResampledObserver {
    /// Sample `inner` every `step_nm` nm over its range. Step 1 on a 1 nm table (the CIE
    /// observers) reproduces the table exactly.
    pub fn new(inner: &dyn Observer, step_nm: u32) -> Result<Self, ResampleError> {
        if step_nm == 0 {
            return Err(ResampleError::ZeroStep(step_nm));
        }
        let (lo, hi) = inner.range();
        let step = step_nm as f64;
        if !(lo.is_finite() && hi.is_finite() && hi - lo >= step) {
            return Err(ResampleError::BadRange {
                name: inner.name().to_string(),
                lo,
                hi,
                step: step_nm,
            });
        }
        let mut nodes: Vec<f64> = (0..)
            .map(|i| lo + i as f64 * step)
            .take_while(|&l| l < hi)
            .collect();
        nodes.push(hi);
        let values = nodes.iter().map(|&l| inner.xyz_bar(l)).collect();
        let mut obs = Self {
            name: format!("{}@{step_nm}nm", inner.name()),
            nodes,
            values,
            integral_y: 0.0,
        };
        // The trait's default: Σ ȳ over the integer-nm grid, here of the interpolated curve, so
        // the film's normalisation matches what this observer actually returns.
        obs.integral_y = super::observer::integration_grid(&obs)
            .map(|l| obs.xyz_bar(l)[1])
            .sum();
        Ok(obs)
    }

    /// `inner` itself for step 1 (bit-for-bit the original), else the resampled observer.
    pub fn wrap(
        inner: Arc<dyn Observer>,
        step_nm: u32,
    ) -> Result<Arc<dyn Observer>, ResampleError> {
        if step_nm == 1 {
            return Ok(inner);
        }
        Ok(Arc::new(Self::new(inner.as_ref(), step_nm)?))
    }

    /// The node wavelengths (nm).
    pub fn nodes(&self) -> &[f64] {
        &self.nodes
    }
}

impl Observer for ResampledObserver {
    fn name(&self) -> &str {
        &self.name
    }

    fn range(&self) -> (f64, f64) {
        (self.nodes[0], self.nodes[self.nodes.len() - 1])
    }

    fn xyz_bar(&self, lambda_nm: f64) -> [f64; 3] {
        let (lo, hi) = self.range();
        if !(lambda_nm >= lo && lambda_nm <= hi) {
            return [0.0; 3];
        }
        let n = self.nodes.len();
        let i = (self.nodes.partition_point(|&x| x <= lambda_nm).max(1) - 1).min(n - 2);
        let (x0, x1) = (self.nodes[i], self.nodes[i + 1]);
        let s = (lambda_nm - x0) / (x1 - x0);
        let (a, b) = (self.values[i], self.values[i + 1]);
        std::array::from_fn(|c| a[c] + s * (b[c] - a[c]))
    }

    fn integral_y(&self) -> f64 {
        self.integral_y
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::color::xyz::reflectance_xyz;
    use crate::color::{emitter_xyz, CieObserverKind};
    use crate::spectrum::parse_spd_spec;

    fn cie() -> &'static crate::color::CieObserver {
        CieObserverKind::Cie1931_2.get()
    }

    /// Step 1 is the CIE table itself: equal values (exactly, both are one lerp between the
    /// same two 1 nm entries, to 1e-15 for rounding of the two lerp forms) and the same Σȳ
    /// (1e-12 relative: the same 471 numbers summed in the same order).
    #[test]
    fn step_one_is_the_table() {
        let r = ResampledObserver::new(cie(), 1).unwrap();
        assert_eq!(r.range(), cie().range());
        for k in 0..4800 {
            let l = 359.0 + k as f64 * 0.1;
            let (a, b) = (r.xyz_bar(l), cie().xyz_bar(l));
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() <= 1e-15, "{l}: {a:?} vs {b:?}");
            }
        }
        assert!((r.integral_y() / cie().integral_y() - 1.0).abs() < 1e-12);
        // wrap(…, 1) hands back the very same observer.
        let inner: Arc<dyn Observer> = Arc::new(cie().clone());
        let w = ResampledObserver::wrap(inner.clone(), 1).unwrap();
        assert!(Arc::ptr_eq(&inner, &w));
    }

    /// The coarse observer keeps the table values at its nodes (exact) and is linear between
    /// them: at a midpoint it is the mean of the neighbouring nodes (1e-14: one lerp against
    /// one mean, a few ulps of values ≤ 2).
    #[test]
    fn nodes_exact_and_linear_between() {
        for step in [5, 10] {
            let r = ResampledObserver::new(cie(), step).unwrap();
            assert_eq!(r.nodes().len(), 470 / step as usize + 1);
            for &l in r.nodes() {
                assert_eq!(r.xyz_bar(l), cie().xyz_bar(l));
            }
            let m = 550.0 + step as f64 / 2.0;
            let (a, b) = (r.xyz_bar(550.0), r.xyz_bar(550.0 + step as f64));
            let mid = r.xyz_bar(m);
            for c in 0..3 {
                assert!((mid[c] - 0.5 * (a[c] + b[c])).abs() < 1e-14);
            }
            assert_eq!(r.xyz_bar(359.0), [0.0; 3]);
            assert_eq!(r.xyz_bar(831.0), [0.0; 3]);
        }
    }

    /// ∫ȳ of the piecewise-linear curve is exact by the trapezoid rule on its own nodes. The
    /// film's normalisation Σȳ (1 nm grid, end points counted whole) equals that integral plus
    /// half the two end values — an identity for a polyline with integer-nm nodes, so 1e-9
    /// relative (rounding of ~500 terms). It must differ from the 1 nm table's Σȳ (else the
    /// coarse observer would not be coarse), but only slightly: measured 1.1e-6 (5 nm) and
    /// 1.1e-5 (10 nm) relative; bound 1e-4, ten times the 10 nm figure.
    #[test]
    fn integral_y_is_that_of_the_interpolant() {
        for step in [5u32, 10] {
            let r = ResampledObserver::new(cie(), step).unwrap();
            let n = r.nodes();
            let y = |l: f64| r.xyz_bar(l)[1];
            let trapezoid: f64 = n
                .windows(2)
                .map(|w| 0.5 * (w[1] - w[0]) * (y(w[0]) + y(w[1])))
                .sum();
            let ends = 0.5 * (y(n[0]) + y(n[n.len() - 1]));
            let expect = trapezoid + ends;
            assert!(
                (r.integral_y() / expect - 1.0).abs() < 1e-9,
                "{step} nm: {} vs {expect}",
                r.integral_y()
            );
            let rel = r.integral_y() / cie().integral_y() - 1.0;
            assert!(rel != 0.0 && rel.abs() < 1e-4, "{step} nm: Σȳ off by {rel}");
        }
    }

    /// XYZ (Y = 100 scale) of D65 and Illuminant A as emitters, and of a mid-grey and a
    /// ColorChecker red under D65, with the 5 and 10 nm observers against the 1 nm table. The
    /// CIE (15:2018 §7.1) considers 5 nm data adequate for most purposes. Measured here: the
    /// chromaticity moves by ≤ 1.4e-4 at 5 nm and ≤ 6.4e-4 at 10 nm (the red patch is the worst;
    /// bounds 5e-4 and 2e-3), XYZ components by ≤ 0.015 and ≤ 0.18 on the 0–100 scale (bounds
    /// 0.05 and 0.5): small, stated, and not zero.
    #[test]
    fn illuminant_xyz_close_to_1nm() {
        let obs_1: &dyn Observer = cie();
        let d65 = parse_spd_spec("d65").unwrap();
        let a = parse_spd_spec("a").unwrap();
        let red = crate::spectrum::SpectralCurve::parse("colorchecker:red").unwrap();
        for (step, xy_tol, xyz_tol) in [(5u32, 5e-4, 0.05), (10, 2e-3, 0.5)] {
            let r = ResampledObserver::new(cie(), step).unwrap();
            let mut changed = false;
            for (what, fine, coarse) in [
                ("D65", emitter_xyz(&d65, obs_1), emitter_xyz(&d65, &r)),
                ("A", emitter_xyz(&a, obs_1), emitter_xyz(&a, &r)),
                (
                    "red under D65",
                    reflectance_xyz(|l| red.value(l), &d65, obs_1),
                    reflectance_xyz(|l| red.value(l), &d65, &r),
                ),
            ] {
                let (f, c) = (
                    crate::color::chromaticity(fine),
                    crate::color::chromaticity(coarse),
                );
                let dxy = (f.0 - c.0).hypot(f.1 - c.1);
                assert!(dxy < xy_tol, "{step} nm {what}: Δxy {dxy}");
                for k in 0..3 {
                    let d = (fine[k] - coarse[k]).abs();
                    assert!(d < xyz_tol, "{step} nm {what}: {fine:?} vs {coarse:?}");
                    changed |= d > 1e-6;
                }
            }
            assert!(changed, "{step} nm observer gave the 1 nm XYZ exactly");
        }
    }

    /// Bad steps are errors, not panics.
    #[test]
    fn rejects_bad_steps() {
        assert!(matches!(
            ResampledObserver::new(cie(), 0),
            Err(ResampleError::ZeroStep(0))
        ));
        assert!(ResampledObserver::new(cie(), 1000).is_err());
    }
}
