//! Textures: what a material asks when it needs a wavelength-dependent parameter at a surface
//! point ([`SpectralTexture`], with constant and curve textures, in [`spectral_texture`]), the
//! images behind image textures and environment maps: reading the files ([`image_file`]),
//! looking them up over a surface ([`image_texture`]) and the radiance of textured emitters
//! ([`emission_texture`]). A floor below [`crate::material`]: materials evaluate textures,
//! never the reverse.

pub mod emission_texture;
pub mod image_file;
pub mod image_texture;
pub mod spectral_texture;

pub use spectral_texture::{ConstantTexture, CurveTexture, SpectralTexture};
