//! The root module each plugin library exports, and the metadata it reports.
//!
//! # Compatibility rule
//!
//! Tested by the workspace test `api_growth`: a plugin built against a frozen copy of this
//! crate's 0.1.0 source (`plugins/fixtures/api-0.1.0/`) must keep loading and rendering in the
//! current host.
//!
//! 1. **Version.** A plugin built against `spectrace-plugin-api` 0.y.z loads in a host built
//!    against 0.y.z' when y is the same and z ≥ z' (abi_stable's rule; while the major version
//!    is 0, y counts as the major). So an addition that old plugins survive does NOT bump z: a
//!    host at 0.1.1 would refuse every plugin built at 0.1.0. Anything that breaks them bumps y.
//! 2. **Layout.** When a library is loaded, abi_stable compares the whole layout of the root
//!    module and of every type it reaches (names, packages, fields, sizes) with the host's. For
//!    prefix types (this root module, the trait vtables) the library may have MORE fields than
//!    the host, never fewer: abi_stable lets a newer plugin into an older host, not the reverse.
//! 3. **Hence nothing the root module reaches ever grows within one y.** [`PluginModule`], the
//!    `Abi*` traits and every `#[repr(C)]` type they use ([`TypeInfo`], [`PluginInfo`],
//!    [`Beam`](crate::Beam), …) keep their 0.y.0 layout. Adding a field after a
//!    `#[sabi(last_prefix_field)]` marker would be legal for abi_stable and still lock out every
//!    existing plugin (the frozen-API test fails with "too many fields").
//! 4. **Growth goes into extension modules.** Each is a separate, optional, versioned symbol
//!    ([`crate::extension`]): a host looks it up after loading the root module, checks its
//!    layout the same way, and treats a library without it as a plugin built before it existed
//!    (today: every light type has native beams). A published extension version is frozen like
//!    the root module; the next addition is a new version next to it, and plugins export all
//!    the versions they support.
//!
//! Extensions so far: `spectrace_plugin_extensions_v1` (beams in another representation, see
//! [`representation`](crate::representation)) and `spectrace_plugin_extensions_v2` (scene
//! bounds and emission spectra for lights, surface normals and exact emission for materials,
//! spectral lines for SPDs; see [`extension`](crate::extension)) and
//! `spectrace_plugin_extensions_v3` (fluorescent materials' re-radiation, see
//! [`reradiation`](crate::reradiation)) and `spectrace_plugin_extensions_v4` (spectral flatness
//! of materials, one spectral shape of lights, and the material calls in the host's layout, see
//! [`fast`](crate::fast)) and `spectrace_plugin_extensions_v5` (one BSDF value for every
//! direction, the material calls with the surface by reference and results through a
//! reference) and `spectrace_plugin_extensions_v6` (the cosine-weighted density, emission and
//! the lights' calls in the host's layout). The workspace test `api_growth` loads plugins built
//! against frozen copies of the API at 0.1.0 (`plugins/fixtures/api-0.1.0/`), at extension v1
//! (`plugins/fixtures/api-ext-v1/`), at extension v2 (`plugins/fixtures/api-ext-v2/`), at
//! extension v3 (`plugins/fixtures/api-ext-v3/`), at extension v4 (`plugins/fixtures/api-ext-v4/`)
//! and at extension v5 (`plugins/fixtures/api-ext-v5/`).

use crate::error::PluginError;
use crate::host::HostRef;
use crate::light::LightBox;
use crate::material::MaterialBox;
use crate::observer::ObserverBox;
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
}

impl RootModule for PluginModuleRef {
    declare_root_module_statics! {PluginModuleRef}
    const BASE_NAME: &'static str = "spectrace_plugin";
    const NAME: &'static str = "spectrace_plugin";
    const VERSION_STRINGS: VersionStrings = package_version_strings!();
}
