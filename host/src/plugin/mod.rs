//! The plugin host: loading plugin libraries, the registry that maps (kind, type name) to
//! constructors for built-in and loaded types alike, the services plugins call back into, the
//! adapters that make plugin objects look like built-in ones, and the blob file format.

pub mod adapter;
pub mod blob;
pub mod factory;
pub mod library_check;
pub mod loader;
pub mod registry;
pub mod ron_text;
pub mod services;

pub use loader::{LoadError, LoadedPlugin};

/// A registry holding every built-in type (as the built-in scene factory knows them), ready for
/// plugins to be added: a plugin type with a built-in's name is then refused as a duplicate.
pub fn builtin_registry() -> Registry {
    use crate::scene::{BuiltinFactory, ObjectFactory};
    let mut registry = Registry::new();
    let blob = ("light", factory::BLOB_LIGHT.to_string());
    for (kind, name) in BuiltinFactory
        .known_types()
        .into_iter()
        .chain(std::iter::once(blob))
    {
        let Some(kind) = ObjectKind::parse(kind) else {
            continue;
        };
        let info = spectrace_plugin_api::TypeInfo {
            kind,
            name: name.as_str().into(),
            version: 1,
            description: format!("built-in {kind} (see the scene format docs)").into(),
            params: Default::default(),
        };
        // Built-in names are unique by construction; a clash would be a programming error that
        // the registry reports rather than hides.
        if let Err(e) = registry.register_builtin(info) {
            eprintln!("spectrace: internal: {e}");
        }
    }
    registry
}
pub use registry::{Registry, RegistryError};
pub use spectrace_plugin_api::ObjectKind;
