//! The film: per-pixel CIE XYZ accumulated in f64 from spectral samples, a thread-safe splat
//! buffer for light tracing, and image output (OpenEXR with R,G,B + X,Y,Z; sRGB PNG preview).
//!
//! Convention (pbrt-v4 and Mitsuba 3): `XYZ = ∫ L(λ) [x̄,ȳ,z̄](λ) dλ / ∫ ȳ(λ) dλ`, so a spectrally
//! constant radiance of 1 W/(m²·sr·nm) gives Y = 1.

pub mod image;
pub mod output;
pub mod pixel_film;
pub mod sensor;
pub mod splat;

pub use image::XyzImage;
pub use output::{write_exr, write_png, OutputError};
pub use pixel_film::{PixelFilm, TileBuffer};
pub use sensor::Sensor;
pub use splat::SplatFilm;
