//! [`SpectralCurve`]: a spectral quantity that is *not* a power distribution and so is not
//! normalized: reflectance, transmittance, index of refraction, … Shares the CSV tabulation
//! with the SPDs.

use super::bundled::colorchecker_table;
use super::error::SpectrumError;
use super::spec::raw_table_for_spec;
use super::tabulation::interpolate;
use super::{SampledSpectrum, SampledWavelengths};

/// A non-normalized spectral function of wavelength (nm); units are the caller's.
#[derive(Clone, Debug, PartialEq)]
pub enum SpectralCurve {
    /// The same value at every wavelength.
    Constant(f64),
    /// Linear interpolation of a table, 0 outside its range.
    Tabulated {
        /// Wavelengths in nm, strictly increasing.
        lambda: Vec<f64>,
        /// Values at those wavelengths.
        value: Vec<f64>,
    },
}

impl SpectralCurve {
    /// A table; wavelengths must increase strictly and all entries be finite.
    pub fn tabulated(lambda: Vec<f64>, value: Vec<f64>) -> Result<Self, SpectrumError> {
        let ok = lambda.len() >= 2
            && lambda.len() == value.len()
            && lambda.iter().chain(&value).all(|v| v.is_finite())
            && lambda.windows(2).all(|w| w[1] > w[0]);
        if !ok {
            return Err(SpectrumError::Invalid {
                file: "<curve>".into(),
                what: "need ≥ 2 finite entries with strictly increasing wavelengths".into(),
            });
        }
        Ok(Self::Tabulated { lambda, value })
    }

    /// Value at `lambda_nm` (0 outside a table's range).
    pub fn value(&self, lambda_nm: f64) -> f64 {
        match self {
            Self::Constant(c) => *c,
            Self::Tabulated { lambda, value } => interpolate(lambda, value, lambda_nm),
        }
    }

    /// `(min, max)` nm of a table; the whole positive axis for a constant.
    pub fn range(&self) -> (f64, f64) {
        match self {
            Self::Constant(_) => (0.0, f64::INFINITY),
            Self::Tabulated { lambda, .. } => (lambda[0], lambda[lambda.len() - 1]),
        }
    }

    /// Value at each lane's wavelength.
    pub fn eval(&self, lambda: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum(std::array::from_fn(|i| {
            self.value(lambda.lambda[i] as f64) as f32
        }))
    }

    /// ColorChecker patch `name_or_index` (header name, case-insensitive, or 1..24).
    pub fn colorchecker(name_or_index: &str) -> Result<Self, SpectrumError> {
        let t = colorchecker_table();
        let col = super::spec::select_column(
            &t,
            "reflectance/colorchecker_babelcolor_average.csv",
            Some(name_or_index),
        )?;
        Self::tabulated(t.wavelengths, col)
    }

    /// Parse a curve spec: a number (constant), `colorchecker:NAME|INDEX`, a bundled spectrum
    /// name (its raw relative values), or a CSV path (`path.csv#COLUMN` for multi-column files).
    pub fn parse(spec: &str) -> Result<Self, SpectrumError> {
        let s = spec.trim();
        if let Ok(v) = s.parse::<f64>() {
            if v.is_finite() {
                return Ok(Self::Constant(v));
            }
        }
        if let Some(patch) = s.strip_prefix("colorchecker:") {
            return Self::colorchecker(patch);
        }
        match raw_table_for_spec(s) {
            Some(r) => {
                let (l, v) = r?;
                Self::tabulated(l, v)
            }
            None => Err(SpectrumError::Spec {
                spec: spec.to_string(),
                what: "not a number, colorchecker:PATCH, bundled spectrum or CSV file".into(),
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // ColorChecker patch lookup by name and index, and the table values at a node (exact).
    #[test]
    fn colorchecker_lookup() {
        let white = SpectralCurve::parse("colorchecker:white 9.5 (.05 D)").unwrap();
        let by_index = SpectralCurve::parse("colorchecker:19").unwrap();
        assert_eq!(white, by_index);
        assert_eq!(white.value(400.0), 0.423);
        assert_eq!(SpectralCurve::parse("0.5").unwrap().value(123.0), 0.5);
        assert!(SpectralCurve::parse("colorchecker:99").is_err());
    }
}
