//! A weighted sum of normalized SPDs, itself normalized: `Σ wᵢ·sᵢ / Σ wᵢ`. The weights are the
//! fractions of power in each part ("scalings"), e.g. a white LED plus a 532 nm laser line.
//! Sampling picks a part with probability wᵢ/Σw, then samples it, so the pdf is exact.

use super::builtin_spd::BuiltinSpd;
use super::discrete::DiscreteDistribution;
use super::error::SpectrumError;
use super::spd::{DeltaLine, Spd, SpdSample};

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
