//! Spectral power distributions (seed §2): value at a wavelength and sampling from themselves.
//! An SPD integrates to 1 over its range; absolute power belongs to whoever uses it.

use crate::error::{PluginError, PluginResult};
use crate::guard::guarded;
use crate::types::WavelengthRange;
use abi_stable::{
    sabi_trait,
    std_types::{RBox, RResult, RVec},
    StableAbi,
};
use std::sync::Arc;

/// A wavelength drawn from a spectrum.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct WavelengthSample {
    /// Wavelength, nm.
    pub nm: f64,
    /// Density, 1/nm; for a spectral line, the line's probability (its share of the total).
    pub pdf: f64,
}

/// One spectral line of an SPD: all of `weight` at `nm`.
#[repr(C)]
#[derive(StableAbi, Clone, Copy, Debug, Default, PartialEq)]
pub struct SpectralLine {
    /// Wavelength, nm.
    pub nm: f64,
    /// Share of the SPD's total (unitless, ≤ 1); the continuous part carries the rest.
    pub weight: f64,
}

/// What a plugin author implements for an SPD.
///
/// `value` and `pdf` describe the continuous part (1/nm); the lines ([`lines`](Self::lines))
/// carry the rest of the unit total. `sample` draws from the whole: a continuous wavelength with
/// its density, or a line's wavelength with the line's weight as `pdf`.
pub trait Spd: Send + Sync + 'static {
    /// Normalised value of the continuous part at `nm`, 1/nm (its integral plus the lines'
    /// weights is 1).
    fn value(&self, nm: f64) -> PluginResult<f64>;
    /// Draw a wavelength (`u` in [0,1)) with density proportional to the SPD.
    fn sample(&self, u: f64) -> PluginResult<WavelengthSample>;
    /// Density of `sample` at `nm` (continuous part), 1/nm.
    fn pdf(&self, nm: f64) -> PluginResult<f64>;
    /// Wavelength range in nm outside which the SPD is 0. Read once, when the object is built.
    fn range_nm(&self) -> WavelengthRange;
    /// The spectral lines (deltas in λ) and the share of the total each carries; empty (the
    /// default) for a continuous SPD. Read once, when the object is built: the host then weighs
    /// lines exactly as its own line SPDs.
    fn lines(&self) -> Vec<SpectralLine> {
        Vec::new()
    }
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
    fn lines(&self) -> Vec<SpectralLine> {
        (**self).lines()
    }
}

/// The stable-ABI face of an SPD: its calls. What is declared once (range, lines) travels as
/// data in [`SpdObject`].
#[sabi_trait]
pub trait AbiSpd: Send + Sync {
    /// See [`Spd::value`].
    fn value(&self, nm: f64) -> RResult<f64, PluginError>;
    /// See [`Spd::sample`].
    fn sample(&self, u: f64) -> RResult<WavelengthSample, PluginError>;
    /// See [`Spd::pdf`].
    fn pdf(&self, nm: f64) -> RResult<f64, PluginError>;
    /// The object's state as bytes (bincode of its parameters), for blobs.
    #[sabi(last_prefix_field)]
    fn save_state(&self) -> RResult<RVec<u8>, PluginError>;
}

/// An SPD behind the stable ABI, owned.
pub type SpdBox = AbiSpd_TO<'static, RBox<()>>;

/// An SPD as it crosses the boundary: the object and what it declares once.
#[repr(C)]
#[derive(StableAbi)]
pub struct SpdObject {
    /// The calls.
    pub spd: SpdBox,
    /// See [`Spd::range_nm`].
    pub range: WavelengthRange,
    /// See [`Spd::lines`].
    pub lines: RVec<SpectralLine>,
}

/// Wraps an author's SPD so panics come back as errors.
pub struct GuardedSpd<T> {
    inner: T,
    state: fn(&T) -> PluginResult<Vec<u8>>,
}

impl<T: Spd> GuardedSpd<T> {
    /// Box `inner` behind the ABI with its declarations (asked once, here); `state` serialises
    /// it for blobs.
    pub fn object(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<SpdObject, PluginError> {
        let declared = guarded("range_nm", || Ok((inner.range_nm(), inner.lines())));
        let (range, lines) = match declared {
            RResult::ROk(d) => d,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(SpdObject {
            spd: AbiSpd_TO::from_value(Self { inner, state }, abi_stable::sabi_trait::TD_Opaque),
            range,
            lines: lines.into(),
        })
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
    fn save_state(&self) -> RResult<RVec<u8>, PluginError> {
        guarded("save_state", || (self.state)(&self.inner).map(RVec::from))
    }
}

/// An SPD a plugin got from the host (possibly from another plugin), callable as ordinary Rust
/// and itself an [`Spd`]: what a light keeps to draw and weigh its wavelengths, and may hand back
/// as its emission spectrum. Clones share the object.
#[derive(Clone)]
pub struct SpdHandle(pub Arc<SpdObject>);

impl SpdHandle {
    /// Wrap an SPD object.
    pub fn new(spd: SpdObject) -> Self {
        Self(Arc::new(spd))
    }
}

impl Spd for SpdHandle {
    fn value(&self, nm: f64) -> PluginResult<f64> {
        self.0.spd.value(nm).into_result()
    }
    fn sample(&self, u: f64) -> PluginResult<WavelengthSample> {
        self.0.spd.sample(u).into_result()
    }
    fn pdf(&self, nm: f64) -> PluginResult<f64> {
        self.0.spd.pdf(nm).into_result()
    }
    fn range_nm(&self) -> WavelengthRange {
        self.0.range
    }
    fn lines(&self) -> Vec<SpectralLine> {
        self.0.lines.to_vec()
    }
}
