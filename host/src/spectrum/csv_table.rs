//! Reading spectral tables from CSV text: `wavelength_nm,value[,value…]`, `#` comment lines,
//! blank lines, and an optional header row.
//!
//! Data are validated strictly because a silently wrong spectrum gives a plausible but wrong
//! image: wavelengths must be finite, positive and strictly increasing, values finite and
//! non-negative, and every row must have the same number of columns. Errors carry the line.

use super::error::SpectrumError;

/// A parsed table: one wavelength column (nm) and one or more value columns.
#[derive(Clone, Debug, PartialEq)]
pub struct CsvTable {
    /// Column names from the header row (value columns only), if the file had a header.
    pub header: Option<Vec<String>>,
    /// Wavelengths in nm, strictly increasing.
    pub wavelengths: Vec<f64>,
    /// `columns[c][i]` is the value of column `c` at `wavelengths[i]`.
    pub columns: Vec<Vec<f64>>,
}

impl CsvTable {
    /// Index of the value column called `name` (case-insensitive), if the file had a header.
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.header
            .as_ref()?
            .iter()
            .position(|h| h.eq_ignore_ascii_case(name))
    }
}

/// Split one CSV line into trimmed fields, honouring double quotes (header names such as
/// `"dark skin"` are quoted in the ColorChecker file).
fn split_fields(line: &str) -> Vec<String> {
    let mut fields = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    for ch in line.chars() {
        match ch {
            '"' => quoted = !quoted,
            ',' if !quoted => fields.push(std::mem::take(&mut cur).trim().to_string()),
            _ => cur.push(ch),
        }
    }
    fields.push(cur.trim().to_string());
    fields
}

/// Parse CSV `text` read from `file` (used only in messages). Requires at least two data rows
/// and at least one value column; rejects unsorted, duplicate, negative and non-finite entries.
pub fn parse_csv_table(text: &str, file: &str) -> Result<CsvTable, SpectrumError> {
    let err = |line: usize, what: String| SpectrumError::Parse {
        file: file.to_string(),
        line,
        what,
    };
    let mut header = None;
    let mut wavelengths: Vec<f64> = Vec::new();
    let mut columns: Vec<Vec<f64>> = Vec::new();
    let mut width: Option<usize> = None;
    let mut last_line = 0;
    for (idx, raw) in text.lines().enumerate() {
        let line_no = idx + 1;
        last_line = line_no;
        let line = raw.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let fields = split_fields(line);
        if fields.len() < 2 {
            return Err(err(
                line_no,
                format!("expected `wavelength_nm,value`, found `{line}`"),
            ));
        }
        let first_is_number = fields[0].parse::<f64>().is_ok();
        if !first_is_number {
            if width.is_none() && header.is_none() {
                header = Some(fields[1..].to_vec());
                width = Some(fields.len());
                continue;
            }
            return Err(err(
                line_no,
                format!("wavelength `{}` is not a number", fields[0]),
            ));
        }
        match width {
            None => width = Some(fields.len()),
            Some(w) if w != fields.len() => {
                return Err(err(
                    line_no,
                    format!("expected {w} columns, found {}", fields.len()),
                ))
            }
            _ => {}
        }
        if columns.is_empty() {
            columns = vec![Vec::new(); fields.len() - 1];
        }
        let lambda: f64 = fields[0].parse().expect("checked above");
        if !lambda.is_finite() || lambda <= 0.0 {
            return Err(err(
                line_no,
                format!("wavelength {lambda} must be finite and positive (nm)"),
            ));
        }
        if let Some(&prev) = wavelengths.last() {
            if lambda == prev {
                return Err(err(line_no, format!("duplicate wavelength {lambda} nm")));
            }
            if lambda < prev {
                return Err(err(
                    line_no,
                    format!("wavelength {lambda} nm is not sorted (follows {prev} nm)"),
                ));
            }
        }
        for (c, field) in fields[1..].iter().enumerate() {
            let v: f64 = field.parse().map_err(|_| {
                err(
                    line_no,
                    format!("value `{field}` in column {} is not a number", c + 2),
                )
            })?;
            if !v.is_finite() {
                return Err(err(
                    line_no,
                    format!("value {v} in column {} is not finite", c + 2),
                ));
            }
            if v < 0.0 {
                return Err(err(
                    line_no,
                    format!("value {v} in column {} is negative", c + 2),
                ));
            }
            columns[c].push(v);
        }
        wavelengths.push(lambda);
    }
    if wavelengths.len() < 2 {
        return Err(SpectrumError::Parse {
            file: file.to_string(),
            line: last_line.max(1),
            what: format!(
                "need at least 2 data rows, found {} (end of file)",
                wavelengths.len()
            ),
        });
    }
    Ok(CsvTable {
        header,
        wavelengths,
        columns,
    })
}

/// Read and parse the CSV file at `path`; I/O errors name the path.
pub fn read_csv_table(path: &std::path::Path) -> Result<CsvTable, SpectrumError> {
    let name = path.display().to_string();
    let limit = crate::limits::TABLE_FILE_MAX_BYTES;
    let text = crate::limits::read_text_limited(path, limit, "spectrum table").map_err(|e| {
        SpectrumError::Io {
            file: name.clone(),
            what: e.to_string(),
        }
    })?;
    parse_csv_table(&text, &name)
}

#[cfg(test)]
mod tests {
    use super::*;

    // Checks the happy path including comments, a quoted header and irregular spacing; exact
    // equality because parsing decimal literals is deterministic.
    #[test]
    fn parses_header_comments_and_multiple_columns() {
        let t = parse_csv_table(
            "# c\nwavelength_nm,\"a b\",c\n400,1,2\n\n401.5,3,4\n410,0,0\n",
            "t.csv",
        )
        .unwrap();
        assert_eq!(t.header, Some(vec!["a b".to_string(), "c".to_string()]));
        assert_eq!(t.wavelengths, vec![400.0, 401.5, 410.0]);
        assert_eq!(t.columns[1], vec![2.0, 4.0, 0.0]);
        assert_eq!(t.column_index("A B"), Some(0));
    }
}
