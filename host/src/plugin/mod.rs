//! The plugin host: loading plugin libraries, the registry that maps (kind, type name) to
//! constructors for built-in and loaded types alike, the services plugins call back into, the
//! adapters that make plugin objects look like built-in ones, and the blob file format.

pub mod adapter;
pub mod blob;
pub mod loader;
pub mod registry;
pub mod services;

pub use loader::{LoadError, LoadedPlugin};

/// A registry holding every built-in type, ready for plugins to be added.
pub fn builtin_registry() -> Registry {
    Registry::new()
}
pub use registry::{Registry, RegistryError};
pub use spectrace_plugin_api::ObjectKind;
