//! The entry point: an expanded Mitsuba element tree to a scene description and its notes.

use super::converter::Converter;
use super::props::PROPERTY_TAGS;
use crate::scene::mitsuba::xml::Element;
use crate::scene::SceneError;
use crate::scene_file::description::{OutputDescription, SceneDescription};
use glam::DMat4;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};

/// A converted scene and what the conversion changed.
#[derive(Debug)]
pub struct Conversion {
    /// The spectrace scene. Relative file paths in it resolve against the XML file's directory.
    pub desc: SceneDescription,
    /// One line per kind of change, approximation or dropped element.
    pub notes: Vec<String>,
}

/// Convert an expanded scene tree; `dir` is the main scene file's directory.
pub fn convert_tree(root: &Element, dir: &Path) -> Result<Conversion, SceneError> {
    let mut ids: HashMap<&str, &Element> = HashMap::new();
    fn collect<'a>(
        e: &'a Element,
        ids: &mut HashMap<&'a str, &'a Element>,
    ) -> Result<(), SceneError> {
        for c in &e.children {
            if c.tag != "ref" {
                if let Some(id) = c.attr("id") {
                    if let Some(prev) = ids.insert(id, c) {
                        return Err(c.error(format!(
                            "id \"{id}\" is used twice (first at {})",
                            prev.at()
                        )));
                    }
                }
            }
            collect(c, ids)?;
        }
        Ok(())
    }
    collect(root, &mut ids)?;
    // `<path>` folders anywhere at scene level (includes are already expanded), last first.
    let search: Vec<PathBuf> = root
        .children
        .iter()
        .rev()
        .filter(|c| c.tag == "path")
        .filter_map(|c| c.attr("value").map(PathBuf::from))
        .collect();
    let mut cv = Converter {
        dir: dir.to_path_buf(),
        search,
        ids,
        desc: SceneDescription {
            units: Some("m".into()),
            emission_units: None,
            observer: Some("cie1931-2".into()),
            output: OutputDescription {
                rgb_space: Some("srgb".into()),
                ..Default::default()
            },
            materials: vec![],
            objects: vec![],
            lights: vec![],
            cameras: vec![],
            sensors: vec![],
            plugins: vec![],
        },
        notes: BTreeMap::new(),
        used_names: HashSet::new(),
        made: HashMap::new(),
        default_material: None,
    };
    let version = root.attr("version").unwrap_or("3.0.0");
    if !version.starts_with('3') && !version.starts_with('2') {
        cv.note(
            "scene version",
            format!("a Mitsuba {version} file: parameter names upgraded as Mitsuba 3 does (camelCase → snake_case)"),
            "",
        );
    }
    for c in &root.children {
        match c.tag.as_str() {
            "shape" => cv.shape(c, &DMat4::IDENTITY, "")?,
            "emitter" => cv.emitter(c)?,
            "sensor" => cv.sensor(c)?,
            "integrator" => cv.integrator(c)?,
            "bsdf" => {
                // Made when a shape refers to it; one nobody uses is noted.
                let used = root_refers(root, c.attr("id"));
                if !used {
                    cv.note(
                        "unused bsdf",
                        "declared but used by no shape: left out",
                        c.attr("id").unwrap_or(""),
                    );
                }
            }
            "texture" | "spectrum" | "rgb" | "float" | "path" => {}
            "medium" | "phase" | "volume" => cv.note(
                "media",
                "participating media are not supported: dropped",
                c.attr("id").unwrap_or(""),
            ),
            other if PROPERTY_TAGS.contains(&other) => cv.note(
                &format!("<{other}> at scene level"),
                "ignored",
                c.attr("id").unwrap_or(""),
            ),
            other => return Err(c.error(format!("unknown element <{other}>"))),
        }
    }
    if cv.desc.cameras.is_empty() {
        cv.note(
            "no sensor",
            "Mitsuba's default camera is not made: add a <sensor>",
            "",
        );
    }
    let notes = cv
        .notes
        .iter()
        .map(|(k, n)| {
            if n.items.is_empty() {
                format!("{k}: {}", n.message)
            } else {
                let shown: Vec<&str> = n.items.iter().take(6).map(|s| s.as_str()).collect();
                let more = if n.items.len() > 6 {
                    format!(" and {} more", n.items.len() - 6)
                } else {
                    String::new()
                };
                format!("{k}: {} ({}{more})", n.message, shown.join(", "))
            }
        })
        .collect();
    Ok(Conversion {
        desc: cv.desc,
        notes,
    })
}

pub(super) fn root_refers(root: &Element, id: Option<&str>) -> bool {
    let Some(id) = id else { return false };
    fn walk(e: &Element, id: &str) -> bool {
        e.children
            .iter()
            .any(|c| (c.tag == "ref" && c.attr("id") == Some(id)) || walk(c, id))
    }
    walk(root, id)
}
