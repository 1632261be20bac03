//! Scenes: the in-memory [`Scene`] (the seed's SceneObjectManager + CameraManager +
//! LightSourceManager, plus geometry, observer and output settings), its RON file format
//! ([`description`]), object construction through [`factory::ObjectFactory`], the builder and the
//! embedded default Cornell box.

pub mod builder;
pub mod cornell;
pub mod description;
pub mod error;
pub mod factory;
pub mod mitsuba;
pub mod model;
pub mod objects;
pub mod params;
pub mod representation;
pub mod source;
pub mod units;
pub mod warnings;

pub use crate::builtin::BuiltinFactory;
pub use builder::{
    build_scene, build_scene_with, load_scene_file, load_scene_file_with, parse_scene_str,
    read_scene_file,
};
pub use cornell::{cornell_box_description, default_scene, default_scene_with};
pub use description::SceneDescription;
pub use error::SceneError;
pub use factory::{FactoryContext, FactoryError, ObjectFactory, SpdFactories};
pub use objects::{SceneObject, SceneObjectManager};
pub use representation::{ReflectanceSource, RepresentationOptions};
pub use source::SceneSource;
pub use units::LengthUnit;

pub use model::{Scene, SceneOptions};
