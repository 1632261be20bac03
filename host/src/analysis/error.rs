//! Errors of the analysis tools: each names the file and what is wrong with it.

use std::path::PathBuf;

/// A failure to read, compare, resume or plot; never a panic.
#[derive(Debug, thiserror::Error)]
pub enum AnalysisError {
    /// The file does not exist or cannot be opened.
    #[error("cannot read {path}: {message}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's or decoder's message.
        message: String,
    },
    /// The file was read but its content is not what is needed.
    #[error("{path}: {message}")]
    Content {
        /// The file.
        path: PathBuf,
        /// What is wrong, for example a missing channel.
        message: String,
    },
    /// Two images that must be compared pixel by pixel differ in size.
    #[error("{a} is {aw}×{ah} but {b} is {bw}×{bh}; images must have the same size")]
    SizeMismatch {
        /// First file.
        a: PathBuf,
        /// Its width.
        aw: u32,
        /// Its height.
        ah: u32,
        /// Second file.
        b: PathBuf,
        /// Its width.
        bw: u32,
        /// Its height.
        bh: u32,
    },
    /// A file could not be written.
    #[error("cannot write {path}: {message}")]
    Write {
        /// The file.
        path: PathBuf,
        /// Cause.
        message: String,
    },
    /// Rendering failed.
    #[error("rendering failed: {0}")]
    Render(String),
}
