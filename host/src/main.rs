//! The `spectrace` command line. Each subcommand lives in `spectrace::cli`; this file only
//! parses arguments and reports errors.

fn main() {
    // Plugin libraries are opened in a probe process first: one that crashes while loading
    // takes the probe down, not this render.
    if let Ok(exe) = std::env::current_exe() {
        spectrace::plugin::loader::enable_child_probe(exe);
    }
    std::process::exit(spectrace::cli::main_with_args(std::env::args_os()));
}
