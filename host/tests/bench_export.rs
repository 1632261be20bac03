//! `spectrace bench export`: a bench scene is written once and each renderer gets the same
//! geometry, spectra and camera. Checked against the scene files' own numbers and against the
//! built scene; and, where `SPECTRACE_ANCHOR_PYTHON` names a Python with Mitsuba 3 and
//! pyluxcore (not in CI), against what those renderers report they loaded.

use spectrace::analysis::bench_scene::export_scene;
use spectrace::geometry::{load_ply, WorldShape};
use spectrace::scene::SceneSource;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "spectrace-bench-export-{name}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// World-space bounds of a built shape.
fn bounds(shape: &WorldShape) -> ([f64; 3], [f64; 3]) {
    let pts: Vec<[f64; 3]> = match shape {
        WorldShape::Mesh(m) => m
            .positions
            .iter()
            .map(|p| [p.x as f64, p.y as f64, p.z as f64])
            .collect(),
        WorldShape::Quad(q) => q
            .vertices
            .iter()
            .map(|p| [p.x as f64, p.y as f64, p.z as f64])
            .collect(),
        WorldShape::Sphere(s) => {
            let (c, r) = (s.center, s.radius as f64);
            vec![
                [c.x as f64 - r, c.y as f64 - r, c.z as f64 - r],
                [c.x as f64 + r, c.y as f64 + r, c.z as f64 + r],
            ]
        }
    };
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in pts {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// `material[key]` at `nm` on the export's wavelength grid.
fn at(export: &serde_json::Value, material: &serde_json::Value, key: &str, nm: f64) -> f64 {
    let grid = export["wavelengths_nm"].as_array().unwrap();
    let i = grid.iter().position(|w| w.as_f64() == Some(nm)).unwrap();
    material[key][i].as_f64().unwrap()
}

// The Cornell box (millimetres in the file, metres exported): the white reflectance at 400 nm
// is the table's 0.343 and at 402 nm halfway to the next entry (0.445 at 404 nm), linear as
// spectrace interpolates (1e-6: f32 evaluation); the lamp's radiance at 450 nm is halfway
// between 0 at 400 nm and 8 at 500 nm (relative units, as written); the camera is the file's
// (0.278, 0.273, −0.8) m; every PLY re-read has the built shape's triangles and vertices
// (1e-6 m: f32 positions written and read back unchanged).
#[test]
fn cornell_box_exports_the_files_numbers_and_the_built_geometry() {
    let scene_path = repo().join("scenes/cornell_box.ron");
    let dir = tmp("cornell");
    let e = export_scene(&scene_path, &dir).unwrap();
    let j = &e.json;
    assert_eq!(j["format"], "spectrace-bench-scene/1");
    let white = &j["materials"]["white"];
    assert_eq!(white["type"], "diffuse");
    assert!((at(j, white, "reflectance", 400.0) - 0.343).abs() < 1e-6);
    let mid = 0.5 * (0.343 + 0.445);
    assert!((at(j, white, "reflectance", 402.0) - mid).abs() < 1e-6);
    let lamp = &j["materials"]["light_emitter"];
    let l450 = at(j, lamp, "radiance", 450.0);
    assert!((l450 - 4.0).abs() < 1e-5, "{l450}");
    let pos: Vec<f64> = j["camera"]["position"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    for (a, b) in pos.iter().zip([0.278, 0.273, -0.8]) {
        assert!((a - b).abs() < 1e-9, "{pos:?}");
    }
    assert_eq!(
        (j["width"].as_u64(), j["height"].as_u64()),
        (Some(256), Some(256))
    );
    let scene = SceneSource::from_path(Some(scene_path))
        .build(&Default::default())
        .unwrap();
    let shapes = j["shapes"].as_array().unwrap();
    assert_eq!(shapes.len(), scene.objects.objects().len());
    for (i, s) in shapes.iter().enumerate() {
        let mesh = load_ply(&dir.join(s["ply"].as_str().unwrap())).unwrap();
        let built = scene.geometry.shape(i as u32).unwrap();
        let (lo, hi) = bounds(built);
        let (elo, ehi) = bounds(&WorldShape::Mesh(mesh.clone()));
        for k in 0..3 {
            assert!((lo[k] - elo[k]).abs() < 1e-6 && (hi[k] - ehi[k]).abs() < 1e-6);
        }
        if let WorldShape::Mesh(m) = built {
            assert_eq!(m.indices.len(), mesh.indices.len());
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

// What an anchor cannot render the same way is refused, naming the item: a dispersive glass
// (Mitsuba's dielectric takes one IOR), a material type without an equivalent, a non-area light.
#[test]
fn what_the_anchors_cannot_share_is_refused() {
    let dir = tmp("refuse");
    std::fs::create_dir_all(&dir).unwrap();
    let base = |materials: &str, lights: &str| {
        format!(
            "(materials: [{materials}, (name: \"lamp\", type: \"emissive\", params: (radiance: \"e\", scale: 1.0))],
              objects: [(name: \"thing\", type: \"quad\", material: \"m\", params: (corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (0, 1, 0))),
                        (name: \"lamp\", type: \"quad\", material: \"lamp\", params: (corner: (0, 0, 1), edge0: (1, 0, 0), edge1: (0, 1, 0)))],
              lights: [{lights}],
              cameras: [(name: \"c\", type: \"perspective\", params: (position: (0.5, 0.5, 3), look_at: (0.5, 0.5, 0), resolution: (8, 8)))])"
        )
    };
    let cases = [
        (
            base(
                "(name: \"m\", type: \"dielectric\", params: (ior: \"N-BK7\"))",
                "",
            ),
            "dispersive",
        ),
        (base("(name: \"m\", type: \"mirror\")", ""), "mirror"),
        (
            base(
                "(name: \"m\", type: \"lambertian\", params: (reflectance: 0.5))",
                "(name: \"p\", type: \"point\", params: (position: (0, 1, 0), power: 1))",
            ),
            "light 'p'",
        ),
    ];
    for (k, (text, expect)) in cases.iter().enumerate() {
        let path = dir.join(format!("case{k}.ron"));
        std::fs::write(&path, text).unwrap();
        let err = export_scene(&path, &dir.join(format!("out{k}"))).unwrap_err();
        assert!(err.contains(expect) && err.contains("case"), "{err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Python named by SPECTRACE_ANCHOR_PYTHON, when it can import the renderers.
fn anchor_python() -> Option<PathBuf> {
    let Some(py) = std::env::var_os("SPECTRACE_ANCHOR_PYTHON") else {
        println!(
            "skipped: SPECTRACE_ANCHOR_PYTHON is not set (a Python with mitsuba and pyluxcore)"
        );
        return None;
    };
    Some(PathBuf::from(py))
}

fn describe(py: &Path, scene_json: &Path, renderer: &str) -> Option<serde_json::Value> {
    let out = std::process::Command::new(py)
        .arg(repo().join("scripts/anchors/anchor_render.py"))
        .args(["describe", "--renderer", renderer, "--scene-json"])
        .arg(scene_json)
        .output()
        .ok()?;
    if out.status.code() == Some(3) {
        println!(
            "skipped: {renderer} cannot be imported ({})",
            String::from_utf8_lossy(&out.stderr)
        );
        return None;
    }
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let line = String::from_utf8_lossy(&out.stdout)
        .lines()
        .rev()
        .find_map(|l| l.find("{\"").map(|i| l[i..].to_string()))
        .unwrap();
    Some(serde_json::from_str(&line).unwrap())
}

// What Mitsuba 3 and LuxCore load from the export is what spectrace renders: Mitsuba's shape
// bounds equal the built shapes' (1e-5 m: f32 geometry), its diffuse reflectances and
// emitters' radiances at 450/550/650 nm equal spectrace's own material evaluation (1e-4
// relative: f32 on both sides, linear interpolation between the 1-nm samples, which fall on
// these wavelengths), its camera sits at the scene's position looking at the scene's target
// with the scene's horizontal field of view; LuxCore's camera has the same origin and target
// and every shape is defined. Scenes: the Cornell box, the spectral caustic (mesh with
// normals), the glossy metals.
#[test]
fn anchors_load_what_spectrace_renders() {
    let Some(py) = anchor_python() else { return };
    for name in [
        "scenes/cornell_box.ron",
        "scenes/bench/spectral_caustic.ron",
        "scenes/bench/glossy_metals.ron",
    ] {
        let scene_path = repo().join(name);
        let dir = tmp(&name.replace('/', "_"));
        let e = export_scene(&scene_path, &dir).unwrap();
        let j = &e.json;
        let scene = SceneSource::from_path(Some(scene_path.clone()))
            .build(&Default::default())
            .unwrap();
        let Some(m) = describe(&py, &e.path, "mitsuba") else {
            return;
        };
        // The anchors' frame: centred on the specular objects and scaled up where there are
        // some (the spectral caustic's glass), the scene's own frame otherwise; the bounds
        // below are reported back in the scene's frame, so they check the transform too.
        let scale = m["frame"]["scale"].as_f64().unwrap();
        let has_specular =
            j["materials"].as_object().unwrap().values().any(|m| {
                m["type"] == "dielectric" || (m["type"] == "conductor" && m["alpha"] == 0.0)
            });
        assert_eq!(scale > 1.0, has_specular, "{name}: frame {}", m["frame"]);
        for (i, s) in j["shapes"].as_array().unwrap().iter().enumerate() {
            let name = s["name"].as_str().unwrap();
            let got = &m["shapes"][name];
            let (lo, hi) = bounds(scene.geometry.shape(i as u32).unwrap());
            for k in 0..3 {
                let (gl, gh) = (
                    got["min"][k].as_f64().unwrap(),
                    got["max"][k].as_f64().unwrap(),
                );
                assert!(
                    (gl - lo[k]).abs() < 1e-5 && (gh - hi[k]).abs() < 1e-5,
                    "{name}: {got} vs {lo:?} {hi:?}"
                );
            }
            let mat = &j["materials"][s["material"].as_str().unwrap()];
            let key = match mat["type"].as_str().unwrap() {
                "diffuse" => "reflectance",
                "emitter" => "radiance",
                _ => continue,
            };
            for (k, nm) in [450.0, 550.0, 650.0].iter().enumerate() {
                let ours = at(j, mat, key, *nm);
                let theirs = got[key][k].as_f64().unwrap_or(f64::NAN);
                assert!(
                    (ours - theirs).abs() <= 1e-4 * ours.abs().max(1e-3),
                    "{name} {key} at {nm} nm: spectrace {ours}, Mitsuba {theirs}"
                );
            }
        }
        let cam = &j["camera"];
        let v = |x: &serde_json::Value| -> Vec<f64> {
            x.as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect()
        };
        let (pos, look) = (v(&cam["position"]), v(&cam["look_at"]));
        let len = (0..3)
            .map(|k| (look[k] - pos[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let origin = v(&m["camera"]["origin"]);
        let forward = v(&m["camera"]["forward"]);
        for k in 0..3 {
            assert!((origin[k] - pos[k]).abs() < 1e-5, "{origin:?} {pos:?}");
            assert!(
                (forward[k] - (look[k] - pos[k]) / len).abs() < 1e-5,
                "{forward:?}"
            );
        }
        if cam["fov_axis"] == "x" {
            let fov = m["camera"]["x_fov"].as_f64().unwrap();
            assert!(
                (fov - cam["fov_deg"].as_f64().unwrap()).abs() < 1e-4,
                "{fov}"
            );
        }
        if let Some(l) = describe(&py, &e.path, "luxcore") {
            let (o, t) = (v(&l["camera"]["origin"]), v(&l["camera"]["target"]));
            for k in 0..3 {
                assert!((o[k] - pos[k]).abs() < 1e-6 && (t[k] - look[k]).abs() < 1e-6);
            }
            for s in j["shapes"].as_array().unwrap() {
                assert_eq!(
                    l["shapes"][s["name"].as_str().unwrap()]["defined"],
                    true,
                    "{l}"
                );
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}
