//! Ctrl-C (SIGINT) or SIGTERM during a render or reference run: the first asks the renderer to
//! stop after the tiles in flight (the whole passes rendered so far are written, with a
//! checkpoint for `render --resume`); a second exits at once.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;

static FLAG: AtomicBool = AtomicBool::new(false);
static INSTALLED: OnceLock<bool> = OnceLock::new();

/// The flag set by Ctrl-C, installing the handler on first use. If the handler cannot be
/// installed (another one exists), the flag simply never gets set.
pub fn interrupt_flag() -> &'static AtomicBool {
    INSTALLED.get_or_init(|| {
        ctrlc::set_handler(|| {
            if FLAG.swap(true, Ordering::SeqCst) {
                eprintln!("\nspectrace: interrupted again, exiting without saving");
                std::process::exit(130);
            }
            eprintln!("\nspectrace: interrupted; finishing the tiles in flight and saving what is rendered (interrupt again to quit at once)");
        })
        .is_ok()
    });
    &FLAG
}

/// True once Ctrl-C has been pressed.
pub fn interrupted() -> bool {
    FLAG.load(Ordering::SeqCst)
}
