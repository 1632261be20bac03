//! The `spectrace` command line. Each subcommand lives in `spectrace::cli`; this file only
//! parses arguments and reports errors.

fn main() {
    // Rust starts with SIGPIPE ignored, so writing to a closed pipe (`spectrace … | head`)
    // makes every `println!` panic. Restoring the default action ends the process quietly
    // instead, as other command-line tools do; nothing here writes to pipes or sockets whose
    // closing should be survived (images and checkpoints go to files).
    #[cfg(unix)]
    // SAFETY: `signal` with `SIG_DFL` only changes this process's disposition for SIGPIPE; it
    // runs first in `main`, before any thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // Plugin libraries are opened in a probe process first: one that crashes while loading
    // takes the probe down, not this render.
    if let Ok(exe) = std::env::current_exe() {
        spectrace::plugin::loader::enable_child_probe(exe);
    }
    std::process::exit(spectrace::cli::main_with_args(std::env::args_os()));
}
