//! How the checks reach an object's calls: the object behind the API's stable-ABI trait object
//! (the same whether it was built in-process or by a loaded library), where its failed calls
//! keep their errors, and how to rebuild it from saved state.

use spectrace_plugin_api::PluginError;

/// Rebuilds an object from its saved state.
pub type Restore<'a, O> = &'a dyn Fn(&[u8]) -> Result<O, PluginError>;

/// What every kind's checks need besides the object itself.
pub struct Calls<'a, O> {
    /// Takes the error a failed per-sample call kept on this thread (the root module's
    /// `take_error`, or the API's `guard::take_kept_error` in-process).
    pub take_error: &'a (dyn Fn() -> Option<PluginError> + Sync),
    /// Builds the same type from saved state; `None` when the type cannot be rebuilt (then the
    /// `state` check is skipped).
    pub restore: Option<Restore<'a, O>>,
}

impl<O> Calls<'_, O> {
    /// The message of the kept error, or a stand-in when the call kept none.
    pub fn error_text(&self) -> String {
        match (self.take_error)() {
            Some(e) => e.to_string(),
            None => "the call answered an error but kept no message".into(),
        }
    }
}

/// Bits of an `f32`, for answers compared to the bit.
pub fn bits(v: f32) -> u32 {
    v.to_bits()
}
