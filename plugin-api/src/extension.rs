//! Extension modules: how the interface grows without locking out existing plugins.
//!
//! abi_stable refuses a library whose root module or trait vtables have FEWER fields than the
//! host's (see the rule in [`module`](crate::module)), so nothing the root module reaches may
//! grow within one API version. New capabilities are exported instead under their own symbol,
//! one per extension version, which a host looks up after loading the root module: found, its
//! layout is checked exactly as the root module's; absent, the library predates it and the host
//! keeps the old behaviour. A published version is frozen; the next addition is a new version.
//!
//! Version 1 (`spectrace_plugin_extensions_v1`): light types whose beams are in another
//! representation ([`representation`](crate::representation)): which types, and a constructor
//! for the object that hands out those beams. [`export_plugin!`](crate::export_plugin) exports
//! it for every plugin.

use crate::error::PluginError;
use crate::host::HostRef;
use crate::module::ObjectSource;
use crate::representation::{BeamRepresentation, RepresentedBeam, TypeRepresentation};
use crate::types::RandomSample;
use abi_stable::{
    sabi_trait,
    std_types::{RBox, RResult, RStr, RVec},
    type_layout::TypeLayout,
    StableAbi,
};

/// The symbol (NUL-terminated) of extension version 1: an `extern "C" fn() ->`
/// [`ExtensionsV1Export`].
pub const EXTENSIONS_V1_SYMBOL: &[u8] = b"spectrace_plugin_extensions_v1\0";

/// A light handing out beams in its declared representation (extension version 1).
#[sabi_trait]
pub trait AbiRepresentedLight: Send + Sync {
    /// The representation of the beams (as the type declares it).
    fn representation(&self) -> BeamRepresentation;
    /// The seed's `numberOfBeams`: beams handed out so far.
    fn number_of_beams(&self) -> f64;
    /// One beam in the declared representation; counts it.
    #[sabi(last_prefix_field)]
    fn next_represented_beam(&self, sample: &RandomSample)
        -> RResult<RepresentedBeam, PluginError>;
}

/// A light in its own representation behind the stable ABI, owned.
pub type RepresentedLightBox = AbiRepresentedLight_TO<'static, RBox<()>>;

/// Extension version 1.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = ExtensionsV1Ref)))]
#[sabi(missing_field(panic))]
pub struct ExtensionsV1 {
    /// The light types whose beams are NOT native, with their declared representation.
    pub type_representations: extern "C" fn() -> RResult<RVec<TypeRepresentation>, PluginError>,
    /// Build such a light from parameters or saved state (as `create_light`).
    #[sabi(last_prefix_field)]
    pub create_represented_light: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<RepresentedLightBox, PluginError>,
}

/// What the version-1 symbol returns: the module's layout, which the host checks against its
/// own before touching the module, and the module. This pair itself never changes.
#[repr(C)]
#[derive(StableAbi, Clone, Copy)]
pub struct ExtensionsV1Export {
    /// `<ExtensionsV1Ref as StableAbi>::LAYOUT` as the plugin was compiled.
    pub layout: &'static TypeLayout,
    /// The module.
    pub module: ExtensionsV1Ref,
}
