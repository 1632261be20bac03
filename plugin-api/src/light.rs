//! Light sources: the seed's two calls (`next_beam`, `number_of_beams`), plus what a
//! bidirectional path tracer needs to connect to a light, each call in one form.
//!
//! A plugin author implements [`LightSource`]. The host sees it as a [`LightObject`]: the
//! stable-ABI object (through a guard that catches panics and counts beams) and what the light
//! declares once (its bits and its emission spectrum).

use crate::error::{PluginError, PluginResult};
use crate::guard::{guarded, guarded_call};
use crate::lanes::{
    status, EmissionPdf, EmittedRay, Incident, Receiver, Values, Vec4f, Wavelengths,
};
use crate::material::kept_or;
use crate::representation::RepresentedBeam;
use crate::spd::{GuardedSpd, Spd, SpdObject};
use crate::types::{Flags, RandomSample, SceneBounds, LANES};
use abi_stable::{
    sabi_trait,
    std_types::{RBox, ROption, RResult, RVec},
    StableAbi,
};
use std::sync::atomic::{AtomicU64, Ordering};

/// Bits of a light source, declared once by [`LightSource::flags`].
pub mod light_flags {
    use crate::types::Flags;
    /// Emits from a single point (point and spot lights): position pdfs are discrete.
    pub const DELTA_POSITION: Flags = Flags(1);
    /// Emits in a single direction (directional lights): direction pdfs are discrete.
    pub const DELTA_DIRECTION: Flags = Flags(2);
    /// Implements `sample_toward`, `sample_emission` and `emission_pdf`, so paths can be
    /// connected to it; such a light must declare its emission spectrum. Without it the host
    /// can only trace the beams it hands out (`next_beam`).
    pub const CONNECTABLE: Flags = Flags(4);
    /// Rays that leave the scene see it (`radiance` and `incident_pdf` are meaningful); the
    /// host places the emitting sphere around the scene itself.
    pub const ENVIRONMENT: Flags = Flags(8);
    /// Declaration: the emitted spectral radiance factors as `g(p, ω) · S(λ)` with one shape
    /// `S` (the emission spectrum) at every point and in every direction. The host then gives a
    /// path from this light through spectrally flat surfaces the exact colour of `S`. Checked
    /// where it matters when the light is built.
    pub const UNIFORM_SPECTRAL_SHAPE: Flags = Flags(16);
    /// ENVIRONMENT lights: `sample_emission` and `emission_pdf` are implemented on the host's
    /// sphere, so the host starts the light's subpaths (light tracing, bidirectional path
    /// tracing, light-tracing sensors) from them instead of uniformly. That sphere is the one
    /// whose radiance rays see ([`SceneBounds::environment_sphere`](crate::SceneBounds::environment_sphere)
    /// of the bounds given to `scene_bounds`): centre `c`, the centre of the view box, and
    /// radius `R = 1.01 · max(½ |view_max − view_min|, 10⁻³)`.
    /// An emitted ray starts on it and travels inwards; `pdf_position` is per area of the
    /// sphere (1/m²), `pdf_direction` per solid angle (1/sr), and `emission_pdf` answers the
    /// same densities for any inward ray from a point of the sphere. Only their product enters
    /// a light path's weight; how it is split must agree between the two calls. The host drops
    /// (and reports) emitted rays that do not start on its sphere or point outwards. Without
    /// this bit an environment's subpaths start uniformly on the sphere, cosine-distributed
    /// inwards. Defined in 0.2.z: older hosts ignore it.
    pub const SPHERE_EMISSION: Flags = Flags(32);
    /// Every bit this version of the interface defines.
    pub const ALL: Flags = Flags(63);
}

/// What a plugin author implements for a light source.
///
/// Only [`flags`](Self::flags), [`next_beam`](Self::next_beam) and
/// [`total_power_w`](Self::total_power_w) are required: with them any light renders (the host
/// traces its beams). The per-sample calls are the CONNECTABLE capability (and `radiance`,
/// `incident_pdf` the ENVIRONMENT one), declared in the flags.
pub trait LightSource: Send + Sync + 'static {
    /// The light's bits ([`light_flags`]). Read once, when the object is built.
    fn flags(&self) -> Flags;
    /// The light's normalised emission spectrum (1/nm), the distribution its wavelengths are
    /// drawn from; required for CONNECTABLE lights. Read once.
    fn emission_spectrum(&self) -> PluginResult<Option<Box<dyn Spd>>> {
        Ok(None)
    }
    /// Total radiant flux, W (the host picks lights in proportion to it). Asked when the light
    /// is built and again after [`scene_bounds`](Self::scene_bounds).
    fn total_power_w(&self) -> PluginResult<f64>;
    /// The scene's extent, given once the scene is built and before anything is rendered. A
    /// light that covers the whole scene sizes itself here (a distant light's emitting disc);
    /// it takes `&self`, so such a light keeps the bounds in a `OnceLock` or the like.
    fn scene_bounds(&self, _bounds: &SceneBounds) -> PluginResult<()> {
        Ok(())
    }
    /// The seed's `getNextBeam`, in the type's declared
    /// [`BEAM_REPRESENTATION`](crate::PluginType::BEAM_REPRESENTATION) (a native
    /// [`Beam`](crate::Beam) converts with `.into()`). Uses `sample.u[0..5]` at most: position
    /// (2), direction (2), wavelength (1); `u[5..8]` belong to the host. Must be a pure function
    /// of `sample`.
    fn next_beam(&self, sample: &RandomSample) -> PluginResult<RepresentedBeam>;
    /// Sample a point on the light as seen from `receiver` (next-event estimation), writing it
    /// into `out`: `Ok(true)` when written, `Ok(false)` when nothing arrives (a density of 0
    /// in `out` means none as well). `u` in [0, 1). CONNECTABLE lights.
    fn sample_toward(
        &self,
        _receiver: &Receiver,
        _u: [f32; 2],
        _lambda: &Wavelengths,
        _out: &mut Incident,
    ) -> PluginResult<bool> {
        Err(PluginError::unsupported("sample_toward"))
    }
    /// Solid-angle density (1/sr) with which `sample_toward` from `receiver` picks `direction`
    /// (ENVIRONMENT lights; 0 for others).
    fn incident_pdf(&self, _receiver: &Receiver, _direction: &Vec4f) -> PluginResult<f32> {
        Ok(0.0)
    }
    /// Sample a ray leaving the light (light subpaths), writing it into `out`: `u[0..2]` pick
    /// the origin, `u[2..4]` the direction. CONNECTABLE lights.
    fn sample_emission(
        &self,
        _u: [f32; 4],
        _lambda: &Wavelengths,
        _out: &mut EmittedRay,
    ) -> PluginResult<bool> {
        Err(PluginError::unsupported("sample_emission"))
    }
    /// Densities with which `sample_emission` produces the ray from `origin` along `direction`.
    /// CONNECTABLE lights.
    fn emission_pdf(&self, _origin: &Vec4f, _direction: &Vec4f) -> PluginResult<EmissionPdf> {
        Err(PluginError::unsupported("emission_pdf"))
    }
    /// Radiance per lane seen by a ray leaving the scene along `direction`, W/(m²·sr·nm)
    /// (ENVIRONMENT lights; zero for others).
    fn radiance(&self, _direction: &Vec4f, _lambda: &Wavelengths) -> PluginResult<[f32; LANES]> {
        Ok([0.0; LANES])
    }
}

/// The stable-ABI face of a light source: its calls. A failed per-sample call keeps its error
/// for the root module's `take_error` and answers [`status::ERROR`] or NaN.
#[sabi_trait]
pub trait AbiLightSource: Send + Sync {
    /// See [`LightSource::total_power_w`].
    fn total_power_w(&self) -> RResult<f64, PluginError>;
    /// See [`LightSource::scene_bounds`].
    fn scene_bounds(&self, bounds: &SceneBounds) -> RResult<(), PluginError>;
    /// See [`LightSource::next_beam`]; also counts the beam.
    fn next_beam(&self, sample: &RandomSample) -> RResult<RepresentedBeam, PluginError>;
    /// The seed's `numberOfBeams`: beams handed out by `next_beam` so far.
    fn number_of_beams(&self) -> f64;
    /// See [`LightSource::sample_toward`]; answers a [`status`] word.
    fn sample_toward(
        &self,
        receiver: &Receiver,
        u0: f32,
        u1: f32,
        lambda: &Wavelengths,
        out: &mut Incident,
    ) -> u32;
    /// See [`LightSource::incident_pdf`].
    fn incident_pdf(&self, receiver: &Receiver, direction: &Vec4f) -> f32;
    /// See [`LightSource::sample_emission`]; answers a [`status`] word.
    fn sample_emission(&self, u: &[f32; 4], lambda: &Wavelengths, out: &mut EmittedRay) -> u32;
    /// See [`LightSource::emission_pdf`].
    fn emission_pdf(&self, origin: &Vec4f, direction: &Vec4f) -> EmissionPdf;
    /// See [`LightSource::radiance`].
    fn radiance(&self, direction: &Vec4f, lambda: &Wavelengths) -> Values;
    /// The object's state as bytes (bincode of its parameters), for blobs.
    #[sabi(last_prefix_field)]
    fn save_state(&self) -> RResult<RVec<u8>, PluginError>;
}

/// A light source behind the stable ABI, owned.
pub type LightBox = AbiLightSource_TO<'static, RBox<()>>;

/// A light as it crosses the boundary: the object and what it declares once.
#[repr(C)]
#[derive(StableAbi)]
pub struct LightObject {
    /// The calls.
    pub light: LightBox,
    /// See [`LightSource::flags`].
    pub flags: Flags,
    /// See [`LightSource::emission_spectrum`].
    pub spectrum: ROption<SpdObject>,
}

/// Wraps an author's light: catches panics, keeps errors for `take_error`, counts beams.
pub struct GuardedLight<T> {
    inner: T,
    beams: AtomicU64,
    state: fn(&T) -> PluginResult<Vec<u8>>,
}

/// Saved state of an object that is part of another (an emission spectrum): there is none.
fn no_state<T>(_: &T) -> PluginResult<Vec<u8>> {
    Err(PluginError::unsupported(
        "save_state of an emission spectrum",
    ))
}

impl<T: LightSource> GuardedLight<T> {
    /// Box `inner` behind the ABI with its declarations (asked once, here); `state` serialises
    /// it for blobs.
    pub fn object(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<LightObject, PluginError> {
        crate::guard::install();
        let flags = match guarded("flags", || Ok(inner.flags())) {
            RResult::ROk(f) => f,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        let spectrum = match guarded("emission_spectrum", || inner.emission_spectrum()) {
            RResult::ROk(Some(spd)) => match GuardedSpd::object(spd, no_state) {
                RResult::ROk(s) => ROption::RSome(s),
                RResult::RErr(e) => return RResult::RErr(e),
            },
            RResult::ROk(None) => ROption::RNone,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(LightObject {
            light: AbiLightSource_TO::from_value(
                Self {
                    inner,
                    beams: AtomicU64::new(0),
                    state,
                },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            flags,
            spectrum,
        })
    }
}

impl<T: LightSource> AbiLightSource for GuardedLight<T> {
    fn total_power_w(&self) -> RResult<f64, PluginError> {
        guarded("total_power_w", || self.inner.total_power_w())
    }
    fn scene_bounds(&self, bounds: &SceneBounds) -> RResult<(), PluginError> {
        guarded("scene_bounds", || self.inner.scene_bounds(bounds))
    }
    fn next_beam(&self, sample: &RandomSample) -> RResult<RepresentedBeam, PluginError> {
        let r = guarded("next_beam", || self.inner.next_beam(sample));
        if r.is_ok() {
            self.beams.fetch_add(1, Ordering::Relaxed);
        }
        r
    }
    fn number_of_beams(&self) -> f64 {
        self.beams.load(Ordering::Relaxed) as f64
    }
    #[inline]
    fn sample_toward(
        &self,
        receiver: &Receiver,
        u0: f32,
        u1: f32,
        lambda: &Wavelengths,
        out: &mut Incident,
    ) -> u32 {
        let r = guarded_call("sample_toward", || {
            let written = self.inner.sample_toward(receiver, [u0, u1], lambda, out)?;
            Ok(if written {
                status::WRITTEN
            } else {
                status::NONE
            })
        });
        kept_or(r, status::ERROR)
    }
    fn incident_pdf(&self, receiver: &Receiver, direction: &Vec4f) -> f32 {
        let r = guarded_call("incident_pdf", || {
            self.inner.incident_pdf(receiver, direction)
        });
        kept_or(r, f32::NAN)
    }
    #[inline]
    fn sample_emission(&self, u: &[f32; 4], lambda: &Wavelengths, out: &mut EmittedRay) -> u32 {
        let r = guarded_call("sample_emission", || {
            let written = self.inner.sample_emission(*u, lambda, out)?;
            Ok(if written {
                status::WRITTEN
            } else {
                status::NONE
            })
        });
        kept_or(r, status::ERROR)
    }
    #[inline]
    fn emission_pdf(&self, origin: &Vec4f, direction: &Vec4f) -> EmissionPdf {
        let r = guarded_call("emission_pdf", || {
            self.inner.emission_pdf(origin, direction)
        });
        kept_or(
            r,
            EmissionPdf {
                position: f32::NAN,
                direction: f32::NAN,
            },
        )
    }
    fn radiance(&self, direction: &Vec4f, lambda: &Wavelengths) -> Values {
        let r = guarded_call("radiance", || {
            self.inner.radiance(direction, lambda).map(|v| Values { v })
        });
        kept_or(r, Values::FAILED)
    }
    fn save_state(&self) -> RResult<RVec<u8>, PluginError> {
        guarded("save_state", || (self.state)(&self.inner).map(RVec::from))
    }
}
