//! # spectrace-plugin-api
//!
//! The stable-ABI interface between spectrace and its plugins, and the only crate a plugin author
//! depends on. A plugin is a `cdylib` that provides any of four kinds of object:
//!
//! * [`LightSource`]: the seed's light, anything that hands out [`Beam`]s (`next_beam`) and says
//!   how many it emitted (`number_of_beams`), optionally connectable for bidirectional tracing;
//! * [`Spd`]: a spectral power distribution that evaluates and samples itself (∫ = 1);
//! * [`ColorObserver`]: colour-matching functions x̄ȳz̄;
//! * [`Material`]: turns an incoming direction into an outgoing one, per wavelength.
//!
//! Authors implement those plain Rust traits plus [`PluginType`] and list their types in
//! [`export_plugin!`]. The macro puts each object behind a guard (panics are caught on the
//! plugin's side and come back as [`PluginError`]s) and behind an abi_stable trait object.
//! See `module` for the compatibility rule between host and plugin versions, and `extension`
//! for what later versions added (v2: scene bounds and emission spectra for lights, the
//! surface's normals and exact emission for materials, spectral lines for SPDs; v3: fluorescent
//! materials' re-radiation, see `reradiation`; v4: spectral flatness of materials and one
//! spectral shape of lights, and the material calls in the host's own layout, see `fast`; v5:
//! one BSDF value for every direction, the surface by reference; v6: the cosine-weighted
//! density declared, emission and the lights' calls in the host's layout):
//! provided methods of the same traits, so a plugin uses them by overriding them.
//!
//! Units: lengths in scene units, wavelengths in nm, power in W, solid angle in sr.

// No `unsafe` of our own here; abi_stable's derives generate the unsafe glue, so it is not forbidden.
#![warn(missing_docs)]
// abi_stable's `#[sabi_trait]` expands to impls inside a const block, which this lint flags.
#![allow(non_local_definitions)]

pub mod error;
pub mod export;
pub mod extension;
pub mod fast;
pub mod guard;
pub mod host;
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
pub use fast::{
    EmissionF32, IncidentF32, LanesF32, MaterialQuery, QueryV5, QueryV7, ReceiverF32, ScatterF32,
    SurfaceF32, Vec4f, WavelengthsF32,
};
pub use host::{Host, HostRef};
pub use light::{
    light_flags, EmissionPdf, EmissionSample, IncidentSample, LightBox, LightSource,
    WavelengthSample,
};
pub use material::{
    material_flags, Emission, Material, MaterialBox, ScatterSample, ShadingContext, SurfaceContext,
};
pub use module::{ObjectKind, PluginInfo, PluginModuleRef, TypeInfo, API_VERSION};
pub use observer::{ColorObserver, ObserverBox, ObserverTable};
pub use representation::{
    BeamRepresentation, ColourEncoding, DirectionEncoding, Handedness, RepresentedBeam,
    TypeRepresentation,
};
pub use reradiation::{Reradiation, WavelengthDraw};
pub use spd::{spd_flags, Spd, SpdBox, SpdHandle, SpectralLine};
pub use types::{
    Beam, Flags, RandomSample, SceneBounds, SpectralValues, TransportMode, Vec3, WavelengthRange,
    Wavelengths, Xyz, LANES,
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
