//! `spectrace plugins new NAME --kind light|material|spd|observer [--dir D]`: write an
//! out-of-tree plugin crate to start from — a `cdylib` exporting one type of the kind with a
//! minimal, physically valid implementation, and `tests/conformance.rs` running the
//! conformance kit on it. The templates are `host/templates/plugin/`.
//!
//! The crate depends on `spectrace-plugin-api` (and, for its tests, `spectrace-plugin-kit`) by
//! path to this source tree's copies by default (`--api-path` names another tree), or on the
//! published crates with `--api-version 0.2`.

use std::path::{Path, PathBuf};

/// Arguments of `spectrace plugins new`.
#[derive(clap::Args, Debug)]
pub struct NewArgs {
    /// Package name of the new crate (letters, digits, `-`, `_`; starting with a letter); its
    /// type is named the same with `_` for `-`.
    pub name: String,
    /// Which kind of object it provides.
    #[arg(long, value_parser = ["light", "material", "spd", "observer"])]
    pub kind: String,
    /// Directory to create the crate in (it is written to DIR/NAME).
    #[arg(long, value_name = "DIR", default_value = ".")]
    pub dir: PathBuf,
    /// Depend on the API and the kit in this spectrace source tree (default: the tree this
    /// `spectrace` was built from, when it still exists).
    #[arg(long, value_name = "DIR", conflicts_with = "api_version")]
    pub api_path: Option<PathBuf>,
    /// Depend on the published crates of this version instead (e.g. `0.2`).
    #[arg(long, value_name = "VERSION")]
    pub api_version: Option<String>,
}

const CARGO_TOML: &str = include_str!("../../templates/plugin/Cargo.toml.in");
const CONFORMANCE: &str = include_str!("../../templates/plugin/conformance.rs");
const LIGHT: &str = include_str!("../../templates/plugin/light.rs");
const MATERIAL: &str = include_str!("../../templates/plugin/material.rs");
const SPD: &str = include_str!("../../templates/plugin/spd.rs");
const OBSERVER: &str = include_str!("../../templates/plugin/observer.rs");

/// The source tree this binary was built from (the workspace root), when it still exists.
fn own_tree() -> Option<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()?
        .to_path_buf();
    root.join("plugin-api/Cargo.toml").is_file().then_some(root)
}

/// A TOML string literal for a path (basic string, escaped).
fn toml_path(p: &Path) -> String {
    let s = p.display().to_string();
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// Write the crate; the error names what is wrong.
pub fn run(args: &NewArgs) -> Result<(), String> {
    let name = args.name.as_str();
    check_name(name)?;
    let ident = name.replace('-', "_");
    let (api, kit) = dependency_lines(args)?;
    let (source, rust_type, check) = match args.kind.as_str() {
        "light" => (LIGHT, "PointLight", "check_light"),
        "material" => (MATERIAL, "Diffuse", "check_material"),
        "spd" => (SPD, "Triangle", "check_spd"),
        "observer" => (OBSERVER, "GaussianSensor", "check_observer"),
        other => {
            return Err(format!(
                "--kind {other}: use light, material, spd or observer"
            ))
        }
    };
    let fill = |t: &str| {
        t.replace("__API__", &api)
            .replace("__KIT__", &kit)
            .replace("__NAME__", name)
            .replace("__CRATE__", &ident)
            .replace("__TYPE__", &ident)
            .replace("__RUST_TYPE__", rust_type)
            .replace("__CHECK__", check)
    };
    let root = args.dir.join(name);
    if root.exists() {
        return Err(format!(
            "{} exists already; choose another name or --dir",
            root.display()
        ));
    }
    write_file(&root, "Cargo.toml", fill(CARGO_TOML))?;
    write_file(&root, "src/lib.rs", fill(source))?;
    write_file(&root, "tests/conformance.rs", fill(CONFORMANCE))?;
    write_file(&root, ".gitignore", "/target\n".into())?;
    println!(
        "wrote {} ({} `{ident}`): build with `cargo build --release`, test with `cargo test`, \
         check the library with `spectrace plugins check {}`",
        root.display(),
        args.kind,
        root.join("target/release")
            .join(format!(
                "{}{ident}{}",
                std::env::consts::DLL_PREFIX,
                std::env::consts::DLL_SUFFIX
            ))
            .display()
    );
    Ok(())
}

/// A crate name cargo and the loader both accept.
fn check_name(name: &str) -> Result<(), String> {
    let valid = name.chars().next().is_some_and(|c| c.is_ascii_lowercase())
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_');
    if valid {
        Ok(())
    } else {
        Err(format!(
            "plugin name `{name}`: use lower-case letters, digits, `-` and `_`, starting with a letter"
        ))
    }
}

/// The `Cargo.toml` lines of the API and the kit: the published version, or a spectrace tree by
/// path (`--api-path`, else the tree this binary was built from).
fn dependency_lines(args: &NewArgs) -> Result<(String, String), String> {
    if let Some(v) = &args.api_version {
        return Ok((
            format!("spectrace-plugin-api = \"{v}\""),
            format!("spectrace-plugin-kit = \"{v}\""),
        ));
    }
    let tree = match &args.api_path {
        Some(p) => p.clone(),
        None => own_tree().ok_or_else(|| {
            "the spectrace source tree this binary was built from is gone: give \
             --api-path DIR (a spectrace checkout) or --api-version 0.2"
                .to_string()
        })?,
    };
    let tree = tree
        .canonicalize()
        .map_err(|e| format!("--api-path {}: {e}", tree.display()))?;
    if !tree.join("plugin-api/Cargo.toml").is_file() {
        return Err(format!(
            "--api-path {}: no plugin-api/Cargo.toml there (give a spectrace checkout)",
            tree.display()
        ));
    }
    Ok((
        format!(
            "# This spectrace tree's API; to build against the published crate instead:\n\
             # spectrace-plugin-api = \"0.2\"\n\
             spectrace-plugin-api = {{ path = {} }}",
            toml_path(&tree.join("plugin-api"))
        ),
        format!(
            "# The conformance kit; published: spectrace-plugin-kit = \"0.2\"\n\
             spectrace-plugin-kit = {{ path = {} }}",
            toml_path(&tree.join("plugin-kit"))
        ),
    ))
}

/// Write `rel` under the new crate's `root`, making its folders.
fn write_file(root: &std::path::Path, rel: &str, text: String) -> Result<(), String> {
    let path = root.join(rel);
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(|e| format!("{}: {e}", parent.display()))?;
    }
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
}
