//! Blobs of every kind (material, light, SPD, observer) for built-in types: packed from a
//! scene's items, moved to another folder, the scene's files (CSV spectra included) deleted,
//! and loaded again to an identical object.

use spectrace::integrator::{render, RenderSettings, SampleBudget};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::blob::Blob;
use spectrace::plugin::factory::{Built, RegistryFactory};
use spectrace::plugin::ObjectKind;
use spectrace::scene::{load_scene_file, ObjectFactory};
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "spectrace-blob-kinds-{}-{name}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn factory() -> RegistryFactory {
    RegistryFactory::new(
        Arc::new(spectrace::plugin::builtin_registry()),
        PluginFaults::new(),
    )
}

const SCENE: &str = r#"(
    observer: "cie1964-10",
    materials: [
        (name: "wall", type: "lambertian", params: (reflectance: "refl.csv")),
        (name: "glass", type: "dielectric", params: (ior: (sellmeier: (b: (1.03961212, 0.231792344, 1.01046945), c: (0.00600069867, 0.0200179144, 103.560653))))),
        (name: "metal", type: "rough_conductor", params: (metal: "gold", roughness: 0.3)),
        (name: "glow", type: "emissive", params: (radiance: "lamp.csv", scale: 5)),
    ],
    objects: [
        (name: "floor", type: "quad", material: "wall", params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
        (name: "ball", type: "sphere", material: "metal", params: (center: (-0.6, 0.5, 0), radius: 0.5)),
        (name: "lens", type: "sphere", material: "glass", params: (center: (0.6, 0.4, 0.3), radius: 0.4)),
        (name: "panel", type: "quad", material: "glow", params: (corner: (-0.5, 2, -0.5), edge0: (0, 0, 1), edge1: (1, 0, 0))),
    ],
    lights: [
        (name: "lamp", type: "point", params: (position: (0, 1.5, 1), power: 40, spd: "lamp.csv")),
        (name: "sun", type: "spot", params: (position: (2, 2, 2), target: (0, 0, 0), power: 20, spd: (type: "spec", params: (spec: "blackbody:3000")))),
    ],
    cameras: [(name: "c", type: "perspective", params: (position: (0, 1, 4), look_at: (0, 0.5, 0), fov: 45, resolution: (24, 16)))],
)"#;

/// The items packed: (kind, name in the scene, blob file).
const ITEMS: [(ObjectKind, &str, &str); 10] = [
    (ObjectKind::Material, "wall", "wall.blob"),
    (ObjectKind::Material, "glass", "glass.blob"),
    (ObjectKind::Material, "metal", "metal.blob"),
    (ObjectKind::Material, "glow", "glow.blob"),
    (ObjectKind::Light, "lamp", "lamp.blob"),
    (ObjectKind::Light, "sun", "sun.blob"),
    (ObjectKind::Spd, "lamp.spd", "lamp_spd.blob"),
    (ObjectKind::Spd, "sun.spd", "sun_spd.blob"),
    (ObjectKind::Spd, "glow.radiance", "glow_radiance.blob"),
    (ObjectKind::Observer, "cie1964-10", "eye.blob"),
];

/// The scene with every material, light and the observer replaced by its blob.
fn blob_scene() -> String {
    let mut s = SCENE.replace(
        "observer: \"cie1964-10\"",
        "observer: (type: \"blob\", params: (file: \"eye.blob\"))",
    );
    let start = s.find("materials: [").unwrap();
    let end = s.find("    objects:").unwrap();
    s.replace_range(start..end, "materials: [\n".to_string().as_str());
    let mut mats = String::new();
    for m in ["wall", "glass", "metal", "glow"] {
        mats +=
            &format!("        (name: \"{m}\", type: \"blob\", params: (file: \"{m}.blob\")),\n");
    }
    s.insert_str(start + "materials: [\n".len(), &format!("{mats}    ],\n"));
    let start = s.find("lights: [").unwrap();
    let end = s.find("    cameras:").unwrap();
    s.replace_range(
        start..end,
        "lights: [\n        (name: \"lamp\", type: \"blob\", params: (file: \"lamp.blob\")),\n        (name: \"sun\", type: \"blob\", params: (file: \"sun.blob\")),\n    ],\n",
    );
    s
}

fn image(scene: &Path) -> Vec<[f64; 3]> {
    let f = factory();
    let factories: [&dyn ObjectFactory; 1] = [&f];
    let s = load_scene_file(scene, &factories).unwrap_or_else(|e| panic!("{e}"));
    let settings = RenderSettings {
        budget: SampleBudget::Spp(2),
        seed: 11,
        threads: Some(2),
        ..RenderSettings::default()
    };
    let img = render(&s, &settings, &|_, _| {}, None).unwrap().image;
    assert!(img.mean_xyz()[1] > 0.0, "the test scene is lit");
    img.xyz
}

/// Sampled values of an object at many wavelengths (SPD: value, pdf, sample; observer: x̄ȳz̄).
fn probe(b: &Built) -> Vec<f64> {
    let mut out = Vec::new();
    for i in 0..=470 {
        let nm = 360.0 + i as f64;
        match b {
            Built::Spd(s) => {
                out.push(s.value(nm));
                out.push(s.pdf(nm));
                out.push(s.sample(i as f64 / 471.0).lambda);
            }
            Built::Observer(o) => out.extend(o.xyz_bar(nm)),
            _ => {}
        }
    }
    out
}

/// Quantity: every pixel of a small render (24×16, 2 spp, fixed seed) of a scene whose four
/// materials, two lights and observer are all blobs, against the same render of the original
/// scene; and SPD values, pdfs and samples (and the observer's x̄ȳz̄) at 471 wavelengths
/// against the originals. Tolerance: none (bit-identical): a blob holds the same parameters
/// (CSV tables embedded with their exact values) and the same constructors build from them, so
/// anything but equality is a bug. Checked after the blobs are moved to another folder and the
/// scene folder, with its CSV files, is deleted.
#[test]
fn every_kind_round_trips_through_a_moved_blob_without_its_sources() {
    let src = dir("src");
    let moved = dir("moved");
    let csv = "wavelength_nm,value\n380,0.1\n450,0.8\n520,0.3\n600,1.0\n700,0.4\n780,0.2\n";
    std::fs::write(src.join("lamp.csv"), csv).unwrap();
    std::fs::write(
        src.join("refl.csv"),
        "wavelength_nm,value\n380,0.05\n500,0.4\n620,0.9\n780,0.7\n",
    )
    .unwrap();
    let scene = src.join("scene.ron");
    std::fs::write(&scene, SCENE).unwrap();

    let registry = spectrace::plugin::builtin_registry();
    let f = factory();
    let mut originals = Vec::new();
    for (kind, name, file) in ITEMS {
        let blob = Blob::pack_scene_item(&registry, &scene, kind, name)
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(blob.plugin, "builtin");
        let tmp = src.join(file);
        blob.write_file(&tmp).unwrap();
        originals.push(probe(
            &Blob::read_file(&tmp).unwrap().instantiate(&f).unwrap(),
        ));
        std::fs::rename(&tmp, moved.join(file)).unwrap();
    }
    let reference = image(&scene);
    // The original SPDs and observer, built from the scene's own parameters.
    let direct: Vec<Vec<f64>> = ITEMS
        .iter()
        .map(|(kind, name, _)| match kind {
            ObjectKind::Spd => {
                let (item, param) = name.split_once('.').unwrap();
                let desc = spectrace::scene::parse_scene_str(SCENE, &scene).unwrap();
                let owner = desc
                    .lights
                    .iter()
                    .chain(&desc.materials)
                    .find(|i| i.name == item)
                    .unwrap();
                let v = spectrace::scene_file::params::Params::new(&owner.params)
                    .get(param)
                    .unwrap()
                    .clone();
                let spectrum: spectrace::builtin::spectral::Spectrum =
                    spectrace::builtin::from_value(&v).unwrap();
                let ctx = f.context(&src, "probe".into());
                let (spd, _) = spectrace::builtin::spectral::spd(&spectrum, param, &ctx).unwrap();
                probe(&Built::Spd(spd))
            }
            ObjectKind::Observer => probe(&Built::Observer(
                f.observer(name, &ron::Value::Unit, &f.context(&src, "probe".into()))
                    .unwrap(),
            )),
            _ => Vec::new(),
        })
        .collect();
    assert_eq!(originals, direct, "blob objects sample like the originals");

    std::fs::remove_dir_all(&src).unwrap();
    let blob_scene_path = moved.join("scene.ron");
    std::fs::write(&blob_scene_path, blob_scene()).unwrap();
    for ((kind, name, file), original) in ITEMS.iter().zip(&originals) {
        let b = Blob::read_file(&moved.join(file))
            .unwrap()
            .instantiate(&f)
            .unwrap_or_else(|e| panic!("{kind} {name}: {e}"));
        assert_eq!(&probe(&b), original, "{kind} {name} after the move");
    }
    assert_eq!(
        image(&blob_scene_path),
        reference,
        "same image from the blobs"
    );
    let _ = std::fs::remove_dir_all(&moved);
}

/// A blob of format 1 (built-in parameters as RON text) is refused with the way out.
#[test]
fn old_format_blobs_are_refused_clearly() {
    let mut bytes = Blob {
        kind: ObjectKind::Light,
        plugin: "builtin".into(),
        plugin_version: "0.1.0".into(),
        type_name: "point".into(),
        type_version: 1,
        payload: vec![1, 2, 3],
    }
    .encode()
    .unwrap();
    bytes[8..10].copy_from_slice(&1u16.to_le_bytes());
    let e = Blob::decode(&bytes).unwrap_err().to_string();
    assert!(e.contains("version 1") && e.contains("blob pack"), "{e}");
}
