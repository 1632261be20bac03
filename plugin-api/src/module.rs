//! The root module each plugin library exports, and the metadata it reports.
//!
//! # Compatibility rule
//!
//! Enforced by abi_stable when the host loads a library, and tested by the workspace test
//! `api_growth` (a plugin built against a frozen copy of this crate's 0.1.0 source,
//! `plugins/fixtures/api-0.1.0/`, must keep loading and rendering in the current host):
//!
//! 1. **Version.** A plugin built against `spectrace-plugin-api` 0.y.z loads in a host built
//!    against 0.y.z' when y is the same and z ≥ z' (while the major version is 0, y counts as
//!    the major). So growing the interface in a way old plugins survive does NOT bump z: a host
//!    at 0.1.1 would refuse every plugin built at 0.1.0. Anything that breaks old plugins bumps y.
//! 2. **Layout.** The whole layout of the root module and of every type it reaches is compared
//!    at load time (names, packages, fields, sizes). Plain `#[repr(C)]` structs such as
//!    [`TypeInfo`], [`PluginInfo`] and [`Beam`](crate::Beam) never change within one y.
//! 3. **Growth only after the markers.** The root module ([`PluginModule`]) and the trait
//!    vtables ([`AbiLightSource`](crate::light::AbiLightSource) and friends) are prefix types:
//!    new fields and methods go after the `#[sabi(last_prefix_field)]` marker, which never
//!    moves within one y. An older plugin simply lacks them, so every addition must say what the
//!    host does then: a root-module field is declared `#[sabi(missing_field(option))]` and the
//!    host treats `None` as "the old behaviour"; a trait method has a default body, which
//!    abi_stable calls in place of the missing one. A newer plugin in an older host is refused by
//!    rule 1, never half-used.
//!
//! Additions so far, all after the markers: [`PluginModule::type_representations`] and
//! `AbiLightSource::{beam_representation, next_represented_beam}` (beams in another
//! representation, see [`representation`](crate::representation)).

use crate::error::PluginError;
use crate::host::HostRef;
use crate::light::LightBox;
use crate::material::MaterialBox;
use crate::observer::ObserverBox;
use crate::representation::TypeRepresentation;
use crate::spd::SpdBox;
use abi_stable::{
    declare_root_module_statics,
    library::RootModule,
    package_version_strings,
    sabi_types::VersionStrings,
    std_types::{ROption, RResult, RSlice, RStr, RString, RVec},
    StableAbi,
};

/// The version of this interface crate a plugin was compiled against.
pub const API_VERSION: &str = env!("CARGO_PKG_VERSION");

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
/// its kind from a type name and either parameters or saved state; the host's services (SPD
/// lookup) are lent for the duration of the call.
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
    ) -> RResult<LightBox, PluginError>,
    /// Construct an SPD.
    pub create_spd: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<SpdBox, PluginError>,
    /// Construct a colour observer.
    pub create_observer: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<ObserverBox, PluginError>,
    /// Construct a material.
    pub create_material: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<MaterialBox, PluginError>,
    /// Decode saved state of a type into its parameters in scene (RON) syntax, without building
    /// the object: what `spectrace blob inspect` prints. Fields added in later API versions go
    /// after this one.
    #[sabi(last_prefix_field)]
    pub describe_state: extern "C" fn(
        kind: ObjectKind,
        type_name: RStr<'_>,
        type_version: u32,
        bytes: RSlice<'_, u8>,
    ) -> RResult<RString, PluginError>,
    /// Added after the marker: the light types whose beams are NOT in the native
    /// representation, with their declared one (type information that [`TypeInfo`] cannot carry
    /// without breaking its layout). Absent in plugins built before it existed: all native.
    #[sabi(missing_field(option))]
    pub type_representations: extern "C" fn() -> RResult<RVec<TypeRepresentation>, PluginError>,
}

impl RootModule for PluginModuleRef {
    declare_root_module_statics! {PluginModuleRef}
    const BASE_NAME: &'static str = "spectrace_plugin";
    const NAME: &'static str = "spectrace_plugin";
    const VERSION_STRINGS: VersionStrings = package_version_strings!();
}
