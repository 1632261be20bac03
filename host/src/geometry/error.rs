//! Errors from geometry construction and mesh loading. Messages name the file and the place
//! (line for text files, byte offset for binary data) and say what was wrong.

use std::path::PathBuf;

/// Anything that can go wrong building geometry or reading a mesh file.
#[derive(Debug, thiserror::Error)]
pub enum GeometryError {
    /// A transform that is singular, projective or not finite.
    #[error("invalid transform: {0}")]
    InvalidTransform(String),
    /// A mesh whose data is inconsistent (index out of range, NaN position, length mismatch).
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
    /// An object handed to [`super::Geometry::build`] that cannot be built.
    #[error("object {object}: {message}")]
    InvalidObject {
        /// Index of the object in the list given to `build`.
        object: usize,
        /// What is wrong.
        message: String,
    },
    /// A text mesh file with a problem on a given line (1-based).
    #[error("{}: line {line}: {message}", path.display())]
    ParseLine {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A binary mesh file with a problem at a given byte offset.
    #[error("{}: byte {offset}: {message}", path.display())]
    ParseByte {
        /// The file.
        path: PathBuf,
        /// Byte offset from the start of the file.
        offset: usize,
        /// What is wrong.
        message: String,
    },
    /// A mesh file that is wrong as a whole (e.g. has no faces).
    #[error("{}: {message}", path.display())]
    File {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A mesh file that could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
}
