//! Scene errors: every message names the file and either the RON position (line, column) or the
//! scene item and parameter that is wrong.

use std::path::PathBuf;

/// Anything that can go wrong loading or building a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{}: {source}", file.display())]
    Io {
        /// The file.
        file: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// RON syntax or structure error at a position.
    #[error("{}:{line}:{column}: {message}", file.display())]
    Syntax {
        /// The file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What the parser expected.
        message: String,
    },
    /// A semantically invalid item (unknown type, bad or missing parameter, bad reference).
    #[error("{}: {item}: {message}", file.display())]
    Item {
        /// The file.
        file: PathBuf,
        /// The item, e.g. `material "red"` or `object "floor"`.
        item: String,
        /// What is wrong (names the parameter).
        message: String,
    },
    /// The scene as a whole is unusable (no camera, empty geometry, …).
    #[error("{}: {message}", file.display())]
    Scene {
        /// The file.
        file: PathBuf,
        /// What is wrong.
        message: String,
    },
}
