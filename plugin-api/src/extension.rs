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
//! for the object that hands out those beams.
//!
//! Version 2 (`spectrace_plugin_extensions_v2`): constructors that hand the host, beside the
//! object it already knows (a [`LightBox`], [`MaterialBox`] or [`SpdBox`] of the root module),
//! a second face of the same object with the calls added in v2:
//!
//! * lights learn the scene's extent ([`LightSource::scene_bounds`]) and hand over their own
//!   emission SPD ([`LightSource::emission_spectrum`]);
//! * materials see the surface's normals ([`SurfaceContext`], the `*_at` calls of
//!   [`Material`](crate::Material)) and describe their emission exactly
//!   ([`Material::emission`](crate::Material::emission));
//! * SPDs list their spectral lines ([`Spd::delta_lines`](crate::Spd::delta_lines)).
//!
//! Both faces share one object (the same state, the same beam count). A host that predates v2
//! uses the root module alone; a library that predates v2 gets the old behaviour (no bounds, no
//! normals, emission spectra read through the v1 calls).
//!
//! Version 3 (`spectrace_plugin_extensions_v3`): fluorescence. A material constructor that
//! returns, beside the faces of v1 and v2, the material's re-radiation face
//! ([`ReradiationBox`], see [`crate::reradiation`]): reflectance, re-radiation F(λᵢ → λₒ),
//! emission and excitation draws with their densities. A `FLUORESCENT` material offers it by
//! overriding [`Material::reradiation`](crate::Material::reradiation); a host older than v3
//! renders such a material's reflectance only, and a library older than v3 is served through v2
//! (the host then warns that the material's re-radiation is not simulated).
//!
//! Why not a new method after the `AbiMaterial` vtable's `last_prefix_field`, as the request for
//! fluorescence first put it: abi_stable lets a library with MORE prefix fields into a host
//! with fewer, never the reverse, so growing a vtable the root module reaches would lock every
//! existing plugin out of the new host (the rule in [`module`](crate::module)). The extension
//! gives what the request asked for — a material declares `FLUORESCENT` and offers
//! wavelength-shifting sampling and evaluation, and plugins built against the earlier API still
//! load — by putting the new calls on a second vtable that only the v3 symbol reaches.
//!
//! Version 4 (`spectrace_plugin_extensions_v4`): what an object declares about its spectrum, and
//! the material calls without conversions. A material says whether it is spectrally flat
//! ([`Material::spectrally_flat`](crate::Material::spectrally_flat): the same response at every
//! wavelength), a light whether its emission has one spectral shape everywhere
//! ([`LightSource::uniform_spectral_shape`](crate::LightSource::uniform_spectral_shape)); the
//! host then gives a path through such objects the exact colour of its emitter, as for its own
//! grey surfaces and area lights (`flat-path-colour`). Both are read once when the object is
//! built and travel as fields of [`MaterialWithV4`] and [`LightWithV4`]. Its material face
//! ([`AbiMaterialV4`]) takes `sample`, `eval` and `pdf` with one [`MaterialQuery`] by reference in
//! the host's own single-precision layout ([`crate::fast`]), so that a call costs the host little
//! more than calling one of its own materials. A library older than v4 is served through v3
//! (not flat, not uniform: always safe).
//!
//! Version 5 (`spectrace_plugin_extensions_v5`): a material says whether its BSDF value is the
//! same for every direction on a side
//! ([`Material::f_same_for_all_directions`](crate::Material::f_same_for_all_directions): an
//! ideal diffuse reflector), so the host reuses a sampled value for next-event estimation
//! instead of calling `eval` again; and its face [`AbiMaterialV5`] takes the query with the
//! surface by reference ([`QueryV5`]: the host's own record, not a copy) and writes its result
//! through a reference, with a panic guard that needs no thread-local (`guard::guarded_call_v5`). Read once when the material is built and
//! carried in [`MaterialWithV5`]; the host checks the claim. Lights are built through v4 as
//! before. A library older than v5 is served through v4 (evaluated again: always safe).
//!
//! Version 6 (`spectrace_plugin_extensions_v6`): a material says whether it samples directions
//! with the cosine-weighted density
//! ([`Material::cosine_weighted_pdf`](crate::Material::cosine_weighted_pdf): `|cos θi|/π` on
//! `wo`'s side, 0 on the other), so the host computes the density itself instead of calling
//! `pdf` (checked when the material is built); its emission comes through the host's layout
//! ([`AbiMaterialEmittedV6`]); and lights get a face in the host's layout ([`AbiLightV6`]:
//! `sample_toward`, `sample_emission` and `emission_pdf` with [`ReceiverF32`], [`IncidentF32`]
//! and [`EmissionF32`] by reference, results written through a reference, no `f64`). The
//! material calls of v5 stay as they are (already in the host's layout) and travel in
//! [`MaterialWithV6`]. A library older than v6 is served through v5 (its density asked for, its
//! lights through the `f64` calls: always safe).
//!
//! Version 7 (`spectrace_plugin_extensions_v7`): an observer says that its colour-matching
//! functions are a table on a 1 nm grid, interpolated linearly
//! ([`ColorObserver::declared_table`](crate::ColorObserver::declared_table)), and hands the
//! table over once when it is built ([`ObserverWithTable`]); the host checks the claim then
//! and evaluates its own copy (bidirectional and light tracing weigh every path's wavelengths
//! with the observer: four calls per sample). A library older than v7 is served through the
//! root module (`xyz_bar` called per wavelength: always safe). Its material face
//! ([`AbiMaterialV7`], carried in [`MaterialWithV7`] beside everything of v6) takes the
//! wavelengths by reference too ([`QueryV7`]: the host's own record) and answers with a status
//! word ([`status`](crate::fast::status)), the error written through a reference only when
//! there is one, instead of an `RResult` moved back on every call. A library older than v7 is
//! served through v6.
//!
//! Version 8 (`spectrace_plugin_extensions_v8`): a material face whose calls take their
//! arguments as the host's own calls do ([`AbiMaterialV8`]: the directions and the surface and
//! wavelength records by reference, the uniforms and transport mode by value, in registers),
//! with no error slot: a failed call answers `ERROR` (`sample`) or NaN (`eval`, `pdf`) and keeps
//! its error on its thread until the host takes it ([`ExtensionsV8::take_error`]), so the calls
//! that succeed carry nothing for it. Carried in [`MaterialWithV8`] beside everything of v7. A
//! library older than v8 is served through v7.
//!
//! [`export_plugin!`](crate::export_plugin) exports every version for every plugin.
//!
//! [`LightSource::scene_bounds`]: crate::LightSource::scene_bounds
//! [`LightSource::emission_spectrum`]: crate::LightSource::emission_spectrum

// `#[sabi_trait]` generates a vtable function per method taking the object too, outside the
// method's own `#[allow]`: extension v8's `sample` passes its eight arguments in registers.
#![allow(clippy::too_many_arguments)]

use crate::error::PluginError;
use crate::fast::{
    EmissionF32, IncidentF32, LanesF32, MaterialQuery, QueryV5, QueryV7, ReceiverF32, ScatterF32,
    SurfaceF32, ValuesF32, Vec4f, WavelengthsF32,
};
use crate::guard::guarded;
use crate::host::HostRef;
use crate::light::LightBox;
use crate::material::{MaterialBox, ScatterSample, SurfaceContext};
use crate::module::ObjectSource;
use crate::observer::{ObserverBox, ObserverTable};
use crate::representation::{BeamRepresentation, RepresentedBeam, TypeRepresentation};
use crate::reradiation::ReradiationBox;
use crate::spd::{GuardedSpd, Spd, SpdBox, SpectralLine};
use crate::types::{
    RandomSample, SceneBounds, SpectralValues, TransportMode, Vec3, Wavelengths, LANES,
};
use crate::PluginResult;
use abi_stable::{
    sabi_trait,
    std_types::{RBox, ROption, RResult, RStr, RVec},
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

// ----------------------------------------------------------------------------------------------
// Version 2

/// The symbol (NUL-terminated) of extension version 2: an `extern "C" fn() ->`
/// [`ExtensionsV2Export`].
pub const EXTENSIONS_V2_SYMBOL: &[u8] = b"spectrace_plugin_extensions_v2\0";

/// An SPD with its spectral lines (extension version 2).
#[repr(C)]
#[derive(StableAbi)]
pub struct SpdWithLines {
    /// The SPD.
    pub spd: SpdBox,
    /// Its lines ([`Spd::delta_lines`]), read once when it was built.
    pub lines: RVec<SpectralLine>,
}

impl SpdWithLines {
    /// Box `spd` behind the ABI with its lines; `state` serialises it for blobs.
    pub fn new<T: Spd>(
        spd: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<Self, PluginError> {
        let lines = match guarded("delta_lines", || Ok(spd.delta_lines())) {
            RResult::ROk(l) => l,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(Self {
            spd: GuardedSpd::boxed(spd, state),
            lines: lines.into(),
        })
    }
}

/// How an emissive material emits (extension version 2): radiance `scale · spd(λ)`
/// W/(m²·sr·nm), the same at every point of a side and in every direction (Lambertian).
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialEmission {
    /// Normalised SPD (1/nm), with its lines.
    pub spectrum: SpdWithLines,
    /// Integrated radiance, W/(m²·sr).
    pub scale: f64,
    /// Whether the back side emits as well.
    pub two_sided: bool,
}

/// The calls version 2 adds to a light (see [`crate::LightSource`] for their meaning).
#[sabi_trait]
pub trait AbiLightV2: Send + Sync {
    /// See [`crate::LightSource::scene_bounds`]; the host calls it once, before rendering.
    fn scene_bounds(&self, bounds: &SceneBounds) -> RResult<(), PluginError>;
    /// See [`crate::LightSource::emission_spectrum`].
    #[sabi(last_prefix_field)]
    fn emission_spectrum(&self) -> RResult<ROption<SpdWithLines>, PluginError>;
}

/// The version-2 face of a light, owned.
pub type LightV2Box = AbiLightV2_TO<'static, RBox<()>>;

/// The calls version 2 adds to a material: the four calls of [`AbiMaterial`] with the surface's
/// normals (see [`crate::Material`]'s `*_at` calls), and its emission.
///
/// [`AbiMaterial`]: crate::material::AbiMaterial
#[sabi_trait]
pub trait AbiMaterialV2: Send + Sync {
    /// See [`crate::Material::sample_at`].
    fn sample(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        lambda: &Wavelengths,
        u: &RandomSample,
        mode: TransportMode,
    ) -> RResult<ROption<ScatterSample>, PluginError>;
    /// See [`crate::Material::eval_at`].
    fn eval(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<SpectralValues, PluginError>;
    /// See [`crate::Material::pdf_at`].
    fn pdf(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<f64, PluginError>;
    /// See [`crate::Material::emitted_at`].
    fn emitted(
        &self,
        ctx: &SurfaceContext,
        wo: Vec3,
        lambda: &Wavelengths,
    ) -> RResult<SpectralValues, PluginError>;
    /// See [`crate::Material::emission`].
    #[sabi(last_prefix_field)]
    fn emission(&self) -> RResult<ROption<MaterialEmission>, PluginError>;
}

/// The version-2 face of a material, owned.
pub type MaterialV2Box = AbiMaterialV2_TO<'static, RBox<()>>;

/// A light built through version 2: the root module's face and the v2 face of one object.
#[repr(C)]
#[derive(StableAbi)]
pub struct LightWithV2 {
    /// What the root module's `create_light` returns.
    pub light: LightBox,
    /// The calls added in version 2, on the same object.
    pub v2: LightV2Box,
}

/// A material built through version 2: the root module's face and the v2 face of one object.
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialWithV2 {
    /// What the root module's `create_material` returns.
    pub material: MaterialBox,
    /// The calls added in version 2, on the same object.
    pub v2: MaterialV2Box,
}

/// Extension version 2: the constructors of the root module, returning both faces. Parameters
/// and saved state as for the root module's.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = ExtensionsV2Ref)))]
#[sabi(missing_field(panic))]
pub struct ExtensionsV2 {
    /// Build a light.
    pub create_light: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<LightWithV2, PluginError>,
    /// Build a material.
    pub create_material: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<MaterialWithV2, PluginError>,
    /// Build an SPD, with its lines.
    #[sabi(last_prefix_field)]
    pub create_spd: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<SpdWithLines, PluginError>,
}

/// What the version-2 symbol returns: the module's layout (checked by the host against its own
/// before the module is touched) and the module.
#[repr(C)]
#[derive(StableAbi, Clone, Copy)]
pub struct ExtensionsV2Export {
    /// `<ExtensionsV2Ref as StableAbi>::LAYOUT` as the plugin was compiled.
    pub layout: &'static TypeLayout,
    /// The module.
    pub module: ExtensionsV2Ref,
}

// ----------------------------------------------------------------------------------------------
// Version 3

/// The symbol (NUL-terminated) of extension version 3: an `extern "C" fn() ->`
/// [`ExtensionsV3Export`].
pub const EXTENSIONS_V3_SYMBOL: &[u8] = b"spectrace_plugin_extensions_v3\0";

/// A material built through version 3: the faces of versions 1 and 2, and for a `FLUORESCENT`
/// material that offers one ([`Material::reradiation`](crate::Material::reradiation)) its
/// wavelength-shifting face. All three share one object.
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialWithV3 {
    /// What the root module's `create_material` returns.
    pub material: MaterialBox,
    /// The calls added in version 2, on the same object.
    pub v2: MaterialV2Box,
    /// The re-radiation added in version 3; none for a material that does not fluoresce.
    pub reradiation: ROption<ReradiationBox>,
}

/// Extension version 3: fluorescence through the plugin API. A material constructor that also
/// returns the re-radiation face ([`crate::reradiation`]). Parameters and saved state as for
/// the root module's.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = ExtensionsV3Ref)))]
#[sabi(missing_field(panic))]
pub struct ExtensionsV3 {
    /// Build a material with its version-2 and version-3 faces.
    #[sabi(last_prefix_field)]
    pub create_material: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<MaterialWithV3, PluginError>,
}

/// What the version-3 symbol returns: the module's layout (checked by the host against its own
/// before the module is touched) and the module.
#[repr(C)]
#[derive(StableAbi, Clone, Copy)]
pub struct ExtensionsV3Export {
    /// `<ExtensionsV3Ref as StableAbi>::LAYOUT` as the plugin was compiled.
    pub layout: &'static TypeLayout,
    /// The module.
    pub module: ExtensionsV3Ref,
}

// ----------------------------------------------------------------------------------------------
// Version 4

/// The symbol (NUL-terminated) of extension version 4: an `extern "C" fn() ->`
/// [`ExtensionsV4Export`].
pub const EXTENSIONS_V4_SYMBOL: &[u8] = b"spectrace_plugin_extensions_v4\0";

/// The calls version 4 adds to a material: `sample`, `eval` and `pdf` with one argument, a
/// [`MaterialQuery`] by reference, in the host's own single-precision layout (see
/// [`crate::fast`]). The same object and meaning as the v2 calls; a host that has v4 calls these
/// instead. A panic is caught on the plugin's side as for every call.
#[sabi_trait]
pub trait AbiMaterialV4: Send + Sync {
    /// See [`crate::Material::sample_v4`].
    fn sample(&self, q: &MaterialQuery) -> RResult<ROption<ScatterF32>, PluginError>;
    /// See [`crate::Material::eval_v4`]: the BSDF value per lane (1/sr).
    fn eval(&self, q: &MaterialQuery) -> RResult<[f32; LANES], PluginError>;
    /// See [`crate::Material::pdf_v4`] (1/sr).
    #[sabi(last_prefix_field)]
    fn pdf(&self, q: &MaterialQuery) -> RResult<f32, PluginError>;
}

/// The version-4 face of a material, owned.
pub type MaterialV4Box = AbiMaterialV4_TO<'static, RBox<()>>;

/// A material built through version 4: the faces of versions 1–3, the v4 calls, and what the
/// material declares about its spectrum. All faces share one object.
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialWithV4 {
    /// What the root module's `create_material` returns.
    pub material: MaterialBox,
    /// The calls added in version 2, on the same object.
    pub v2: MaterialV2Box,
    /// The re-radiation added in version 3; none for a material that does not fluoresce.
    pub reradiation: ROption<ReradiationBox>,
    /// The calls added in version 4, on the same object.
    pub v4: MaterialV4Box,
    /// [`Material::spectrally_flat`](crate::Material::spectrally_flat), read once when the
    /// material was built.
    pub spectrally_flat: bool,
}

/// A light built through version 4: the faces of versions 1 and 2 and what the light declares
/// about its spectrum.
#[repr(C)]
#[derive(StableAbi)]
pub struct LightWithV4 {
    /// What the root module's `create_light` returns.
    pub light: LightBox,
    /// The calls added in version 2, on the same object.
    pub v2: LightV2Box,
    /// [`LightSource::uniform_spectral_shape`](crate::LightSource::uniform_spectral_shape),
    /// read once when the light was built.
    pub uniform_spectral_shape: bool,
}

/// Extension version 4: spectral declarations (a material is spectrally flat, a light has one
/// spectral shape everywhere) and the material calls in the host's layout. Constructors as the
/// root module's, returning every face.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = ExtensionsV4Ref)))]
#[sabi(missing_field(panic))]
pub struct ExtensionsV4 {
    /// Build a light with its version-2 face and its declaration.
    pub create_light: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<LightWithV4, PluginError>,
    /// Build a material with its faces of versions 2–4 and its declaration.
    #[sabi(last_prefix_field)]
    pub create_material: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<MaterialWithV4, PluginError>,
}

/// What the version-4 symbol returns: the module's layout (checked by the host against its own
/// before the module is touched) and the module.
#[repr(C)]
#[derive(StableAbi, Clone, Copy)]
pub struct ExtensionsV4Export {
    /// `<ExtensionsV4Ref as StableAbi>::LAYOUT` as the plugin was compiled.
    pub layout: &'static TypeLayout,
    /// The module.
    pub module: ExtensionsV4Ref,
}

// ----------------------------------------------------------------------------------------------
// Version 5

/// The symbol (NUL-terminated) of extension version 5: an `extern "C" fn() ->`
/// [`ExtensionsV5Export`].
pub const EXTENSIONS_V5_SYMBOL: &[u8] = b"spectrace_plugin_extensions_v5\0";

/// The material calls of version 5: those of [`AbiMaterialV4`] with the surface by reference
/// ([`QueryV5`], pointing at the host's own record of it) and the result written through `out`
/// instead of returned: `sample` answers whether it scattered (`false`: absorbed, `out`
/// untouched), `eval` writes the BSDF value per lane (1/sr), `pdf` the density (1/sr). An error,
/// or a panic caught on the plugin's side, comes back as `RErr` and `out` is not to be read.
#[sabi_trait]
pub trait AbiMaterialV5: Send + Sync {
    /// See [`crate::Material::sample_v5`].
    fn sample(&self, q: &QueryV5<'_>, out: &mut ScatterF32) -> RResult<bool, PluginError>;
    /// See [`crate::Material::eval_v5`].
    fn eval(&self, q: &QueryV5<'_>, out: &mut [f32; LANES]) -> RResult<(), PluginError>;
    /// See [`crate::Material::pdf_v5`].
    #[sabi(last_prefix_field)]
    fn pdf(&self, q: &QueryV5<'_>, out: &mut f32) -> RResult<(), PluginError>;
}

/// The version-5 face of a material, owned.
pub type MaterialV5Box = AbiMaterialV5_TO<'static, RBox<()>>;

/// A material built through version 5: the faces of versions 1–3, the v5 calls, and what the
/// material declares. All faces share one object.
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialWithV5 {
    /// What the root module's `create_material` returns.
    pub material: MaterialBox,
    /// The calls added in version 2, on the same object.
    pub v2: MaterialV2Box,
    /// The re-radiation added in version 3; none for a material that does not fluoresce.
    pub reradiation: ROption<ReradiationBox>,
    /// The calls of version 5, on the same object.
    pub v5: MaterialV5Box,
    /// [`Material::spectrally_flat`](crate::Material::spectrally_flat), read once when the
    /// material was built.
    pub spectrally_flat: bool,
    /// [`Material::f_same_for_all_directions`](crate::Material::f_same_for_all_directions),
    /// read once when the material was built.
    pub f_same_for_all_directions: bool,
}

/// Extension version 5: a material constructor returning the v5 face and declarations.
/// Parameters and saved state as for the root module's.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = ExtensionsV5Ref)))]
#[sabi(missing_field(panic))]
pub struct ExtensionsV5 {
    /// Build a material with its faces and declarations.
    #[sabi(last_prefix_field)]
    pub create_material: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<MaterialWithV5, PluginError>,
}

/// What the version-5 symbol returns: the module's layout (checked by the host against its own
/// before the module is touched) and the module.
#[repr(C)]
#[derive(StableAbi, Clone, Copy)]
pub struct ExtensionsV5Export {
    /// `<ExtensionsV5Ref as StableAbi>::LAYOUT` as the plugin was compiled.
    pub layout: &'static TypeLayout,
    /// The module.
    pub module: ExtensionsV5Ref,
}

// ----------------------------------------------------------------------------------------------
// Version 6

/// The symbol (NUL-terminated) of extension version 6: an `extern "C" fn() ->`
/// [`ExtensionsV6Export`].
pub const EXTENSIONS_V6_SYMBOL: &[u8] = b"spectrace_plugin_extensions_v6\0";

/// A material's emission in the host's layout (extension v6): writes the radiance towards
/// `q.wo` per lane (W/(m²·sr·nm)) through `out`. An error, or a panic caught on the plugin's
/// side, comes back as `RErr` and `out` is not to be read.
#[sabi_trait]
pub trait AbiMaterialEmittedV6: Send + Sync {
    /// See [`crate::Material::emitted_v6`].
    #[sabi(last_prefix_field)]
    fn emitted(&self, q: &QueryV5<'_>, out: &mut [f32; LANES]) -> RResult<(), PluginError>;
}

/// The version-6 emission face of a material, owned.
pub type MaterialEmittedV6Box = AbiMaterialEmittedV6_TO<'static, RBox<()>>;

/// A material built through version 6: the faces of versions 1–3, the v5 calls, its emission
/// in the host's layout, and what the material declares. All faces share one object.
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialWithV6 {
    /// What the root module's `create_material` returns.
    pub material: MaterialBox,
    /// The calls added in version 2, on the same object.
    pub v2: MaterialV2Box,
    /// The re-radiation added in version 3; none for a material that does not fluoresce.
    pub reradiation: ROption<ReradiationBox>,
    /// The calls of version 5 (sample, eval, pdf), on the same object.
    pub v5: MaterialV5Box,
    /// The emission of version 6, on the same object.
    pub emitted: MaterialEmittedV6Box,
    /// [`Material::spectrally_flat`](crate::Material::spectrally_flat), read once.
    pub spectrally_flat: bool,
    /// [`Material::f_same_for_all_directions`](crate::Material::f_same_for_all_directions),
    /// read once.
    pub f_same_for_all_directions: bool,
    /// [`Material::cosine_weighted_pdf`](crate::Material::cosine_weighted_pdf), read once.
    pub cosine_weighted_pdf: bool,
}

/// The light calls of version 6: those of the root module that the renderer makes per sample,
/// in the host's single-precision layout, by reference, the result written through `out`
/// (`sample_toward` and `sample_emission` answer whether they wrote one; a density of 0 in it
/// also means no sample). An error, or a panic caught on the plugin's side, comes back as `RErr`
/// and `out` is not to be read.
#[sabi_trait]
pub trait AbiLightV6: Send + Sync {
    /// See [`crate::LightSource::sample_toward_v6`].
    fn sample_toward(
        &self,
        receiver: &ReceiverF32,
        u: &[f32; 2],
        lambda: &LanesF32,
        out: &mut IncidentF32,
    ) -> RResult<bool, PluginError>;
    /// See [`crate::LightSource::sample_emission_v6`].
    fn sample_emission(
        &self,
        u: &[f32; 4],
        lambda: &LanesF32,
        out: &mut EmissionF32,
    ) -> RResult<bool, PluginError>;
    /// See [`crate::LightSource::emission_pdf_v6`]: writes the densities of position (1/m²) and
    /// direction (1/sr).
    #[sabi(last_prefix_field)]
    fn emission_pdf(
        &self,
        origin: &Vec4f,
        direction: &Vec4f,
        out: &mut [f32; 2],
    ) -> RResult<(), PluginError>;
}

/// The version-6 face of a light, owned.
pub type LightV6Box = AbiLightV6_TO<'static, RBox<()>>;

/// A light built through version 6: the faces of versions 1, 2 and 6 and what the light
/// declares about its spectrum. All faces share one object.
#[repr(C)]
#[derive(StableAbi)]
pub struct LightWithV6 {
    /// What the root module's `create_light` returns.
    pub light: LightBox,
    /// The calls added in version 2, on the same object.
    pub v2: LightV2Box,
    /// The calls of version 6, on the same object.
    pub v6: LightV6Box,
    /// [`LightSource::uniform_spectral_shape`](crate::LightSource::uniform_spectral_shape),
    /// read once when the light was built.
    pub uniform_spectral_shape: bool,
}

/// Extension version 6: constructors returning the v6 faces and declarations. Parameters and
/// saved state as for the root module's.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = ExtensionsV6Ref)))]
#[sabi(missing_field(panic))]
pub struct ExtensionsV6 {
    /// Build a light with its faces and declaration.
    pub create_light: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<LightWithV6, PluginError>,
    /// Build a material with its faces and declarations.
    #[sabi(last_prefix_field)]
    pub create_material: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<MaterialWithV6, PluginError>,
}

/// What the version-6 symbol returns: the module's layout (checked by the host against its own
/// before the module is touched) and the module.
#[repr(C)]
#[derive(StableAbi, Clone, Copy)]
pub struct ExtensionsV6Export {
    /// `<ExtensionsV6Ref as StableAbi>::LAYOUT` as the plugin was compiled.
    pub layout: &'static TypeLayout,
    /// The module.
    pub module: ExtensionsV6Ref,
}

// ----------------------------------------------------------------------------------------------
// Version 7

/// The symbol (NUL-terminated) of extension version 7: an `extern "C" fn() ->`
/// [`ExtensionsV7Export`].
pub const EXTENSIONS_V7_SYMBOL: &[u8] = b"spectrace_plugin_extensions_v7\0";

/// An observer built through version 7: the root module's object and, when the observer
/// declares one, its table ([`ColorObserver::declared_table`](crate::ColorObserver::declared_table)),
/// read once when it was built.
#[repr(C)]
#[derive(StableAbi)]
pub struct ObserverWithTable {
    /// What the root module's `create_observer` returns.
    pub observer: ObserverBox,
    /// The declared 1 nm table; none when the observer declares none.
    pub table: ROption<ObserverTable>,
}

/// The material calls of version 7: those of [`AbiMaterialV5`] with the wavelengths by
/// reference ([`QueryV7`]) and a status word for an answer
/// ([`status`](crate::fast::status)): `NONE` (`sample` only: absorbed, `out` untouched),
/// `WRITTEN` (the result is in `out`) or `ERROR` (an error, or a panic caught on the plugin's
/// side, written through `err`; `out` is not to be read). `eval` writes the BSDF value per lane
/// (1/sr), `pdf` the density (1/sr).
#[sabi_trait]
pub trait AbiMaterialV7: Send + Sync {
    /// See [`crate::Material::sample_v7`].
    fn sample(&self, q: &QueryV7<'_>, out: &mut ScatterF32, err: &mut ROption<PluginError>) -> u32;
    /// See [`crate::Material::eval_v7`].
    fn eval(&self, q: &QueryV7<'_>, out: &mut [f32; LANES], err: &mut ROption<PluginError>) -> u32;
    /// See [`crate::Material::pdf_v7`].
    #[sabi(last_prefix_field)]
    fn pdf(&self, q: &QueryV7<'_>, out: &mut f32, err: &mut ROption<PluginError>) -> u32;
}

/// The version-7 face of a material, owned.
pub type MaterialV7Box = AbiMaterialV7_TO<'static, RBox<()>>;

/// A material built through version 7: everything of version 6 and the v7 calls, on the same
/// object.
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialWithV7 {
    /// The faces and declarations of version 6.
    pub with_v6: MaterialWithV6,
    /// The calls of version 7 (sample, eval, pdf), on the same object.
    pub v7: MaterialV7Box,
}

/// Extension version 7: an observer constructor returning its declared table, and a material
/// constructor returning the v7 face. Parameters and saved state as for the root module's.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = ExtensionsV7Ref)))]
#[sabi(missing_field(panic))]
pub struct ExtensionsV7 {
    /// Build an observer with its declared table.
    pub create_observer: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<ObserverWithTable, PluginError>,
    /// Build a material with its faces and declarations.
    #[sabi(last_prefix_field)]
    pub create_material: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<MaterialWithV7, PluginError>,
}

/// What the version-7 symbol returns: the module's layout (checked by the host against its own
/// before the module is touched) and the module.
#[repr(C)]
#[derive(StableAbi, Clone, Copy)]
pub struct ExtensionsV7Export {
    /// `<ExtensionsV7Ref as StableAbi>::LAYOUT` as the plugin was compiled.
    pub layout: &'static TypeLayout,
    /// The module.
    pub module: ExtensionsV7Ref,
}

// ----------------------------------------------------------------------------------------------
// Version 8

/// The symbol (NUL-terminated) of extension version 8: an `extern "C" fn() ->`
/// [`ExtensionsV8Export`].
pub const EXTENSIONS_V8_SYMBOL: &[u8] = b"spectrace_plugin_extensions_v8\0";

/// The material calls of version 8: those of [`AbiMaterialV7`] with their arguments as the
/// host's own material calls take them, so that neither side builds or reads a query record:
/// `wo` and `wi` (local frame) and the surface and wavelength records by reference, each the
/// host's own memory (the vectors' `w` lanes unspecified: read `x, y, z` only), the uniforms
/// and the transport mode by value. No error slot: a call that fails (an error, or a panic
/// caught on the plugin's side) keeps its error on the calling thread and says so in its
/// answer, and the host then takes the error with [`ExtensionsV8::take_error`] on the same
/// thread.
///
/// `sample` answers a status word ([`status`](crate::fast::status)): `NONE` (absorbed, `out`
/// untouched), `WRITTEN` (the sample is in `out`) or `ERROR` (`out` is not to be read). `eval`
/// answers the BSDF value per lane (1/sr) and `pdf` the density (1/sr) by value: NaN (in every
/// lane) when the call failed, which the host refuses as a value unless it finds the error.
#[sabi_trait]
pub trait AbiMaterialV8: Send + Sync {
    /// See [`crate::Material::sample_v8`].
    #[allow(clippy::too_many_arguments)]
    fn sample(
        &self,
        wo: &Vec4f,
        ctx: &SurfaceF32,
        lambda: &WavelengthsF32,
        u_lobe: f32,
        u1: f32,
        u2: f32,
        mode: TransportMode,
        out: &mut ScatterF32,
    ) -> u32;
    /// See [`crate::Material::eval_v8`].
    fn eval(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        ctx: &SurfaceF32,
        lambda: &WavelengthsF32,
        mode: TransportMode,
    ) -> ValuesF32;
    /// See [`crate::Material::pdf_v8`].
    #[sabi(last_prefix_field)]
    fn pdf(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        ctx: &SurfaceF32,
        lambda: &WavelengthsF32,
        mode: TransportMode,
    ) -> f32;
}

/// The version-8 face of a material, owned.
pub type MaterialV8Box = AbiMaterialV8_TO<'static, RBox<()>>;

/// A material built through version 8: everything of version 7 and the v8 calls, on the same
/// object.
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialWithV8 {
    /// The faces and declarations of version 7.
    pub with_v7: MaterialWithV7,
    /// The calls of version 8 (sample, eval, pdf), on the same object.
    pub v8: MaterialV8Box,
}

/// Extension version 8: a material constructor returning the v8 face, and where the errors of
/// that face's failed calls are taken. Parameters and saved state as for the root module's.
#[repr(C)]
#[derive(StableAbi)]
#[sabi(kind(Prefix(prefix_ref = ExtensionsV8Ref)))]
#[sabi(missing_field(panic))]
pub struct ExtensionsV8 {
    /// Build a material with its faces and declarations.
    pub create_material: extern "C" fn(
        type_name: RStr<'_>,
        source: ObjectSource<'_>,
        host: HostRef<'_>,
    ) -> RResult<MaterialWithV8, PluginError>,
    /// The error of the last v8 call on the calling thread that failed, taken (none when it
    /// was taken already, or no call failed).
    #[sabi(last_prefix_field)]
    pub take_error: extern "C" fn() -> ROption<PluginError>,
}

/// What the version-8 symbol returns: the module's layout (checked by the host against its own
/// before the module is touched) and the module.
#[repr(C)]
#[derive(StableAbi, Clone, Copy)]
pub struct ExtensionsV8Export {
    /// `<ExtensionsV8Ref as StableAbi>::LAYOUT` as the plugin was compiled.
    pub layout: &'static TypeLayout,
    /// The module.
    pub module: ExtensionsV8Ref,
}
