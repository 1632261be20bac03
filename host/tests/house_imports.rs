//! The house has no import circles: the module graph of `host/src`, read from its paths
//! (`use crate::…`, `use super::…`, `use self::…`, a child module's name, and the same paths
//! written inline in code), has no cycle between files, and no file imports the module that
//! contains it (a `mod.rs` that re-exports its children is the usual way such a circle starts).
//!
//! The same holds one level up: between the crate's top-level modules (its floors), imports run
//! only down the list [`HOST_FLOORS`], so the floors form no circle either; `plugin-api/src`,
//! whose floors are its files, has no circle between them.
//!
//! Quantity: the number of strongly connected components with more than one file, the number
//! of imports of an enclosing module, and the number of floor circles and imports from a floor
//! to one at or above it. Tolerance: zero for each; a count is exact, not sampled.
//! Test code (`#[cfg(test)]` modules and files) is left out: a test may reach anywhere.
//!
//! `cargo test --release -p spectrace --test house_imports -- --nocapture` prints every circle
//! and every upward import it finds, and the imports between the floors with the file imports
//! behind any that runs up. `HOUSE_IMPORTS_SRC=DIR` measures another checkout's `host/src`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// One source file: its module path (`["integrator", "path"]`), its file, its code with
/// comments, strings and test modules removed, and its child modules declared for tests only.
struct Module {
    file: PathBuf,
    code: String,
}

/// The module graph of one crate: modules by path, and the imports of each (module → modules).
struct Graph {
    modules: BTreeMap<Vec<String>, Module>,
    /// For each module, the names it re-exports and the paths they stand for.
    reexports: BTreeMap<Vec<String>, BTreeMap<String, Vec<String>>>,
    edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
    /// For each module, the modules its paths name before any re-export is followed
    /// (`crate::scene::FactoryContext` names `scene` even when `scene` re-exports it from
    /// elsewhere): a floor that writes a higher floor's path depends on it in the reader's eyes.
    named: BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
}

/// `host/src`, or the tree named by `HOUSE_IMPORTS_SRC` (to measure another checkout).
fn host_src() -> PathBuf {
    std::env::var_os("HOUSE_IMPORTS_SRC")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("src"))
}

/// Code without comments, string and char literals (replaced by spaces, so `crate::` in a
/// doc comment or a message is not an import).
fn strip_comments_and_strings(src: &str) -> String {
    let b = src.as_bytes();
    let mut out = String::with_capacity(src.len());
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if c == b'/' && b.get(i + 1) == Some(&b'*') {
            let mut depth = 0;
            while i < b.len() {
                if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
                    depth += 1;
                    i += 2;
                } else if b[i] == b'*' && b.get(i + 1) == Some(&b'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
        } else if c == b'r'
            && (b.get(i + 1) == Some(&b'"') || b.get(i + 1) == Some(&b'#'))
            && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_'))
        {
            // Raw string r"…" or r#"…"#.
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&b'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) != Some(&b'"') {
                out.push(c as char);
                i += 1;
                continue;
            }
            j += 1;
            let closing: Vec<u8> = std::iter::once(b'"')
                .chain(std::iter::repeat_n(b'#', hashes))
                .collect();
            while j < b.len() && !b[j..].starts_with(&closing) {
                j += 1;
            }
            i = j + closing.len();
            out.push(' ');
        } else if c == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                if b[i] == b'\\' {
                    i += 1;
                }
                i += 1;
            }
            i += 1;
            out.push(' ');
        } else if c == b'\'' {
            // A char literal ('a', '\n', '\u{..}') or a lifetime ('a): skip only the literal.
            let close = if b.get(i + 1) == Some(&b'\\') {
                b[i + 2..]
                    .iter()
                    .position(|&x| x == b'\'')
                    .map(|p| i + 2 + p)
            } else if b.get(i + 2) == Some(&b'\'') {
                Some(i + 2)
            } else {
                // Multi-byte UTF-8 char literal.
                let s = &src[i + 1..];
                let ch = s.chars().next().unwrap_or(' ');
                let len = ch.len_utf8();
                (b.get(i + 1 + len) == Some(&b'\'') && len > 1).then_some(i + 1 + len)
            };
            match close {
                Some(end) => {
                    i = end + 1;
                    out.push(' ');
                }
                None => {
                    out.push('\'');
                    i += 1;
                }
            }
        } else {
            let ch = src[i..].chars().next().unwrap();
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

/// Removes every item that follows `#[cfg(test)]` (an inline module or any braced item) and
/// returns the code left and the names of `#[cfg(test)] mod name;` declarations.
fn strip_test_items(code: &str) -> (String, Vec<String>) {
    let mut out = String::with_capacity(code.len());
    let mut test_files = Vec::new();
    let mut rest = code;
    while let Some(at) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..at]);
        let after = &rest[at + "#[cfg(test)]".len()..];
        // The item ends at its first `;` before any `{`, or at the `}` matching its first `{`.
        let semi = after.find(';');
        let brace = after.find('{');
        match (semi, brace) {
            (Some(s), b) if b.is_none_or(|b| s < b) => {
                let item = after[..s].trim();
                if let Some(name) = item.strip_prefix("mod ").or(item.strip_prefix("pub mod ")) {
                    test_files.push(name.trim().to_string());
                }
                rest = &after[s + 1..];
            }
            (_, Some(b)) => {
                let mut depth = 0;
                let mut end = after.len();
                for (k, ch) in after[b..].char_indices() {
                    match ch {
                        '{' => depth += 1,
                        '}' => {
                            depth -= 1;
                            if depth == 0 {
                                end = b + k + 1;
                                break;
                            }
                        }
                        _ => {}
                    }
                }
                rest = &after[end..];
            }
            _ => rest = "",
        }
    }
    out.push_str(rest);
    (out, test_files)
}

/// Reads every module of the crate rooted at `root` (`lib.rs`), leaving out test-only files.
fn read_modules(root: &Path) -> BTreeMap<Vec<String>, Module> {
    let mut modules = BTreeMap::new();
    let mut queue = vec![(Vec::<String>::new(), root.join("lib.rs"))];
    while let Some((path, file)) = queue.pop() {
        let src = std::fs::read_to_string(&file)
            .unwrap_or_else(|e| panic!("{}: cannot read: {e}", file.display()));
        let (code, test_files) = strip_test_items(&strip_comments_and_strings(&src));
        // The directory holding this module's children.
        let dir = if path.is_empty() || file.ends_with("mod.rs") {
            file.parent().unwrap().to_path_buf()
        } else {
            file.with_extension("")
        };
        for child in declared_modules(&code) {
            if test_files.contains(&child) {
                continue;
            }
            let flat = dir.join(format!("{child}.rs"));
            let nested = dir.join(&child).join("mod.rs");
            let child_file = if flat.exists() { flat } else { nested };
            let mut child_path = path.clone();
            child_path.push(child);
            queue.push((child_path, child_file));
        }
        modules.insert(path, Module { file, code });
    }
    modules
}

/// Names of the `mod name;` declarations (out-of-line modules) in `code`.
fn declared_modules(code: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut start = 0;
    // Only statements ended by `;`: `mod x { … }` is an inline module, not a file.
    for (end, sep) in code.match_indices([';', '{', '}']) {
        let stmt = &code[start..end];
        start = end + 1;
        if sep != ";" {
            continue;
        }
        let words: Vec<&str> = stmt.split_whitespace().collect();
        if let Some(k) = words.iter().position(|w| *w == "mod") {
            // `pub mod x`, `pub(crate) mod x`, `mod x`, possibly after attributes.
            if k + 2 == words.len()
                && words[..k]
                    .iter()
                    .all(|w| w.starts_with("pub") || w.starts_with("#[") || w.ends_with(']'))
            {
                names.push(words[k + 1].to_string());
            }
        }
    }
    names
}

fn is_ident_byte(c: u8) -> bool {
    c.is_ascii_alphanumeric() || c == b'_'
}

/// The byte ranges of the `use …;` statements of `code` (from `use` to before the `;`).
fn use_statement_spans(code: &str) -> Vec<(usize, usize)> {
    let b = code.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while let Some(at) = code[i..].find("use ") {
        let start = i + at;
        i = start + 4;
        if start > 0 && is_ident_byte(b[start - 1]) {
            continue;
        }
        let Some(end) = code[i..].find(';') else {
            break;
        };
        spans.push((start, i + end));
        i += end;
    }
    spans
}

/// The `use` statements of `code` with their braces expanded, as (path, name it binds, public).
fn use_statements(code: &str) -> Vec<(Vec<String>, String, bool)> {
    let mut uses = Vec::new();
    for (start, end) in use_statement_spans(code) {
        let tree = code[start + 4..end]
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ");
        // `pub use`, `pub(crate) use`, `pub(super) use`: a re-export, not a dependency.
        let before = code[..start].trim_end();
        let public = before.ends_with("pub")
            || (before.ends_with(')')
                && before[..before.len() - 1]
                    .trim_end()
                    .rsplit('(')
                    .nth(1)
                    .is_some_and(|w| w.trim_end().ends_with("pub")));
        let mut out = Vec::new();
        expand_use_tree(&tree, &mut Vec::new(), &mut out);
        uses.extend(out.into_iter().map(|(p, a)| (p, a, public)));
    }
    uses
}

/// `code` with every `use …;` statement replaced by spaces.
fn blank_use_statements(code: &str) -> String {
    let mut out = code.as_bytes().to_vec();
    for (start, end) in use_statement_spans(code) {
        for c in &mut out[start..end] {
            if !c.is_ascii_whitespace() {
                *c = b' ';
            }
        }
    }
    // Whole statements were replaced, every byte of a multi-byte character with a space.
    String::from_utf8(out).unwrap_or_default()
}

/// Every path in `code` that starts with `crate`, `super` or `self` (in `use` trees, with their
/// braces expanded, and inline), plus `use` paths that start with a child module's name.
/// Re-exports (`pub use`) are left out: they name an item, they do not use it.
fn paths_in(code: &str, children: &BTreeSet<String>) -> Vec<Vec<String>> {
    let mut paths: Vec<Vec<String>> = use_statements(code)
        .into_iter()
        .filter(|(_, _, public)| !public)
        .map(|(p, _, _)| p)
        .collect();
    // The inline scan reads the code with its `use` statements blanked out (read above).
    let code = &blank_use_statements(code);
    let b = code.as_bytes();
    paths.retain(|p| {
        p.first()
            .is_some_and(|h| h == "crate" || h == "super" || h == "self" || children.contains(h))
    });
    // Inline paths such as `crate::film::tonemap(…)`, `super::x::Y` or `child::TYPE`.
    let heads: Vec<String> = ["crate", "super"]
        .iter()
        .map(|h| h.to_string())
        .chain(children.iter().cloned())
        .map(|h| h + "::")
        .collect();
    for head in &heads {
        let mut j = 0;
        while let Some(at) = code[j..].find(head.as_str()) {
            let start = j + at;
            j = start + head.len();
            if start > 0 && (is_ident_byte(b[start - 1]) || b[start - 1] == b':') {
                continue;
            }
            let mut segs = Vec::new();
            let mut k = start;
            loop {
                let s = k;
                while k < b.len() && is_ident_byte(b[k]) {
                    k += 1;
                }
                if s == k {
                    break;
                }
                segs.push(code[s..k].to_string());
                if code[k..].starts_with("::")
                    && code[k + 2..].starts_with(|c: char| c.is_alphanumeric() || c == '_')
                {
                    k += 2;
                } else {
                    break;
                }
            }
            // `a::b::{…}` or `a::*` is a `use` tree, read above with its braces expanded.
            if !code[k..].starts_with("::") {
                paths.push(segs);
            }
        }
    }
    paths
}

/// Expands a `use` tree such as `super::{a::B, c::{D, E}}` into its paths.
fn expand_use_tree(tree: &str, prefix: &mut Vec<String>, out: &mut Vec<(Vec<String>, String)>) {
    let tree = tree.trim().trim_start_matches("::").trim();
    if let Some(open) = tree.find('{') {
        let head = &tree[..open];
        let inner = &tree[open + 1..tree.rfind('}').unwrap_or(tree.len())];
        let n = prefix.len();
        prefix.extend(
            head.split("::")
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .map(str::to_string),
        );
        let mut depth = 0;
        let mut s = 0;
        for (k, ch) in inner.char_indices() {
            match ch {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    expand_use_tree(&inner[s..k], prefix, out);
                    s = k + 1;
                }
                _ => {}
            }
        }
        expand_use_tree(&inner[s..], prefix, out);
        prefix.truncate(n);
    } else if !tree.is_empty() {
        let mut parts = tree.split(" as ");
        let tree = parts.next().unwrap_or(tree);
        let mut p = prefix.clone();
        p.extend(
            tree.split("::")
                .map(str::trim)
                .filter(|s| !s.is_empty())
                .map(str::to_string),
        );
        let alias = parts.next().map(str::trim).map(str::to_string);
        let alias = alias.or_else(|| p.last().cloned()).unwrap_or_default();
        out.push((p, alias));
    }
}

/// The module that defines what a path inside module `here` names: the longest prefix that
/// names a module, followed through that module's re-exports (`pub use`) to where the item lives.
fn resolve(here: &[String], path: &[String], g: &Graph) -> Option<Vec<String>> {
    let mut here = here.to_vec();
    let mut path = path.to_vec();
    for _ in 0..16 {
        let (module, rest) = resolve_module(&here, &path, &g.modules)?;
        let Some(target) = rest
            .first()
            .and_then(|item| g.reexports.get(&module)?.get(item))
        else {
            return Some(module);
        };
        let mut next = target.clone();
        next.extend(rest[1..].iter().cloned());
        here = module;
        path = next;
    }
    None
}

/// The longest prefix of a path inside module `here` that names a module, and the rest.
fn resolve_module(
    here: &[String],
    path: &[String],
    modules: &BTreeMap<Vec<String>, Module>,
) -> Option<(Vec<String>, Vec<String>)> {
    let mut abs: Vec<String> = Vec::new();
    let mut rest = path;
    match path.first().map(String::as_str) {
        Some("crate") => rest = &path[1..],
        Some("self") => {
            abs = here.to_vec();
            rest = &path[1..];
        }
        Some("super") => {
            abs = here.to_vec();
            while rest.first().map(String::as_str) == Some("super") {
                abs.pop()?;
                rest = &rest[1..];
            }
        }
        _ => abs = here.to_vec(),
    }
    abs.extend(rest.iter().cloned());
    let mut tail = Vec::new();
    while !abs.is_empty() {
        if modules.contains_key(&abs) {
            tail.reverse();
            return Some((abs, tail));
        }
        tail.push(abs.pop()?);
    }
    tail.reverse();
    Some((abs, tail))
}

fn graph(root: &Path) -> Graph {
    let modules = read_modules(root);
    let reexports = modules
        .iter()
        .map(|(path, m)| {
            let names = use_statements(&m.code)
                .into_iter()
                .filter(|(p, alias, public)| {
                    *public && alias != "*" && alias != "self" && !p.is_empty()
                })
                .map(|(p, alias, _)| (alias, p))
                .collect();
            (path.clone(), names)
        })
        .collect();
    let mut g = Graph {
        modules,
        reexports,
        edges: BTreeMap::new(),
        named: BTreeMap::new(),
    };
    let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    let mut named: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    for (path, module) in &g.modules {
        let children: BTreeSet<String> = g
            .modules
            .keys()
            .filter(|k| k.len() == path.len() + 1 && k.starts_with(path))
            .map(|k| k.last().unwrap().clone())
            .collect();
        let out = edges.entry(path.clone()).or_default();
        let names = named.entry(path.clone()).or_default();
        for p in paths_in(&module.code, &children) {
            if let Some(target) = resolve(path, &p, &g) {
                if &target != path && !target.is_empty() {
                    out.insert(target);
                }
            }
            if let Some((module, _)) = resolve_module(path, &p, &g.modules) {
                if &module != path && !module.is_empty() {
                    names.insert(module);
                }
            }
        }
    }
    g.edges = edges;
    g.named = named;
    g
}

/// Strongly connected components with more than one module (Tarjan's algorithm).
fn circles(g: &Graph) -> Vec<Vec<Vec<String>>> {
    struct State<'a> {
        g: &'a Graph,
        index: BTreeMap<&'a Vec<String>, usize>,
        low: BTreeMap<&'a Vec<String>, usize>,
        stack: Vec<&'a Vec<String>>,
        on_stack: BTreeSet<&'a Vec<String>>,
        out: Vec<Vec<Vec<String>>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a Vec<String>) {
        let n = s.index.len();
        s.index.insert(v, n);
        s.low.insert(v, n);
        s.stack.push(v);
        s.on_stack.insert(v);
        let g = s.g;
        for w in g.edges.get(v).into_iter().flatten() {
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.on_stack.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack.remove(w);
                comp.push(w.clone());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        g,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on_stack: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in g.modules.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

/// Imports of a module that contains the importing one (`integrator::path` → `integrator`).
fn upward_imports(g: &Graph) -> Vec<(Vec<String>, Vec<String>)> {
    let mut up = Vec::new();
    for (from, tos) in &g.edges {
        for to in tos {
            if from.len() > to.len() && from.starts_with(to) {
                up.push((from.clone(), to.clone()));
            }
        }
    }
    up
}

/// The crate's top-level modules (its floors) and the imports between them: an import of
/// `light::point` from `scene::builder` counts as `scene` → `light`, and so does a path that
/// names a floor only to reach what it re-exports from another (`crate::scene::FactoryContext`
/// counts for `scene` and for the floor that defines it). A circle here is an import that runs
/// from a lower floor back up.
fn floors(g: &Graph) -> Graph {
    let top = |p: &Vec<String>| p.iter().take(1).cloned().collect::<Vec<String>>();
    let mut modules = BTreeMap::new();
    let mut edges: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
    for (from, tos) in g.edges.iter().chain(&g.named) {
        let f = top(from);
        modules.entry(f.clone()).or_insert_with(|| Module {
            file: g.modules[from].file.clone(),
            code: String::new(),
        });
        for to in tos {
            let t = top(to);
            if t != f && !t.is_empty() && !f.is_empty() {
                edges.entry(f.clone()).or_default().insert(t);
            }
        }
    }
    Graph {
        modules,
        reexports: BTreeMap::new(),
        edges,
        named: BTreeMap::new(),
    }
}

fn name(p: &[String]) -> String {
    if p.is_empty() {
        "crate".into()
    } else {
        p.join("::")
    }
}

fn report(g: &Graph, circles: &[Vec<Vec<String>>], up: &[(Vec<String>, Vec<String>)]) {
    let edges: usize = g.edges.values().map(BTreeSet::len).sum();
    eprintln!(
        "{} modules, {} imports between them",
        g.modules.len(),
        edges
    );
    eprintln!(
        "{} circles ({} modules in them):",
        circles.len(),
        circles.iter().map(Vec::len).sum::<usize>()
    );
    for c in circles {
        let names: Vec<String> = c.iter().map(|m| name(m)).collect();
        eprintln!("  {}", names.join(" <-> "));
        for m in c {
            for t in &g.edges[m] {
                if c.contains(t) {
                    eprintln!(
                        "      {} -> {}  ({})",
                        name(m),
                        name(t),
                        g.modules[m].file.display()
                    );
                }
            }
        }
    }
    eprintln!("{} imports of an enclosing module:", up.len());
    for (from, to) in up {
        eprintln!("  {} -> {}", name(from), name(to));
    }
}

/// The floors of `host/src`, lowest first: its top-level modules, each importing only from the
/// floors before it in this list (what each holds: `docs/README.md`, "How the code is
/// organised").
///
/// - base: `limits`, `spectrum`, `color`, `geometry`, `sampler` (random numbers), `film`;
/// - objects: `texture` < `material` (a material evaluates textures) < `camera` < `photometry`
///   (photometric data files) < `light` (including lights measured as instruments do);
/// - `scene_file` (the file format and the `ObjectFactory` contract) < `builtin` (the built-in
///   types and sensor items) < `scene` (the builder and the built scene);
/// - `effects` (what a scene calls for) < `integrator` (the render plan and the integrators);
/// - `plugin` (the plugin host and registry: it builds scene items through the factory contract
///   and lists the integrators' types) < `analysis` < `sensor` (measurements that render) < `cli`.
const HOST_FLOORS: [&str; 20] = [
    "limits",
    "spectrum",
    "color",
    "geometry",
    "sampler",
    "film",
    "texture",
    "material",
    "camera",
    "photometry",
    "light",
    "scene_file",
    "builtin",
    "scene",
    "effects",
    "integrator",
    "plugin",
    "analysis",
    "sensor",
    "cli",
];

/// The imports between the floors (top-level modules) of `g`, printed floor by floor, with every
/// circle among them and the file imports behind each edge of a circle. Returns the problems:
/// each circle, and with `order` (lowest floor first) each floor missing from it and each import
/// from a floor to one at or above it.
fn check_floors(g: &Graph, order: Option<&[&str]>) -> Vec<String> {
    let fl = floors(g);
    let mut problems = Vec::new();
    for (from, tos) in &fl.edges {
        let tos: Vec<String> = tos.iter().map(|t| name(t)).collect();
        eprintln!("floor {} -> {}", name(from), tos.join(", "));
    }
    let behind = |m: &Vec<String>, t: &Vec<String>| {
        let mut seen = BTreeSet::new();
        for (from, tos) in g.edges.iter().chain(&g.named) {
            for to in tos {
                if from.first() == m.first()
                    && to.first() == t.first()
                    && seen.insert((from.clone(), to.clone()))
                {
                    eprintln!("          {} -> {}", name(from), name(to));
                }
            }
        }
    };
    let fc = circles(&fl);
    eprintln!(
        "floor circles: {}",
        if fc.is_empty() {
            "none".to_string()
        } else {
            fc.len().to_string()
        }
    );
    for c in &fc {
        let names: Vec<String> = c.iter().map(|m| name(m)).collect();
        eprintln!("  {}", names.join(" <-> "));
        problems.push(format!("floors in a circle: {}", names.join(" <-> ")));
        for m in c {
            for t in fl.edges.get(m).into_iter().flatten() {
                if c.contains(t) {
                    eprintln!("      {} -> {}", name(m), name(t));
                    behind(m, t);
                }
            }
        }
    }
    if let Some(order) = order {
        let rank = |f: &Vec<String>| order.iter().position(|o| f.first().is_some_and(|n| n == o));
        for f in fl.modules.keys().filter(|f| !f.is_empty()) {
            if rank(f).is_none() {
                problems.push(format!("floor {} is not in the list of floors", name(f)));
            }
        }
        for (from, tos) in &fl.edges {
            for to in tos {
                if let (Some(a), Some(b)) = (rank(from), rank(to)) {
                    if b >= a {
                        eprintln!("import up: {} -> {}", name(from), name(to));
                        behind(from, to);
                        problems.push(format!("import up: {} -> {}", name(from), name(to)));
                    }
                }
            }
        }
    }
    problems
}

/// No circle between the files of `host/src`, and no file importing a module that contains it
/// (each folder's `mod.rs` only declares and re-exports; what its files share lives in a file
/// of its own). Between the top-level modules, the floors of [`HOST_FLOORS`], imports run only
/// down: no circle, and no import from a floor to one above it.
#[test]
fn the_host_has_no_import_circles_and_no_upward_imports() {
    let g = graph(&host_src());
    assert!(
        g.modules.len() > 100,
        "found only {} modules under host/src",
        g.modules.len()
    );
    let c = circles(&g);
    let up = upward_imports(&g);
    report(&g, &c, &up);
    let floor_problems = check_floors(&g, Some(&HOST_FLOORS));
    let found: Vec<String> = c
        .iter()
        .map(|m| m.iter().map(|p| name(p)).collect::<Vec<_>>().join(" "))
        .collect();
    assert!(
        found.is_empty(),
        "import circles in host/src (run with --nocapture for the imports): {found:#?}"
    );
    let up: Vec<String> = up
        .iter()
        .map(|(from, to)| format!("{} -> {}", name(from), name(to)))
        .collect();
    assert!(
        up.is_empty(),
        "imports of an enclosing module (move what the children share out of its mod.rs): {up:#?}"
    );
    assert!(
        floor_problems.is_empty(),
        "imports between the floors of host/src that do not run down (run with --nocapture for \
         the file imports behind each): {floor_problems:#?}"
    );
}

/// The plugin API crate (`plugin-api/src`) read the same way: no circle, no upward import, no
/// circle between its top-level modules.
#[test]
fn the_plugin_api_has_no_import_circles_and_no_upward_imports() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../plugin-api/src");
    let g = graph(&root);
    assert!(
        g.modules.len() > 5,
        "found only {} modules under {}",
        g.modules.len(),
        root.display()
    );
    let c = circles(&g);
    let up = upward_imports(&g);
    report(&g, &c, &up);
    let floor_problems = check_floors(&g, None);
    assert!(c.is_empty(), "import circles in plugin-api/src: {c:?}");
    assert!(
        floor_problems.is_empty(),
        "circles between the top-level modules of plugin-api/src: {floor_problems:#?}"
    );
    assert!(
        up.is_empty(),
        "imports of an enclosing module in plugin-api/src: {up:?}"
    );
}

/// The reader finds what it should: a circle written on purpose in a small tree is reported
/// (a `mod.rs` calling its child, the child calling a function of the `mod.rs`), an import of a
/// re-exported name counts for the file that defines it, paths in doc comments, in test
/// modules and in re-exports are not imports, and an import against the order of the floors is
/// reported.
#[test]
fn the_reader_sees_a_circle_and_an_upward_import() {
    let dir = std::env::temp_dir().join(format!("spectrace-house-imports-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("a")).unwrap();
    std::fs::write(dir.join("lib.rs"), "pub mod a;\npub mod b;\npub mod c;\n").unwrap();
    std::fs::write(dir.join("a/mod.rs"), "pub mod x;\npub use x::X;\npub fn h() { x::g(); }\n#[cfg(test)]\nmod t { use crate::c::Z; }\n").unwrap();
    std::fs::write(
        dir.join("a/x.rs"),
        "use super::h as _;\npub struct X;\npub fn g() {}\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("b.rs"),
        "/// [`crate::c::Z`]\npub fn f() { crate::a::x::g(); }\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("c.rs"),
        "use crate::{a::X, b::{f}};\npub struct Z;\n",
    )
    .unwrap();
    let g = graph(&dir);
    let c = circles(&g);
    let up = upward_imports(&g);
    let _ = std::fs::remove_dir_all(&dir);
    let s = |p: &str| p.split("::").map(str::to_string).collect::<Vec<_>>();
    assert_eq!(c, vec![vec![s("a"), s("a::x")]]);
    assert_eq!(up, vec![(s("a::x"), s("a"))]);
    assert_eq!(g.edges[&s("b")], BTreeSet::from([s("a::x")]));
    assert_eq!(g.edges[&s("c")], BTreeSet::from([s("a::x"), s("b")]));
    // `crate::a::X` names `a` (which re-exports `X` from `a::x`): for the floors, `c` uses `a`.
    assert_eq!(g.named[&s("c")], BTreeSet::from([s("a"), s("b")]));
    // Floors a < b < c: every import runs down. Listed b < a < c, `b` imports a floor above it;
    // a floor left out of the list is reported.
    assert!(check_floors(&g, Some(&["a", "b", "c"])).is_empty());
    assert_eq!(
        check_floors(&g, Some(&["b", "a", "c"])),
        vec!["import up: b -> a".to_string()]
    );
    assert_eq!(
        check_floors(&g, Some(&["a", "b"])),
        vec!["floor c is not in the list of floors".to_string()]
    );
}
