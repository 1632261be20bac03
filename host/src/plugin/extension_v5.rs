//! Finding a plugin library's extension module, version 5 (see
//! `spectrace_plugin_api::extension`): a material constructor that returns, beside the faces of
//! v1–v3, the material calls writing their results through a reference (`adapter::PluginMaterial`)
//! and what the material declares (spectrally flat, the same BSDF value for every direction).
//!
//! The same lookup as every version (`extension_lookup`): the symbol is looked up in a library
//! the loader has accepted, its layout is checked by abi_stable before anything in it is called,
//! and a library without it (built before it existed) is served through v4 or older: its
//! materials are then evaluated again for next-event estimation, which is always safe.

use crate::plugin::extension_lookup::{lookup, Cache};
use spectrace_plugin_api::extension::{ExtensionsV5Export, ExtensionsV5Ref, EXTENSIONS_V5_SYMBOL};
use std::path::Path;
use std::sync::OnceLock;

fn cache() -> &'static Cache<ExtensionsV5Ref> {
    static CACHE: OnceLock<Cache<ExtensionsV5Ref>> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The version-5 extension module of the library at `path`, if it exports one. Only call this
/// for a library the loader has already accepted. An error says why an exported module is
/// unusable (its layout differs from the host's).
pub fn extensions_v5(path: &Path) -> Result<Option<ExtensionsV5Ref>, String> {
    lookup(
        path,
        EXTENSIONS_V5_SYMBOL,
        "v5",
        cache(),
        |e: ExtensionsV5Export| (e.layout, e.module),
    )
}
