//! The built-in sensor types of a scene's `sensors` list, each with its parameter table:
//! illuminance grids ([`grid`]) and glare observers ([`glare_observer`]), built from the scene
//! file's items with their lengths in metres. What a render measures at them is in
//! [`crate::sensor`]. Sensors are not registry types: no plugin provides one.

pub mod glare_observer;
pub mod grid;
pub mod limits;
