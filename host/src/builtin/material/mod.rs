//! Built-in materials, one per file.

pub mod conductor;
pub mod dielectric;
pub mod emissive;
pub mod fluorescent;
pub mod lambertian;
pub mod mirror;
pub mod plastic;
pub mod rough_dielectric;
pub mod rough_plastic;
pub mod thin_film;
