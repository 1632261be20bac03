//! Helpers for the tests that build plugins outside the workspace and compare renders.

#![allow(dead_code)] // each test binary uses its own subset

use spectrace::film::XyzImage;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Mutex;

/// The repository root.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ lives in the repository")
        .to_path_buf()
}

static BUILD: Mutex<()> = Mutex::new(());

/// Build the Cargo project at `dir` (relative to the repository; it has its own `[workspace]`
/// and lock file) in release mode and return its library `lib_name`. The target directory is
/// `target/external` beside this test's profile directory, shared by every such project, so the
/// dependencies (the workspace's versions, pinned by `--locked`) compile once; later runs are
/// no-ops. No network is needed when the workspace's own build has filled the registry cache.
pub fn build_external(dir: &str, lib_name: &str) -> PathBuf {
    let _one_at_a_time = BUILD.lock().unwrap_or_else(|e| e.into_inner());
    let target = spectrace_tests::artifact_dir()
        .parent()
        .expect("target/<profile> has a parent")
        .join("external");
    let manifest = repo().join(dir).join("Cargo.toml");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let out = Command::new(cargo)
        .args(["build", "--release", "--locked", "--manifest-path"])
        .arg(&manifest)
        .arg("--target-dir")
        .arg(&target)
        .output()
        .expect("run cargo");
    assert!(
        out.status.success(),
        "building {} failed:\n{}",
        manifest.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let file = format!(
        "{}{}{}",
        std::env::consts::DLL_PREFIX,
        lib_name.replace('-', "_"),
        std::env::consts::DLL_SUFFIX
    );
    let path = target.join("release").join(file);
    assert!(path.exists(), "{} was not built", path.display());
    path
}

/// Mean Y over the whole image and over a `tiles × tiles` grid of tiles (row-major).
pub fn region_means(img: &XyzImage, tiles: u32) -> Vec<f64> {
    let mut out = vec![img.mean_xyz()[1]];
    for ty in 0..tiles {
        for tx in 0..tiles {
            let (x0, x1) = (tx * img.width / tiles, (tx + 1) * img.width / tiles);
            let (y0, y1) = (ty * img.height / tiles, (ty + 1) * img.height / tiles);
            let mut sum = 0.0;
            for y in y0..y1 {
                for x in x0..x1 {
                    sum += img.xyz[(y * img.width + x) as usize][1];
                }
            }
            out.push(sum / ((x1 - x0) * (y1 - y0)) as f64);
        }
    }
    out
}

/// Mean and standard error of the mean over independent renders (one value per render).
pub fn mean_and_se(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}
