//! Spectra: SPDs, wavelength sampling, and the per-path spectral sample types.
//!
//! Colour is carried as wavelength (nm) and power; an SPD ([`Spd`]) is normalized to integrate
//! to 1 and is both evaluated and sampled. Non-normalized spectral data (reflectance, IOR) are
//! [`SpectralCurve`]s. Both read the same CSV format ([`csv_table`]).

pub mod bandwidth;
pub mod bfc;
pub mod bispectral_matrix;
pub mod blackbody;
pub mod builtin_spd;
pub mod bundled;
pub mod csv_table;
pub mod curve;
pub mod dense;
pub mod discrete;
pub mod error;
pub mod fluorescence_model;
pub mod guide_table;
pub mod lane_mask;
pub mod line_spd;
pub mod piecewise_constant;
pub mod piecewise_linear;
pub mod reradiation;
pub mod sampled;
pub mod spd;
pub mod spec;
pub mod tabulated_spd;
pub mod tabulation;
pub mod wavelength_sampling;
pub mod wavelength_table;

pub use builtin_spd::BuiltinSpd;
pub use curve::SpectralCurve;
pub use error::SpectrumError;
pub use lane_mask::LaneMask;
pub use sampled::{SampledSpectrum, SampledWavelengths, LANES};
pub use spd::{DeltaLine, Spd, SpdSample};
pub use spec::parse_spd_spec;
pub use tabulated_spd::{Interpolation, TabulatedSpd};
