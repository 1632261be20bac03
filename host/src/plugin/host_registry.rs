//! The registry a host starts from: its own types (built-ins, the `blob` type of each blob
//! kind, the integrators' type information), before any plugin is loaded.

use super::factory::{blob_type_doc, BLOB_KINDS};
use super::registry::Registry;
use crate::scene_file::type_doc::{Kind, ParamDoc, TypeDoc};

/// A registry holding every built-in type of [`crate::builtin`] (with its aliases) and the
/// host's `blob` type of each blob kind, ready for plugins to be added: a plugin type with a
/// built-in's name (or alias) is then refused as a duplicate, naming both.
pub fn builtin_registry() -> Registry {
    let mut registry = core_registry();
    for ty in crate::builtin::all().filter(|t| t.kind().object_kind().is_some()) {
        // Built-in names are unique by construction (a test checks); a clash would be a
        // programming error that the registry reports rather than hides.
        if let Err(e) = registry.register_builtin_type(ty) {
            eprintln!("spectrace: internal: {e}");
        }
    }
    registry
}

/// A registry with only the types no plugin can provide: the built-in shapes and cameras and
/// the host's `blob` type of each blob kind. This is what `--no-builtins` starts from, so that
/// a library providing the standard materials, lights, SPDs and observers under the built-in
/// names (`plugins/standard`) can be loaded instead.
pub fn core_registry() -> Registry {
    let mut registry = Registry::new();
    for kind in BLOB_KINDS {
        if let Err(e) = registry.register_doc(blob_type_doc(kind)) {
            eprintln!("spectrace: internal: {e}");
        }
    }
    for ty in crate::builtin::all().filter(|t| t.kind().object_kind().is_none()) {
        if let Err(e) = registry.register_builtin_type(ty) {
            eprintln!("spectrace: internal: {e}");
        }
    }
    // Integrators are built from the render settings by `integrator::select`; the registry
    // holds their type information (names and aliases reserved, listed, documented).
    for r in crate::integrator::select::registered() {
        for name in std::iter::once(r.info.name).chain(r.info.aliases.iter().copied()) {
            let doc = TypeDoc {
                kind: Kind::Integrator,
                name: name.to_string(),
                version: r.info.version,
                description: if name == r.info.name {
                    r.info.description.to_string()
                } else {
                    format!("alias of `{}`", r.info.name)
                },
                params: r
                    .info
                    .params
                    .iter()
                    .map(|p| ParamDoc {
                        name: p.name.into(),
                        unit: p.unit.into(),
                        default: p.default.map(Into::into),
                        description: p.description.into(),
                    })
                    .collect(),
                alias_of: (name != r.info.name).then(|| r.info.name.to_string()),
            };
            if let Err(e) = registry.register_doc(doc) {
                eprintln!("spectrace: internal: {e}");
            }
        }
    }
    registry
}
