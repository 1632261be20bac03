//! Materials (seed §6): turn an incoming beam into an outgoing one. Directions are in the local
//! shading frame: z is the shading normal, and both `wo` and `wi` point away from the surface.

use crate::error::{PluginError, PluginResult};
use crate::guard::guarded;
use crate::types::{Flags, RandomSample, SpectralValues, TransportMode, Vec3, Wavelengths};
use abi_stable::{
    sabi_trait,
    std_types::{RBox, RResult, RVec},
    StableAbi,
};

/// Capability bits of a material (and of one scattering event).
pub mod material_flags {
    use crate::types::Flags;
    /// Scatters diffusely.
    pub const DIFFUSE: Flags = Flags(1);
    /// Has glossy lobes.
    pub const GLOSSY: Flags = Flags(2);
    /// Has delta lobes (mirror, smooth glass): `eval` and `pdf` are 0 for them.
    pub const SPECULAR: Flags = Flags(4);
    /// Transmits light.
    pub const TRANSMISSION: Flags = Flags(8);
    /// Scattering direction depends on wavelength: the host keeps only the hero wavelength.
    pub const DISPERSIVE: Flags = Flags(16);
    /// Emits light (`emitted` is meaningful).
    pub const EMISSIVE: Flags = Flags(32);
    /// Shifts wavelength (fluorescence); not yet simulated by the host, which says so.
    pub const FLUORESCENT: Flags = Flags(64);
}

/// Where on the surface a material is evaluated.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadingContext {
    /// Surface parameterisation (texture coordinates).
    pub uv: [f64; 2],
    /// World-space position (scene units), for procedural materials.
    pub position: Vec3,
}

/// A sampled scattering direction.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct ScatterSample {
    /// Incident direction (local frame, away from the surface).
    pub wi: Vec3,
    /// BSDF value per lane (1/sr), or for delta lobes the value that a pdf of `pdf` turns into
    /// the right weight.
    pub value: SpectralValues,
    /// Solid-angle density of `wi` (1/sr); for delta lobes the discrete lobe probability.
    pub pdf: f64,
    /// Bits of this event ([`material_flags`]): SPECULAR, TRANSMISSION, DISPERSIVE …
    pub flags: Flags,
    /// Relative index of refraction across the surface for transmission, else 1.
    pub eta: f64,
}

/// What a plugin author implements for a material.
pub trait Material: Send + Sync + 'static {
    /// Capability bits ([`material_flags`]).
    fn capabilities(&self) -> Flags;
    /// Sample `wi` given `wo` (uses `u.u[0]` to choose a lobe, `u.u[1..3]` for the direction).
    /// `Ok(None)` when the sample is absorbed.
    fn sample(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
        u: &RandomSample,
        mode: TransportMode,
    ) -> PluginResult<Option<ScatterSample>>;
    /// BSDF value for the pair (1/sr), 0 for delta lobes.
    fn eval(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> PluginResult<SpectralValues>;
    /// Density with which `sample` would produce `wi` (1/sr).
    fn pdf(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> PluginResult<f64>;
    /// Emitted radiance towards `wo`, W/(m²·sr·nm); only for EMISSIVE materials.
    fn emitted(
        &self,
        _ctx: &ShadingContext,
        _wo: Vec3,
        _lambda: &Wavelengths,
    ) -> PluginResult<SpectralValues> {
        Ok(SpectralValues::ZERO)
    }
}

/// The stable-ABI face of a material.
#[sabi_trait]
pub trait AbiMaterial: Send + Sync {
    /// See [`Material::capabilities`].
    fn capabilities(&self) -> Flags;
    /// See [`Material::sample`].
    fn sample(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
        u: &RandomSample,
        mode: TransportMode,
    ) -> RResult<abi_stable::std_types::ROption<ScatterSample>, PluginError>;
    /// See [`Material::eval`].
    fn eval(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<SpectralValues, PluginError>;
    /// See [`Material::pdf`].
    fn pdf(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<f64, PluginError>;
    /// See [`Material::emitted`].
    fn emitted(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
    ) -> RResult<SpectralValues, PluginError>;
    /// The object's state as bytes, for blobs.
    #[sabi(last_prefix_field)]
    fn save_state(&self) -> RResult<RVec<u8>, PluginError>;
}

/// A material behind the stable ABI, owned.
pub type MaterialBox = AbiMaterial_TO<'static, RBox<()>>;

/// Wraps an author's material so panics come back as errors.
pub struct GuardedMaterial<T> {
    inner: T,
    state: fn(&T) -> PluginResult<Vec<u8>>,
}

impl<T: Material> GuardedMaterial<T> {
    /// Box `inner` behind the ABI.
    pub fn boxed(inner: T, state: fn(&T) -> PluginResult<Vec<u8>>) -> MaterialBox {
        AbiMaterial_TO::from_value(Self { inner, state }, abi_stable::sabi_trait::TD_Opaque)
    }
}

impl<T: Material> AbiMaterial for GuardedMaterial<T> {
    fn capabilities(&self) -> Flags {
        guarded("capabilities", || Ok(self.inner.capabilities())).unwrap_or(Flags::NONE)
    }
    fn sample(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
        u: &RandomSample,
        mode: TransportMode,
    ) -> RResult<abi_stable::std_types::ROption<ScatterSample>, PluginError> {
        guarded("sample", || {
            self.inner.sample(ctx, wo, lambda, u, mode).map(Into::into)
        })
    }
    fn eval(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<SpectralValues, PluginError> {
        guarded("eval", || self.inner.eval(ctx, wo, wi, lambda, mode))
    }
    fn pdf(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        wi: Vec3,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> RResult<f64, PluginError> {
        guarded("pdf", || self.inner.pdf(ctx, wo, wi, lambda, mode))
    }
    fn emitted(
        &self,
        ctx: &ShadingContext,
        wo: Vec3,
        lambda: &Wavelengths,
    ) -> RResult<SpectralValues, PluginError> {
        guarded("emitted", || self.inner.emitted(ctx, wo, lambda))
    }
    fn save_state(&self) -> RResult<RVec<u8>, PluginError> {
        guarded("save_state", || (self.state)(&self.inner).map(RVec::from))
    }
}
