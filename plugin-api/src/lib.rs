//! # spectrace-plugin-api
//!
//! The stable-ABI interface between spectrace and its plugins, and the only crate a plugin author
//! depends on. A plugin is a `cdylib` that provides any of four kinds of object, each through ONE
//! trait in which every call appears once:
//!
//! | kind | trait | per-sample calls | declared once (data) |
//! |---|---|---|---|
//! | light | [`LightSource`] | `sample_toward`, `incident_pdf`, `sample_emission`, `emission_pdf`, `radiance`; the seed's `next_beam` | `flags` ([`light_flags`]), `emission_spectrum`; `total_power_w`, `scene_bounds` |
//! | material | [`Material`] | `sample`, `eval`, `pdf`, `emitted` | `flags` ([`material_flags`]), `emission`, `reradiation` |
//! | SPD | [`Spd`] | `value`, `sample`, `pdf` | `range_nm`, `lines` |
//! | observer | [`ColorObserver`] | `xyz_bar` | `name`, `range_nm`, `table` |
//!
//! The per-sample calls take the host's own records by reference, in the render loop's layout
//! (four wavelength lanes of `f32`, 16-byte vectors, [`lanes`]) and write their answers into the
//! host's records in place, so no host speed-up ever needs another form of them. Capabilities
//! are bits declared once (`flags`), not extra methods.
//!
//! Authors implement the kind's trait plus [`PluginType`] (name, parameters, version) and list
//! their types in [`export_plugin!`]. The macro puts each object behind a guard (panics are
//! caught on the plugin's side and come back as [`PluginError`]s naming the call) and behind an
//! abi_stable trait object. See [`module`] for how versions work and how the interface grows.
//!
//! Units: lengths in scene units, wavelengths in nm, power in W, solid angle in sr, radiance in
//! W/(m²·sr·nm).

// No `unsafe` of our own here; abi_stable's derives generate the unsafe glue, so it is not forbidden.
#![warn(missing_docs)]
// abi_stable's `#[sabi_trait]` expands to impls inside a const block, which this lint flags.
#![allow(non_local_definitions)]

pub mod error;
pub mod export;
pub mod guard;
pub mod host;
pub mod lanes;
pub mod light;
pub mod material;
pub mod module;
pub mod observer;
pub mod representation;
pub mod reradiation;
pub mod spd;
pub mod types;

pub use error::{ErrorKind, PluginError, PluginResult};
pub use export::{ParamDoc, PluginType};
pub use host::{Host, HostRef};
pub use lanes::{
    status, EmissionPdf, EmittedRay, Incident, Receiver, Scatter, Surface, Values, Vec4f,
    Wavelengths,
};
pub use light::{light_flags, LightBox, LightObject, LightSource};
pub use material::{material_flags, Emission, Material, MaterialBox, MaterialObject};
pub use module::{ObjectKind, PluginInfo, PluginModuleRef, TypeInfo, ABI_VERSION, API_VERSION};
pub use observer::{ColorObserver, ObserverBox, ObserverObject, ObserverTable};
pub use representation::{
    BeamRepresentation, ColourEncoding, DirectionEncoding, Handedness, RepresentedBeam,
};
pub use reradiation::{Reradiation, WavelengthDraw};
pub use spd::{Spd, SpdBox, SpdHandle, SpdObject, SpectralLine, WavelengthSample};
pub use types::{
    Beam, Flags, RandomSample, SceneBounds, TransportMode, Vec3, WavelengthRange, Xyz, LANES,
};

/// Re-exported so plugins and the host use the very same abi_stable.
pub use abi_stable as abi;
/// Re-exported so plugin parameter structs can derive without another dependency.
pub use serde;

/// abi_stable's export machinery names `::abi_stable::library`; [`export_plugin!`] aliases this
/// crate as `abi_stable`, so the path must exist here.
#[doc(hidden)]
pub use abi_stable::library;

#[doc(hidden)]
pub mod __private {
    pub use abi_stable::export_root_module;
    pub use abi_stable::prefix_type::PrefixTypeTrait;
    pub use abi_stable::std_types::{ROption, RResult, RSlice, RStr, RString, RVec};
    pub use abi_stable::StableAbi;
}
