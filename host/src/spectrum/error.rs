//! Errors from reading and building spectra. Every message names the file (or spec string) and,
//! for text input, the 1-based line, so a user can fix bad data without a debugger.

use thiserror::Error;

/// What can go wrong when loading, parsing or building a spectrum.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SpectrumError {
    /// A malformed line in a tabulated text file.
    #[error("{file}:{line}: {what}")]
    Parse {
        /// File name (or a label such as `<bundled d65>`).
        file: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong with that line.
        what: String,
    },
    /// The file as a whole is unusable (too few rows, all zero, …).
    #[error("{file}: {what}")]
    Invalid {
        /// File name or label.
        file: String,
        /// What is wrong.
        what: String,
    },
    /// The file could not be read.
    #[error("{file}: cannot read: {what}")]
    Io {
        /// File path.
        file: String,
        /// The operating-system error text.
        what: String,
    },
    /// A spectrum spec string (`d65`, `blackbody:2856`, …) could not be understood.
    #[error("spectrum spec `{spec}`: {what}")]
    Spec {
        /// The offending spec string.
        spec: String,
        /// What is wrong with it.
        what: String,
    },
}
