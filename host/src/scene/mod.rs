//! Scenes: the in-memory [`Scene`] (the seed's SceneObjectManager + CameraManager +
//! LightSourceManager, plus geometry, observer and output settings), the builder that makes one
//! from a scene file through the factories it is given, the embedded default Cornell box and the
//! Mitsuba importer. The file format and the factory contract are a floor below
//! ([`crate::scene_file`]); the names a caller needs to load a scene are re-exported here.

pub mod builder;
pub mod cornell;
pub mod error;
pub mod mitsuba;
pub mod model;
pub mod objects;
pub mod source;
pub mod warnings;

pub use crate::builtin::BuiltinFactory;
pub use crate::scene_file::{
    FactoryContext, FactoryError, LengthUnit, ObjectFactory, ReflectanceSource,
    RepresentationOptions, SceneDescription, SpdFactories,
};
pub use builder::{
    build_scene, build_scene_with, load_scene_file, load_scene_file_with, parse_scene_str,
    read_scene_file,
};
pub use cornell::{cornell_box_description, default_scene, default_scene_with};
pub use error::SceneError;
pub use objects::{SceneObject, SceneObjectManager};
pub use source::SceneSource;

pub use model::{Scene, SceneOptions};
