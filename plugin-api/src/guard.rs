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
//!
//! What the hook must know is whether a guard will catch the panic. Outside library mode (below)
//! [`guarded`] tells it through a thread-local depth counter; in a library (a `cdylib`) every
//! access to it is a call to `__tls_get_addr`, about 50 instructions per guarded call counting
//! both accesses. Library mode does without it: a library the host has
//! loaded through its exported root module ([`set_library_mode`]; only a host loading the
//! library reaches that symbol) has a hook that sees only the plugin's own panics, so it can defer every
//! panic instead of asking, and every guard ([`guarded`], [`guarded_call`]) is then
//! `catch_unwind` alone. A deferred report is taken by the guard that catches the
//! panic (it becomes the error's location, as before); a report no guard takes is never lost: it
//! is printed when the same thread panics again (a panic that cannot unwind, about to abort, is
//! such a second panic) and when the thread ends (a plugin's own thread that died of it).
//! Outside library mode (a plugin linked into the host) [`guarded_call`] panics reach the
//! previous hook like any unguarded panic: reported at once, still caught and returned as an
//! error.

use crate::error::{ErrorKind, PluginError};
use abi_stable::std_types::RResult;
use std::cell::{Cell, RefCell};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Once;

thread_local! {
    /// How many guarded calls are running on this thread (guards may nest).
    static DEPTH: Cell<u32> = const { Cell::new(0) };
    /// Location of the last panic caught by a guard on this thread.
    static LOCATION: RefCell<Option<String>> = const { RefCell::new(None) };
    /// A panic deferred in library mode that no guard has taken yet: printed when the thread
    /// panics again or ends (see the module docs).
    static UNCLAIMED: Unclaimed = const { Unclaimed(RefCell::new(None)) };
    /// The error of the last per-sample call on this thread that failed, until the host takes
    /// it ([`keep_error`], [`take_kept_error`]): touched only when a call fails.
    static KEPT: RefCell<Option<PluginError>> = const { RefCell::new(None) };
}

/// Keep `e`, the error of a failed per-sample call ([`crate::lanes::status`]), for the host to take on this thread
/// ([`take_kept_error`]); replaces one never taken. Out of line: the calls that succeed carry
/// nothing for it.
#[cold]
#[inline(never)]
pub fn keep_error(e: PluginError) {
    // A thread being torn down cannot keep it; the host then reports the call's answer alone.
    let _ = KEPT.try_with(|k| *k.borrow_mut() = Some(e));
}

/// The error [`keep_error`] kept on this thread, taken (what the root module's `take_error`
/// answers).
pub fn take_kept_error() -> Option<PluginError> {
    KEPT.try_with(|k| k.borrow_mut().take()).ok().flatten()
}

static HOOK: Once = Once::new();

/// Set once the host has loaded the library through its exported root module: this copy
/// of std (and its panic hook) then serves the plugin's code alone.
static LIBRARY_MODE: AtomicBool = AtomicBool::new(false);

/// Deferred reports printed because no guard took them (for the tests).
static PRINTED_UNCLAIMED: AtomicUsize = AtomicUsize::new(0);

/// A deferred panic report: location and message.
struct Report {
    at: Option<String>,
    text: String,
}

/// The slot of [`UNCLAIMED`]: prints what is left in it when the thread ends.
struct Unclaimed(RefCell<Option<Report>>);

impl Drop for Unclaimed {
    fn drop(&mut self) {
        if let Some(r) = self.0.get_mut().take() {
            print_unclaimed(&r);
        }
    }
}

#[cold]
fn print_unclaimed(r: &Report) {
    PRINTED_UNCLAIMED.fetch_add(1, Ordering::Relaxed);
    let at = r.at.as_deref().unwrap_or("an unknown location");
    let thread = std::thread::current();
    let name = thread.name().unwrap_or("<unnamed>");
    eprintln!("plugin thread '{name}' panicked at {at}:\n{}", r.text);
}

/// The panic's message, when it is text.
fn payload_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "non-string panic payload".to_string()
    }
}

/// Library mode (see the module docs): called by the exported root-module symbol, which only a
/// host reaches (through the dynamic loader), never code linked into the host.
pub fn set_library_mode() {
    install_quiet_hook();
    LIBRARY_MODE.store(true, Ordering::Relaxed);
}

fn install_quiet_hook() {
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let at = info
                .location()
                .map(|l| format!("{}:{}", l.file(), l.line()));
            if DEPTH.with(Cell::get) > 0 {
                LOCATION.with(|c| *c.borrow_mut() = at);
            } else if LIBRARY_MODE.load(Ordering::Relaxed) {
                let report = Report {
                    at,
                    text: payload_text(info.payload()),
                };
                // A report still unclaimed is printed now: nothing caught its panic. On a thread
                // whose slot is already gone (a panic while it ends) the report is printed at once.
                let mut report = Some(report);
                let _ = UNCLAIMED.try_with(|u| {
                    if let Some(r) = report.take() {
                        if let Some(old) = u.0.borrow_mut().replace(r) {
                            print_unclaimed(&old);
                        }
                    }
                });
                if let Some(r) = report {
                    print_unclaimed(&r);
                }
            } else {
                LOCATION.with(|c| *c.borrow_mut() = at);
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
/// the first `": "` names the call site (the host counts by it). Inlined into each entry point:
/// in library mode (a library a host loaded) the call costs a flag test and
/// `catch_unwind`, nothing else; the depth-counting path is out of line.
#[inline]
pub fn guarded<T>(
    what: &str,
    f: impl FnOnce() -> Result<T, PluginError>,
) -> RResult<T, PluginError> {
    if LIBRARY_MODE.load(Ordering::Relaxed) {
        return guarded_call(what, f).into();
    }
    guarded_counting(what, f)
}

/// [`guarded`] outside library mode: the hook installed and the thread-local depth counted, so
/// that the hook knows the panic is caught.
#[inline(never)]
fn guarded_counting<T>(
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

/// [`guarded`] for the per-sample calls (a material's `sample`, `eval`, `pdf`, a light's
/// `sample_toward`, …): no thread-local on the way in or out, only `catch_unwind`, which costs nothing while
/// nothing panics. The panic hook learns nothing from it; in library mode it defers the report,
/// which the error here takes (see the module docs). The same message as [`guarded`].
#[inline]
pub fn guarded_call<T>(
    what: &str,
    f: impl FnOnce() -> Result<T, PluginError>,
) -> Result<T, PluginError> {
    match catch_unwind(AssertUnwindSafe(f)) {
        Ok(r) => r,
        Err(payload) => Err(panic_error(what, payload)),
    }
}

/// The error for a caught panic: `"{what} panicked at {file}:{line}: {message}"`. The location is
/// the one the hook left: a deferred report (library mode) or the guard's.
#[cold]
fn panic_error(what: &str, payload: Box<dyn std::any::Any + Send>) -> PluginError {
    let msg = payload_text(&*payload);
    let deferred = UNCLAIMED
        .try_with(|u| u.0.borrow_mut().take())
        .ok()
        .flatten();
    let at = match deferred {
        Some(r) => r.at,
        None => LOCATION.with(|c| c.borrow_mut().take()),
    }
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
    }

    // The kept-error slot: a kept error is taken once, on its own thread only; a second
    // one kept before the take replaces the first.
    #[test]
    fn a_kept_error_is_taken_once_on_its_thread() {
        assert!(take_kept_error().is_none());
        keep_error(PluginError::new(ErrorKind::Other, "first"));
        keep_error(PluginError::new(ErrorKind::Other, "second"));
        let other = std::thread::spawn(take_kept_error).join().unwrap();
        assert!(other.is_none(), "another thread's");
        assert_eq!(take_kept_error().unwrap().message.as_str(), "second");
        assert!(take_kept_error().is_none());
    }

    // Library mode, in one test because it is process-wide (no other test of this crate panics
    // outside a guard). A panic inside the per-sample guard comes back as the same error with its
    // location, and its deferred report is taken (nothing printed); a panic on a thread of the
    // plugin's own, outside any guard, is printed when that thread ends (counted: exactly one).
    #[test]
    fn library_mode_loses_no_report() {
        set_library_mode();
        let before = PRINTED_UNCLAIMED.load(Ordering::Relaxed);
        let e = guarded_call::<()>("pdf", || panic!("lanes {}", 2)).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Panic);
        let site = e.message.split(": ").next().unwrap();
        assert!(
            site.starts_with("pdf panicked at ") && site.contains("guard.rs:"),
            "{e}"
        );
        assert!(e.message.ends_with("lanes 2"), "{e}");
        assert_eq!(PRINTED_UNCLAIMED.load(Ordering::Relaxed), before);
        let r = std::thread::spawn(|| panic!("the plugin's own thread")).join();
        assert!(r.is_err());
        assert_eq!(PRINTED_UNCLAIMED.load(Ordering::Relaxed), before + 1);
        // The older guards take the same path in library mode, with the same message.
        let e = guarded::<()>("x", || panic!("old guard")).unwrap_err();
        assert!(
            e.message.starts_with("x panicked at ") && e.message.contains("guard.rs:"),
            "{e}"
        );
        assert_eq!(PRINTED_UNCLAIMED.load(Ordering::Relaxed), before + 1);
    }
}
