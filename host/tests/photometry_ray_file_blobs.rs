//! `ray_file` lights as blobs (`spectrace blob pack`): a file up to the embedding limit travels
//! inside the blob (base64, with its SHA-256) and the blob renders after the file is gone; a
//! larger file is referred to by absolute path and SHA-256, and a changed file is refused by name.
//! Run: `cargo test --release -p spectrace --test photometry_ray_file_blobs`.

use spectrace::builtin::light::ray_file::EMBED_LIMIT_BYTES;
use spectrace::light::Light;
use spectrace::photometry::tm25::{write_tm25, Tm25Spectrum, WriteHeader, WriteRay};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::PluginFactory;
use spectrace::scene::{load_scene_file, Scene};
use spectrace_plugin_api::RandomSample;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::Arc;

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spectrace-ray-blobs-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn spectrace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spectrace"))
        .args(args)
        .output()
        .unwrap()
}

fn run(args: &[&str]) -> String {
    let out = spectrace(args);
    assert!(
        out.status.success(),
        "spectrace {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned() + &String::from_utf8_lossy(&out.stderr)
}

fn scene_text(light: &str) -> String {
    format!(
        r#"(
        units: "cm",
        materials: [(name: "grey", type: "lambertian", params: (reflectance: 0.5))],
        objects: [(name: "floor", type: "quad", material: "grey",
                   params: (corner: (-200, 0, 200), edge0: (400, 0, 0), edge1: (0, 0, -400)))],
        lights: [{light}],
        cameras: [(name: "c", type: "pinhole", params: (position: (0, 100, 300), look_at: (0, 0, 0),
                   resolution: (4, 4)))],
    )"#
    )
}

fn try_load(path: &Path) -> Result<Scene, String> {
    let factory = PluginFactory::new(
        Arc::new(spectrace::plugin::builtin_registry()),
        PluginFaults::new(),
    );
    load_scene_file(path, &[&factory]).map_err(|e| e.to_string())
}

/// 5 000 beams drawn with the same random numbers from two lights: equal bit for bit.
fn assert_same_beams(a: &dyn Light, b: &dyn Light) {
    assert_eq!(a.power().to_bits(), b.power().to_bits());
    for i in 0..5000u32 {
        let u = RandomSample {
            u: std::array::from_fn(|k| ((i as f64 + 0.5) / 5000.0 + 0.291 * k as f64).fract()),
        };
        assert_eq!(a.next_beam(&u), b.next_beam(&u), "beam {i}");
    }
}

/// Quantity: the beams (origin, direction, wavelength, power) of a `ray_file` light and of its
/// blob, after the file was removed: identical bit for bit (no tolerance: the blob holds the
/// same bytes and the same parameters, the scene's centimetres converted to metres as the scene
/// does). The blob's payload holds the file (base64: 4/3 of 316 288 bytes); `blob inspect`
/// shows the SHA-256 and not the whole base64 text.
#[test]
fn small_ray_file_travels_inside_the_blob() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes/rays/cylinder_10k_lighttools.TM25RAY");
    let copy = temp("led.TM25RAY");
    std::fs::copy(&src, &copy).unwrap();
    let scene = temp("small.ron");
    std::fs::write(
        &scene,
        scene_text(
            r#"(name: "led", type: "ray_file", params: (file: "led.TM25RAY",
                 position: (0, 50, 0), spd: "d65", max_rays: 3000))"#,
        ),
    )
    .unwrap();
    let original = try_load(&scene).unwrap();
    let blob = temp("led.blob");
    run(&[
        "blob",
        "pack",
        "--scene",
        scene.to_str().unwrap(),
        "--light",
        "led",
        "-o",
        blob.to_str().unwrap(),
    ]);
    let size = std::fs::metadata(&blob).unwrap().len();
    assert!(size > 316_288 * 4 / 3, "blob of {size} bytes");
    std::fs::remove_file(&copy).unwrap();
    let inspect = run(&["blob", "inspect", blob.to_str().unwrap()]);
    assert!(inspect.contains("sha256"), "{inspect}");
    assert!(inspect.len() < 10_000, "{} bytes printed", inspect.len());
    let baked = temp("small_blob.ron");
    std::fs::write(
        &baked,
        scene_text(r#"(name: "b", type: "blob", params: (file: "led.blob"))"#),
    )
    .unwrap();
    let from_blob = try_load(&baked).unwrap();
    assert_same_beams(
        original.lights.lights()[0].as_ref(),
        from_blob.lights.lights()[0].as_ref(),
    );
}

/// A file over the embedding limit (600 000 rays, 16.8 MB): the blob refers to it (its payload
/// stays under 1 KB plus the path), loads to the same beams while the file is unchanged, and
/// is refused, naming the SHA-256 it expected, once one ray's flux changed. A scene may pin a
/// file the same way (`sha256`): a wrong hash is refused naming both.
#[test]
fn large_ray_file_is_pinned_by_sha256() {
    let n = 600_000u64;
    let big = temp("big.TM25RAY");
    let header = WriteHeader {
        luminous_flux_lm: f32::NAN,
        radiant_flux_w: 0.6,
        date: "2026-12-06T00:00:00Z".into(),
        texts: Default::default(),
        spectrum: Tm25Spectrum::Single(555.0),
    };
    let rays = (0..n).map(|i| {
        let t = (i as f32 + 0.5) / n as f32;
        let (s, c) = (t * 40.0).sin_cos();
        let z = 1.0 - t;
        let r = (1.0 - z * z).sqrt();
        WriteRay {
            position_mm: [c, s, 0.0],
            direction: [r * c, r * s, z],
            flux_w: 1e-6,
            wavelength_nm: 555.0,
        }
    });
    let mut out = std::io::BufWriter::new(std::fs::File::create(&big).unwrap());
    write_tm25(&mut out, &header, n, rays).unwrap();
    drop(out);
    assert!(std::fs::metadata(&big).unwrap().len() > EMBED_LIMIT_BYTES);
    let scene = temp("big.ron");
    std::fs::write(
        &scene,
        scene_text(
            r#"(name: "led", type: "ray_file", params: (file: "big.TM25RAY",
                 position: (0, 50, 0), max_rays: 2000))"#,
        ),
    )
    .unwrap();
    let original = try_load(&scene).unwrap();
    let blob = temp("big.blob");
    let said = run(&[
        "blob",
        "pack",
        "--scene",
        scene.to_str().unwrap(),
        "--light",
        "led",
        "-o",
        blob.to_str().unwrap(),
    ]);
    assert!(said.contains("SHA-256"), "{said}");
    assert!(std::fs::metadata(&blob).unwrap().len() < 1024 + 4096);
    let from_blob_scene = temp("big_blob.ron");
    std::fs::write(
        &from_blob_scene,
        scene_text(r#"(name: "b", type: "blob", params: (file: "big.blob"))"#),
    )
    .unwrap();
    let from_blob = try_load(&from_blob_scene).unwrap();
    assert_same_beams(
        original.lights.lights()[0].as_ref(),
        from_blob.lights.lights()[0].as_ref(),
    );
    // One ray's flux changed (still a valid file): the blob no longer loads.
    let mut bytes = std::fs::read(&big).unwrap();
    let at = bytes.len() - 4;
    bytes[at..].copy_from_slice(&2e-6f32.to_le_bytes());
    std::fs::write(&big, &bytes).unwrap();
    let err = try_load(&from_blob_scene).unwrap_err();
    println!("{err}");
    assert!(
        err.contains("SHA-256") && err.contains("big.TM25RAY"),
        "{err}"
    );
    // A scene's own pin.
    let pinned = temp("pinned.ron");
    std::fs::write(
        &pinned,
        scene_text(&format!(
            r#"(name: "led", type: "ray_file", params: (file: "big.TM25RAY",
                 position: (0, 50, 0), sha256: "{}"))"#,
            "0".repeat(64)
        )),
    )
    .unwrap();
    let err = try_load(&pinned).unwrap_err();
    assert!(
        err.contains(&"0".repeat(64)) && err.contains("sha256"),
        "{err}"
    );
    let _ = std::fs::remove_file(&big);
}
