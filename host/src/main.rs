//! The `spectrace` command line. Each subcommand lives in `spectrace::cli`; this file only
//! parses arguments and reports errors.

fn main() {
    std::process::exit(spectrace::cli::main_with_args(std::env::args_os()));
}
