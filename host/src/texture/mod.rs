//! Image textures and the images behind environment maps: reading the files
//! ([`image_file`]), looking them up over a surface ([`image_texture`]) and the radiance of
//! textured emitters ([`emission_texture`]).

pub mod emission_texture;
pub mod image_file;
pub mod image_texture;
