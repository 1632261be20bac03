//! Finding a plugin library's extension module, version 1 (see
//! `spectrace_plugin_api::extension`): the lights whose beams are in another representation.
//!
//! The root module is frozen within one API version (abi_stable refuses a library whose root
//! module has fewer fields than the host's), so this arrives under its own symbol. A library
//! built before it existed lacks the symbol and is treated as all-native. The symbol's layout is
//! checked by abi_stable exactly as the root module's before anything in it is called.

use crate::plugin::extension_lookup::{lookup, Cache};
use spectrace_plugin_api::extension::{ExtensionsV1Export, ExtensionsV1Ref, EXTENSIONS_V1_SYMBOL};
use std::path::Path;
use std::sync::OnceLock;

fn cache() -> &'static Cache<ExtensionsV1Ref> {
    static CACHE: OnceLock<Cache<ExtensionsV1Ref>> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The version-1 extension module of the library at `path`, if it exports one. Only call this
/// for a library the loader has already accepted (it is then mapped: this looks it up again).
/// An error says why an exported module is unusable (its layout differs from the host's).
pub fn extensions_v1(path: &Path) -> Result<Option<ExtensionsV1Ref>, String> {
    lookup(
        path,
        EXTENSIONS_V1_SYMBOL,
        "v1",
        cache(),
        |e: ExtensionsV1Export| (e.layout, e.module),
    )
}
