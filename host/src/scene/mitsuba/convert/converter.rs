//! The converter's state (the element ids, the description being built, the notes) and what
//! every part of it uses: notes, unique names, references and files.

use super::props::Props;
use crate::scene::mitsuba::xml::Element;
use crate::scene::SceneError;
use crate::scene_file::description::SceneDescription;
use std::collections::{BTreeMap, HashMap, HashSet};
use std::path::{Path, PathBuf};

#[derive(Default)]
pub(super) struct Note {
    pub(super) message: String,
    pub(super) items: Vec<String>,
}

pub(super) struct Converter<'a> {
    pub(super) dir: PathBuf,
    /// Folders from `<path value>` elements, the last one first (Mitsuba prepends them).
    pub(super) search: Vec<PathBuf>,
    pub(super) ids: HashMap<&'a str, &'a Element>,
    pub(super) desc: SceneDescription,
    pub(super) notes: BTreeMap<String, Note>,
    pub(super) used_names: HashSet<String>,
    /// Material already made for a bsdf element (by its address) or emitter key.
    pub(super) made: HashMap<usize, String>,
    pub(super) default_material: Option<String>,
}

impl<'a> Converter<'a> {
    pub(super) fn note(&mut self, key: &str, message: impl Into<String>, item: impl Into<String>) {
        let n = self.notes.entry(key.to_string()).or_default();
        if n.message.is_empty() {
            n.message = message.into();
        }
        let item = item.into();
        if !item.is_empty() && !n.items.contains(&item) {
            n.items.push(item);
        }
    }

    pub(super) fn finish(&mut self, p: &Props, what: &str, item: &str) {
        for name in p.unused() {
            self.note(
                &format!("{what}: parameter `{name}` ignored"),
                "spectrace has no equivalent; the parameter is dropped",
                item,
            );
        }
    }

    pub(super) fn unique(&mut self, base: &str) -> String {
        let base = if base.is_empty() { "item" } else { base };
        let mut name = base.to_string();
        let mut k = 1;
        while !self.used_names.insert(name.clone()) {
            k += 1;
            name = format!("{base}.{k}");
        }
        name
    }

    pub(super) fn resolve(&self, r: &'a Element) -> Result<&'a Element, SceneError> {
        if r.tag != "ref" {
            return Ok(r);
        }
        let id = r.attr("id").ok_or_else(|| r.error("<ref> needs `id`"))?;
        self.ids
            .get(id)
            .copied()
            .ok_or_else(|| r.error(format!("no element has id \"{id}\"")))
    }

    /// A file named in the scene: relative to the element's file, else to the `<path>` folders
    /// (the last declared first), else to the main scene's directory (Mitsuba's resolver);
    /// returned relative to the main directory when inside it.
    pub(super) fn file(&self, el: &Element, name: &str) -> Result<String, SceneError> {
        let here = el.file.parent().unwrap_or(Path::new("."));
        let first = here.join(name);
        let candidates = std::iter::once(first.clone())
            .chain(self.search.iter().map(|d| d.join(name)))
            .chain(std::iter::once(self.dir.join(name)));
        let Some(p) = candidates.into_iter().find(|c| c.exists()) else {
            let tried: Vec<String> = self
                .search
                .iter()
                .chain(std::iter::once(&self.dir))
                .map(|d| d.join(name).display().to_string())
                .collect();
            return Err(el.error(format!(
                "file not found: {} (nor {})",
                first.display(),
                tried.join(", ")
            )));
        };
        Ok(match p.strip_prefix(&self.dir) {
            Ok(rel) => rel.to_string_lossy().into_owned(),
            Err(_) => p.to_string_lossy().into_owned(),
        })
    }
}
