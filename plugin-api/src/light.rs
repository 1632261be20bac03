//! Light sources: the seed's two calls, plus what a bidirectional path tracer needs to connect.
//!
//! A plugin author implements [`LightSource`]. The host sees it as a [`LightBox`], the stable-ABI
//! trait object, through a guard that catches panics and counts beams for `number_of_beams`.

use crate::error::{PluginError, PluginResult};
use crate::export::PluginType;
use crate::extension::{
    AbiLightV2, AbiLightV6, LightWithV2, LightWithV4, LightWithV6, SpdWithLines,
};
use crate::fast::{EmissionF32, IncidentF32, LanesF32, ReceiverF32, Vec4f};
use crate::guard::{guarded, guarded_call_v5};
use crate::representation::{BeamRepresentation, RepresentedBeam};
use crate::spd::Spd;
use crate::types::{Beam, Flags, RandomSample, SceneBounds, SpectralValues, Vec3, Wavelengths};
use abi_stable::{
    sabi_trait,
    std_types::{RBox, ROption, RResult, RVec},
    StableAbi,
};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// Capability bits of a light source.
pub mod light_flags {
    use crate::types::Flags;
    /// Emits from a single point (point and spot lights): position pdfs are discrete.
    pub const DELTA_POSITION: Flags = Flags(1);
    /// Emits in a single direction (directional lights): direction pdfs are discrete.
    pub const DELTA_DIRECTION: Flags = Flags(2);
    /// Implements `sample_emission`, `emission_pdf` and `sample_toward`, so paths can be
    /// connected to it. Without it the host can only trace the beams it hands out.
    pub const CONNECTABLE: Flags = Flags(4);
    /// Rays that leave the scene see it (`radiance` and `incident_pdf` are meaningful).
    pub const ENVIRONMENT: Flags = Flags(8);
}

/// A position and direction drawn from the light's emission, for light subpaths.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct EmissionSample {
    /// Start point (scene units).
    pub origin: Vec3,
    /// Unit direction of travel.
    pub direction: Vec3,
    /// Surface normal at `origin`; zero for lights without a surface.
    pub normal: Vec3,
    /// Emitted value per lane: intensity W/(sr·nm) for point-like sources, radiance
    /// W/(m²·sr·nm) for surfaces.
    pub value: SpectralValues,
    /// Density of `origin`: per area (1/m²), or 1 for a delta position.
    pub pdf_position: f64,
    /// Density of `direction`: per solid angle (1/sr), or 1 for a delta direction.
    pub pdf_direction: f64,
}

/// The densities with which [`LightSource::sample_emission`] would produce a given beam.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct EmissionPdf {
    /// Per area, or 1 for a delta position.
    pub position: f64,
    /// Per solid angle, or 1 for a delta direction.
    pub direction: f64,
}

/// A point on the light chosen as seen from a receiver, for next-event estimation and
/// camera-to-light connections.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct IncidentSample {
    /// Point on the light (or far along `direction` for directional lights).
    pub point: Vec3,
    /// Light surface normal at `point`; zero when the light has no surface.
    pub normal: Vec3,
    /// Unit direction from the receiver towards the light.
    pub direction: Vec3,
    /// Distance from receiver to `point` (scene units); infinite for directional lights.
    pub distance: f64,
    /// Radiance arriving at the receiver per lane, W/(m²·sr·nm); for delta lights the
    /// irradiance-like value I/d² that a pdf of 1 turns into the right estimate.
    pub value: SpectralValues,
    /// Solid-angle density of `direction` (1/sr), or 1 for delta lights.
    pub pdf: f64,
}

/// A wavelength drawn from a light's spectrum.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct WavelengthSample {
    /// Wavelength, nm.
    pub nm: f64,
    /// Density, 1/nm (or a probability for a spectral line).
    pub pdf: f64,
}

/// What a plugin author implements for a light source.
///
/// Only [`next_beam`](Self::next_beam) and [`total_power_w`](Self::total_power_w) are required:
/// with them any light renders (the host traces its beams). The rest is the optional
/// `CONNECTABLE` capability, declared through [`capabilities`](Self::capabilities).
pub trait LightSource: Send + Sync + 'static {
    /// The seed's `getNextBeam`. Uses `sample.u[0..5]` at most: position (2), direction (2),
    /// wavelength (1); `u[5..8]` belong to the host. Must be a pure function of `sample`.
    fn next_beam(&self, sample: &RandomSample) -> PluginResult<Beam>;
    /// `next_beam` in the type's declared
    /// [`BEAM_REPRESENTATION`](crate::PluginType::BEAM_REPRESENTATION); same random numbers
    /// (`u[0..5]`). Only called for non-native representations, and then `next_beam` never is.
    fn next_represented_beam(&self, _sample: &RandomSample) -> PluginResult<RepresentedBeam> {
        Err(PluginError::unsupported("next_represented_beam"))
    }
    /// Total radiant flux, W (the host picks lights in proportion to it).
    fn total_power_w(&self) -> PluginResult<f64>;
    /// Capability bits ([`light_flags`]).
    fn capabilities(&self) -> Flags {
        Flags::NONE
    }
    /// Draw a wavelength from the light's spectrum (`u` in [0,1)).
    fn sample_wavelength(&self, _u: f64) -> PluginResult<WavelengthSample> {
        Err(PluginError::unsupported("sample_wavelength"))
    }
    /// Density of [`sample_wavelength`](Self::sample_wavelength) at `nm`.
    fn wavelength_pdf(&self, _nm: f64) -> PluginResult<f64> {
        Err(PluginError::unsupported("wavelength_pdf"))
    }
    /// Sample an emitted beam for the given wavelengths (uses `sample.u[0..4]`).
    fn sample_emission(
        &self,
        _sample: &RandomSample,
        _lambda: &Wavelengths,
    ) -> PluginResult<EmissionSample> {
        Err(PluginError::unsupported("sample_emission"))
    }
    /// Densities of emitting from `origin` along `direction`.
    fn emission_pdf(&self, _origin: Vec3, _direction: Vec3) -> PluginResult<EmissionPdf> {
        Err(PluginError::unsupported("emission_pdf"))
    }
    /// Sample a point on the light as seen from `receiver` (uses `sample.u[0..2]`).
    fn sample_toward(
        &self,
        _receiver: Vec3,
        _sample: &RandomSample,
        _lambda: &Wavelengths,
    ) -> PluginResult<IncidentSample> {
        Err(PluginError::unsupported("sample_toward"))
    }
    /// Radiance seen by a ray leaving the scene along `direction` (environment lights).
    fn radiance(&self, _direction: Vec3, _lambda: &Wavelengths) -> PluginResult<SpectralValues> {
        Ok(SpectralValues::ZERO)
    }
    /// Solid-angle density with which `sample_toward` picks `direction` (environment lights).
    fn incident_pdf(&self, _receiver: Vec3, _direction: Vec3) -> PluginResult<f64> {
        Ok(0.0)
    }
    /// Extension v2: the scene's extent, given once the scene is built and before anything is
    /// rendered (the host asks [`total_power_w`](Self::total_power_w) again afterwards). A light
    /// that covers the whole scene sizes itself here (a distant light's emitting disc, a sky's
    /// sphere); it takes `&self`, so such a light keeps the bounds in a `OnceLock` or the like.
    /// An ENVIRONMENT light that keeps them reports its power for light selection as a light of
    /// its own sphere; the host places the sky's sphere itself (1% beyond the view bounds'
    /// sphere), so only light selection depends on that number.
    fn scene_bounds(&self, _bounds: &SceneBounds) -> PluginResult<()> {
        Ok(())
    }
    /// Extension v2: the light's normalised emission spectrum (1/nm), the distribution
    /// [`sample_wavelength`](Self::sample_wavelength) draws from. With it the host evaluates,
    /// samples and weighs the light's spectrum exactly (lines included) wherever it needs the
    /// spectrum as a whole; without it (the default) it knows the spectrum only through
    /// `sample_wavelength` and `wavelength_pdf`.
    fn emission_spectrum(&self) -> PluginResult<Option<Box<dyn Spd>>> {
        Ok(None)
    }
    /// Extension v4: true when the emitted spectral radiance factors as `g(p, ω) · S(λ)` with
    /// one shape `S` at every point and in every direction (only the magnitude varies), `S`
    /// being [`emission_spectrum`](Self::emission_spectrum) or, without it, the distribution of
    /// [`sample_wavelength`](Self::sample_wavelength). The host then gives a path from this
    /// light through spectrally flat surfaces the exact colour of `S` (`flat-path-colour`), as
    /// for its own area lights. Asked once, when the light is built. `false` (the default) is
    /// always safe.
    fn uniform_spectral_shape(&self) -> bool {
        false
    }
    /// Extension v6: [`sample_toward`](Self::sample_toward) in the host's single-precision
    /// layout (see [`crate::fast`]), writing the sample into `out` (`Ok(false)`: none; a
    /// density of 0 in `out` means none as well). The default converts to `f64`, calls
    /// `sample_toward` and rounds the result to `f32`, exactly what the host did with that call
    /// (the sample's `distance` is not passed on: the host measures it from the points); a light
    /// that computes in `f32` may override it and skip both conversions.
    fn sample_toward_v6(
        &self,
        receiver: &ReceiverF32,
        u: [f32; 2],
        lambda: &LanesF32,
        out: &mut IncidentF32,
    ) -> PluginResult<bool> {
        let mut sample = RandomSample::default();
        sample.u[0] = u[0] as f64;
        sample.u[1] = u[1] as f64;
        let s = self.sample_toward(receiver.p.to_f64(), &sample, &lambda.to_f64())?;
        *out = IncidentF32::from_f64(&s);
        Ok(true)
    }
    /// Extension v6: [`sample_emission`](Self::sample_emission) in the host's layout (`u` as
    /// its `sample.u[0..4]`), writing into `out`. The default converts as
    /// [`sample_toward_v6`](Self::sample_toward_v6) does.
    fn sample_emission_v6(
        &self,
        u: [f32; 4],
        lambda: &LanesF32,
        out: &mut EmissionF32,
    ) -> PluginResult<bool> {
        let mut sample = RandomSample::default();
        for (d, s) in sample.u.iter_mut().zip(u) {
            *d = s as f64;
        }
        *out = EmissionF32::from_f64(&self.sample_emission(&sample, &lambda.to_f64())?);
        Ok(true)
    }
    /// Extension v6: [`emission_pdf`](Self::emission_pdf) in the host's layout: the densities
    /// of position (1/m²) and direction (1/sr). The default converts as
    /// [`sample_toward_v6`](Self::sample_toward_v6) does.
    fn emission_pdf_v6(&self, origin: &Vec4f, direction: &Vec4f) -> PluginResult<[f32; 2]> {
        let p = self.emission_pdf(origin.to_f64(), direction.to_f64())?;
        Ok([p.position as f32, p.direction as f32])
    }
}

/// The stable-ABI face of a light source. Hosts call this; authors implement [`LightSource`].
/// Frozen within API 0.1 (see `module` for why growing it would break every existing plugin);
/// later capabilities come through [`crate::extension`].
#[sabi_trait]
pub trait AbiLightSource: Send + Sync {
    /// See [`LightSource::next_beam`]; also counts the beam.
    fn next_beam(&self, sample: &RandomSample) -> RResult<Beam, PluginError>;
    /// The seed's `numberOfBeams`: beams handed out by `next_beam` so far.
    fn number_of_beams(&self) -> f64;
    /// See [`LightSource::total_power_w`].
    fn total_power_w(&self) -> RResult<f64, PluginError>;
    /// See [`LightSource::capabilities`].
    fn capabilities(&self) -> Flags;
    /// See [`LightSource::sample_wavelength`].
    fn sample_wavelength(&self, u: f64) -> RResult<WavelengthSample, PluginError>;
    /// See [`LightSource::wavelength_pdf`].
    fn wavelength_pdf(&self, nm: f64) -> RResult<f64, PluginError>;
    /// See [`LightSource::sample_emission`].
    fn sample_emission(
        &self,
        sample: &RandomSample,
        lambda: &Wavelengths,
    ) -> RResult<EmissionSample, PluginError>;
    /// See [`LightSource::emission_pdf`].
    fn emission_pdf(&self, origin: Vec3, direction: Vec3) -> RResult<EmissionPdf, PluginError>;
    /// See [`LightSource::sample_toward`].
    fn sample_toward(
        &self,
        receiver: Vec3,
        sample: &RandomSample,
        lambda: &Wavelengths,
    ) -> RResult<IncidentSample, PluginError>;
    /// See [`LightSource::radiance`].
    fn radiance(
        &self,
        direction: Vec3,
        lambda: &Wavelengths,
    ) -> RResult<SpectralValues, PluginError>;
    /// See [`LightSource::incident_pdf`].
    fn incident_pdf(&self, receiver: Vec3, direction: Vec3) -> RResult<f64, PluginError>;
    /// The object's state as bytes (bincode of its parameters), for blobs.
    #[sabi(last_prefix_field)]
    fn save_state(&self) -> RResult<RVec<u8>, PluginError>;
}

/// A light source behind the stable ABI, owned.
pub type LightBox = AbiLightSource_TO<'static, RBox<()>>;

/// Wraps an author's light: catches panics and counts beams. Clones share the light and its
/// beam count (the root module's face and the v2 face of one object).
pub struct GuardedLight<T> {
    inner: Arc<T>,
    beams: Arc<AtomicU64>,
    state: fn(&T) -> PluginResult<Vec<u8>>,
}

impl<T> Clone for GuardedLight<T> {
    fn clone(&self) -> Self {
        Self {
            inner: self.inner.clone(),
            beams: self.beams.clone(),
            state: self.state,
        }
    }
}

impl<T: LightSource + PluginType> GuardedLight<T> {
    fn new(inner: T, state: fn(&T) -> PluginResult<Vec<u8>>) -> Self {
        Self {
            inner: Arc::new(inner),
            beams: Arc::new(AtomicU64::new(0)),
            state,
        }
    }

    /// Box `inner` behind the ABI; `state` serialises it for blobs.
    pub fn boxed(inner: T, state: fn(&T) -> PluginResult<Vec<u8>>) -> LightBox {
        AbiLightSource_TO::from_value(Self::new(inner, state), abi_stable::sabi_trait::TD_Opaque)
    }

    /// Box `inner` behind the ABI with its version-2 face (extension v2), one object behind both.
    pub fn boxed_v2(inner: T, state: fn(&T) -> PluginResult<Vec<u8>>) -> LightWithV2 {
        let guarded = Self::new(inner, state);
        LightWithV2 {
            light: AbiLightSource_TO::from_value(
                guarded.clone(),
                abi_stable::sabi_trait::TD_Opaque,
            ),
            v2: crate::extension::AbiLightV2_TO::from_value(
                guarded,
                abi_stable::sabi_trait::TD_Opaque,
            ),
        }
    }

    /// Box `inner` behind the ABI with its version-2 face and its declaration (extension v4),
    /// one object behind both faces.
    pub fn boxed_v4(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<LightWithV4, PluginError> {
        let uniform = match guarded("uniform_spectral_shape", || {
            Ok(inner.uniform_spectral_shape())
        }) {
            RResult::ROk(u) => u,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        let v2 = Self::boxed_v2(inner, state);
        RResult::ROk(LightWithV4 {
            light: v2.light,
            v2: v2.v2,
            uniform_spectral_shape: uniform,
        })
    }

    /// Box `inner` behind the ABI with its faces of versions 2 and 6 and its declaration
    /// (extension v6), one object behind every face.
    pub fn boxed_v6(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<LightWithV6, PluginError> {
        crate::guard::install();
        let uniform = match guarded("uniform_spectral_shape", || {
            Ok(inner.uniform_spectral_shape())
        }) {
            RResult::ROk(u) => u,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        let guarded = Self::new(inner, state);
        RResult::ROk(LightWithV6 {
            light: AbiLightSource_TO::from_value(
                guarded.clone(),
                abi_stable::sabi_trait::TD_Opaque,
            ),
            v2: crate::extension::AbiLightV2_TO::from_value(
                guarded.clone(),
                abi_stable::sabi_trait::TD_Opaque,
            ),
            v6: crate::extension::AbiLightV6_TO::from_value(
                guarded,
                abi_stable::sabi_trait::TD_Opaque,
            ),
            uniform_spectral_shape: uniform,
        })
    }

    /// Box `inner` behind the ABI as a light in its own representation
    /// ([`crate::extension::AbiRepresentedLight`]).
    pub fn boxed_represented(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> crate::extension::RepresentedLightBox {
        crate::extension::AbiRepresentedLight_TO::from_value(
            Self::new(inner, state),
            abi_stable::sabi_trait::TD_Opaque,
        )
    }
}

/// Saved state of an object that is part of another (an emission spectrum): there is none.
fn no_state<T>(_: &T) -> PluginResult<Vec<u8>> {
    Err(PluginError::unsupported(
        "save_state of an emission spectrum",
    ))
}

impl<T: LightSource + PluginType> AbiLightV2 for GuardedLight<T> {
    fn scene_bounds(&self, bounds: &SceneBounds) -> RResult<(), PluginError> {
        guarded("scene_bounds", || self.inner.scene_bounds(bounds))
    }
    fn emission_spectrum(&self) -> RResult<ROption<SpdWithLines>, PluginError> {
        match guarded("emission_spectrum", || self.inner.emission_spectrum()) {
            RResult::ROk(Some(spd)) => SpdWithLines::new(spd, no_state).map(ROption::RSome),
            RResult::ROk(None) => RResult::ROk(ROption::RNone),
            RResult::RErr(e) => RResult::RErr(e),
        }
    }
}

impl<T: LightSource + PluginType> AbiLightV6 for GuardedLight<T> {
    #[inline]
    fn sample_toward(
        &self,
        receiver: &ReceiverF32,
        u: &[f32; 2],
        lambda: &LanesF32,
        out: &mut IncidentF32,
    ) -> RResult<bool, PluginError> {
        guarded_call_v5("sample_toward (v6)", || {
            self.inner.sample_toward_v6(receiver, *u, lambda, out)
        })
        .into()
    }
    #[inline]
    fn sample_emission(
        &self,
        u: &[f32; 4],
        lambda: &LanesF32,
        out: &mut EmissionF32,
    ) -> RResult<bool, PluginError> {
        guarded_call_v5("sample_emission (v6)", || {
            self.inner.sample_emission_v6(*u, lambda, out)
        })
        .into()
    }
    #[inline]
    fn emission_pdf(
        &self,
        origin: &Vec4f,
        direction: &Vec4f,
        out: &mut [f32; 2],
    ) -> RResult<(), PluginError> {
        guarded_call_v5("emission_pdf (v6)", || {
            *out = self.inner.emission_pdf_v6(origin, direction)?;
            Ok(())
        })
        .into()
    }
}

impl<T: LightSource + PluginType> AbiLightSource for GuardedLight<T> {
    fn next_beam(&self, sample: &RandomSample) -> RResult<Beam, PluginError> {
        let r = guarded("next_beam", || self.inner.next_beam(sample));
        if r.is_ok() {
            self.beams.fetch_add(1, Ordering::Relaxed);
        }
        r
    }
    fn number_of_beams(&self) -> f64 {
        self.beams.load(Ordering::Relaxed) as f64
    }
    fn total_power_w(&self) -> RResult<f64, PluginError> {
        guarded("total_power_w", || self.inner.total_power_w())
    }
    fn capabilities(&self) -> Flags {
        match guarded("capabilities", || Ok(self.inner.capabilities())) {
            RResult::ROk(f) => f,
            RResult::RErr(_) => Flags::NONE,
        }
    }
    fn sample_wavelength(&self, u: f64) -> RResult<WavelengthSample, PluginError> {
        guarded("sample_wavelength", || self.inner.sample_wavelength(u))
    }
    fn wavelength_pdf(&self, nm: f64) -> RResult<f64, PluginError> {
        guarded("wavelength_pdf", || self.inner.wavelength_pdf(nm))
    }
    fn sample_emission(
        &self,
        sample: &RandomSample,
        lambda: &Wavelengths,
    ) -> RResult<EmissionSample, PluginError> {
        guarded("sample_emission", || {
            self.inner.sample_emission(sample, lambda)
        })
    }
    fn emission_pdf(&self, origin: Vec3, direction: Vec3) -> RResult<EmissionPdf, PluginError> {
        guarded("emission_pdf", || {
            self.inner.emission_pdf(origin, direction)
        })
    }
    fn sample_toward(
        &self,
        receiver: Vec3,
        sample: &RandomSample,
        lambda: &Wavelengths,
    ) -> RResult<IncidentSample, PluginError> {
        guarded("sample_toward", || {
            self.inner.sample_toward(receiver, sample, lambda)
        })
    }
    fn radiance(
        &self,
        direction: Vec3,
        lambda: &Wavelengths,
    ) -> RResult<SpectralValues, PluginError> {
        guarded("radiance", || self.inner.radiance(direction, lambda))
    }
    fn incident_pdf(&self, receiver: Vec3, direction: Vec3) -> RResult<f64, PluginError> {
        guarded("incident_pdf", || {
            self.inner.incident_pdf(receiver, direction)
        })
    }
    fn save_state(&self) -> RResult<RVec<u8>, PluginError> {
        guarded("save_state", || (self.state)(&self.inner).map(RVec::from))
    }
}

impl<T: LightSource + PluginType> crate::extension::AbiRepresentedLight for GuardedLight<T> {
    fn representation(&self) -> BeamRepresentation {
        <T as PluginType>::BEAM_REPRESENTATION
    }
    fn number_of_beams(&self) -> f64 {
        self.beams.load(Ordering::Relaxed) as f64
    }
    fn next_represented_beam(
        &self,
        sample: &RandomSample,
    ) -> RResult<RepresentedBeam, PluginError> {
        let r = guarded("next_represented_beam", || {
            self.inner.next_represented_beam(sample)
        });
        if r.is_ok() {
            self.beams.fetch_add(1, Ordering::Relaxed);
        }
        r
    }
}
