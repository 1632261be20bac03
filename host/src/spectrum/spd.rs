//! The [`Spd`] trait: a spectral power distribution normalized so that its integral over its
//! range is 1 (seed §2). Absolute power belongs to the light that uses it.
//!
//! Every SPD can also *generate* wavelengths with a density proportional to itself, which is
//! how light subpaths pick their wavelength. Delta lines (lasers, idealized emission lines) carry
//! probability mass instead of density and are reported separately.

use super::{SampledSpectrum, SampledWavelengths, LANES};

/// One wavelength drawn from an SPD.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpdSample {
    /// Wavelength in nm.
    pub lambda: f64,
    /// Density in 1/nm for a continuous draw, or the discrete probability (unitless) when
    /// `is_delta` is true.
    pub pdf: f64,
    /// True when the draw picked a delta line.
    pub is_delta: bool,
}

/// A delta component of an SPD: all of `weight` (fraction of the total power) at `lambda`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeltaLine {
    /// Wavelength in nm.
    pub lambda: f64,
    /// Fraction of the SPD's total power in this line (unitless, ≤ 1).
    pub weight: f64,
}

/// A normalized spectral power distribution. Implemented by the built-ins ([`super::BuiltinSpd`])
/// and by the plugin adapter for SPDs supplied by plugins.
pub trait Spd: Send + Sync + std::fmt::Debug {
    /// Continuous part of the normalized SPD at `lambda_nm`, in 1/nm; 0 outside the range.
    /// Delta lines contribute nothing here (see [`Spd::delta_lines`]).
    fn value(&self, lambda_nm: f64) -> f64;

    /// Draw a wavelength with `u ∈ [0,1)` with probability proportional to the SPD.
    fn sample(&self, u: f64) -> SpdSample;

    /// Density (1/nm) with which [`Spd::sample`] produces a continuous `lambda_nm`. For the
    /// built-ins this equals [`Spd::value`] because sampling is exact.
    fn pdf(&self, lambda_nm: f64) -> f64;

    /// `(min, max)` wavelengths in nm outside which the SPD is zero.
    fn range(&self) -> (f64, f64);

    /// Delta lines and their power fractions; empty for a purely continuous SPD.
    fn delta_lines(&self) -> Vec<DeltaLine> {
        Vec::new()
    }

    /// True when the SPD has any delta line, so estimators must treat matching draws as discrete.
    fn is_delta(&self) -> bool {
        !self.delta_lines().is_empty()
    }
}

/// Evaluate the continuous part of `spd` at each lane's wavelength (1/nm).
pub fn spd_at(spd: &dyn Spd, lambda: &SampledWavelengths) -> SampledSpectrum {
    SampledSpectrum(std::array::from_fn(|i| {
        spd.value(lambda.lambda[i] as f64) as f32
    }))
}

/// Probability mass of the delta lines of `spd` at exactly `lambda_nm` (sum of their weights).
pub fn delta_mass_at(spd: &dyn Spd, lambda_nm: f64) -> f64 {
    spd.delta_lines()
        .iter()
        .filter(|l| l.lambda == lambda_nm)
        .map(|l| l.weight)
        .sum()
}

/// Compile-time check that the lane count used by `spd_at` matches the rest of the crate.
const _: () = assert!(LANES >= 1);
