//! Helpers shared by the workspace integration tests.

use std::path::PathBuf;

/// The directory cargo put this test's artifacts in (`target/<profile>`), where the plugin
/// libraries built by `cargo build --workspace` live beside it.
pub fn artifact_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test executable path");
    // target/<profile>/deps/<test-binary>
    exe.parent()
        .and_then(|deps| deps.parent())
        .expect("test binary lives in target/<profile>/deps")
        .to_path_buf()
}

/// Path of the built plugin library of crate `name` (dashes or underscores).
///
/// Panics with the command to run when it is missing: `cargo test` does not build `cdylib`s,
/// the README's test command does.
pub fn plugin_library(name: &str) -> PathBuf {
    let file = format!(
        "{}{}{}",
        std::env::consts::DLL_PREFIX,
        name.replace('-', "_"),
        std::env::consts::DLL_SUFFIX
    );
    let path = artifact_dir().join(&file);
    assert!(
        path.exists(),
        "{} is missing: build the plugin libraries first with the README's test command \
         (`cargo build --workspace` in the same profile)",
        path.display()
    );
    path
}
