//! How a scene's spectral data are represented when it is built: the accuracy switches of
//! `spectrace bench accuracy` and `spectrace render`. Each non-default choice is a deliberate
//! representation error (against the measured tables and the 1 nm CIE observer) whose effect on
//! the image can then be measured. The defaults reproduce the scene exactly as written.

use crate::color::RgbUplifter;
use crate::spectrum::{Interpolation, SpectralCurve};
use std::sync::Arc;

/// Where a spectral reflectance's values come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ReflectanceSource {
    /// The spectrum as given (measured table, curve file, …).
    #[default]
    Measured,
    /// The spectrum an RGB pipeline would have: the reflectance's linear sRGB colour under D65
    /// (CIE 1931 2°), uplifted back to a smooth spectrum (Jakob–Hanika sigmoid). Same colour
    /// under D65, different spectrum (so different colours under other lights and after
    /// inter-reflection).
    RgbUplift,
}

/// The representation switches applied while a scene is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RepresentationOptions {
    /// How tabulated spectra (reflectance tables, emission tables, CSV and bundled spectra) are
    /// reconstructed between their entries: `Linear` (default) or `Step` (seed §5's piecewise
    /// constant: entry i holds on [λᵢ, λᵢ₊₁)). Analytic SPDs (blackbody, Gaussian) stay as they
    /// are.
    pub spd_interpolation: Interpolation,
    /// Measured reflectances or their RGB uplift.
    pub reflectance: ReflectanceSource,
    /// Spacing (nm) at which the observer's colour-matching functions are known; 1 = the CIE
    /// table as is, 5 or 10 = sampled every k nm and interpolated linearly.
    pub observer_step_nm: u32,
}

impl Default for RepresentationOptions {
    fn default() -> Self {
        Self {
            spd_interpolation: Interpolation::Linear,
            reflectance: ReflectanceSource::Measured,
            observer_step_nm: 1,
        }
    }
}

impl RepresentationOptions {
    /// True for the defaults (the scene exactly as written).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    /// A short label such as `step, rgb-uplift, observer 5 nm` (`as written` for the defaults).
    pub fn label(&self) -> String {
        let mut parts = Vec::new();
        if self.spd_interpolation == Interpolation::Step {
            parts.push("step spectra".to_string());
        }
        if self.reflectance == ReflectanceSource::RgbUplift {
            parts.push("rgb-uplifted reflectances".to_string());
        }
        if self.observer_step_nm != 1 {
            parts.push(format!("observer every {} nm", self.observer_step_nm));
        }
        if parts.is_empty() {
            "as written".into()
        } else {
            parts.join(", ")
        }
    }
}

/// Value at `x` of the step reading of a table: `f[i]` on `[λᵢ, λᵢ₊₁)`, and the last bin's value
/// also at `λ_{n−1}` itself (the last entry only closes the range), 0 outside: exactly how
/// [`crate::spectrum::piecewise_constant::PiecewiseConstant1D::from_steps`] reads a table.
pub fn step_value(lambda: &[f64], f: &[f64], x: f64) -> f64 {
    let n = lambda.len();
    if n < 2 || !(x >= lambda[0] && x <= lambda[n - 1]) {
        return 0.0;
    }
    let i = (lambda.partition_point(|&l| l <= x).max(1) - 1).min(n - 2);
    f[i]
}

/// A reflectance-like curve as a function of nm under `opts` (interpolation, then uplift).
/// Constant curves are returned unchanged: a grey is represented exactly either way.
pub fn reflectance_fn(
    curve: SpectralCurve,
    opts: &RepresentationOptions,
) -> Arc<dyn Fn(f64) -> f64 + Send + Sync> {
    let base: Arc<dyn Fn(f64) -> f64 + Send + Sync> = match (curve, opts.spd_interpolation) {
        (SpectralCurve::Constant(c), _) => return Arc::new(move |_| c),
        (SpectralCurve::Tabulated { lambda, value }, Interpolation::Step) => {
            Arc::new(move |l| step_value(&lambda, &value, l))
        }
        (curve, Interpolation::Linear) => Arc::new(move |l| curve.value(l)),
    };
    match opts.reflectance {
        ReflectanceSource::Measured => base,
        ReflectanceSource::RgbUplift => {
            let poly = uplift_of(base.as_ref());
            Arc::new(move |l| poly.value(l))
        }
    }
}

/// The sigmoid spectrum with the same linear sRGB (D65, CIE 1931 2°) as `reflectance`.
pub fn uplift_of(reflectance: &dyn Fn(f64) -> f64) -> crate::color::SigmoidPolynomial {
    let up = RgbUplifter::srgb();
    up.fit(up.rgb_of(reflectance))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{Spd, TabulatedSpd};

    /// The step reading of a table is the shape the step-interpolated SPD samples from:
    /// `TabulatedSpd(Step).value = step_value / Σ fᵢΔλᵢ` at and between nodes, including the
    /// last wavelength (1e-15 relative: one division), and 0 outside.
    #[test]
    fn step_value_matches_step_spd() {
        let l = [400.0, 450.0, 460.0, 700.0];
        let f = [1.0, 5.0, 0.5, 2.0];
        let spd = TabulatedSpd::new("t", &l, &f, Interpolation::Step).unwrap();
        let total = 1.0 * 50.0 + 5.0 * 10.0 + 0.5 * 240.0;
        for x in [400.0, 420.0, 449.999, 450.0, 455.0, 460.0, 699.0, 700.0] {
            let a = step_value(&l, &f, x) / total;
            assert!(
                (a - spd.value(x)).abs() <= 1e-15 * a.abs(),
                "{x}: {a} vs {}",
                spd.value(x)
            );
        }
        assert_eq!(step_value(&l, &f, 399.0), 0.0);
        assert_eq!(step_value(&l, &f, 701.0), 0.0);
        assert_eq!(step_value(&l, &f, f64::NAN), 0.0);
    }

    /// Default options keep a table's linear values (exact: the same interpolation routine), and
    /// constants stay constants under every option.
    #[test]
    fn defaults_and_constants_unchanged() {
        let curve = SpectralCurve::parse("colorchecker:red").unwrap();
        let f = reflectance_fn(curve.clone(), &RepresentationOptions::default());
        for x in [380.0, 512.3, 700.0, 731.0] {
            assert_eq!(f(x), curve.value(x));
        }
        let all = RepresentationOptions {
            spd_interpolation: Interpolation::Step,
            reflectance: ReflectanceSource::RgbUplift,
            observer_step_nm: 10,
        };
        assert_eq!(
            reflectance_fn(SpectralCurve::Constant(0.3), &all)(555.0),
            0.3
        );
        assert!(RepresentationOptions::default().is_default() && !all.is_default());
    }
}
