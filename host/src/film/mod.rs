//! The film: per-pixel CIE XYZ accumulated exactly from spectral samples ([`exact_sum`]), a
//! thread-safe splat buffer for light tracing, the guard that keeps NaN, infinite and negative
//! samples out ([`rejected`]), the whole film state that slices and checkpoints save
//! ([`film_state`], [`state_file`]), image output (OpenEXR with R,G,B + X,Y,Z; sRGB PNG) and
//! the optional spectral image ([`spectral`], [`spectral_film`]).
//!
//! Convention (pbrt-v4 and Mitsuba 3): `XYZ = ∫ L(λ) [x̄,ȳ,z̄](λ) dλ / ∫ ȳ(λ) dλ`, so a spectrally
//! constant radiance of 1 W/(m²·sr·nm) gives Y = 1.

pub mod exact_sum;
pub mod exposure;
pub mod film_state;
pub mod image;
pub mod output;
pub mod pixel_film;
pub mod rejected;
pub mod sensor;
pub mod spectral;
pub mod spectral_film;
pub mod splat;
pub mod state_file;

pub use exact_sum::ExactSum;
pub use film_state::FilmState;
pub use image::XyzImage;
pub use output::{write_exr, write_exr_with_layers, write_png, OutputError};
pub use pixel_film::{PixelFilm, PixelSum, TileBuffer};
pub use rejected::{RejectedSamples, Rejection};
pub use sensor::Sensor;
pub use splat::SplatFilm;
pub use state_file::{RenderState, SliceSpec, StateError};
