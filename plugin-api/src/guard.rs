//! Panics must not cross the boundary: an unwinding panic through an `extern "C"` function aborts
//! the whole host. Every ABI entry point runs the author's code inside [`guarded`], which catches
//! the panic on the plugin side and turns it into a [`PluginError`] of kind `Panic`.

use crate::error::{ErrorKind, PluginError};
use abi_stable::std_types::RResult;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Run `f`, returning its result or the caught panic as an error naming `what` was being done.
pub fn guarded<T>(
    what: &str,
    f: impl FnOnce() -> Result<T, PluginError>,
) -> RResult<T, PluginError> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(Ok(v)) => RResult::ROk(v),
        Ok(Err(e)) => RResult::RErr(e),
        Err(payload) => {
            let msg = if let Some(s) = payload.downcast_ref::<&str>() {
                (*s).to_string()
            } else if let Some(s) = payload.downcast_ref::<String>() {
                s.clone()
            } else {
                "non-string panic payload".to_string()
            };
            RResult::RErr(PluginError::new(ErrorKind::Panic, format!("{what}: {msg}")))
        }
    }
}
