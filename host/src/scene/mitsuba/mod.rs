//! Mitsuba 3 XML scenes: `spectrace render scene.xml` reads them through [`convert_file`], and
//! `spectrace convert scene.xml -o scene.ron` writes the spectrace scene they become.
//!
//! Three layers, data flowing one way: [`xml`] reads the files (includes, `default`, `$name`,
//! limits), [`convert`] maps the element tree to a [`SceneDescription`] with a note for every
//! change, [`serialized`] reads Mitsuba's compressed mesh format and [`spectra`] its spectra.
//! What is supported, approximated and dropped: `docs/mitsuba-import.md`.

pub mod convert;
pub mod serialized;
pub mod spectra;
pub mod xml;

pub use convert::Conversion;

use crate::scene::SceneError;
use crate::scene_file::description::SceneDescription;
use std::path::Path;

/// True when `path` names a Mitsuba XML scene (by its extension).
pub fn is_mitsuba_file(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
}

/// Read and convert a Mitsuba 3 scene file with command-line parameters `defines`
/// (`-D name=value`, which win over the file's `default`s). Relative paths in the result
/// resolve against the file's directory.
pub fn convert_file(path: &Path, defines: &[(String, String)]) -> Result<Conversion, SceneError> {
    let root = xml::read_scene(path, defines)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    convert::convert_tree(&root, dir)
}

/// [`convert_file`] for the scene loader: the conversion notes go to standard error, one line
/// each, and the description is returned.
pub fn read_description(
    path: &Path,
    defines: &[(String, String)],
) -> Result<SceneDescription, SceneError> {
    let c = convert_file(path, defines)?;
    for n in &c.notes {
        eprintln!("warning: {}: Mitsuba import: {n}", path.display());
    }
    Ok(c.desc)
}

/// Parse `-D name=value` arguments.
pub fn parse_defines(args: &[String]) -> Result<Vec<(String, String)>, String> {
    args.iter()
        .map(|a| {
            let (k, v) = a
                .split_once('=')
                .ok_or_else(|| format!("-D {a}: expected name=value"))?;
            let k = k.trim();
            if k.is_empty() || !k.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Err(format!("-D {a}: the name must be letters, digits and _"));
            }
            Ok((k.to_string(), v.to_string()))
        })
        .collect()
}

#[cfg(test)]
mod tests;
