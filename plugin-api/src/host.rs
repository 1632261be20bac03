//! Services the host offers to a plugin while it constructs an object: today, resolving an SPD
//! by its scene spec (a bundled name such as `"d65"`, `"blackbody:2856"`, a CSV path, or a type
//! from another plugin). This is how a light from one author uses a spectrum from another.

use crate::error::{PluginError, PluginResult};
use crate::spd::{SpdHandle, SpdObject};
use abi_stable::{
    sabi_trait,
    std_types::{RResult, RStr},
};

/// The stable-ABI face of the host's services.
#[sabi_trait]
pub trait AbiHost {
    /// Resolve an SPD spec to an SPD object.
    #[sabi(last_prefix_field)]
    fn spd(&self, spec: RStr<'_>) -> RResult<SpdObject, PluginError>;
}

/// Borrowed host services, as passed to constructors.
pub type HostRef<'a> = AbiHost_TO<'a, abi_stable::sabi_types::RRef<'a, ()>>;

/// What a plugin's constructor sees of the host.
pub struct Host<'a, 'b> {
    services: &'a HostRef<'b>,
}

impl<'a, 'b> Host<'a, 'b> {
    /// Wrap the borrowed services.
    pub fn new(services: &'a HostRef<'b>) -> Self {
        Self { services }
    }
    /// Resolve an SPD spec (see the module docs) to an SPD the object may keep.
    pub fn spd(&self, spec: &str) -> PluginResult<SpdHandle> {
        self.services
            .spd(RStr::from_str(spec))
            .into_result()
            .map(SpdHandle::new)
    }
}

/// Host services that resolve nothing: for plugins tested on their own.
pub struct NoHost;

impl AbiHost for NoHost {
    fn spd(&self, spec: RStr<'_>) -> RResult<SpdObject, PluginError> {
        RResult::RErr(PluginError::invalid_parameter(format!(
            "spd `{spec}`: no host is present to resolve SPDs"
        )))
    }
}
