//! The plugin host: loading plugin libraries, the registry that maps (kind, type name) to
//! constructors for built-in and loaded types alike, the services plugins call back into, the
//! adapters that make plugin objects look like built-in ones, and the blob file format.

pub mod adapter;
pub mod blob;
pub mod checked;
pub mod cosine_pdf;
pub mod factory;
pub mod faults;
pub mod flatness;
pub mod host_registry;
pub mod layout;
pub mod library_check;
pub mod loader;
pub mod observer_table;
pub mod pack;
pub mod reference;
pub mod registry;
pub mod representation;
pub mod reradiation;
pub mod ron_text;
pub mod same_f;
pub mod services;
pub mod uniform_shape;

pub use loader::{LoadError, LoadedPlugin};

pub use crate::scene_file::type_doc::{Kind, ParamDoc, TypeDoc};
pub use host_registry::{builtin_registry, core_registry};
pub use registry::{Registry, RegistryError};
pub use spectrace_plugin_api::ObjectKind;
