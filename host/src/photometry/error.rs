//! One error type for every photometric file reader: it names the file, the 1-based line and
//! the field that is wrong, so a user can open the file and fix it.

use std::fmt;
use std::path::{Path, PathBuf};

/// A malformed or unreadable photometric file (IES LM-63, EULUMDAT or a tilt file).
#[derive(Clone, Debug, PartialEq)]
pub struct PhotometryError {
    /// The file that is wrong.
    pub file: PathBuf,
    /// 1-based line number, when the problem sits on one line.
    pub line: Option<usize>,
    /// The field being read (for example "candela multiplier" or "Isym").
    pub field: String,
    /// What is wrong with it.
    pub message: String,
}

impl PhotometryError {
    /// An error at `line` (1-based) of `file` while reading `field`.
    pub fn at(
        file: &Path,
        line: usize,
        field: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        Self {
            file: file.to_path_buf(),
            line: Some(line),
            field: field.into(),
            message: message.into(),
        }
    }

    /// An error about the whole file (unreadable, truncated before any line, …).
    pub fn file(file: &Path, field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            file: file.to_path_buf(),
            line: None,
            field: field.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for PhotometryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(
                f,
                "{}:{}: {}: {}",
                self.file.display(),
                line,
                self.field,
                self.message
            ),
            None => write!(
                f,
                "{}: {}: {}",
                self.file.display(),
                self.field,
                self.message
            ),
        }
    }
}

impl std::error::Error for PhotometryError {}
