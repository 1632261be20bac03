//! The root module each plugin library exports, and the metadata it reports.
//!
//! # Versions and the growth rule
//!
//! The interface's ABI is versioned by [`ABI_VERSION`] (`0.2`), separately from the crate's
//! patch number: a library built against any `spectrace-plugin-api` 0.2.z declares ABI 0.2.0 and
//! loads in every host built against any 0.2.z'. Tested by the workspace test `api_growth`,
//! which loads a plugin built against a frozen copy of the 0.2.0 crate
//! (`plugins/fixtures/api-0.2.0/`).
//!
//! 1. **Frozen layouts.** When a library is loaded, abi_stable compares the whole layout of the
//!    root module ([`PluginModule`]) and of every type it reaches (the four object traits'
//!    vtables, [`TypeInfo`], [`Beam`](crate::Beam), the [`crate::lanes`] records, …) with the
//!    host's. Within 0.2 none of them changes. Each prefix type (this module, the vtables) marks
//!    its last 0.2.0 field with `#[sabi(last_prefix_field)]`; abi_stable 0.11 accepts a library
//!    whose prefix types have MORE fields than the host's and refuses one with fewer ("too many
//!    fields", `abi_checking.rs`), so a field appended in 0.2.1 would let 0.2.1 plugins into a
//!    0.2.0 host but lock every 0.2.0 plugin out of a 0.2.1 host. Hence nothing is appended.
//! 2. **New capabilities only, in new modules.** A later 0.2.z that adds a capability (a new
//!    kind of call, not a faster or different encoding of an existing one) exports it as a
//!    separate, optional symbol of its own (a prefix-type module, layout-checked on its own when
//!    the host looks it up). A library without it is a plugin built before it existed, and the
//!    host treats it as not having the capability. Once published, such a module is frozen like
//!    the root module.
//! 3. **Never re-encodings.** The per-sample calls are already in the render loop's layout
//!    (wavelength lanes, records by reference, answers written in place): a host speed-up is the
//!    host's business and never a new interface.
//! 4. **Breaking changes bump the minor version** (0.3): the host then refuses 0.2 libraries by
//!    version, naming both versions and asking for a rebuild, as it refuses 0.1 libraries now.
//!
//! See `plugin-api/CHANGELOG.md` for what each version changed.

use crate::error::PluginError;
use crate::host::HostRef;
use crate::light::LightObject;
use crate::material::MaterialObject;
use crate::observer::ObserverObject;
use crate::representation::BeamRepresentation;
use crate::spd::SpdObject;
use abi_stable::{
    declare_root_module_statics,
    library::RootModule,
    sabi_types::VersionStrings,
    std_types::{ROption, RResult, RSlice, RStr, RString, RVec},
    StableAbi,
};

/// The version of this interface crate a plugin was compiled against.
pub const API_VERSION: &str = env!("CARGO_PKG_VERSION");

/// The version of the binary interface: what the root module declares to the loader. It stays
/// `0.2.0` for every 0.2.z of the crate (see the growth rule above); a test checks that its
/// major and minor numbers are the crate's.
pub const ABI_VERSION: &str = "0.2.0";

/// The kinds of object a plugin can provide.
#[repr(u8)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ObjectKind {
    /// A light source.
    Light,
    /// A spectral power distribution.
    Spd,
    /// A colour observer.
    Observer,
    /// A material.
    Material,
}

impl ObjectKind {
    /// Lower-case name as used in scene files and messages.
    pub fn as_str(self) -> &'static str {
        match self {
            ObjectKind::Light => "light",
            ObjectKind::Spd => "spd",
            ObjectKind::Observer => "observer",
            ObjectKind::Material => "material",
        }
    }
    /// All kinds, in a stable order.
    pub const ALL: [ObjectKind; 4] = [
        ObjectKind::Light,
        ObjectKind::Spd,
        ObjectKind::Observer,
        ObjectKind::Material,
    ];
    /// Parse a kind name.
    pub fn parse(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.as_str() == s)
    }
}

impl std::fmt::Display for ObjectKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// One constructor parameter, for documentation and `spectrace plugins`.
#[repr(C)]
#[derive(StableAbi, Clone, Debug, PartialEq)]
pub struct ParamInfo {
    /// Name as written in the scene.
    pub name: RString,
    /// Unit, e.g. "W", "nm", "scene units"; empty when unitless.
    pub unit: RString,
    /// Default value in scene syntax; none when required.
    pub default: ROption<RString>,
    /// What it does.
    pub description: RString,
}

/// One type a plugin provides.
#[repr(C)]
#[derive(StableAbi, Clone, Debug, PartialEq)]
pub struct TypeInfo {
    /// Object kind.
    pub kind: ObjectKind,
    /// Type name, found by scenes (`type: "point"`).
    pub name: RString,
    /// Version of the saved-state schema; bumps whenever the parameter struct changes.
    pub version: u32,
    /// One line on what it is.
    pub description: RString,
    /// Constructor parameters.
    pub params: RVec<ParamInfo>,
    /// Lights: the representation of the type's beams ([`crate::representation`]); native for
    /// every other kind.
    pub beams: BeamRepresentation,
}

/// What a plugin says about itself.
#[repr(C)]
#[derive(StableAbi, Clone, Debug, PartialEq)]
pub struct PluginInfo {
    /// Plugin name (unique among loaded plugins).
    pub name: RString,
    /// Plugin version.
    pub version: RString,
    /// [`API_VERSION`] as seen when the plugin was compiled.
    pub api_version: RString,
    /// Provided types.
    pub types: RVec<TypeInfo>,
}

/// Where a constructor takes its values from.
#[repr(u8)]
#[derive(StableAbi, Clone, Copy, Debug)]
pub enum ObjectSource<'a> {
    /// Parameters as RON text in scene syntax, e.g. `(power_w: 100.0, spd: "d65")`.
    Params(RStr<'a>),
    /// State saved by `save_state`, with the type version that wrote it.
    State {
        /// Version of the type that wrote `bytes`.
        type_version: u32,
        /// The bincode payload.
        bytes: RSlice<'a, u8>,
    },
}

/// The root module: the one symbol a plugin library exports. Each `create_*` builds an object of
/// its kind from a type name and either parameters or saved state, and returns it with what it
/// declares once; the host's services (SPD lookup) are lent for the duration of the call.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = PluginModuleRef)))]
#[sabi(missing_field(panic))]
pub struct PluginModule {
    /// Name, version, API version and provided types.
    pub info: extern "C" fn() -> RResult<PluginInfo, PluginError>,
    /// Construct a light source.
    pub create_light: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<LightObject, PluginError>,
    /// Construct an SPD.
    pub create_spd: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<SpdObject, PluginError>,
    /// Construct a colour observer.
    pub create_observer: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<ObserverObject, PluginError>,
    /// Construct a material.
    pub create_material: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<MaterialObject, PluginError>,
    /// Decode saved state of a type into its parameters in scene (RON) syntax, without building
    /// the object: what `spectrace blob inspect` prints.
    pub describe_state: extern "C" fn(
        kind: ObjectKind,
        type_name: RStr<'_>,
        type_version: u32,
        bytes: RSlice<'_, u8>,
    ) -> RResult<RString, PluginError>,
    /// The error of the last per-sample call that failed on the calling thread (its answer was
    /// [`status::ERROR`](crate::lanes::status) or NaN), taken. The last 0.2.0 field: see the
    /// growth rule above.
    #[sabi(last_prefix_field)]
    pub take_error: extern "C" fn() -> ROption<PluginError>,
}

impl RootModule for PluginModuleRef {
    declare_root_module_statics! {PluginModuleRef}
    const BASE_NAME: &'static str = "spectrace_plugin";
    const NAME: &'static str = "spectrace_plugin";
    const VERSION_STRINGS: VersionStrings = VersionStrings::new(ABI_VERSION);
}

#[cfg(test)]
mod tests {
    // The ABI version names the crate's minor line: bumping the crate to 0.3 without it (or
    // the other way round) fails here.
    #[test]
    fn the_abi_version_is_the_crates_minor_line() {
        let minor = |v: &str| v.split('.').take(2).collect::<Vec<_>>().join(".");
        assert_eq!(minor(super::ABI_VERSION), minor(super::API_VERSION));
        assert!(super::ABI_VERSION.ends_with(".0"));
    }
}
