//! Finding a plugin library's extension module, version 6 (see
//! `spectrace_plugin_api::extension`): constructors that return a material's emission in the
//! host's layout and its declaration of the cosine-weighted density (`plugin::cosine_pdf`), and
//! a light's calls in the host's layout (`adapter::PluginLight`).
//!
//! The same lookup as every version (`extension_lookup`): the symbol is looked up in a library
//! the loader has accepted, its layout is checked by abi_stable before anything in it is called,
//! and a library without it (built before it existed) is served through v5 or older: its
//! materials' densities are then asked for through the interface and its lights go through the
//! `f64` calls, which is always safe.

use crate::plugin::extension_lookup::{lookup, Cache};
use spectrace_plugin_api::extension::{ExtensionsV6Export, ExtensionsV6Ref, EXTENSIONS_V6_SYMBOL};
use std::path::Path;
use std::sync::OnceLock;

fn cache() -> &'static Cache<ExtensionsV6Ref> {
    static CACHE: OnceLock<Cache<ExtensionsV6Ref>> = OnceLock::new();
    CACHE.get_or_init(Default::default)
}

/// The version-6 extension module of the library at `path`, if it exports one. Only call this
/// for a library the loader has already accepted. An error says why an exported module is
/// unusable (its layout differs from the host's).
pub fn extensions_v6(path: &Path) -> Result<Option<ExtensionsV6Ref>, String> {
    lookup(
        path,
        EXTENSIONS_V6_SYMBOL,
        "v6",
        cache(),
        |e: ExtensionsV6Export| (e.layout, e.module),
    )
}
