//! The sun-and-sky environment map shared by the environment tests
//! (`render_envmap_paths.rs`, `integrators_bdpt_environment_mis.rs`): a small sky whose sun
//! carries half the light from a tiny solid angle, the case where the light's sampling matters.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// A fresh folder for one test's files (`prefix`-`tag`-pid under the temporary folder).
pub fn temp_dir(prefix: &str, tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("spectrace-{prefix}-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A 64 × 32 sky: white-blue above the horizon, dark ground below, and a "sun" of 2 × 2 nodes
/// (≈ 0.03 sr once interpolated) at 300× the sky, about 45° up: it gives about half of the
/// light on a horizontal plane, from 0.3% of the directions.
pub fn write_sun_sky(path: &Path) {
    let (w, h) = (64usize, 32usize);
    exr::prelude::write_rgb_file(path, w, h, |x, y| {
        if (20..22).contains(&x) && (8..10).contains(&y) {
            (300.0, 290.0, 270.0)
        } else if y < h / 2 {
            (0.6, 0.8, 1.0)
        } else {
            (0.1, 0.08, 0.06)
        }
    })
    .unwrap();
}
