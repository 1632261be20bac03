//! Light sources as the integrators see them, the built-in lights (area, point, spot,
//! directional, environment, luminaire) and the [`LightSourceManager`] that picks lights in proportion to their power.
//!
//! Every light has a normalised SPD `S(λ)` (1/nm) and an overall scale, so its emission is
//! `scale · S(λ)`; light subpaths draw their wavelengths from `S`. Units: radiance
//! W/(m²·sr·nm), intensity W/(sr·nm), irradiance W/(m²·nm), power W (scene length units stand in
//! for metres).

pub mod area;
pub mod daylight;
pub mod directional;
pub mod distribution2d;
pub mod emission_beam;
pub mod environment;
pub mod envmap;
pub mod flags;
pub mod interface;
pub mod luminaire;
pub mod luminous;
pub mod manager;
pub mod measure;
pub mod near_field;
pub mod point;
pub mod ray_file;
pub mod scene_sphere;
pub mod spot;
pub mod textured_area;

pub use area::AreaLight;
pub use directional::DirectionalLight;
pub use environment::{ConstantEnvironment, EnvironmentLight, EnvironmentRadiance};
pub use envmap::EnvironmentMap;
pub use flags::LightFlags;
pub use luminaire::LuminaireLight;
pub use manager::LightSourceManager;
pub use point::PointLight;
pub use spot::SpotLight;
pub use textured_area::TexturedAreaLight;

pub(crate) use interface::{incident_from_point, incident_from_point_into};
pub use interface::{
    sample_uniform_sphere, uniform_sphere_coords, Light, LightLeSample, LightLiSample,
    LightSampleContext,
};
