//! Pinned plugin libraries: a scene may name a library together with the SHA-256 of its file,
//!
//! ```ron
//! plugins: [
//!     "plugins/libmy_lights.so",
//!     (path: "plugins/libmy_materials.so", sha256: "9f86d081884c7d65…"),
//! ],
//! ```
//!
//! and the host then refuses to load a file whose hash differs, naming both hashes. Paths are
//! relative to the scene file. The pin is checked on the bytes of the very file that is then
//! opened; it protects a render against the wrong or a changed library (a rebuilt plugin, a stale
//! copy), not against someone who can write to the library between the check and the load: a
//! library is trusted native code (docs/plugins.md, "Trust").
//!
//! | item | form | meaning |
//! |---|---|---|
//! | `"PATH"` | string | load the library at PATH (relative to the scene file) |
//! | `(path: "PATH", sha256: "HEX")` | struct | load it only if its SHA-256 is HEX (64 hex digits, either case) |

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};

/// One entry of a scene's `plugins` list.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ScenePlugin {
    /// A library by path alone.
    Path(String),
    /// A library by path, pinned to the SHA-256 of its file.
    Pinned {
        /// The library file, relative to the scene file.
        path: String,
        /// The SHA-256 of the file, 64 hex digits.
        sha256: String,
    },
}

impl ScenePlugin {
    /// The library path as written.
    pub fn path(&self) -> &str {
        match self {
            ScenePlugin::Path(p) | ScenePlugin::Pinned { path: p, .. } => p,
        }
    }

    /// The pinned hash, when there is one.
    pub fn sha256(&self) -> Option<&str> {
        match self {
            ScenePlugin::Path(_) => None,
            ScenePlugin::Pinned { sha256, .. } => Some(sha256),
        }
    }

    /// The library path, relative paths taken from `base_dir` (the scene file's directory).
    pub fn resolve(&self, base_dir: &Path) -> PathBuf {
        let p = Path::new(self.path());
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            base_dir.join(p)
        }
    }
}

/// A scene file read for its `plugins` field alone (the rest is the scene loader's).
#[derive(Deserialize)]
struct PluginsOnly {
    #[serde(default)]
    plugins: Vec<ScenePlugin>,
}

/// The `plugins` list of the scene file at `scene` (empty when it has none); an error names the
/// file and what is wrong.
pub fn scene_plugins(scene: &Path) -> Result<Vec<ScenePlugin>, String> {
    // A Mitsuba 3 XML scene (read by `scene::mitsuba`) names no spectrace libraries.
    if scene
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("xml"))
    {
        return Ok(Vec::new());
    }
    // The same limit as the scene reader's: `/dev/zero` named as a scene must not be read
    // until memory runs out.
    let text =
        crate::limits::read_text_limited(scene, crate::limits::SCENE_FILE_MAX_BYTES, "scene file")
            .map_err(|e| format!("{}: {e}", scene.display()))?;
    let parsed: PluginsOnly = ron::Options::default()
        .with_default_extension(ron::extensions::Extensions::IMPLICIT_SOME)
        .from_str(&text)
        .map_err(|e| {
            format!(
                "{}: plugins: expected a list of \"PATH\" or (path: \"PATH\", sha256: \"HEX\"): {e}",
                scene.display()
            )
        })?;
    Ok(parsed.plugins)
}

/// The SHA-256 of `bytes`, as 64 lower-case hex digits.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// The SHA-256 of the file at `path`; the error says what went wrong (the caller names the
/// file, as the loader's errors do).
pub fn sha256_file(path: &Path) -> Result<String, String> {
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read it to hash it: {e}"))?;
    Ok(sha256_hex(&bytes))
}

/// `Ok` when `expected` is a well-formed SHA-256 (64 hex digits) equal to `actual`; otherwise
/// the refusal, naming both hashes (the caller names the file).
pub fn check(expected: &str, actual: &str) -> Result<(), String> {
    let expected_norm = expected.trim().to_ascii_lowercase();
    if expected_norm.len() != 64 || !expected_norm.bytes().all(|b| b.is_ascii_hexdigit()) {
        return Err(format!(
            "its pinned sha256 `{expected}` is not a SHA-256 (64 hexadecimal digits); the \
             file's is {actual}"
        ));
    }
    if expected_norm != actual {
        return Err(format!(
            "SHA-256 mismatch: the scene pins {expected_norm}, the file is {actual}; refusing to \
             load a library other than the one pinned (rebuild or re-pin it)"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    // FIPS 180-2 appendix B.1 test vector: SHA-256("abc").
    #[test]
    fn the_hash_is_sha256() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }

    // Both forms parse; a mismatch names both hashes; case does not matter; a malformed pin is
    // refused as such.
    #[test]
    fn pins_parse_and_are_checked() {
        let list: Vec<ScenePlugin> =
            ron::from_str(r#"["a.so", (path: "b.so", sha256: "AB")]"#).unwrap();
        assert_eq!(list[0], ScenePlugin::Path("a.so".into()));
        assert_eq!(list[1].path(), "b.so");
        assert_eq!(list[1].sha256(), Some("AB"));
        let abc = sha256_hex(b"abc");
        assert!(check(&abc.to_uppercase(), &abc).is_ok());
        let other = sha256_hex(b"abd");
        let e = check(&other, &abc).unwrap_err().to_string();
        assert!(
            e.contains(&other) && e.contains(&abc) && e.contains("mismatch"),
            "{e}"
        );
        let e = check("12ab", &abc).unwrap_err().to_string();
        assert!(e.contains("not a SHA-256"), "{e}");
    }
}
