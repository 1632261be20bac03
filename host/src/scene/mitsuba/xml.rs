//! The Mitsuba 3 XML layer: files read into an owned element tree with `include` expanded,
//! `default` parameters and `$name` substitution applied, and Mitsuba 0.x names upgraded.
//!
//! Parsing is roxmltree's with DTDs refused, so no entity can expand (the "billion laughs" file
//! is an error, not a gigabyte); files are read within the scene-file size limit, the tree within
//! [`MAX_ELEMENTS`] elements and `include` within [`MAX_INCLUDE_DEPTH`] levels, a cycle named.
//! Every element keeps its file, line and column for messages.

use crate::scene::SceneError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Most elements of a scene with all its includes.
pub const MAX_ELEMENTS: usize = 4_000_000;
/// Deepest chain of `include`s.
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// One XML element after expansion.
#[derive(Clone, Debug)]
pub struct Element {
    /// Tag name (`shape`, `float`, …), Mitsuba 0.x names upgraded (`lookAt` → `lookat`).
    pub tag: String,
    /// Attributes in document order, `$name` substituted.
    pub attrs: Vec<(String, String)>,
    /// Child elements (comments and text dropped).
    pub children: Vec<Element>,
    /// File the element is in.
    pub file: Arc<PathBuf>,
    /// 1-based line.
    pub line: u32,
    /// 1-based column.
    pub col: u32,
}

impl Element {
    /// An attribute's value.
    pub fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// `file:line:col: <tag>` for messages.
    pub fn at(&self) -> String {
        format!(
            "{}:{}:{}: <{}{}>",
            self.file.display(),
            self.line,
            self.col,
            self.tag,
            self.attr("type")
                .map(|t| format!(" type=\"{t}\""))
                .unwrap_or_default()
        )
    }

    /// An error at this element.
    pub fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::Syntax {
            file: self.file.as_ref().clone(),
            line: self.line as usize,
            column: self.col as usize,
            message: format!("<{}>: {}", self.tag, message.into()),
        }
    }
}

/// Reading state: the parameters, the include chain and the element budget.
struct Reader {
    params: HashMap<String, String>,
    /// Names set on the command line (they win over `default`).
    fixed: std::collections::HashSet<String>,
    chain: Vec<PathBuf>,
    elements: usize,
    main_dir: PathBuf,
}

/// Read `path` (a `<scene>` file) with the command-line parameters `defines` (`-D name=value`).
pub fn read_scene(path: &Path, defines: &[(String, String)]) -> Result<Element, SceneError> {
    let mut r = Reader {
        params: defines.iter().cloned().collect(),
        fixed: defines.iter().map(|(k, _)| k.clone()).collect(),
        chain: Vec::new(),
        elements: 0,
        main_dir: path.parent().unwrap_or(Path::new(".")).to_path_buf(),
    };
    let text = read_text(path)?;
    r.read_root(&text, path, None)
}

/// Parse XML text as a scene file (for the fuzz target and tests: `include` resolves against
/// the current directory).
pub fn parse_scene_text(text: &str, file: &Path) -> Result<Element, SceneError> {
    let mut r = Reader {
        params: HashMap::new(),
        fixed: Default::default(),
        chain: Vec::new(),
        elements: 0,
        main_dir: file.parent().unwrap_or(Path::new(".")).to_path_buf(),
    };
    r.read_root(text, file, None)
}

fn read_text(path: &Path) -> Result<String, SceneError> {
    crate::limits::read_text_limited(path, crate::limits::SCENE_FILE_MAX_BYTES, "scene file")
        .map_err(|source| SceneError::Io {
            file: path.to_path_buf(),
            source,
        })
}

fn syntax(file: &Path, line: u32, col: u32, message: String) -> SceneError {
    SceneError::Syntax {
        file: file.to_path_buf(),
        line: line as usize,
        column: col as usize,
        message,
    }
}

/// `intIOR` → `int_ior`, `toWorld` → `to_world` (Mitsuba 3's own upgrade of 0.x names).
pub fn camel_to_snake(name: &str) -> String {
    let mut out = String::with_capacity(name.len() + 4);
    let chars: Vec<char> = name.chars().collect();
    for (i, &c) in chars.iter().enumerate() {
        if c.is_ascii_uppercase() && i > 0 {
            let prev = chars[i - 1];
            if prev.is_ascii_lowercase() || prev.is_ascii_digit() {
                out.push('_');
            }
        }
        out.push(c.to_ascii_lowercase());
    }
    out
}

impl Reader {
    fn read_root(
        &mut self,
        text: &str,
        file: &Path,
        include_site: Option<&Element>,
    ) -> Result<Element, SceneError> {
        let opts = roxmltree::ParsingOptions {
            allow_dtd: false,
            nodes_limit: u32::try_from(MAX_ELEMENTS * 2).unwrap_or(u32::MAX),
            ..Default::default()
        };
        let doc = roxmltree::Document::parse_with_options(text, opts).map_err(|e| {
            let p = e.pos();
            let hint = if matches!(e, roxmltree::Error::DtdDetected) {
                " (DTDs and entities are refused: a Mitsuba scene has none)"
            } else {
                ""
            };
            syntax(file, p.row, p.col, format!("malformed XML: {e}{hint}"))
        })?;
        let root = doc.root_element();
        if root.tag_name().name() != "scene" {
            let p = doc.text_pos_at(root.range().start);
            return Err(syntax(
                file,
                p.row,
                p.col,
                format!(
                    "the root element is <{}>, a Mitsuba scene file has <scene>{}",
                    root.tag_name().name(),
                    include_site
                        .map(|s| format!(" (included from {})", s.at()))
                        .unwrap_or_default()
                ),
            ));
        }
        let version = root.attribute("version").unwrap_or("3.0.0");
        let major: u32 = version
            .split('.')
            .next()
            .and_then(|m| m.trim().parse().ok())
            .unwrap_or(3);
        let file = Arc::new(file.to_path_buf());
        let mut children = Vec::new();
        for child in root.children().filter(|n| n.is_element()) {
            self.expand(&doc, child, &file, major, &mut children)?;
        }
        let p = doc.text_pos_at(root.range().start);
        Ok(Element {
            tag: "scene".into(),
            attrs: vec![("version".into(), version.to_string())],
            children,
            file,
            line: p.row,
            col: p.col,
        })
    }

    fn substitute(
        &self,
        value: &str,
        file: &Path,
        line: u32,
        col: u32,
    ) -> Result<String, SceneError> {
        if !value.contains('$') {
            return Ok(value.to_string());
        }
        let mut out = String::with_capacity(value.len());
        let mut rest = value;
        while let Some(i) = rest.find('$') {
            out.push_str(&rest[..i]);
            let after = &rest[i + 1..];
            let len = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            let name = &after[..len];
            if name.is_empty() {
                out.push('$');
            } else {
                match self.params.get(name) {
                    Some(v) => out.push_str(v),
                    None => {
                        return Err(syntax(
                            file,
                            line,
                            col,
                            format!(
                                "`${name}` is not defined: add <default name=\"{name}\" value=\"…\"/> or pass -D {name}=…"
                            ),
                        ))
                    }
                }
            }
            rest = &after[len..];
        }
        out.push_str(rest);
        Ok(out)
    }

    fn expand(
        &mut self,
        doc: &roxmltree::Document,
        node: roxmltree::Node,
        file: &Arc<PathBuf>,
        major: u32,
        out: &mut Vec<Element>,
    ) -> Result<(), SceneError> {
        self.elements += 1;
        let p = doc.text_pos_at(node.range().start);
        if self.elements > MAX_ELEMENTS {
            return Err(syntax(
                file,
                p.row,
                p.col,
                format!("more than {MAX_ELEMENTS} elements (with includes): refused"),
            ));
        }
        let mut tag = node.tag_name().name().to_string();
        if major < 2 {
            tag = match tag.as_str() {
                "lookAt" => "lookat".into(),
                _ => tag,
            };
        }
        let mut attrs = Vec::new();
        for a in node.attributes() {
            let mut v = self.substitute(a.value(), file, p.row, p.col)?;
            if major < 2 && a.name() == "name" {
                v = camel_to_snake(&v);
            }
            attrs.push((a.name().to_string(), v));
        }
        let here = Element {
            tag: tag.clone(),
            attrs,
            children: Vec::new(),
            file: file.clone(),
            line: p.row,
            col: p.col,
        };
        match tag.as_str() {
            "default" => {
                let (Some(name), Some(value)) = (here.attr("name"), here.attr("value")) else {
                    return Err(here.error("needs `name` and `value`"));
                };
                if !self.fixed.contains(name) {
                    self.params.insert(name.to_string(), value.to_string());
                }
                return Ok(());
            }
            "path" => {
                out.push(path_folder(here, file)?);
                return Ok(());
            }
            "include" => {
                let root = self.include(&here, file)?;
                out.extend(root.children);
                return Ok(());
            }
            _ => {}
        }
        let mut here = here;
        for child in node.children().filter(|n| n.is_element()) {
            self.expand(doc, child, file, major, &mut here.children)?;
        }
        out.push(here);
        Ok(())
    }

    /// The root element of the file an `<include filename="…"/>` names (relative to the including
    /// file, else to the main scene's folder); cycles and deep nesting are refused.
    fn include(&mut self, here: &Element, file: &Arc<PathBuf>) -> Result<Element, SceneError> {
        let Some(name) = here.attr("filename") else {
            return Err(here.error("needs `filename`"));
        };
        let dir = file.parent().unwrap_or(Path::new("."));
        let mut target = dir.join(name);
        if !target.exists() {
            let alt = self.main_dir.join(name);
            if alt.exists() {
                target = alt;
            }
        }
        let canon = std::fs::canonicalize(&target)
            .map_err(|e| here.error(format!("cannot open {}: {e}", target.display())))?;
        if self.chain.contains(&canon) || canon.as_path() == file.as_path() {
            return Err(here.error(format!(
                "cyclic include: {} includes itself through {}",
                canon.display(),
                self.chain
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" → ")
            )));
        }
        if self.chain.len() >= MAX_INCLUDE_DEPTH {
            return Err(here.error(format!(
                "includes nested deeper than {MAX_INCLUDE_DEPTH} levels"
            )));
        }
        if let Ok(me) = std::fs::canonicalize(file.as_path()) {
            if me == canon {
                return Err(here.error("cyclic include: a file includes itself"));
            }
            if self.chain.is_empty() {
                self.chain.push(me);
            }
        }
        let text = read_text(&target)?;
        self.chain.push(canon);
        let root = self.read_root(&text, &target, Some(here))?;
        self.chain.pop();
        Ok(root)
    }
}

/// Mitsuba 3's `<path value="…"/>`: a folder added to the file resolver, relative to the file
/// that names it. Kept in the tree, made absolute, for the converter.
fn path_folder(here: Element, file: &Arc<PathBuf>) -> Result<Element, SceneError> {
    let Some(value) = here.attr("value") else {
        return Err(here.error("needs `value` (a folder)"));
    };
    let dir = file.parent().unwrap_or(Path::new(".")).join(value);
    if !dir.is_dir() {
        return Err(here.error(format!("folder not found: {}", dir.display())));
    }
    let mut here = here;
    let v = dir.to_string_lossy().into_owned();
    here.attrs = vec![("value".into(), v)];
    Ok(here)
}
