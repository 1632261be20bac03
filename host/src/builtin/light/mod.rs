//! Built-in lights (besides area lights, which are emissive objects), one per file.

pub mod cie_sky;
pub mod directional;
pub mod emission;
pub mod environment;
pub mod envmap;
pub mod gldf;
pub mod luminaire;
pub mod near_field;
pub mod point;
pub mod ray_file;
pub mod spot;
pub mod sun;
pub mod sun_place;

pub use emission::{exactly_one, from_photometric, light_spd, non_negative};
