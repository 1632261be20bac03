//! Spectra: SPDs, wavelength sampling, and the per-path spectral sample types.

pub mod sampled;
pub use sampled::{SampledSpectrum, SampledWavelengths, LANES};
