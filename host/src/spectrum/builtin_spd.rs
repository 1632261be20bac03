//! [`BuiltinSpd`]: the concrete SPDs the host knows without plugins, and [`SumSpd`], the
//! weighted sum of them that is itself one of them (the two types are defined in terms of each
//! other, so they live in one file).
//!
//! [`SumSpd`] is a weighted sum of normalized SPDs, itself normalized: `Σ wᵢ·sᵢ / Σ wᵢ`. The weights are the
//! fractions of power in each part ("scalings"), e.g. a white LED plus a 532 nm laser line.
//! Sampling picks a part with probability wᵢ/Σw, then samples it, so the pdf is exact.

use super::discrete::DiscreteDistribution;
use super::error::SpectrumError;
use super::line_spd::LineSpd;
use super::spd::{DeltaLine, Spd, SpdSample};
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

/// `Σ wᵢ·sᵢ`, with weights normalized to sum to 1.
#[derive(Clone, Debug, PartialEq)]
pub struct SumSpd {
    parts: Vec<(f64, BuiltinSpd)>,
    chooser: DiscreteDistribution,
}

impl SumSpd {
    /// Build from `(weight, spd)` pairs; weights must be finite, ≥ 0 and not all zero.
    pub fn new(parts: Vec<(f64, BuiltinSpd)>) -> Result<Self, SpectrumError> {
        let weights: Vec<f64> = parts.iter().map(|(w, _)| *w).collect();
        let chooser =
            DiscreteDistribution::new(&weights).ok_or_else(|| SpectrumError::Invalid {
                file: "<sum of spectra>".into(),
                what: format!("weights {weights:?} must be finite, non-negative and not all zero"),
            })?;
        let total = chooser.total();
        let parts = parts.into_iter().map(|(w, s)| (w / total, s)).collect();
        Ok(Self { parts, chooser })
    }

    /// The parts with their normalized weights.
    pub fn parts(&self) -> &[(f64, BuiltinSpd)] {
        &self.parts
    }
}

impl Spd for SumSpd {
    fn value(&self, lambda_nm: f64) -> f64 {
        self.parts.iter().map(|(w, s)| w * s.value(lambda_nm)).sum()
    }

    fn sample(&self, u: f64) -> SpdSample {
        let (i, _, u2) = self.chooser.sample(u);
        let s = self.parts[i].1.sample(u2);
        if s.is_delta {
            // Several parts may put a line at the same wavelength: their masses add.
            let mass = self
                .delta_lines()
                .iter()
                .filter(|l| l.lambda == s.lambda)
                .map(|l| l.weight)
                .sum();
            SpdSample {
                lambda: s.lambda,
                pdf: mass,
                is_delta: true,
            }
        } else {
            SpdSample {
                lambda: s.lambda,
                pdf: self.pdf(s.lambda),
                is_delta: false,
            }
        }
    }

    fn pdf(&self, lambda_nm: f64) -> f64 {
        self.parts.iter().map(|(w, s)| w * s.pdf(lambda_nm)).sum()
    }

    fn range(&self) -> (f64, f64) {
        self.parts
            .iter()
            .filter(|(w, _)| *w > 0.0)
            .map(|(_, s)| s.range())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |a, b| {
                (a.0.min(b.0), a.1.max(b.1))
            })
    }

    fn delta_lines(&self) -> Vec<DeltaLine> {
        self.parts
            .iter()
            .flat_map(|(w, s)| {
                s.delta_lines().into_iter().map(move |l| DeltaLine {
                    lambda: l.lambda,
                    weight: l.weight * w,
                })
            })
            .filter(|l| l.weight > 0.0)
            .collect()
    }
}
