//! Fluorescence: what a `FLUORESCENT` material does to wavelengths.
//!
//! Light of power 1 arriving at the excitation wavelength λᵢ leaves as
//!
//! * the reflectance ρ(λᵢ) at the same wavelength (what the material's ordinary
//!   `sample`/`eval` return, as ρ/π), and
//! * a re-radiated spectrum r(λᵢ → λₒ) (1/nm over λₒ) at other wavelengths,
//!
//! both with a cosine (Lambertian) lobe: the host scatters a fluorescent surface diffusely in
//! both parts, and draws the direction itself. Under an illuminant E(λ) the light leaving is
//! `S(λₒ) = ρ(λₒ)E(λₒ) + ∫ E(λᵢ) r(λᵢ → λₒ) dλᵢ`; as a BSDF the shifting part is
//! f(λᵢ → λₒ) = r(λᵢ → λₒ)/π in 1/(sr·nm). These are the units and conventions of the host's
//! built-in `fluorescent` material, so a plugin that returns the same numbers renders the same
//! image.
//!
//! Rules the host relies on (and checks, see `docs/plugins.md`):
//!
//! * energy is never created: ρ(λᵢ) + ∫ r(λᵢ → λₒ) dλₒ ≤ 1 for every λᵢ;
//! * no anti-Stokes emission: r(λᵢ → λₒ) = 0 for λₒ ≤ λᵢ, and draws respect it;
//! * every value and density is finite and ≥ 0; a draw's density is > 0 and is the density
//!   the matching `*_pdf` call returns for that wavelength.
//!
//! Camera paths arrive with the observed wavelength λₒ and ask for an excitation
//! ([`Reradiation::sample_excitation`]); light paths arrive with λᵢ and ask for an emission
//! ([`Reradiation::sample_emission`]). Each path weighs its draw by `r / pdf`, so the densities
//! need not be proportional to r, only positive wherever r is.

use crate::error::{PluginError, PluginResult};
use crate::guard::guarded;
use abi_stable::{
    sabi_trait,
    std_types::{RBox, ROption, RResult},
    StableAbi,
};
use std::sync::Arc;

/// A wavelength drawn at a fluorescent event.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq)]
pub struct WavelengthDraw {
    /// The drawn wavelength, nm.
    pub lambda_nm: f64,
    /// Its density, 1/nm (> 0).
    pub pdf: f64,
}

/// What a plugin author implements for the wavelength-shifting part of a `FLUORESCENT`
/// material (see the module docs); returned by [`crate::Material::reradiation`]. Wavelengths
/// in nm.
pub trait Reradiation: Send + Sync {
    /// Ordinary reflectance ρ(λ) in [0, 1]: light leaving at the wavelength it arrived with.
    /// Must equal what the material's `eval` returns times π.
    fn reflectance(&self, lambda_nm: f64) -> PluginResult<f64>;
    /// Re-radiation density r(λᵢ → λₒ), 1/nm over λₒ: spectral power leaving at λₒ per unit
    /// power arriving at λᵢ; 0 for λₒ ≤ λᵢ.
    fn reradiation(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> PluginResult<f64>;
    /// ∫ r(λᵢ → λₒ) dλₒ: the fraction of the power arriving at λᵢ that leaves at other
    /// wavelengths (unitless, ρ + this ≤ 1).
    fn reradiated_fraction(&self, lambda_i_nm: f64) -> PluginResult<f64>;
    /// ∫ r(λᵢ → λₒ) dλᵢ: the re-radiated light at λₒ under a unit illuminant at every
    /// excitation wavelength (unitless, may exceed 1). An estimate suffices: the host uses it
    /// only to choose between keeping and shifting the wavelength of a camera path.
    fn excitation_fraction(&self, lambda_o_nm: f64) -> PluginResult<f64>;
    /// Draw an emission wavelength λₒ > λᵢ for excitation λᵢ with `u ∈ [0, 1)`; `None` where
    /// nothing is re-radiated.
    fn sample_emission(&self, lambda_i_nm: f64, u: f64) -> PluginResult<Option<WavelengthDraw>>;
    /// Density (1/nm) with which [`sample_emission`](Self::sample_emission) draws λₒ.
    fn emission_pdf(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> PluginResult<f64>;
    /// Draw an excitation wavelength λᵢ < λₒ for emission λₒ with `u ∈ [0, 1)`; `None` where
    /// nothing re-radiates into λₒ. The density must be positive wherever r(· → λₒ) is.
    fn sample_excitation(&self, lambda_o_nm: f64, u: f64) -> PluginResult<Option<WavelengthDraw>>;
    /// Density (1/nm) with which [`sample_excitation`](Self::sample_excitation) draws λᵢ.
    fn excitation_pdf(&self, lambda_o_nm: f64, lambda_i_nm: f64) -> PluginResult<f64>;
    /// Wavelengths (nm) outside which excitation and emission are both zero: `(low, high)`.
    fn range_nm(&self) -> PluginResult<(f64, f64)>;
}

/// The stable-ABI face of [`Reradiation`]; see its methods for their meaning.
#[sabi_trait]
pub trait AbiReradiation: Send + Sync {
    /// See [`Reradiation::reflectance`].
    fn reflectance(&self, lambda_nm: f64) -> RResult<f64, PluginError>;
    /// See [`Reradiation::reradiation`].
    fn reradiation(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> RResult<f64, PluginError>;
    /// See [`Reradiation::reradiated_fraction`].
    fn reradiated_fraction(&self, lambda_i_nm: f64) -> RResult<f64, PluginError>;
    /// See [`Reradiation::excitation_fraction`].
    fn excitation_fraction(&self, lambda_o_nm: f64) -> RResult<f64, PluginError>;
    /// See [`Reradiation::sample_emission`].
    fn sample_emission(
        &self,
        lambda_i_nm: f64,
        u: f64,
    ) -> RResult<ROption<WavelengthDraw>, PluginError>;
    /// See [`Reradiation::emission_pdf`].
    fn emission_pdf(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> RResult<f64, PluginError>;
    /// See [`Reradiation::sample_excitation`].
    fn sample_excitation(
        &self,
        lambda_o_nm: f64,
        u: f64,
    ) -> RResult<ROption<WavelengthDraw>, PluginError>;
    /// See [`Reradiation::excitation_pdf`].
    fn excitation_pdf(&self, lambda_o_nm: f64, lambda_i_nm: f64) -> RResult<f64, PluginError>;
    /// See [`Reradiation::range_nm`]: `[low, high]`.
    #[sabi(last_prefix_field)]
    fn range_nm(&self) -> RResult<[f64; 2], PluginError>;
}

/// The re-radiation face of a material behind the stable ABI, owned.
pub type ReradiationBox = AbiReradiation_TO<'static, RBox<()>>;

/// What [`GuardedReradiation`] serves: an object that may offer a re-radiation face. Every
/// [`crate::Material`] is one (through [`crate::Material::reradiation`]; the impl is in
/// `material.rs`, so this module needs nothing of materials).
pub trait OffersReradiation: Send + Sync + 'static {
    /// The re-radiation face, if any.
    fn offered_reradiation(&self) -> Option<&dyn Reradiation>;
}

/// Serves a material's [`crate::Material::reradiation`] behind the ABI, panics caught.
pub struct GuardedReradiation<T> {
    inner: Arc<T>,
}

impl<T: OffersReradiation> GuardedReradiation<T> {
    /// The re-radiation face of `inner`, or `None` when it offers none (asked once, here).
    pub fn boxed(inner: Arc<T>) -> RResult<ROption<ReradiationBox>, PluginError> {
        match guarded("reradiation", || Ok(inner.offered_reradiation().is_some())) {
            RResult::ROk(true) => RResult::ROk(ROption::RSome(AbiReradiation_TO::from_value(
                Self { inner },
                abi_stable::sabi_trait::TD_Opaque,
            ))),
            RResult::ROk(false) => RResult::ROk(ROption::RNone),
            RResult::RErr(e) => RResult::RErr(e),
        }
    }

    fn with<R>(
        &self,
        call: &str,
        f: impl FnOnce(&dyn Reradiation) -> PluginResult<R>,
    ) -> RResult<R, PluginError> {
        guarded(call, || match self.inner.offered_reradiation() {
            Some(r) => f(r),
            None => Err(PluginError::unsupported(
                "reradiation() returned None after returning Some when the material was built",
            )),
        })
    }
}

impl<T: OffersReradiation> AbiReradiation for GuardedReradiation<T> {
    fn reflectance(&self, l: f64) -> RResult<f64, PluginError> {
        self.with("reflectance", |r| r.reflectance(l))
    }
    fn reradiation(&self, li: f64, lo: f64) -> RResult<f64, PluginError> {
        self.with("reradiation", |r| r.reradiation(li, lo))
    }
    fn reradiated_fraction(&self, li: f64) -> RResult<f64, PluginError> {
        self.with("reradiated_fraction", |r| r.reradiated_fraction(li))
    }
    fn excitation_fraction(&self, lo: f64) -> RResult<f64, PluginError> {
        self.with("excitation_fraction", |r| r.excitation_fraction(lo))
    }
    fn sample_emission(&self, li: f64, u: f64) -> RResult<ROption<WavelengthDraw>, PluginError> {
        self.with("sample_emission", |r| {
            r.sample_emission(li, u).map(Into::into)
        })
    }
    fn emission_pdf(&self, li: f64, lo: f64) -> RResult<f64, PluginError> {
        self.with("emission_pdf", |r| r.emission_pdf(li, lo))
    }
    fn sample_excitation(&self, lo: f64, u: f64) -> RResult<ROption<WavelengthDraw>, PluginError> {
        self.with("sample_excitation", |r| {
            r.sample_excitation(lo, u).map(Into::into)
        })
    }
    fn excitation_pdf(&self, lo: f64, li: f64) -> RResult<f64, PluginError> {
        self.with("excitation_pdf", |r| r.excitation_pdf(lo, li))
    }
    fn range_nm(&self) -> RResult<[f64; 2], PluginError> {
        self.with("range_nm", |r| r.range_nm().map(|(a, b)| [a, b]))
    }
}
