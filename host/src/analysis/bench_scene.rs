//! A benchmark scene written once (a spectrace scene file) and exported to the anchor renderers:
//! `spectrace bench export SCENE --out DIR` writes DIR/scene.json and one PLY per object, which
//! `scripts/anchors/anchor_render.py` turns into a Mitsuba 3 or LuxCore scene. Everything is
//! taken from the scene spectrace builds, not from a second description:
//!
//! | exported        | taken from                                                          |
//! |-----------------|---------------------------------------------------------------------|
//! | geometry        | the built geometry in world space, metres (meshes with their vertex normals; quads as two triangles with the same winding); analytic spheres as spheres |
//! | reflectance     | the built material: π·f(n, n) of a `lambertian` at every wavelength |
//! | radiance        | the built emitter: its normalised SPD × its scale, W/(m²·sr·nm)     |
//! | IOR, n and k, α | the material's parameters (`dielectric`: constant IOR only; `conductor`: its n, k table) |
//! | camera          | the first camera's parameters (pinhole, box filter), in metres     |
//!
//! Spectra are sampled every nanometre from 360 to 830 nm (the CIE 1931 table's range), so the
//! anchors' linear interpolation reproduces spectrace's curves to within the curvature over
//! 1 nm. Anything an anchor cannot represent the same way (other materials, textures that vary
//! over the surface, a thin lens, another observer or RGB space, non-area lights) is an error
//! naming the item: a bench scene is either the same everywhere or not exported.

use crate::builtin::camera::perspective::PerspectiveParams;
use crate::builtin::material::conductor::ConductorParams;
use crate::builtin::material::dielectric::DielectricParams;
use crate::builtin::spectral::{alpha, Ior};
use crate::geometry::{TriangleMesh, WorldShape};
use crate::material::metals::ComplexIorTable;
use crate::material::{Material, ShadingContext, TransportMode};
use crate::scene::{Scene, SceneSource};
use crate::scene_file::SceneDescription;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// Wavelengths of every exported spectrum, nm: 360, 361, …, 830.
pub fn grid_nm() -> Vec<f64> {
    (360..=830).map(f64::from).collect()
}

/// Format tag of scene.json; the Python side refuses other versions.
pub const FORMAT: &str = "spectrace-bench-scene/1";

/// An exported scene: the JSON written to `dir/scene.json` and the files beside it.
#[derive(Debug, Clone)]
pub struct ExportedScene {
    /// The document.
    pub json: Value,
    /// Where scene.json was written.
    pub path: PathBuf,
}

fn fail(scene: &Path, msg: impl std::fmt::Display) -> String {
    format!("{}: cannot export to the anchors: {msg}", scene.display())
}

/// `f` at every wavelength of `grid`, `LANES` at a time.
fn sample_grid(grid: &[f64], f: impl Fn(&SampledWavelengths) -> SampledSpectrum) -> Vec<f64> {
    let mut out = Vec::with_capacity(grid.len());
    for chunk in grid.chunks(LANES) {
        let lambda =
            SampledWavelengths::from_lanes(|i| (chunk[i.min(chunk.len() - 1)] as f32, 1.0));
        let v = f(&lambda);
        for i in 0..chunk.len() {
            out.push(f64::from(v[i]));
        }
    }
    out
}

/// π·f(n, n) of a diffuse material: its reflectance at normal incidence (exact for a Lambertian
/// surface, whose f is ρ/π in every direction).
fn diffuse_reflectance(m: &dyn Material, grid: &[f64]) -> Vec<f64> {
    let n = Vec3A::Z;
    let ctx = ShadingContext::at(Vec3A::ZERO, n, n, Vec2::splat(0.5));
    sample_grid(grid, |l| m.eval(n, n, &ctx, l, TransportMode::Radiance))
        .into_iter()
        .map(|f| f * std::f64::consts::PI)
        .collect()
}

fn write_ply(path: &Path, mesh: &TriangleMesh) -> Result<(), String> {
    let mut b: Vec<u8> = Vec::new();
    let normals = mesh.normals.as_ref();
    let mut header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment written by spectrace bench export\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
        mesh.positions.len()
    );
    if normals.is_some() {
        header += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    header += &format!(
        "element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.indices.len()
    );
    b.extend_from_slice(header.as_bytes());
    for (i, p) in mesh.positions.iter().enumerate() {
        for c in p.to_array() {
            b.extend_from_slice(&c.to_le_bytes());
        }
        if let Some(ns) = normals {
            for c in ns[i].normalize_or_zero().to_array() {
                b.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    for t in &mesh.indices {
        b.push(3);
        for &i in t {
            b.extend_from_slice(&(i as i32).to_le_bytes());
        }
    }
    std::fs::write(path, b).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The triangles of a world-space quad `v0 v1 v2 v3` (spectrace's winding): (0, 1, 2), (0, 2, 3).
fn quad_mesh(v: &[Vec3A; 4]) -> TriangleMesh {
    TriangleMesh {
        positions: v.to_vec(),
        normals: None,
        uvs: None,
        indices: vec![[0, 1, 2], [0, 2, 3]],
    }
}

fn v3(v: Vec3A) -> Value {
    json!([v.x as f64, v.y as f64, v.z as f64])
}

/// Export `scene_path` into `dir` (created): scene.json and shape_N.ply files.
pub fn export_scene(scene_path: &Path, dir: &Path) -> Result<ExportedScene, String> {
    let text = std::fs::read_to_string(scene_path)
        .map_err(|e| format!("cannot read {}: {e}", scene_path.display()))?;
    let desc: SceneDescription =
        crate::scene::builder::parse_scene_str(&text, scene_path).map_err(|e| e.to_string())?;
    let scene = SceneSource::from_path(Some(scene_path.to_path_buf()))
        .build(&Default::default())
        .map_err(|e| e.to_string())?;
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let json = export_built(scene_path, &desc, &scene, dir)?;
    let path = dir.join("scene.json");
    let text = serde_json::to_string_pretty(&json).map_err(|e| e.to_string())?;
    std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(ExportedScene { json, path })
}

fn export_built(
    scene_path: &Path,
    desc: &SceneDescription,
    scene: &Scene,
    dir: &Path,
) -> Result<Value, String> {
    check_exportable(scene_path, desc, scene)?;
    let (camera, width, height) = export_camera(scene_path, desc, scene)?;
    let grid = grid_nm();
    let (materials, shapes) = export_objects(scene_path, desc, scene, dir, &grid)?;
    Ok(json!({
        "format": FORMAT,
        "source": scene_path.display().to_string(),
        "width": width,
        "height": height,
        "max_depth": scene.options.max_depth,
        "camera": camera,
        "wavelengths_nm": grid,
        "materials": materials,
        "shapes": shapes,
        "units": "m; spectral radiance W/(m^2 sr nm); reflectance unitless",
    }))
}

/// An error unless the scene's lights, observer and RGB space are what the anchors render:
/// emissive objects only, CIE 1931 2°, linear sRGB.
fn check_exportable(
    scene_path: &Path,
    desc: &SceneDescription,
    scene: &Scene,
) -> Result<(), String> {
    let err = |m: String| fail(scene_path, m);
    if !desc.lights.is_empty() {
        return Err(err(format!(
            "light '{}' is not an area light (only emissive objects are exported)",
            desc.lights[0].name
        )));
    }
    if let Some(o) = &desc.observer {
        let (name, _) = o.type_and_params();
        if name != "cie1931-2" {
            return Err(err(format!(
                "observer '{name}': the anchors' films use CIE 1931 2°"
            )));
        }
    }
    if !scene.options.rgb_space_name.eq_ignore_ascii_case("srgb") {
        return Err(err(format!(
            "rgb_space '{}': the anchors write linear sRGB",
            scene.options.rgb_space_name
        )));
    }
    Ok(())
}

/// The first camera (perspective or pinhole, no lens, box filter) in metres, and the image size.
fn export_camera(
    scene_path: &Path,
    desc: &SceneDescription,
    scene: &Scene,
) -> Result<(Value, u32, u32), String> {
    let err = |m: String| fail(scene_path, m);
    let metres = scene.options.length_unit.metres();
    let cam_desc = desc
        .cameras
        .first()
        .ok_or_else(|| err("no camera".into()))?;
    if !matches!(
        cam_desc.type_name.as_str(),
        "perspective" | "pinhole" | "thin_lens"
    ) {
        return Err(err(format!(
            "camera '{}' of type '{}' (only perspective/pinhole)",
            cam_desc.name, cam_desc.type_name
        )));
    }
    let cam: PerspectiveParams =
        crate::builtin::from_value(&cam_desc.params).map_err(|e| err(e.to_string()))?;
    if cam_desc.type_name != "pinhole" && cam.lens_radius.unwrap_or(0.0) != 0.0 {
        return Err(err("a thin-lens camera (lens_radius > 0)".into()));
    }
    if cam
        .filter
        .as_ref()
        .is_some_and(|f| !matches!(f, ron::Value::String(s) if s == "box"))
    {
        return Err(err(
            "a pixel filter other than the default box (the anchors use a 1-pixel box)".into(),
        ));
    }
    let (width, height) = scene
        .cameras
        .get(None)
        .map(|c| c.camera.resolution())
        .map_err(|e| err(e.to_string()))?;
    let scale = |p: [f64; 3]| json!([p[0] * metres, p[1] * metres, p[2] * metres]);
    let camera = json!({
        "position": scale(cam.position),
        "look_at": scale(cam.look_at),
        "up": cam.up.unwrap_or([0.0, 1.0, 0.0]),
        "fov_deg": cam.fov.unwrap_or(40.0),
        "fov_axis": cam.fov_axis.clone().unwrap_or_else(|| "x".into()),
    });

    Ok((camera, width, height))
}

/// Each object's material (spectra on `grid`, each material once) and shape (spheres inline,
/// meshes and quads as PLY files in `dir`).
fn export_objects(
    scene_path: &Path,
    desc: &SceneDescription,
    scene: &Scene,
    dir: &Path,
    grid: &[f64],
) -> Result<(serde_json::Map<String, Value>, Vec<Value>), String> {
    let err = |m: String| fail(scene_path, m);
    let mut materials = serde_json::Map::new();
    let mut shapes = Vec::new();
    for (i, obj) in scene.objects.objects().iter().enumerate() {
        let od = desc
            .objects
            .iter()
            .find(|o| o.name == obj.name)
            .ok_or_else(|| err(format!("object '{}' not in the scene file", obj.name)))?;
        let md = desc
            .materials
            .iter()
            .find(|m| m.name == od.material)
            .ok_or_else(|| err(format!("material '{}' not in the scene file", od.material)))?;
        if !materials.contains_key(&md.name) {
            let m = export_material(md, obj.material.as_ref(), grid)
                .map_err(|e| err(format!("material '{}': {e}", md.name)))?;
            materials.insert(md.name.clone(), m);
        }
        let shape = scene
            .geometry
            .shape(i as u32)
            .ok_or_else(|| err(format!("object '{}' has no shape", obj.name)))?;
        let entry = match shape {
            WorldShape::Sphere(s) => json!({
                "name": obj.name, "material": md.name,
                "sphere": {"center": v3(s.center), "radius": s.radius as f64},
            }),
            WorldShape::Mesh(m) => {
                let file = format!("shape_{i}.ply");
                write_ply(&dir.join(&file), m)?;
                json!({"name": obj.name, "material": md.name, "ply": file,
                       "triangles": m.indices.len(), "normals": m.normals.is_some()})
            }
            WorldShape::Quad(q) => {
                let file = format!("shape_{i}.ply");
                write_ply(&dir.join(&file), &quad_mesh(&q.vertices))?;
                json!({"name": obj.name, "material": md.name, "ply": file,
                       "triangles": 2, "normals": false})
            }
        };
        shapes.push(entry);
    }
    Ok((materials, shapes))
}

fn export_material(
    md: &crate::scene_file::description::ItemDescription,
    m: &dyn Material,
    grid: &[f64],
) -> Result<Value, String> {
    match md.type_name.as_str() {
        "lambertian" | "diffuse" => {
            if let ron::Value::Map(map) = &md.params {
                if map.keys().any(|k| matches!(k, ron::Value::String(s) if s != "reflectance")) {
                    return Err("only `reflectance` can be exported".into());
                }
            }
            Ok(json!({"type": "diffuse", "reflectance": diffuse_reflectance(m, grid)}))
        }
        "emissive" => {
            let e = m.emission().ok_or("an emissive material without emission")?;
            if !e.spd.delta_lines().is_empty() {
                return Err("an emission with spectral lines (a sampled grid cannot hold them)".into());
            }
            let values: Vec<f64> = grid
                .iter()
                .map(|&nm| f64::from(e.scale) * e.spd.value(nm))
                .collect();
            Ok(json!({"type": "emitter", "radiance": values, "two_sided": e.two_sided}))
        }
        "dielectric" => {
            let p: DielectricParams =
                crate::builtin::from_value(&md.params).map_err(|e| e.to_string())?;
            match p.ior {
                None => Ok(json!({"type": "dielectric", "ior": 1.5})),
                Some(Ior::Number(n)) => Ok(json!({"type": "dielectric", "ior": n})),
                Some(other) => Err(format!(
                    "a dispersive IOR ({other:?}): Mitsuba's dielectric takes a constant"
                )),
            }
        }
        "conductor" | "rough_conductor" => {
            let p: ConductorParams =
                crate::builtin::from_value(&md.params).map_err(|e| e.to_string())?;
            let table = match (&p.n, &p.k) {
                (Some(n), Some(k)) => {
                    let rows: Vec<(f32, f32, f32)> = n
                        .iter()
                        .zip(k)
                        .map(|(&(l, n), &(_, k))| (l as f32, n as f32, k as f32))
                        .collect();
                    ComplexIorTable::from_rows(&rows)?
                }
                _ => ComplexIorTable::builtin(p.metal.as_deref().unwrap_or("aluminium"))?,
            };
            let a = alpha(p.alpha, p.roughness).map_err(|e| e.to_string())?;
            let (eta, k): (Vec<f64>, Vec<f64>) = grid
                .iter()
                .map(|&nm| {
                    let (n, k) = table.eval(nm as f32);
                    (f64::from(n), f64::from(k))
                })
                .unzip();
            Ok(json!({"type": "conductor", "eta": eta, "k": k, "alpha": f64::from(a)}))
        }
        other => Err(format!(
            "type '{other}' has no exported equivalent (lambertian, emissive, dielectric, conductor)"
        )),
    }
}
