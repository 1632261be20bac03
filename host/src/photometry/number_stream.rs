//! Numbers read one after another across lines, as LM-63 lays out its header numbers, angles
//! and candela values: wrapped at any width, separated by blanks and/or commas. Each number keeps
//! the line it came from so an error can name it.

use super::error::PhotometryError;
use std::path::Path;

/// A token with its 1-based source line.
#[derive(Clone, Debug)]
struct Token {
    text: String,
    line: usize,
}

/// Blank/comma separated tokens of a run of lines, consumed in order.
pub struct NumberStream<'a> {
    file: &'a Path,
    tokens: Vec<Token>,
    next: usize,
    last_line: usize,
}

impl<'a> NumberStream<'a> {
    /// Tokens of `lines`, the first of which is line `first_line` (1-based) of `file`.
    pub fn new(file: &'a Path, lines: &[&str], first_line: usize) -> Self {
        let mut tokens = Vec::new();
        for (i, line) in lines.iter().enumerate() {
            // 0x1A is the DOS end-of-file byte some files end with.
            for t in line.split(|c: char| c.is_whitespace() || c == ',' || c == '\u{1a}') {
                if !t.is_empty() {
                    tokens.push(Token {
                        text: t.to_string(),
                        line: first_line + i,
                    });
                }
            }
        }
        // "The file ends" errors point at the last line that holds anything.
        let last_line = tokens
            .last()
            .map_or(first_line + lines.len().saturating_sub(1), |t: &Token| {
                t.line
            });
        Self {
            file,
            tokens,
            next: 0,
            last_line,
        }
    }

    /// The next number, read as `field`; errors name the line, the field and the text found.
    pub fn number(&mut self, field: &str) -> Result<f64, PhotometryError> {
        let Some(tok) = self.tokens.get(self.next) else {
            return Err(PhotometryError::at(
                self.file,
                self.last_line,
                field,
                "the file ends before this value",
            ));
        };
        self.next += 1;
        match tok.text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(PhotometryError::at(
                self.file,
                tok.line,
                field,
                format!("`{}` is not a number", tok.text),
            )),
        }
    }

    /// The next number as a whole count/code (`3`, `3.0` and `3.` are accepted).
    pub fn integer(&mut self, field: &str) -> Result<i64, PhotometryError> {
        let line = self.line_of_next();
        let v = self.number(field)?;
        if v.fract() != 0.0 || v.abs() > 1e9 {
            return Err(PhotometryError::at(
                self.file,
                line,
                field,
                format!("{v} is not a whole number"),
            ));
        }
        Ok(v as i64)
    }

    /// The line of the next token (or the last line when none is left).
    pub fn line_of_next(&self) -> usize {
        self.tokens
            .get(self.next)
            .map_or(self.last_line, |t| t.line)
    }

    /// Tokens left after the last value read, with the line of the first.
    pub fn rest(&self) -> (Vec<&str>, usize) {
        let rest: Vec<&str> = self.tokens[self.next..]
            .iter()
            .map(|t| t.text.as_str())
            .collect();
        (rest, self.line_of_next())
    }
}
