//! Materials (seed §6): turn an incoming direction into an outgoing one, per wavelength.
//!
//! Directions are in the local shading frame: z is the shading normal, and both `wo` and `wi`
//! point away from the surface. The three per-sample calls take the host's own records by
//! reference ([`crate::lanes`]) and `sample` writes its answer into the host's record in place.

// `#[sabi_trait]` generates a vtable function per method taking the object too, outside the
// method's own `#[allow]`: `sample` passes its eight arguments in registers.
#![allow(clippy::too_many_arguments)]

use crate::error::{PluginError, PluginResult};
use crate::guard::{guarded, guarded_call, keep_error};
use crate::lanes::{status, Scatter, Surface, Values, Vec4f, Wavelengths};
use crate::reradiation::{GuardedReradiation, OffersReradiation, Reradiation, ReradiationBox};
use crate::spd::{GuardedSpd, Spd, SpdObject};
use crate::types::{Flags, TransportMode, LANES};
use abi_stable::{
    sabi_trait,
    std_types::{RBox, ROption, RResult, RVec},
    StableAbi,
};
use std::sync::Arc;

/// Bits of a material, declared once by [`Material::flags`]. The first seven also describe one
/// scattering event ([`Scatter::flags`]); the others are declarations the host checks when the
/// material is built and then relies on.
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
    /// Shifts wavelength (fluorescence): the material offers its re-radiation through
    /// [`Material::reradiation`](crate::Material::reradiation).
    pub const FLUORESCENT: Flags = Flags(64);
    /// Declaration: scatters the same fraction of light at every wavelength, at every point and
    /// for every pair of directions (a grey reflectance, a constant IOR), and never shifts
    /// wavelengths. The host then gives a path whose every surface is flat the exact colour of
    /// its emitter. Checked at a few wavelengths and directions when built.
    pub const SPECTRALLY_FLAT: Flags = Flags(128);
    /// Declaration: `f(wo, wi)` is one value for every `wi` on `wo`'s side and 0 on the other (an
    /// ideal diffuse reflector), and `sample` returns exactly that value. The host then reuses a
    /// sampled direction's value for next-event estimation instead of calling `eval` again.
    /// Checked at a few directions when built.
    pub const SAME_VALUE_ALL_DIRECTIONS: Flags = Flags(256);
    /// Declaration: `sample` draws `wi` with the cosine-weighted density on `wo`'s side, so
    /// `pdf(wo, wi)` is `|cos θi|/π` there and 0 on the other side. The host then computes the
    /// density itself instead of calling `pdf`. Checked at a few directions when built.
    pub const COSINE_PDF: Flags = Flags(512);
    /// Declaration: `eval` is reciprocal, `f(wo, wi) = f(wi, wo)` (for radiance transport). The
    /// conformance kit checks it; the host does not rely on it.
    pub const RECIPROCAL: Flags = Flags(1024);
    /// Every bit this version of the interface defines.
    pub const ALL: Flags = Flags(2047);
}

/// How an emissive material emits, declared once ([`Material::emission`]): radiance
/// `scale · spectrum(λ)` W/(m²·sr·nm), the same at every point of a side and in every direction.
pub struct Emission {
    /// Normalised SPD (1/nm): what the host draws light-path wavelengths from.
    pub spectrum: Box<dyn Spd>,
    /// Integrated radiance, W/(m²·sr).
    pub scale_w_m2_sr: f64,
    /// Whether the back side emits as well.
    pub two_sided: bool,
}

/// What a plugin author implements for a material: three per-sample calls and one for emitters,
/// each in exactly one form, plus what is declared once.
pub trait Material: Send + Sync + 'static {
    /// The material's bits ([`material_flags`]): its lobes and its declarations. Read once, when
    /// the object is built.
    fn flags(&self) -> Flags;

    /// Sample `wi` given `wo`, writing the sample into `out` (the host's record): `Ok(true)`
    /// when written, `Ok(false)` when nothing is scattered (absorbed; `out` untouched). `u[0]`
    /// chooses a lobe, `u[1..3]` the direction within it; all in [0, 1). `out.flags` are the
    /// event's bits (DIFFUSE, GLOSSY or SPECULAR, plus TRANSMISSION and DISPERSIVE as they
    /// apply).
    fn sample(
        &self,
        wo: &Vec4f,
        surface: &Surface,
        lambda: &Wavelengths,
        u: [f32; 3],
        mode: TransportMode,
        out: &mut Scatter,
    ) -> PluginResult<bool>;

    /// BSDF value f(wo, wi) per lane, 1/sr; 0 for delta lobes.
    fn eval(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        surface: &Surface,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> PluginResult<[f32; LANES]>;

    /// Solid-angle density (1/sr) with which `sample` would produce `wi`; 0 for delta lobes.
    fn pdf(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        surface: &Surface,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> PluginResult<f32>;

    /// Emitted radiance towards `wo` per lane, W/(m²·sr·nm); only called for EMISSIVE
    /// materials. The default emits nothing.
    fn emitted(
        &self,
        _wo: &Vec4f,
        _surface: &Surface,
        _lambda: &Wavelengths,
    ) -> PluginResult<[f32; LANES]> {
        Ok([0.0; LANES])
    }

    /// For EMISSIVE materials whose emission is Lambertian and uniform over the surface: that
    /// emission, exactly. The host then builds the area light on every object using the
    /// material from it. `None` (the default) makes the host tabulate
    /// [`emitted`](Self::emitted) along the normal instead, at 1 nm over 360–830 nm. Read once.
    fn emission(&self) -> PluginResult<Option<Emission>> {
        Ok(None)
    }

    /// For FLUORESCENT materials: the wavelength-shifting part (see [`crate::reradiation`]). The
    /// host asks once, when the material is built; `Some` makes it shift wavelengths at this
    /// material, scattering diffusely in both parts (`sample`/`eval` must then be the
    /// Lambertian ρ(λ)/π with ρ = [`Reradiation::reflectance`]). `None` (the default): no
    /// re-radiation.
    fn reradiation(&self) -> Option<&dyn Reradiation> {
        None
    }
}

impl<T: Material> OffersReradiation for T {
    fn offered_reradiation(&self) -> Option<&dyn Reradiation> {
        self.reradiation()
    }
}

/// The stable-ABI face of a material: the per-sample calls in the host's layout. A failed call
/// keeps its error for the root module's `take_error` and answers [`status::ERROR`] (`sample`)
/// or NaN (`eval`, `pdf`, `emitted`).
#[sabi_trait]
pub trait AbiMaterial: Send + Sync {
    /// See [`Material::sample`]; answers a [`status`] word.
    #[allow(clippy::too_many_arguments)]
    fn sample(
        &self,
        wo: &Vec4f,
        surface: &Surface,
        lambda: &Wavelengths,
        u_lobe: f32,
        u1: f32,
        u2: f32,
        mode: TransportMode,
        out: &mut Scatter,
    ) -> u32;
    /// See [`Material::eval`].
    fn eval(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        surface: &Surface,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> Values;
    /// See [`Material::pdf`].
    fn pdf(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        surface: &Surface,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> f32;
    /// See [`Material::emitted`].
    fn emitted(&self, wo: &Vec4f, surface: &Surface, lambda: &Wavelengths) -> Values;
    /// The object's state as bytes (bincode of its parameters), for blobs.
    #[sabi(last_prefix_field)]
    fn save_state(&self) -> RResult<RVec<u8>, PluginError>;
}

/// A material behind the stable ABI, owned.
pub type MaterialBox = AbiMaterial_TO<'static, RBox<()>>;

/// An emissive material's emission as it crosses the boundary ([`Emission`]).
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialEmission {
    /// The normalised emission spectrum (1/nm).
    pub spectrum: SpdObject,
    /// Integrated radiance, W/(m²·sr).
    pub scale: f64,
    /// Whether the back side emits as well.
    pub two_sided: bool,
}

/// A material as it crosses the boundary: the object and what it declares once.
#[repr(C)]
#[derive(StableAbi)]
pub struct MaterialObject {
    /// The calls.
    pub material: MaterialBox,
    /// See [`Material::flags`].
    pub flags: Flags,
    /// See [`Material::emission`].
    pub emission: ROption<MaterialEmission>,
    /// See [`Material::reradiation`].
    pub reradiation: ROption<ReradiationBox>,
}

/// Wraps an author's material: catches panics, keeps errors for `take_error`.
pub struct GuardedMaterial<T> {
    inner: Arc<T>,
    state: fn(&T) -> PluginResult<Vec<u8>>,
}

/// Saved state of an object that is part of another (an emission spectrum): there is none.
fn no_state<T>(_: &T) -> PluginResult<Vec<u8>> {
    Err(PluginError::unsupported(
        "save_state of an emission spectrum",
    ))
}

impl<T: Material> GuardedMaterial<T> {
    /// Box `inner` behind the ABI with its declarations (asked once, here); `state` serialises
    /// it for blobs.
    pub fn object(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<MaterialObject, PluginError> {
        crate::guard::install();
        let declared = guarded("flags", || Ok(inner.flags()));
        let flags = match declared {
            RResult::ROk(f) => f,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        let emission = match guarded("emission", || inner.emission()) {
            RResult::ROk(e) => e,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        let emission = match emission {
            None => ROption::RNone,
            Some(e) => match GuardedSpd::object(e.spectrum, no_state) {
                RResult::ROk(spectrum) => ROption::RSome(MaterialEmission {
                    spectrum,
                    scale: e.scale_w_m2_sr,
                    two_sided: e.two_sided,
                }),
                RResult::RErr(e) => return RResult::RErr(e),
            },
        };
        let inner = Arc::new(inner);
        let reradiation = match GuardedReradiation::boxed(inner.clone()) {
            RResult::ROk(r) => r,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(MaterialObject {
            material: AbiMaterial_TO::from_value(
                Self { inner, state },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            flags,
            emission,
            reradiation,
        })
    }
}

/// A per-sample call's value, or `failed` with the error kept for the host ([`keep_error`]).
#[inline]
pub(crate) fn kept_or<T>(r: Result<T, PluginError>, failed: T) -> T {
    match r {
        Ok(v) => v,
        Err(e) => {
            keep_error(e);
            failed
        }
    }
}

impl<T: Material> AbiMaterial for GuardedMaterial<T> {
    #[inline]
    fn sample(
        &self,
        wo: &Vec4f,
        surface: &Surface,
        lambda: &Wavelengths,
        u_lobe: f32,
        u1: f32,
        u2: f32,
        mode: TransportMode,
        out: &mut Scatter,
    ) -> u32 {
        let r = guarded_call("sample", || {
            let written = self
                .inner
                .sample(wo, surface, lambda, [u_lobe, u1, u2], mode, out)?;
            Ok(if written {
                status::WRITTEN
            } else {
                status::NONE
            })
        });
        kept_or(r, status::ERROR)
    }
    #[inline]
    fn eval(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        surface: &Surface,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> Values {
        // The values written into the answer from inside the guard, which then returns only
        // the error: a `Result<[f32; 4], PluginError>` was assembled byte by byte.
        let mut v = Values::FAILED;
        let r = guarded_call("eval", || {
            v.v = self.inner.eval(wo, wi, surface, lambda, mode)?;
            Ok(())
        });
        match r {
            Ok(()) => v,
            Err(e) => {
                keep_error(e);
                Values::FAILED
            }
        }
    }
    #[inline]
    fn pdf(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        surface: &Surface,
        lambda: &Wavelengths,
        mode: TransportMode,
    ) -> f32 {
        let mut p = f32::NAN;
        let r = guarded_call("pdf", || {
            p = self.inner.pdf(wo, wi, surface, lambda, mode)?;
            Ok(())
        });
        match r {
            Ok(()) => p,
            Err(e) => {
                keep_error(e);
                f32::NAN
            }
        }
    }
    fn emitted(&self, wo: &Vec4f, surface: &Surface, lambda: &Wavelengths) -> Values {
        let r = guarded_call("emitted", || {
            self.inner
                .emitted(wo, surface, lambda)
                .map(|v| Values { v })
        });
        kept_or(r, Values::FAILED)
    }
    fn save_state(&self) -> RResult<RVec<u8>, PluginError> {
        guarded("save_state", || (self.state)(&self.inner).map(RVec::from))
    }
}
