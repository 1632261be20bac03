//! Finding a plugin library's extension module, version 4 (see
//! `spectrace_plugin_api::extension`): constructors that return, beside the faces of v1–v3, what
//! an object declares about its spectrum (a spectrally flat material, a light with one spectral
//! shape everywhere) and a material's calls in the host's own single-precision layout
//! (`spectrace_plugin_api::fast`, used by `adapter::PluginMaterial`).
//!
//! The same lookup as every version (`extension_lookup`): the symbol is looked up in a library
//! the loader has accepted, its layout is checked by abi_stable before anything in it is called,
//! and a library without it (built before it existed) is served through v3, v2 or the root
//! module: its objects are then neither flat nor uniform, which is always safe.

use crate::plugin::extension_lookup::{lookup, Cache};
use spectrace_plugin_api::extension::{ExtensionsV4Export, ExtensionsV4Ref, EXTENSIONS_V4_SYMBOL};
use std::path::Path;
use std::sync::OnceLock;

fn cache() -> &'static Cache<ExtensionsV4Ref> {
    static CACHE: OnceLock<Cache<ExtensionsV4Ref>> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The version-4 extension module of the library at `path`, if it exports one. Only call this
/// for a library the loader has already accepted. An error says why an exported module is
/// unusable (its layout differs from the host's).
pub fn extensions_v4(path: &Path) -> Result<Option<ExtensionsV4Ref>, String> {
    lookup(
        path,
        EXTENSIONS_V4_SYMBOL,
        "v4",
        cache(),
        |e: ExtensionsV4Export| (e.layout, e.module),
    )
}
