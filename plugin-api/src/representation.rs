//! Beam representations: how a light that does not speak the host's native beam language
//! declares its own, so the host can wrap it in adapters (the seed's design: a light whose beams
//! are in another representation is wrapped once, and the conversion happens in `next_beam`).
//!
//! The native representation is the [`Beam`](crate::Beam): origin and unit direction in the
//! right-handed world frame (x right, y up, +z towards the viewer) in scene units (metres), a
//! wavelength in nm and a power in W. A light may instead declare, per type:
//!
//! * a length unit, as metres per plugin unit (`0.001` for millimetres);
//! * [`Handedness::Left`]: x right, y up, +z AWAY from the viewer; the host flips z;
//! * [`DirectionEncoding::Angles`]: `direction = [θ, φ, 0]` in radians, θ the polar angle from
//!   +y (up) and φ the azimuth from +x towards +z, both in the plugin's own frame, i.e.
//!   `(sin θ cos φ, cos θ, sin θ sin φ)` before the handedness flip;
//! * [`ColourEncoding::LinearSrgb`]: `colour = [r, g, b]`, linear sRGB, only the chromaticity
//!   matters (any positive scale); the beam's `power_w` is its flux estimate in W as for a native
//!   beam. The host turns the colour into a spectrum with the same RGB uplift materials use,
//!   draws the wavelength from it (normalised as an SPD) and keeps the expected flux per
//!   wavelength: `E[power] · p(λ)` is the beam's spectral flux.
//!
//! Such a light sets [`PluginType::BEAM_REPRESENTATION`](crate::PluginType); its
//! [`LightSource::next_beam`](crate::LightSource::next_beam) answers in that representation (a
//! native light returns a [`Beam`](crate::Beam) `.into()` a [`RepresentedBeam`]). The
//! declaration is data in the type's [`TypeInfo`](crate::module::TypeInfo).

use crate::types::Vec3;
use abi_stable::StableAbi;

/// Which way the plugin's z axis points (x right and y up in both).
#[repr(u8)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Handedness {
    /// The host's frame: +z towards the viewer.
    Right,
    /// +z away from the viewer (the host negates z of positions and directions).
    Left,
}

/// How a beam's `direction` is written.
#[repr(u8)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq, Eq)]
pub enum DirectionEncoding {
    /// `direction` is a unit vector `[x, y, z]`.
    UnitVector,
    /// `direction` is `[θ, φ, 0]` in radians (see the module docs).
    Angles,
}

/// How a beam's colour is written.
#[repr(u8)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColourEncoding {
    /// `colour = [wavelength_nm, 0, 0]`; `power_w` as for a native beam.
    Spectral,
    /// `colour = [r, g, b]` in linear sRGB (chromaticity only); `power_w` is the flux in W.
    LinearSrgb,
}

/// A light type's beam representation.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq)]
pub struct BeamRepresentation {
    /// Metres per plugin length unit (1 for metres, 0.001 for millimetres); finite and > 0.
    pub metres_per_unit: f64,
    /// Orientation of the plugin's axes.
    pub handedness: Handedness,
    /// How directions are written.
    pub direction: DirectionEncoding,
    /// How colours are written.
    pub colour: ColourEncoding,
}

impl BeamRepresentation {
    /// The host's own: metres, right-handed, unit vectors, wavelength and power.
    pub const NATIVE: Self = Self {
        metres_per_unit: 1.0,
        handedness: Handedness::Right,
        direction: DirectionEncoding::UnitVector,
        colour: ColourEncoding::Spectral,
    };

    /// True for [`Self::NATIVE`]: no adapter is needed.
    pub fn is_native(&self) -> bool {
        *self == Self::NATIVE
    }
}

impl Default for BeamRepresentation {
    fn default() -> Self {
        Self::NATIVE
    }
}

/// One beam in a light's declared representation (see the module docs for each field).
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct RepresentedBeam {
    /// Start point, in the declared unit and handedness.
    pub origin: Vec3,
    /// Unit vector `[x, y, z]` or angles `[θ, φ, 0]` (radians).
    pub direction: [f64; 3],
    /// `[wavelength_nm, 0, 0]` or `[r, g, b]`.
    pub colour: [f64; 3],
    /// Flux estimate of this one sample, W.
    pub power_w: f64,
}

impl From<crate::types::Beam> for RepresentedBeam {
    /// A native beam in the native representation (`source_id` is the host's to assign).
    fn from(b: crate::types::Beam) -> Self {
        Self {
            origin: b.origin,
            direction: [b.direction.x, b.direction.y, b.direction.z],
            colour: [b.wavelength_nm, 0.0, 0.0],
            power_w: b.power_w,
        }
    }
}
