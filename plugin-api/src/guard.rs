//! Panics must not cross the boundary: an unwinding panic through an `extern "C"` function aborts
//! the whole host. Every ABI entry point runs the author's code inside [`guarded`], which catches
//! the panic on the plugin side and turns it into a [`PluginError`] of kind `Panic`.
//!
//! A caught panic is an error like any other, and the host reports it once per call site with a
//! count. The standard panic hook would print it (and, under `RUST_BACKTRACE`, a backtrace) on
//! every call: tens of thousands of messages for a small render. So the first guarded call
//! installs a hook that stays silent for panics raised inside a guard, remembering their
//! location for the error message, and passes every other panic to the hook that was there
//! before. Panic hooks are process-wide, but a plugin library has its own copy of std and so its
//! own hook; when a plugin is linked into the host instead (tests), the chaining keeps the
//! host's panics reported exactly as before.

use crate::error::{ErrorKind, PluginError};
use abi_stable::std_types::RResult;
use std::cell::{Cell, RefCell};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Once;

thread_local! {
    /// How many guarded calls are running on this thread (guards may nest).
    static DEPTH: Cell<u32> = const { Cell::new(0) };
    /// Location of the last panic caught by a guard on this thread.
    static LOCATION: RefCell<Option<String>> = const { RefCell::new(None) };
}

static HOOK: Once = Once::new();

fn install_quiet_hook() {
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if DEPTH.with(Cell::get) > 0 {
                let at = info
                    .location()
                    .map(|l| format!("{}:{}", l.file(), l.line()));
                LOCATION.with(|c| *c.borrow_mut() = at);
            } else {
                previous(info);
            }
        }));
    });
}

/// Decrements the guard depth however the guarded call ends.
struct Depth;

impl Depth {
    fn enter() -> Self {
        DEPTH.with(|d| d.set(d.get() + 1));
        Depth
    }
}

impl Drop for Depth {
    fn drop(&mut self) {
        DEPTH.with(|d| d.set(d.get().saturating_sub(1)));
    }
}

/// Run `f`, returning its result or the caught panic as an error naming `what` was being done.
/// A panic's message reads `"{what} panicked at {file}:{line}: {message}"`, so the text before
/// the first `": "` names the call site (the host counts by it).
pub fn guarded<T>(
    what: &str,
    f: impl FnOnce() -> Result<T, PluginError>,
) -> RResult<T, PluginError> {
    install_quiet_hook();
    let depth = Depth::enter();
    let r = catch_unwind(AssertUnwindSafe(f));
    drop(depth);
    match r {
        Ok(Ok(v)) => RResult::ROk(v),
        Ok(Err(e)) => RResult::RErr(e),
        Err(payload) => RResult::RErr(panic_error(what, payload)),
    }
}

/// Make sure the quiet hook is in place before [`guarded_call`] is used (object constructors
/// call it; they run inside [`guarded`], which installs it as well).
pub fn install() {
    install_quiet_hook();
}

/// [`guarded`] for the per-call entry points of extension v4 (a material's `sample`, `eval`,
/// `pdf`): the same protection and the same message, for less. The thread-local depth is
/// reached once instead of twice (in a `cdylib` each access is a call to `__tls_get_addr`), and
/// the hook is not checked on every call: the object's constructor installed it ([`install`]).
/// `catch_unwind` itself costs nothing while nothing panics.
#[inline]
pub fn guarded_call<T>(
    what: &str,
    f: impl FnOnce() -> Result<T, PluginError>,
) -> RResult<T, PluginError> {
    let r = DEPTH.with(|d| {
        d.set(d.get() + 1);
        // `f` cannot unwind past this point, so the decrement always runs.
        let r = catch_unwind(AssertUnwindSafe(f));
        d.set(d.get().saturating_sub(1));
        r
    });
    match r {
        Ok(Ok(v)) => RResult::ROk(v),
        Ok(Err(e)) => RResult::RErr(e),
        Err(payload) => RResult::RErr(panic_error(what, payload)),
    }
}

/// The error for a caught panic: `"{what} panicked at {file}:{line}: {message}"`.
#[cold]
fn panic_error(what: &str, payload: Box<dyn std::any::Any + Send>) -> PluginError {
    let msg = if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "non-string panic payload".to_string()
    };
    let at = LOCATION
        .with(|c| c.borrow_mut().take())
        .unwrap_or_else(|| "an unknown location".to_string());
    PluginError::new(ErrorKind::Panic, format!("{what} panicked at {at}: {msg}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    // The message names the call and the panic's file:line before the first ": ", which is what
    // the host groups by; the panic's own text follows.
    #[test]
    fn a_caught_panic_names_its_call_site() {
        let r: RResult<(), PluginError> = guarded("next_beam", || panic!("boom {}", 7));
        let e = r.unwrap_err();
        assert_eq!(e.kind, ErrorKind::Panic);
        let site = e.message.split(": ").next().unwrap();
        assert!(
            site.starts_with("next_beam panicked at ") && site.contains("guard.rs:"),
            "{e}"
        );
        assert!(e.message.ends_with("boom 7"), "{e}");
    }

    // The depth goes back to zero after a caught panic, so later panics outside any guard reach
    // the previous hook again.
    #[test]
    fn the_depth_unwinds_with_the_panic() {
        let _ = guarded::<()>("x", || panic!("inner"));
        assert_eq!(DEPTH.with(Cell::get), 0);
        install();
        let e = guarded_call::<()>("sample (v4)", || panic!("fast {}", 1)).unwrap_err();
        assert_eq!(DEPTH.with(Cell::get), 0);
        assert_eq!(e.kind, ErrorKind::Panic);
        assert!(e.message.starts_with("sample (v4) panicked at "), "{e}");
        assert!(
            e.message.contains("guard.rs:") && e.message.ends_with("fast 1"),
            "{e}"
        );
    }
}
