//! Colour science: observers (x̄ȳz̄), XYZ integration, RGB spaces, the sRGB transfer function,
//! RGB → reflectance-spectrum uplift, and the figures of a light source (CCT and Duv, CIE 13.3
//! colour rendering, ANSI/IES TM-30 fidelity and gamut).

pub mod cct;
pub mod cri;
pub mod daylight;
pub mod fluorescent_xyz;
pub mod grid_observer;
pub mod matrix3;
pub mod observer;
pub mod resampled_observer;
pub mod rgb_space;
pub mod rgb_table;
pub mod srgb_transfer;
pub mod tm30;
pub mod uplift;
pub mod xyz;

pub use grid_observer::GridObserver;
pub use observer::{CieObserver, CieObserverKind, Observer};
pub use resampled_observer::ResampledObserver;
pub use rgb_space::{RgbColorSpace, ACES2065_1, DISPLAY_P3, REC2020, SRGB};
pub use srgb_transfer::{linear_to_srgb8, quantize_8bit, srgb_decode, srgb_encode};
pub use uplift::{uplift_srgb, RgbUplifter, SigmoidPolynomial};
pub use xyz::{chromaticity, emitter_xyz, reflectance_xyz, spd_tristimulus};
