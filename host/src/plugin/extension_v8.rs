//! Finding a plugin library's extension module, version 8 (see
//! `spectrace_plugin_api::extension`): a material face whose calls take their arguments as the
//! host's own material calls do, with no error slot (errors taken in a second call).
//!
//! The same lookup as every version (`extension_lookup`): the symbol is looked up in a library
//! the loader has accepted, its layout is checked by abi_stable before anything in it is called,
//! and a library without it (built before it existed) is served through v7.

use crate::plugin::extension_lookup::{lookup, Cache};
use spectrace_plugin_api::extension::{ExtensionsV8Export, ExtensionsV8Ref, EXTENSIONS_V8_SYMBOL};
use std::path::Path;
use std::sync::OnceLock;

fn cache() -> &'static Cache<ExtensionsV8Ref> {
    static CACHE: OnceLock<Cache<ExtensionsV8Ref>> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The version-8 extension module of the library at `path`, if it exports one. Only call this
/// for a library the loader has already accepted. An error says why an exported module is
/// unusable (its layout differs from the host's).
pub fn extensions_v8(path: &Path) -> Result<Option<ExtensionsV8Ref>, String> {
    lookup(
        path,
        EXTENSIONS_V8_SYMBOL,
        "v8",
        cache(),
        |e: ExtensionsV8Export| (e.layout, e.module),
    )
}
