//! Image textures and the images behind environment maps: reading the files
//! ([`image_file`]) and looking them up over a surface ([`image_texture`]).

pub mod image_file;
pub mod image_texture;
