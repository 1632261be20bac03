//! The embedded default scene: the measured spectral Cornell box, built from
//! `host/data/scenes/cornell_box.json` (Cornell Program of Computer Graphics, "Cornell Box
//! Data"; see the file's `sources`): geometry in mm, measured white/red/green reflectances
//! (400–700 nm), the light's spectral radiance, the camera at (278, 273, −800) looking +z with a
//! 39.31° horizontal field, 256×256. The scene says `units: "mm"` (it is built in metres) and
//! `emission_units: "relative"`: the emission spectrum's shape is measured, its scale is not. `scenes/cornell_box.ron` is the same description as a file.

use super::{build_scene_with, BuiltinFactory, Scene, SceneError};
use crate::scene_file::description::{
    ItemDescription, ObjectDescription, OutputDescription, SceneDescription,
};
use crate::scene_file::RepresentationOptions;
use ron::{Map, Number, Value};
use std::path::Path;

/// The measured Cornell box data. Source: host/data/scenes/cornell_box.json (Cornell "Cornell Box Data", see its `sources`).
const CORNELL_JSON: &str = include_str!("../../data/scenes/cornell_box.json");

fn num(v: f64) -> Value {
    Value::Number(Number::new(v))
}

fn tuple(vals: &[f64]) -> Value {
    Value::Seq(vals.iter().map(|&v| num(v)).collect())
}

fn map(entries: Vec<(&str, Value)>) -> Value {
    let mut m = Map::new();
    for (k, v) in entries {
        m.insert(Value::String(k.to_string()), v);
    }
    Value::Map(m)
}

fn json_err(what: &str) -> SceneError {
    SceneError::Scene {
        file: "host/data/scenes/cornell_box.json".into(),
        message: format!("unexpected structure: {what}"),
    }
}

fn f64s(v: &serde_json::Value, what: &str) -> Result<Vec<f64>, SceneError> {
    v.as_array()
        .ok_or_else(|| json_err(what))?
        .iter()
        .map(|x| x.as_f64().ok_or_else(|| json_err(what)))
        .collect()
}

fn spectrum_pairs(v: &serde_json::Value, what: &str) -> Result<Value, SceneError> {
    let rows = v.as_array().ok_or_else(|| json_err(what))?;
    let mut out = Vec::with_capacity(rows.len());
    for r in rows {
        let p = f64s(r, what)?;
        if p.len() != 2 {
            return Err(json_err(what));
        }
        out.push(tuple(&p));
    }
    Ok(Value::Seq(out))
}

/// The Cornell box as a scene description (what `scenes/cornell_box.ron` contains).
pub fn cornell_box_description() -> Result<SceneDescription, SceneError> {
    let d: serde_json::Value =
        serde_json::from_str(CORNELL_JSON).map_err(|e| json_err(&e.to_string()))?;
    let spectra = &d["spectra"];
    let mut materials = Vec::new();
    for name in ["white", "red", "green"] {
        materials.push(ItemDescription {
            name: name.into(),
            type_name: "lambertian".into(),
            params: map(vec![("reflectance", spectrum_pairs(&spectra[name], name)?)]),
        });
    }
    materials.push(ItemDescription {
        name: "light_emitter".into(),
        type_name: "emissive".into(),
        params: map(vec![
            (
                "radiance",
                spectrum_pairs(&spectra["light_emission"], "light_emission")?,
            ),
            ("two_sided", Value::Bool(false)),
        ]),
    });
    let surfaces = d["surfaces"]
        .as_object()
        .ok_or_else(|| json_err("surfaces"))?;
    let mut objects = Vec::new();
    for (name, s) in surfaces {
        let material = s["material"]
            .as_str()
            .ok_or_else(|| json_err("surface material"))?;
        let quads = s["quads"].as_array().ok_or_else(|| json_err("quads"))?;
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        for q in quads {
            let verts = q.as_array().ok_or_else(|| json_err("quad"))?;
            if verts.len() != 4 {
                return Err(json_err("a quad needs 4 vertices"));
            }
            let base = positions.len() as f64;
            for v in verts {
                let p = f64s(v, "vertex")?;
                if p.len() != 3 {
                    return Err(json_err("vertex"));
                }
                positions.push(tuple(&p));
            }
            // Two triangles with the quad's winding (which fixes the front side).
            let int = |v: f64| Value::Number(Number::from(v as i64));
            indices.push(Value::Seq(vec![
                int(base),
                int(base + 1.0),
                int(base + 2.0),
            ]));
            indices.push(Value::Seq(vec![
                int(base),
                int(base + 2.0),
                int(base + 3.0),
            ]));
        }
        objects.push(ObjectDescription {
            name: name.clone(),
            type_name: "mesh".into(),
            material: material.into(),
            params: map(vec![
                ("positions", Value::Seq(positions)),
                ("indices", Value::Seq(indices)),
            ]),
            transform: Vec::new(),
        });
    }
    let cam = &d["camera"];
    let size = f64s(&cam["image_size"], "image_size")?;
    let camera = ItemDescription {
        name: "cornell".into(),
        type_name: "pinhole".into(),
        params: map(vec![
            ("position", tuple(&f64s(&cam["position"], "position")?)),
            ("look_at", tuple(&f64s(&cam["look_at"], "look_at")?)),
            ("up", tuple(&f64s(&cam["up"], "up")?)),
            (
                "fov",
                num(cam["fov_deg"].as_f64().ok_or_else(|| json_err("fov_deg"))?),
            ),
            ("fov_axis", Value::String("x".into())),
            ("resolution", tuple(&size)),
            ("filter", Value::String("box".into())),
        ]),
    };
    Ok(SceneDescription {
        // The data are in millimetres; the light's spectrum is measured in shape only.
        units: Some("mm".into()),
        emission_units: Some("relative".into()),
        observer: Some("cie1931-2".into()),
        output: OutputDescription {
            spp: Some(64),
            max_depth: Some(64),
            rgb_space: Some("srgb".into()),
            png_exposure: Some(1.0),
        },
        materials,
        objects,
        lights: Vec::new(),
        cameras: vec![camera],
        sensors: Vec::new(),
        plugins: Vec::new(),
    })
}

/// The default scene, built with the built-in factory.
pub fn default_scene() -> Result<Scene, SceneError> {
    default_scene_with(&RepresentationOptions::default())
}

/// The default scene with the spectral representation switches `representation`.
pub fn default_scene_with(representation: &RepresentationOptions) -> Result<Scene, SceneError> {
    cornell_box_with(&[&BuiltinFactory], representation)
}

/// The default scene with its types built by `factories` (e.g. the registry's factory, whose
/// types may come from a library instead of the built-ins).
pub fn cornell_box_with(
    factories: &[&dyn crate::scene_file::ObjectFactory],
    representation: &RepresentationOptions,
) -> Result<Scene, SceneError> {
    let desc = cornell_box_description()?;
    build_scene_with(
        &desc,
        Path::new("."),
        Path::new("<embedded cornell box>"),
        factories,
        representation,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `scenes/cornell_box.ron` must describe exactly the embedded default scene (both come from
    /// the same JSON data; this catches either drifting). Regenerate the file with
    /// `SPECTRACE_WRITE_CORNELL_RON=1 cargo test -p spectrace --lib scene::cornell`.
    #[test]
    fn shipped_ron_matches_embedded_scene() {
        let desc = cornell_box_description().unwrap();
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/cornell_box.ron");
        if std::env::var_os("SPECTRACE_WRITE_CORNELL_RON").is_some() {
            let cfg = ron::ser::PrettyConfig::new()
                .depth_limit(4)
                .separate_tuple_members(false)
                .enumerate_arrays(false);
            let text = ron::ser::to_string_pretty(&desc, cfg).unwrap();
            let header = "// The measured spectral Cornell box (Cornell Program of Computer Graphics, \"Cornell Box Data\"),\n// generated from host/data/scenes/cornell_box.json; identical to `spectrace render` with no scene.\n// Units: mm (declared by `units`); reflectances unitless; emission as spectral radiance\n// (W/(m²·sr·nm)) of measured shape but unknown scale, hence `emission_units: \"relative\"`.\n";
            std::fs::write(&path, format!("{header}{text}\n")).unwrap();
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let parsed = crate::scene::parse_scene_str(&text, &path).unwrap();
        assert_eq!(parsed, desc);
    }
}
