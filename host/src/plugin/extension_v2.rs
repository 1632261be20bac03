//! Finding a plugin library's extension module, version 2 (see
//! `spectrace_plugin_api::extension`): constructors that return, beside the object of the root
//! module, its version-2 face (scene bounds and the emission SPD for lights; normals and the
//! exact emission for materials; spectral lines for SPDs).
//!
//! As for version 1 (`representation::extension`): the symbol is looked up in a library the
//! loader has accepted, its layout is checked by abi_stable before anything in it is called, and
//! a library without it (built before it existed) is served through the root module alone.

use crate::plugin::extension_lookup::{lookup, Cache};
use spectrace_plugin_api::extension::{ExtensionsV2Export, ExtensionsV2Ref, EXTENSIONS_V2_SYMBOL};
use std::path::Path;
use std::sync::OnceLock;

fn cache() -> &'static Cache<ExtensionsV2Ref> {
    static CACHE: OnceLock<Cache<ExtensionsV2Ref>> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The version-2 extension module of the library at `path`, if it exports one. Only call this
/// for a library the loader has already accepted. An error says why an exported module is
/// unusable (its layout differs from the host's).
pub fn extensions_v2(path: &Path) -> Result<Option<ExtensionsV2Ref>, String> {
    lookup(
        path,
        EXTENSIONS_V2_SYMBOL,
        "v2",
        cache(),
        |e: ExtensionsV2Export| (e.layout, e.module),
    )
}
