//! Finding a plugin library's extension module, version 7 (see
//! `spectrace_plugin_api::extension`): an observer constructor that returns the observer's
//! declared 1 nm table (`plugin::observer_table`).
//!
//! The same lookup as every version (`extension_lookup`): the symbol is looked up in a library
//! the loader has accepted, its layout is checked by abi_stable before anything in it is called,
//! and a library without it (built before it existed) is served through the root module: its
//! observers' `xyz_bar` is then called per wavelength, which is always safe.

use crate::plugin::extension_lookup::{lookup, Cache};
use spectrace_plugin_api::extension::{ExtensionsV7Export, ExtensionsV7Ref, EXTENSIONS_V7_SYMBOL};
use std::path::Path;
use std::sync::OnceLock;

fn cache() -> &'static Cache<ExtensionsV7Ref> {
    static CACHE: OnceLock<Cache<ExtensionsV7Ref>> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The version-6 extension module of the library at `path`, if it exports one. Only call this
/// for a library the loader has already accepted. An error says why an exported module is
/// unusable (its layout differs from the host's).
pub fn extensions_v7(path: &Path) -> Result<Option<ExtensionsV7Ref>, String> {
    lookup(
        path,
        EXTENSIONS_V7_SYMBOL,
        "v7",
        cache(),
        |e: ExtensionsV7Export| (e.layout, e.module),
    )
}
