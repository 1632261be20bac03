//! Colour observers (seed §3): colour-matching functions x̄ȳz̄ that turn spectra into XYZ.
//! A plugin can ship, say, a camera's measured sensor curves as an observer.

use crate::error::{PluginError, PluginResult};
use crate::guard::guarded;
use crate::types::{WavelengthRange, Xyz};
use abi_stable::{
    sabi_trait,
    std_types::{RBox, ROption, RResult, RString, RVec},
    StableAbi,
};

/// What a plugin author implements for an observer.
pub trait ColorObserver: Send + Sync + 'static {
    /// x̄, ȳ, z̄ at `nm` (unitless, ȳ peaking near 1 for CIE observers); 0 outside the range.
    fn xyz_bar(&self, nm: f64) -> PluginResult<Xyz>;
    /// A short name, e.g. "cie1931-2". Read once, when the object is built.
    fn name(&self) -> String;
    /// Wavelength range in nm where the functions are defined. Read once.
    fn range_nm(&self) -> WavelengthRange;
    /// The functions as a table on a 1 nm grid when [`xyz_bar`](Self::xyz_bar) IS that table,
    /// interpolated linearly between the nodes and 0 outside them (as the CIE tables are):
    /// the host then evaluates its own copy instead of calling `xyz_bar` per wavelength.
    /// Read once; the host checks the claim then (at every node and half-way between nodes, to
    /// the bit) and refuses an observer whose table disagrees with its `xyz_bar`. `None` (the
    /// default) is always safe.
    fn table(&self) -> Option<ObserverTable> {
        None
    }
}

/// An observer's colour-matching functions on a 1 nm grid: `xyz[i]` is x̄, ȳ, z̄ at
/// `start_nm + i` nm; between nodes the functions are the straight line between them, outside
/// `[start_nm, start_nm + xyz.len() − 1]` they are 0.
#[repr(C)]
#[derive(StableAbi, Clone, Debug, Default, PartialEq)]
pub struct ObserverTable {
    /// Wavelength of the first node, nm.
    pub start_nm: f64,
    /// x̄, ȳ, z̄ at each node (unitless), 1 nm apart.
    pub xyz: RVec<Xyz>,
}

/// The stable-ABI face of an observer.
#[sabi_trait]
pub trait AbiColorObserver: Send + Sync {
    /// See [`ColorObserver::xyz_bar`].
    fn xyz_bar(&self, nm: f64) -> RResult<Xyz, PluginError>;
    /// The object's state as bytes, for blobs.
    #[sabi(last_prefix_field)]
    fn save_state(&self) -> RResult<RVec<u8>, PluginError>;
}

/// An observer behind the stable ABI, owned.
pub type ObserverBox = AbiColorObserver_TO<'static, RBox<()>>;

/// An observer as it crosses the boundary: the object and what it declares once.
#[repr(C)]
#[derive(StableAbi)]
pub struct ObserverObject {
    /// The calls.
    pub observer: ObserverBox,
    /// See [`ColorObserver::name`].
    pub name: RString,
    /// See [`ColorObserver::range_nm`].
    pub range: WavelengthRange,
    /// See [`ColorObserver::table`].
    pub table: ROption<ObserverTable>,
}

/// Wraps an author's observer so panics come back as errors.
pub struct GuardedObserver<T> {
    inner: T,
    state: fn(&T) -> PluginResult<Vec<u8>>,
}

impl<T: ColorObserver> GuardedObserver<T> {
    /// Box `inner` behind the ABI with its declarations (asked once, here).
    pub fn object(
        inner: T,
        state: fn(&T) -> PluginResult<Vec<u8>>,
    ) -> RResult<ObserverObject, PluginError> {
        let declared = guarded("name", || {
            Ok((inner.name(), inner.range_nm(), inner.table()))
        });
        let (name, range, table) = match declared {
            RResult::ROk(d) => d,
            RResult::RErr(e) => return RResult::RErr(e),
        };
        RResult::ROk(ObserverObject {
            observer: AbiColorObserver_TO::from_value(
                Self { inner, state },
                abi_stable::sabi_trait::TD_Opaque,
            ),
            name: name.into(),
            range,
            table: table.into(),
        })
    }
}

impl<T: ColorObserver> AbiColorObserver for GuardedObserver<T> {
    fn xyz_bar(&self, nm: f64) -> RResult<Xyz, PluginError> {
        guarded("xyz_bar", || self.inner.xyz_bar(nm))
    }
    fn save_state(&self) -> RResult<RVec<u8>, PluginError> {
        guarded("save_state", || (self.state)(&self.inner).map(RVec::from))
    }
}
