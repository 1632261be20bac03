//! [`BuiltinSpd`]: the concrete SPDs the host knows without plugins.

use super::error::SpectrumError;
use super::line_spd::LineSpd;
use super::spd::{DeltaLine, Spd, SpdSample};
use super::sum_spd::SumSpd;
use super::tabulated_spd::TabulatedSpd;

/// A built-in normalized SPD.
#[derive(Clone, Debug, PartialEq)]
pub enum BuiltinSpd {
    /// A table (CSV file, bundled illuminant or lamp, tabulated blackbody or Gaussian).
    Tabulated(TabulatedSpd),
    /// A monochromatic line.
    Line(LineSpd),
    /// A weighted sum of other built-ins.
    Sum(Box<SumSpd>),
}

impl BuiltinSpd {
    /// Blackbody at `kelvin` over 360–830 nm (the CIE observers' range).
    pub fn blackbody(kelvin: f64) -> Result<Self, SpectrumError> {
        TabulatedSpd::blackbody(kelvin, 360.0, 830.0).map(Self::Tabulated)
    }

    /// Gaussian with centre and full width at half maximum in nm.
    pub fn gaussian(centre_nm: f64, fwhm_nm: f64) -> Result<Self, SpectrumError> {
        TabulatedSpd::gaussian(centre_nm, fwhm_nm).map(Self::Tabulated)
    }

    /// Monochromatic line at `lambda_nm`.
    pub fn line(lambda_nm: f64) -> Result<Self, SpectrumError> {
        if !(lambda_nm > 0.0 && lambda_nm.is_finite()) {
            return Err(SpectrumError::Invalid {
                file: format!("line:{lambda_nm}"),
                what: "the wavelength must be a positive number of nm".into(),
            });
        }
        Ok(Self::Line(LineSpd { lambda: lambda_nm }))
    }

    /// Weighted sum (weights = power fractions, renormalized).
    pub fn sum(parts: Vec<(f64, BuiltinSpd)>) -> Result<Self, SpectrumError> {
        Ok(Self::Sum(Box::new(SumSpd::new(parts)?)))
    }

    fn inner(&self) -> &dyn Spd {
        match self {
            Self::Tabulated(s) => s,
            Self::Line(s) => s,
            Self::Sum(s) => s.as_ref(),
        }
    }
}

impl Spd for BuiltinSpd {
    fn value(&self, lambda_nm: f64) -> f64 {
        self.inner().value(lambda_nm)
    }
    fn sample(&self, u: f64) -> SpdSample {
        self.inner().sample(u)
    }
    fn pdf(&self, lambda_nm: f64) -> f64 {
        self.inner().pdf(lambda_nm)
    }
    fn range(&self) -> (f64, f64) {
        self.inner().range()
    }
    fn delta_lines(&self) -> Vec<DeltaLine> {
        self.inner().delta_lines()
    }
}
