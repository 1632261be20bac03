//! Daylight: the CIE standard general sky ([`cie_sky_model`], the environment light
//! [`CieSky`]), the sun as a disc ([`SunLight`]), the sun's position from place and time
//! ([`solar_position`]) and CIE daylight spectra for them ([`daylight_spd`]).
//! See `docs/daylight.md`.

pub mod cie_sky;
pub mod cie_sky_model;
pub mod shared;
pub mod sky_sampler;
pub mod solar_position;
pub mod sun;

pub use cie_sky::CieSky;
pub use sun::SunLight;

pub use shared::{
    daylight_spd, default_sky_cct, default_sun_cct, direction, sky_frame, DAYLIGHT_CCT_RANGE,
};
