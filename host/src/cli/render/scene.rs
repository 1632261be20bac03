//! The scene of a render (step 3 of the pipeline in [`super`]): the file named by the
//! arguments, or the embedded Cornell box, with `--resolution` applied to every camera.

use super::RenderArgs;
use crate::scene::{load_scene_file_with, Scene};
use crate::scene_file::{ObjectFactory, RepresentationOptions};
use std::path::{Path, PathBuf};

/// Load the scene named by `args` (or the default) with the given factories.
pub fn load(args: &RenderArgs, factories: &[&dyn ObjectFactory]) -> Result<Scene, String> {
    let repr = args.representation.options()?;
    let defines = crate::scene::mitsuba::parse_defines(&args.define)?;
    load_scene(
        args.scene.as_deref(),
        args.resolution,
        &defines,
        &repr,
        factories,
    )
}

/// Load the scene file `scene` (or the embedded Cornell box) with the given factories and
/// spectral representation, every camera's `resolution` replaced by `resolution` if given:
/// the scene step of `render` and `reference`.
pub fn load_scene(
    scene: Option<&Path>,
    resolution: Option<(u32, u32)>,
    defines: &[(String, String)],
    repr: &RepresentationOptions,
    factories: &[&dyn ObjectFactory],
) -> Result<Scene, String> {
    let repr = *repr;
    // `-D` needs the description read here (it is not in the file); (0, 0) keeps the cameras'.
    let fallback = (!defines.is_empty()).then_some((0, 0));
    let Some((w, h)) = resolution.or(fallback) else {
        return match scene {
            Some(p) => load_scene_file_with(p, factories, &repr),
            None => crate::scene::cornell::cornell_box_with(factories, &repr),
        }
        .map_err(|e| e.to_string());
    };
    // --resolution: every camera's `resolution` replaced before the scene is built.
    let (mut desc, base, file) = match scene {
        Some(p) => (
            crate::scene::builder::read_scene_file_defined(p, defines)
                .map_err(|e| e.to_string())?,
            p.parent().unwrap_or(Path::new(".")).to_path_buf(),
            p.to_path_buf(),
        ),
        None => (
            crate::scene::cornell_box_description().map_err(|e| e.to_string())?,
            PathBuf::from("."),
            PathBuf::from("<embedded cornell box>"),
        ),
    };
    for c in desc.cameras.iter_mut().filter(|_| w > 0) {
        let size: ron::Value = ron::from_str(&format!("({w}, {h})")).map_err(|e| e.to_string())?;
        match &mut c.params {
            ron::Value::Map(m) => {
                m.insert(ron::Value::String("resolution".into()), size);
            }
            p @ ron::Value::Unit => {
                let mut m = ron::Map::new();
                m.insert(ron::Value::String("resolution".into()), size);
                *p = ron::Value::Map(m);
            }
            _ => {}
        }
    }
    crate::scene::build_scene_with(&desc, &base, &file, factories, &repr).map_err(|e| e.to_string())
}
