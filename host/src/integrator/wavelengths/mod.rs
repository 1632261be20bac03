//! Which wavelengths a path carries and how they are weighed: wavelength groups, the mixture
//! density, wavelength pairs, XYZ weights and flat colour.

pub mod flat_colour;
pub mod groups;
pub mod mixture;
pub mod pairs;
pub mod sampling;
pub mod xyz_weights;
