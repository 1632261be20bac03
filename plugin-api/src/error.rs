//! The one error type every plugin call can return.

use abi_stable::{std_types::RString, StableAbi};
use std::fmt;

/// What went wrong, broadly, so the host can word its message and decide what to do.
#[repr(u8)]
#[derive(StableAbi, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// A parameter was missing, malformed or out of range; the message names it.
    InvalidParameter,
    /// The plugin does not provide the requested type.
    UnknownType,
    /// The object does not offer this optional capability.
    Unsupported,
    /// Saved state could not be read (wrong version, truncated, corrupted).
    BadState,
    /// The plugin panicked; the panic was caught on the plugin side of the boundary.
    Panic,
    /// Anything else.
    Other,
}

/// An error crossing the plugin boundary: a kind and a human-readable message.
#[repr(C)]
#[derive(StableAbi, Clone, Debug, PartialEq)]
pub struct PluginError {
    /// Broad category.
    pub kind: ErrorKind,
    /// What happened, in words a user can act on.
    pub message: RString,
}

impl PluginError {
    /// An error of `kind` with `message`.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: RString::from(message.into()),
        }
    }
    /// A bad parameter; name it in the message.
    pub fn invalid_parameter(message: impl Into<String>) -> Self {
        Self::new(ErrorKind::InvalidParameter, message)
    }
    /// An optional capability the object lacks.
    pub fn unsupported(what: impl Into<String>) -> Self {
        Self::new(ErrorKind::Unsupported, what)
    }
}

impl fmt::Display for PluginError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let kind = match self.kind {
            ErrorKind::InvalidParameter => "invalid parameter",
            ErrorKind::UnknownType => "unknown type",
            ErrorKind::Unsupported => "unsupported",
            ErrorKind::BadState => "bad saved state",
            ErrorKind::Panic => "plugin panicked",
            ErrorKind::Other => "error",
        };
        write!(f, "{kind}: {}", self.message)
    }
}

impl std::error::Error for PluginError {}

/// Result of a plugin call on the Rust side of the boundary.
pub type PluginResult<T> = Result<T, PluginError>;
