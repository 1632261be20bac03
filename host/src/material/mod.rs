//! Materials: how surfaces scatter (BSDFs) and, for area lights, emit.
//!
//! Everything here works in the local shading frame ([`Frame`]): the shading normal is +z, `wo`
//! points away from the surface towards where the path came from, `wi` towards where it goes.
//! Both are unit vectors. BSDF values are in 1/sr, pdfs in 1/sr (solid angle), emitted radiance
//! in W/(m²·sr·nm).

pub mod beckmann;
pub mod complex;
pub mod conductor;
pub mod dielectric;
pub mod emissive;
pub mod flags;
pub mod fluorescent;
pub mod frame;
pub mod fresnel;
pub mod interface;
pub mod ior;
pub mod lambertian;
pub mod metals;
pub mod microfacet;
pub mod mirror;
pub mod plastic;
pub mod rough_dielectric;
pub mod thin_film;

pub use conductor::RoughConductor;
pub use dielectric::SmoothDielectric;
pub use emissive::Emissive;
pub use flags::MaterialFlags;
pub use frame::Frame;
pub use ior::SpectralIor;
pub use lambertian::Lambertian;
pub use mirror::Mirror;
pub use plastic::Plastic;
pub use rough_dielectric::RoughDielectric;

pub use interface::{
    reflect, refract, same_hemisphere, sample_concentric_disk, sample_cosine_hemisphere,
    sample_cosine_lobe, BsdfSample, EffectsOff, EmissionProfile, Material, ShadingContext,
    TransportMode,
};
