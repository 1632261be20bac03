//! Plugin libraries that are damaged or named the short way, against real built plugins:
//! a library cut short (an interrupted copy) used to kill the process with SIGBUS as soon as it
//! was mapped, even when it merely sat in a plugin folder. It is now one clear error naming the
//! file, the other libraries of the folder still load, and the process lives on.

use spectrace::plugin::Registry;
use spectrace_tests::{artifact_dir, plugin_library};
use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "spectrace-robust-plugins-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A copy of `src` cut to `len` bytes.
fn truncated_copy(src: &Path, dst: &Path, len: usize) {
    let bytes = std::fs::read(src).unwrap();
    std::fs::write(dst, &bytes[..len]).unwrap();
}

/// Cuts at many places of a real plugin (the middle and near the end, where the section
/// headers are; inside the first page, where the segments are described): each one is refused
/// by name as damaged, none is mapped (a mapped one would end this test process with SIGBUS).
#[test]
fn a_cut_short_library_is_one_error_and_the_folder_still_loads() {
    let good = plugin_library("spectrace-point-light");
    let len = std::fs::metadata(&good).unwrap().len() as usize;
    for cut in [len / 2, len - 1, len - 4096, 100, 4096, len / 10] {
        let dir = tmp_dir(&format!("cut{cut}"));
        // The damaged copy sorts first, so the good one loads after it.
        truncated_copy(&good, &dir.join("liba_damaged.so"), cut);
        std::fs::copy(&good, dir.join("libb_point_light.so")).unwrap();
        let mut registry = Registry::new();
        let errors = registry.load_plugin_dir(&dir);
        assert_eq!(errors.len(), 1, "cut at {cut}: {errors:?}");
        let e = errors[0].to_string();
        assert!(
            e.contains("liba_damaged.so") && e.contains("cut short"),
            "cut at {cut}: {e}"
        );
        assert_eq!(
            registry.plugins().len(),
            1,
            "cut at {cut}: the good library loads"
        );
        assert!(registry.plugins()[0].path.ends_with("libb_point_light.so"));
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// Naming the damaged library directly is an error that names it, not a crash.
#[test]
fn a_cut_short_library_named_directly_is_refused() {
    let good = plugin_library("spectrace-rough-diffuse");
    let dir = tmp_dir("direct");
    let bad = dir.join("librough_cut.so");
    let len = std::fs::metadata(&good).unwrap().len() as usize;
    truncated_copy(&good, &bad, len * 3 / 4);
    let e = Registry::new().load_plugin(&bad).unwrap_err().to_string();
    assert!(
        e.contains("librough_cut.so") && e.contains("cut short"),
        "{e}"
    );
}

/// `--plugin libfoo.so` for a file in the current folder failed (the system loader searches
/// only its own path for a name without a slash); it now loads, and `spectrace plugins` lists
/// the plugin. A damaged library on SPECTRACE_PLUGIN_PATH is reported and the process exits 0.
#[test]
fn a_bare_library_name_is_found_in_the_current_folder() {
    let good = plugin_library("spectrace-point-light");
    let dir = tmp_dir("cwd");
    std::fs::copy(&good, dir.join("libfoo.so")).unwrap();
    let damaged = tmp_dir("envpath");
    truncated_copy(&good, &damaged.join("libcut.so"), 5000);
    let out = Command::new(artifact_dir().join("spectrace"))
        .args(["plugins", "--plugin", "libfoo.so"])
        .current_dir(&dir)
        .env("SPECTRACE_PLUGIN_PATH", &damaged)
        .output()
        .expect("run spectrace");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}{stderr}");
    assert!(stdout.contains("isotropic_point"), "{stdout}");
    assert!(
        stderr.contains("libcut.so") && stderr.contains("cut short"),
        "{stderr}"
    );
}

/// A structurally sound library whose start-up code aborts (the `crashing-init` fixture) took
/// the whole process down while it was opened. The `spectrace` command opens every library in a
/// probe process first: the abort costs the probe, the folder's good library still loads, and
/// the command exits 0 with one warning naming the file and the signal.
#[test]
#[cfg(target_os = "linux")]
fn a_library_that_crashes_while_opening_is_caught_by_the_probe() {
    let crashing = plugin_library("spectrace-fixture-crashing-init");
    let good = plugin_library("spectrace-point-light");
    let dir = tmp_dir("probe");
    std::fs::copy(&crashing, dir.join("liba_crashing.so")).unwrap();
    std::fs::copy(&good, dir.join("libb_point_light.so")).unwrap();
    let out = Command::new(artifact_dir().join("spectrace"))
        .args(["plugins", "--plugins"])
        .arg(&dir)
        .env_remove("SPECTRACE_PLUGIN_PATH")
        .output()
        .expect("run spectrace");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{:?}\n{stdout}{stderr}", out.status);
    assert!(stdout.contains("isotropic_point"), "{stdout}");
    assert!(
        stderr.contains("liba_crashing.so") && stderr.contains("crashed a probe process (SIGABRT)"),
        "{stderr}"
    );
    // Named directly, it is an error (exit code 1), still not a crash.
    let out = Command::new(artifact_dir().join("spectrace"))
        .args(["plugins", "--plugin"])
        .arg(dir.join("liba_crashing.so"))
        .env_remove("SPECTRACE_PLUGIN_PATH")
        .output()
        .expect("run spectrace");
    assert_eq!(out.status.code(), Some(1), "{out:?}");
}
