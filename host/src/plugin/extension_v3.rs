//! Finding a plugin library's extension module, version 3 (see
//! `spectrace_plugin_api::extension`): a material constructor that returns, beside the faces of
//! v1 and v2, a fluorescent material's re-radiation (see `plugin::reradiation`).
//!
//! The same lookup as every version (`extension_lookup`): the symbol is looked up in a library
//! the loader has accepted, its layout is checked by abi_stable before anything in it is called,
//! and a library without it (built before it existed) is served through v2 or the root module.

use crate::plugin::extension_lookup::{lookup, Cache};
use spectrace_plugin_api::extension::{ExtensionsV3Export, ExtensionsV3Ref, EXTENSIONS_V3_SYMBOL};
use std::path::Path;
use std::sync::OnceLock;

fn cache() -> &'static Cache<ExtensionsV3Ref> {
    static CACHE: OnceLock<Cache<ExtensionsV3Ref>> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The version-3 extension module of the library at `path`, if it exports one. Only call this
/// for a library the loader has already accepted. An error says why an exported module is
/// unusable (its layout differs from the host's).
pub fn extensions_v3(path: &Path) -> Result<Option<ExtensionsV3Ref>, String> {
    lookup(
        path,
        EXTENSIONS_V3_SYMBOL,
        "v3",
        cache(),
        |e: ExtensionsV3Export| (e.layout, e.module),
    )
}
