//! The built-in types: every material, light, SPD type, observer, shape, camera and sensor the
//! host provides without plugins. One type, one file, its parameter table at the top and a typed
//! serde parameter struct; each file exports a `TYPE` constant ([`BuiltinType`]) that the
//! registry registers exactly like a plugin's type (same type information, same duplicate rule,
//! same constructor call through [`crate::scene_file::ObjectFactory`]).
//!
//! A built-in's parameter struct is also its saved state: a blob of a built-in type is the
//! struct encoded with bincode (see [`crate::plugin::blob`]), with the data it reads from files
//! embedded first ([`Embed`]).
//!
//! Aliases (`diffuse` = `lambertian`, `rough_conductor` = `conductor`, `area_light` = `emissive`,
//! `thin_lens` = `perspective`) are registered under their own names, so a plugin type of such a
//! name is refused as a clash.

pub mod built_in_type;
pub mod camera;
pub mod check;
pub mod factory;
pub mod light;
pub mod material;
pub mod observer;
pub mod params_de;
pub mod registry;
pub mod sensor;
pub mod shape;
pub mod spd;
pub mod spectral;

pub use built_in_type::{
    state_fns, to_scene_text, Build, BuiltinType, CameraFn, Embed, LightFn, MaterialFn, ObserverFn,
    ShapeFn, SpdFn, StateFns,
};
pub use check::{finite, finite3, param_err};
pub use factory::BuiltinFactory;
pub use params_de::{from_value, ParamsError};
pub use registry::{all, find, names, types};
