//! Serialized light sources: pack, inspect, load, and every kind of damaged blob.

use spectrace::plugin::blob::{Blob, BlobError, BlobLoadError, FORMAT_VERSION};
use spectrace::plugin::Registry;
use spectrace_plugin_api::abi::std_types::RStr;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::RandomSample;
use spectrace_tests::{artifact_dir, plugin_library};
use std::path::PathBuf;
use std::process::Command;

const PARAMS: &str =
    "(position: (0, 2, 1), direction: (0, -1, 0), cone_angle_deg: 35, power_w: 42, spd: \"fl11\")";

fn registry() -> Registry {
    let mut r = Registry::new();
    r.load_plugin(&plugin_library("spectrace-point-light"))
        .unwrap();
    r
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spectrace-blob-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn samples() -> impl Iterator<Item = RandomSample> {
    (0..500).map(|i| {
        let mut s = RandomSample::default();
        for (k, u) in s.u.iter_mut().enumerate() {
            // A low-discrepancy-ish deterministic spread (golden-ratio sequence per dimension).
            *u = ((i as f64 + 0.5) * (0.618_033_988_75 + 0.1 * k as f64)).fract();
        }
        s
    })
}

#[test]
fn pack_inspect_load_gives_identical_beams() {
    let r = registry();
    let blob = Blob::pack_plugin_light(&r, "smooth_spot", PARAMS).unwrap();
    let path = tmp("spot.blob");
    blob.write_file(&path).unwrap();

    let read = Blob::read_file(&path).unwrap();
    assert_eq!(read, blob);
    assert_eq!(read.plugin, "point-light");
    let described = read.describe(&r).unwrap();
    assert!(
        described.contains("power_w: 42.0") && described.contains("\"fl11\""),
        "{described}"
    );

    let original = r
        .create_plugin_light("smooth_spot", ObjectSource::Params(RStr::from_str(PARAMS)))
        .unwrap();
    let restored = read.load_plugin_light(&r).unwrap();
    for s in samples() {
        assert_eq!(
            original.light.next_beam(&s).unwrap(),
            restored.light.next_beam(&s).unwrap()
        );
    }
}

#[test]
fn a_blob_whose_plugin_is_absent_names_plugin_and_version() {
    let blob = Blob::pack_plugin_light(
        &registry(),
        "isotropic_point",
        "(position: (0,0,0), power_w: 1)",
    )
    .unwrap();
    let empty = Registry::new();
    let e = blob.load_plugin_light(&empty).err().unwrap();
    assert!(matches!(e, BlobLoadError::MissingPlugin { .. }));
    let msg = e.to_string();
    assert!(
        msg.contains("`point-light`") && msg.contains("version 0.1.0"),
        "{msg}"
    );
}

#[test]
fn a_blob_of_another_type_version_is_refused_by_the_plugin() {
    let mut blob = Blob::pack_plugin_light(
        &registry(),
        "isotropic_point",
        "(position: (0,0,0), power_w: 1)",
    )
    .unwrap();
    blob.type_version = 7;
    let msg = blob
        .load_plugin_light(&registry())
        .err()
        .unwrap()
        .to_string();
    assert!(
        msg.contains("type version 7") && msg.contains("reads version 1"),
        "{msg}"
    );
}

#[test]
fn a_valid_frame_around_a_garbage_payload_is_refused_by_the_plugin() {
    let mut blob = Blob::pack_plugin_light(
        &registry(),
        "isotropic_point",
        "(position: (0,0,0), power_w: 1)",
    )
    .unwrap();
    // A well-formed, checksummed blob whose payload claims a 2^60-byte string.
    blob.payload = vec![0xFF, 0, 0, 0, 0, 0, 0, 0, 0x10];
    let msg = blob
        .load_plugin_light(&registry())
        .err()
        .unwrap()
        .to_string();
    assert!(msg.contains("cannot decode state"), "{msg}");
}

#[test]
fn damaged_blob_files_give_clear_errors() {
    let good = Blob::pack_plugin_light(
        &registry(),
        "isotropic_point",
        "(position: (0,0,0), power_w: 1)",
    )
    .unwrap()
    .encode()
    .unwrap();
    let mut corrupted = good.clone();
    *corrupted.last_mut().unwrap() ^= 0x40;
    let mut wrong_version = good.clone();
    wrong_version[8..10].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
    let mut trailing = good.clone();
    trailing.extend_from_slice(b"extra");
    let mut oversized = good.clone();
    let len_at = good.len() - 4 - 8 - blob_payload_len(&good);
    oversized[len_at..len_at + 8].copy_from_slice(&(1u64 << 40).to_le_bytes());
    let mut beyond = good.clone();
    beyond[len_at..len_at + 8].copy_from_slice(&10_000u64.to_le_bytes());

    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        (
            "truncated.blob",
            good[..good.len() - 3].to_vec(),
            "truncated",
        ),
        (
            "header-cut.blob",
            good[..12].to_vec(),
            "shorter than a blob header",
        ),
        ("corrupted.blob", corrupted, "checksum mismatch"),
        (
            "wrong-version.blob",
            wrong_version,
            "(set below from FORMAT_VERSION)",
        ),
        (
            "not-a-blob.blob",
            b"PK\x03\x04 a zip file, say".to_vec(),
            "not a spectrace blob",
        ),
        (
            "trailing.blob",
            trailing,
            "unexpected bytes after the payload",
        ),
        ("oversized.blob", oversized, "exceeds the limit"),
        ("beyond.blob", beyond, "declares a 10000-byte payload"),
        ("empty.blob", Vec::new(), "truncated"),
    ];
    let newer = format!("format version {} is not supported", FORMAT_VERSION + 1);
    for (name, bytes, needle) in cases {
        let needle = if name == "wrong-version.blob" {
            newer.as_str()
        } else {
            needle
        };
        let path = tmp(name);
        std::fs::write(&path, &bytes).unwrap();
        let msg = Blob::read_file(&path).unwrap_err().to_string();
        assert!(msg.contains(name), "names the file: {msg}");
        assert!(
            msg.contains(needle),
            "{name}: expected `{needle}` in: {msg}"
        );
    }
    let missing = tmp("missing.blob");
    assert!(Blob::read_file(&missing)
        .unwrap_err()
        .to_string()
        .contains("cannot read"));
    assert!(matches!(Blob::decode(&[]), Err(BlobError::TooShort(0))));
}

fn blob_payload_len(bytes: &[u8]) -> usize {
    Blob::decode(bytes).unwrap().payload.len()
}

fn spectrace_bin() -> PathBuf {
    let p = artifact_dir().join(format!("spectrace{}", std::env::consts::EXE_SUFFIX));
    assert!(
        p.exists(),
        "{} missing: run the README's test command",
        p.display()
    );
    p
}

#[test]
fn cli_pack_then_inspect() {
    let lib = plugin_library("spectrace-point-light");
    let out = tmp("cli.blob");
    let pack = Command::new(spectrace_bin())
        .args([
            "blob",
            "pack",
            "isotropic_point",
            "--params",
            "(position: (1, 2, 3), power_w: 7.5, spd: \"a\")",
            "-o",
        ])
        .arg(&out)
        .arg("--plugin")
        .arg(&lib)
        .output()
        .unwrap();
    assert!(
        pack.status.success(),
        "{}",
        String::from_utf8_lossy(&pack.stderr)
    );
    let inspect = Command::new(spectrace_bin())
        .args(["blob", "inspect"])
        .arg(&out)
        .arg("--plugin")
        .arg(&lib)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&inspect.stdout);
    assert!(inspect.status.success());
    for needle in [
        "kind: light",
        "plugin: point-light 0.1.0",
        "type: isotropic_point",
        "power_w: 7.5",
        "position: (1.0, 2.0, 3.0)",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in:\n{text}");
    }
    // Without the plugin: the header still prints, and it says what is needed.
    let bare = Command::new(spectrace_bin())
        .args(["blob", "inspect"])
        .arg(&out)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&bare.stdout);
    assert!(
        text.contains("needs plugin `point-light` (version 0.1.0"),
        "{text}"
    );
}

fn scene(name: &str) -> PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
}

#[test]
fn lights_from_scene_files_pack_both_plugin_and_builtin() {
    let r = {
        let mut r = spectrace::plugin::builtin_registry();
        r.load_plugin(&plugin_library("spectrace-point-light"))
            .unwrap();
        r
    };
    let plugin = Blob::pack_scene_light(&r, &scene("plugin_spot.ron"), "key").unwrap();
    assert_eq!(
        (plugin.plugin.as_str(), plugin.type_name.as_str()),
        ("point-light", "smooth_spot")
    );
    let builtin = Blob::pack_scene_light(&r, &scene("materials.ron"), "spot").unwrap();
    assert_eq!(
        (builtin.plugin.as_str(), builtin.type_name.as_str()),
        ("builtin", "spot")
    );
    let text = builtin.describe(&r).unwrap();
    assert!(
        text.contains("blackbody:2856") && text.contains("1500"),
        "{text}"
    );
    let e = Blob::pack_scene_light(&r, &scene("materials.ron"), "sun").unwrap_err();
    assert!(
        e.contains("materials.ron") && e.contains("no light named `sun`") && e.contains("spot"),
        "{e}"
    );
    // Bad parameters are refused at pack time, naming the parameter.
    let bad: ron::Value = ron::from_str("(position: (0, 1, 0), power: -3)").unwrap();
    let e = Blob::pack_builtin_light("point", &bad).unwrap_err();
    assert!(e.contains("power"), "{e}");
}

#[test]
fn a_scene_lit_by_a_blob_renders_exactly_like_the_original() {
    use spectrace::integrator::{render, RenderSettings, SampleBudget};
    use spectrace::plugin::adapter::PluginFaults;
    use spectrace::plugin::factory::PluginFactory;
    use spectrace::scene::{load_scene_file, BuiltinFactory, ObjectFactory};
    use std::sync::Arc;

    let mut r = spectrace::plugin::builtin_registry();
    r.load_plugin(&plugin_library("spectrace-point-light"))
        .unwrap();
    let blob_path = tmp("key.blob");
    Blob::pack_scene_light(&r, &scene("plugin_spot.ron"), "key")
        .unwrap()
        .write_file(&blob_path)
        .unwrap();
    let original = std::fs::read_to_string(scene("plugin_spot.ron")).unwrap();
    let start = original.find("(name: \"key\"").unwrap();
    let end = start + original[start..].find(")),").unwrap() + 3;
    let with_blob = format!(
        "{}(name: \"key\", type: \"blob\", params: (file: {:?})),{}",
        &original[..start],
        blob_path.to_str().unwrap(),
        &original[end..]
    );
    let blob_scene = tmp("blob_scene.ron");
    std::fs::write(&blob_scene, with_blob).unwrap();

    let registry = Arc::new(r);
    let render_mean = |path: &std::path::Path| {
        let plugins = PluginFactory::new(registry.clone(), PluginFaults::new());
        let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
        let s = load_scene_file(path, &factories).unwrap_or_else(|e| panic!("{e}"));
        let settings = RenderSettings {
            budget: SampleBudget::Spp(2),
            seed: 3,
            threads: Some(2),
            ..RenderSettings::default()
        };
        render(&s, &settings, &|_, _| {}, None).unwrap().image
    };
    let a = render_mean(&scene("plugin_spot.ron"));
    let b = render_mean(&blob_scene);
    // Same light state, same seed: bit-identical images.
    assert_eq!(a.xyz, b.xyz);
    assert!(a.mean_xyz()[1] > 0.0);
}
