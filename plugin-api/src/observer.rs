//! Colour observers (seed §3): colour-matching functions x̄ȳz̄ that turn spectra into XYZ.
//! A plugin can ship, say, a camera's measured sensor curves as an observer.

use crate::error::{PluginError, PluginResult};
use crate::guard::guarded;
use crate::types::{WavelengthRange, Xyz};
use abi_stable::{
    sabi_trait,
    std_types::{RBox, RResult, RString, RVec},
};

/// What a plugin author implements for an observer.
pub trait ColorObserver: Send + Sync + 'static {
    /// x̄, ȳ, z̄ at `nm` (unitless, ȳ peaking near 1 for CIE observers); 0 outside the range.
    fn xyz_bar(&self, nm: f64) -> PluginResult<Xyz>;
    /// A short name, e.g. "cie1931-2".
    fn name(&self) -> String;
    /// Wavelength range in nm where the functions are defined.
    fn range_nm(&self) -> WavelengthRange;
}

/// The stable-ABI face of an observer.
#[sabi_trait]
pub trait AbiColorObserver: Send + Sync {
    /// See [`ColorObserver::xyz_bar`].
    fn xyz_bar(&self, nm: f64) -> RResult<Xyz, PluginError>;
    /// See [`ColorObserver::name`].
    fn name(&self) -> RString;
    /// See [`ColorObserver::range_nm`].
    fn range_nm(&self) -> WavelengthRange;
    /// The object's state as bytes, for blobs.
    #[sabi(last_prefix_field)]
    fn save_state(&self) -> RResult<RVec<u8>, PluginError>;
}

/// An observer behind the stable ABI, owned.
pub type ObserverBox = AbiColorObserver_TO<'static, RBox<()>>;

/// Wraps an author's observer so panics come back as errors.
pub struct GuardedObserver<T> {
    inner: T,
    state: fn(&T) -> PluginResult<Vec<u8>>,
}

impl<T: ColorObserver> GuardedObserver<T> {
    /// Box `inner` behind the ABI.
    pub fn boxed(inner: T, state: fn(&T) -> PluginResult<Vec<u8>>) -> ObserverBox {
        AbiColorObserver_TO::from_value(Self { inner, state }, abi_stable::sabi_trait::TD_Opaque)
    }
}

impl<T: ColorObserver> AbiColorObserver for GuardedObserver<T> {
    fn xyz_bar(&self, nm: f64) -> RResult<Xyz, PluginError> {
        guarded("xyz_bar", || self.inner.xyz_bar(nm))
    }
    fn name(&self) -> RString {
        guarded("name", || Ok(self.inner.name()))
            .unwrap_or_else(|e| e.message.into_string())
            .into()
    }
    fn range_nm(&self) -> WavelengthRange {
        guarded("range_nm", || Ok(self.inner.range_nm())).unwrap_or_default()
    }
    fn save_state(&self) -> RResult<RVec<u8>, PluginError> {
        guarded("save_state", || (self.state)(&self.inner).map(RVec::from))
    }
}
