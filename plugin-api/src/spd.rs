//! Spectral power distributions (seed §2): value at a wavelength and sampling from themselves.
//! An SPD integrates to 1 over its range; absolute power belongs to whoever uses it.

use crate::error::{PluginError, PluginResult};
use crate::guard::guarded;
use crate::light::WavelengthSample;
use crate::types::{Flags, WavelengthRange};
use abi_stable::{
    sabi_trait,
    std_types::{RBox, RResult, RVec},
    StableAbi,
};

/// Capability bits of an SPD.
pub mod spd_flags {
    use crate::types::Flags;
    /// Contains spectral lines (deltas in λ): `sample` may return a line with a discrete
    /// probability in `pdf`, and `value` cannot represent it.
    pub const HAS_LINES: Flags = Flags(1);
}

/// What a plugin author implements for an SPD.
pub trait Spd: Send + Sync + 'static {
    /// Normalised value at `nm`, 1/nm (∫ value dλ = 1 over the range).
    fn value(&self, nm: f64) -> PluginResult<f64>;
    /// Draw a wavelength with density proportional to `value` (`u` in [0,1)).
    fn sample(&self, u: f64) -> PluginResult<WavelengthSample>;
    /// Density of `sample` at `nm`, 1/nm.
    fn pdf(&self, nm: f64) -> PluginResult<f64>;
    /// Wavelength range in nm outside which the value is 0.
    fn range_nm(&self) -> WavelengthRange;
    /// Capability bits ([`spd_flags`]).
    fn capabilities(&self) -> Flags {
        Flags::NONE
    }
    /// The spectral lines (deltas in λ) and the share of the total each carries; empty for a
    /// continuous SPD. Read once, when the object is built, through extension v2
    /// ([`crate::extension`]): with it the host weighs lines exactly as its own line SPDs.
    fn delta_lines(&self) -> Vec<SpectralLine> {
        Vec::new()
    }
}

/// One spectral line of an SPD (extension v2): all of `weight` at `nm`.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct SpectralLine {
    /// Wavelength, nm.
    pub nm: f64,
    /// Share of the SPD's total (unitless, ≤ 1); the continuous part carries the rest.
    pub weight: f64,
}

/// An SPD chosen at run time (a light's or material's emission spectrum handed to the host).
impl Spd for Box<dyn Spd> {
    fn value(&self, nm: f64) -> PluginResult<f64> {
        (**self).value(nm)
    }
    fn sample(&self, u: f64) -> PluginResult<WavelengthSample> {
        (**self).sample(u)
    }
    fn pdf(&self, nm: f64) -> PluginResult<f64> {
        (**self).pdf(nm)
    }
    fn range_nm(&self) -> WavelengthRange {
        (**self).range_nm()
    }
    fn capabilities(&self) -> Flags {
        (**self).capabilities()
    }
    fn delta_lines(&self) -> Vec<SpectralLine> {
        (**self).delta_lines()
    }
}

/// The stable-ABI face of an SPD.
#[sabi_trait]
pub trait AbiSpd: Send + Sync {
    /// See [`Spd::value`].
    fn value(&self, nm: f64) -> RResult<f64, PluginError>;
    /// See [`Spd::sample`].
    fn sample(&self, u: f64) -> RResult<WavelengthSample, PluginError>;
    /// See [`Spd::pdf`].
    fn pdf(&self, nm: f64) -> RResult<f64, PluginError>;
    /// See [`Spd::range_nm`].
    fn range_nm(&self) -> WavelengthRange;
    /// See [`Spd::capabilities`].
    fn capabilities(&self) -> Flags;
    /// The object's state as bytes, for blobs.
    #[sabi(last_prefix_field)]
    fn save_state(&self) -> RResult<RVec<u8>, PluginError>;
}

/// An SPD behind the stable ABI, owned.
pub type SpdBox = AbiSpd_TO<'static, RBox<()>>;

/// Wraps an author's SPD so panics come back as errors.
pub struct GuardedSpd<T> {
    inner: T,
    state: fn(&T) -> PluginResult<Vec<u8>>,
}

impl<T: Spd> GuardedSpd<T> {
    /// Box `inner` behind the ABI.
    pub fn boxed(inner: T, state: fn(&T) -> PluginResult<Vec<u8>>) -> SpdBox {
        AbiSpd_TO::from_value(Self { inner, state }, abi_stable::sabi_trait::TD_Opaque)
    }
}

impl<T: Spd> AbiSpd for GuardedSpd<T> {
    fn value(&self, nm: f64) -> RResult<f64, PluginError> {
        guarded("value", || self.inner.value(nm))
    }
    fn sample(&self, u: f64) -> RResult<WavelengthSample, PluginError> {
        guarded("sample", || self.inner.sample(u))
    }
    fn pdf(&self, nm: f64) -> RResult<f64, PluginError> {
        guarded("pdf", || self.inner.pdf(nm))
    }
    fn range_nm(&self) -> WavelengthRange {
        guarded("range_nm", || Ok(self.inner.range_nm())).unwrap_or_default()
    }
    fn capabilities(&self) -> Flags {
        guarded("capabilities", || Ok(self.inner.capabilities())).unwrap_or(Flags::NONE)
    }
    fn save_state(&self) -> RResult<RVec<u8>, PluginError> {
        guarded("save_state", || (self.state)(&self.inner).map(RVec::from))
    }
}

/// An SPD a plugin got from the host (possibly from another plugin), callable as ordinary Rust:
/// what a light keeps to draw and weigh its wavelengths.
pub struct SpdHandle(pub SpdBox);

impl SpdHandle {
    /// See [`Spd::value`].
    pub fn value(&self, nm: f64) -> PluginResult<f64> {
        self.0.value(nm).into_result()
    }
    /// See [`Spd::sample`].
    pub fn sample(&self, u: f64) -> PluginResult<WavelengthSample> {
        self.0.sample(u).into_result()
    }
    /// See [`Spd::pdf`].
    pub fn pdf(&self, nm: f64) -> PluginResult<f64> {
        self.0.pdf(nm).into_result()
    }
    /// See [`Spd::range_nm`].
    pub fn range_nm(&self) -> WavelengthRange {
        self.0.range_nm()
    }
    /// See [`Spd::capabilities`].
    pub fn capabilities(&self) -> Flags {
        self.0.capabilities()
    }
}
