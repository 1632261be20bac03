//! Reader of bispectral (Donaldson) matrix files written by the Labsphere BFC-450
//! fluorescence colorimeter (`.BFC`). The raw table is returned as read; the physics-based
//! cleaning lives in [`super::bispectral_matrix`].
//!
//! # Format (text, tab-separated, CRLF or LF)
//! - optional preamble lines (the bundled files start with `VEC_01<TAB>5167`);
//! - `BFC-450 Matrix File`;
//! - `;`-comment lines: file name, sample name, operator, instrument settings, date, time;
//! - six numbers: first and last emission wavelength (nm), emission step (nm), number of
//!   excitation columns, first excitation wavelength (nm), excitation step (nm);
//! - `r:c:` followed by the excitation wavelengths;
//! - one row per emission wavelength: the wavelength, then one value per excitation column,
//!   the bispectral radiance factor D(λₒ, λᵢ) (unitless);
//! - `EOD`.
//!
//! Every error names the file, the 1-based line and the field (column) that is wrong.

use super::error::SpectrumError;

/// The preamble lines allowed before the `BFC-450 Matrix File` line.
const MAX_PREAMBLE_LINES: usize = 4;

/// A `.BFC` file as read: the grid and the raw (uncleaned) values.
#[derive(Clone, Debug, PartialEq)]
pub struct BfcFile {
    /// File name or label used in messages.
    pub label: String,
    /// Sample description (the second `;` comment line), empty when absent.
    pub sample: String,
    /// Emission wavelengths λₒ in nm (rows), increasing by a constant step.
    pub emission_nm: Vec<f64>,
    /// Excitation wavelengths λᵢ in nm (columns), increasing by a constant step.
    pub excitation_nm: Vec<f64>,
    /// D(λₒ, λᵢ), row-major: `values[row * excitation_nm.len() + column]`.
    pub values: Vec<f64>,
}

impl BfcFile {
    /// Read and parse a `.BFC` file.
    pub fn read(path: &std::path::Path) -> Result<Self, SpectrumError> {
        let label = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SpectrumError::Io {
            file: label.clone(),
            what: e.to_string(),
        })?;
        Self::parse(&text, &label)
    }

    /// Parse the text of a `.BFC` file; `label` names it in errors.
    pub fn parse(text: &str, label: &str) -> Result<Self, SpectrumError> {
        let mut r = BfcLines {
            label,
            lines: text
                .lines()
                .enumerate()
                .map(|(i, l)| (i + 1, l.trim_end_matches('\r').trim()))
                .collect(),
            next: 0,
        };
        r.skip_to_magic_line()?;
        let comments = r.comments();
        let sample = comments.get(1).cloned().unwrap_or_default();
        let (header_line, emission_nm, excitation_nm) = r.grid()?;
        r.column_header(header_line, &excitation_nm)?;
        let values = r.rows(&emission_nm, &excitation_nm)?;
        r.end_of_data()?;
        Ok(Self {
            label: label.to_string(),
            sample,
            emission_nm,
            excitation_nm,
            values,
        })
    }
}

/// The lines of a `.BFC` file (1-based number, trimmed text) with a cursor; each step of
/// [`BfcFile::parse`] reads the part of the file it names.
struct BfcLines<'a> {
    label: &'a str,
    lines: Vec<(usize, &'a str)>,
    next: usize,
}

impl<'a> BfcLines<'a> {
    fn err(&self, line: usize, what: String) -> SpectrumError {
        SpectrumError::Parse {
            file: self.label.to_string(),
            line,
            what,
        }
    }

    /// The next line, if any.
    fn take(&mut self) -> Option<(usize, &'a str)> {
        let line = self.lines.get(self.next).copied();
        if line.is_some() {
            self.next += 1;
        }
        line
    }

    /// Past the `BFC-450 Matrix File` line, which may follow a short preamble.
    fn skip_to_magic_line(&mut self) -> Result<(), SpectrumError> {
        for _ in 0..=MAX_PREAMBLE_LINES {
            match self.take() {
                Some((_, "BFC-450 Matrix File")) => return Ok(()),
                Some(_) => {}
                None => break,
            }
        }
        Err(self.err(
            1,
            format!(
                "not a BFC-450 matrix file: no `BFC-450 Matrix File` line within the first {} lines",
                MAX_PREAMBLE_LINES + 1
            ),
        ))
    }

    /// The `;` comment lines, without the `;`.
    fn comments(&mut self) -> Vec<String> {
        let mut comments = Vec::new();
        while let Some(&(_, l)) = self.lines.get(self.next) {
            let Some(c) = l.strip_prefix(';') else { break };
            comments.push(c.trim().to_string());
            self.next += 1;
        }
        comments
    }

    /// The grid header's six numbers: its line, the emission and the excitation wavelengths.
    fn grid(&mut self) -> Result<(usize, Vec<f64>, Vec<f64>), SpectrumError> {
        let (hl, header) = self
            .take()
            .ok_or_else(|| self.err(self.lines.len(), "file ends before the grid header".into()))?;
        const NAMES: [&str; 6] = [
            "first emission wavelength",
            "last emission wavelength",
            "emission step",
            "number of excitation columns",
            "first excitation wavelength",
            "excitation step",
        ];
        let fields: Vec<&str> = header.split_whitespace().collect();
        if fields.len() != 6 {
            return Err(self.err(
                hl,
                format!(
                    "grid header: expected 6 numbers ({}), found {} fields",
                    NAMES.join(", "),
                    fields.len()
                ),
            ));
        }
        let mut g = [0.0f64; 6];
        for (k, f) in fields.iter().enumerate() {
            g[k] = f
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v > 0.0)
                .ok_or_else(|| {
                    self.err(
                        hl,
                        format!(
                            "grid header field {} ({}): `{f}` is not a positive number",
                            k + 1,
                            NAMES[k]
                        ),
                    )
                })?;
        }
        let [e0, e1, estep, ncols, x0, xstep] = g;
        if e1 < e0 || ncols.fract() != 0.0 || ((e1 - e0) / estep).fract().abs() > 1e-9 {
            return Err(self.err(
                hl,
                format!("grid header: emission {e0}..{e1} nm in steps of {estep} nm with {ncols} excitation columns is not a regular grid"),
            ));
        }
        let nrows = ((e1 - e0) / estep).round() as usize + 1;
        let ncols = ncols as usize;
        if nrows > 10_000 || ncols > 10_000 {
            return Err(self.err(
                hl,
                format!("grid header: {nrows}×{ncols} is implausibly large"),
            ));
        }
        let emission_nm: Vec<f64> = (0..nrows).map(|k| e0 + k as f64 * estep).collect();
        let excitation_nm: Vec<f64> = (0..ncols).map(|k| x0 + k as f64 * xstep).collect();
        Ok((hl, emission_nm, excitation_nm))
    }

    /// The `r:c:` line, which must list `excitation_nm`; `hl` is the grid header's line.
    fn column_header(&mut self, hl: usize, excitation_nm: &[f64]) -> Result<(), SpectrumError> {
        let ncols = excitation_nm.len();
        let (cl, cols) = self
            .take()
            .ok_or_else(|| self.err(hl, "file ends before the `r:c:` column header".into()))?;
        let mut cf = cols.split_whitespace();
        if cf.next() != Some("r:c:") {
            return Err(self.err(cl, "column header must start with `r:c:`".into()));
        }
        let cols: Vec<&str> = cf.collect();
        if cols.len() != ncols {
            return Err(self.err(
                cl,
                format!(
                    "column header lists {} excitation wavelengths, the grid header says {ncols}",
                    cols.len()
                ),
            ));
        }
        for (k, (f, want)) in cols.iter().zip(excitation_nm).enumerate() {
            match f.parse::<f64>() {
                Ok(v) if (v - want).abs() < 1e-6 => {}
                _ => {
                    return Err(self.err(
                        cl,
                        format!(
                        "column header field {} is `{f}`, expected excitation wavelength {want} nm",
                        k + 2
                    ),
                    ))
                }
            }
        }
        Ok(())
    }

    /// One row per emission wavelength: the wavelength, then one finite value per excitation
    /// column; the values row-major.
    fn rows(
        &mut self,
        emission_nm: &[f64],
        excitation_nm: &[f64],
    ) -> Result<Vec<f64>, SpectrumError> {
        let ncols = excitation_nm.len();
        let mut values = Vec::with_capacity(emission_nm.len() * ncols);
        for want in emission_nm {
            let (rl, row) = self.take().ok_or_else(|| {
                self.err(
                    self.lines.len(),
                    format!("file ends before the row for emission {want} nm"),
                )
            })?;
            let fields: Vec<&str> = row.split_whitespace().collect();
            if fields.len() != ncols + 1 {
                return Err(self.err(
                    rl,
                    format!("row for emission {want} nm: expected {} fields (wavelength + {ncols} values), found {}", ncols + 1, fields.len()),
                ));
            }
            match fields[0].parse::<f64>() {
                Ok(v) if (v - want).abs() < 1e-6 => {}
                _ => {
                    return Err(self.err(
                        rl,
                        format!(
                            "field 1 is `{}`, expected emission wavelength {want} nm",
                            fields[0]
                        ),
                    ))
                }
            }
            for (k, f) in fields[1..].iter().enumerate() {
                let v = f.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| {
                    self.err(
                        rl,
                        format!(
                            "field {} (emission {want} nm, excitation {} nm): `{f}` is not a finite number",
                            k + 2,
                            excitation_nm[k]
                        ),
                    )
                })?;
                values.push(v);
            }
        }
        Ok(values)
    }

    /// The `EOD` line after the last row.
    fn end_of_data(&mut self) -> Result<(), SpectrumError> {
        match self.take() {
            Some((_, "EOD")) => Ok(()),
            Some((l, other)) => Err(self.err(
                l,
                format!("expected `EOD` after the last row, found `{other}`"),
            )),
            None => Err(self.err(self.lines.len(), "missing `EOD` after the last row".into())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tiny(rows: &str) -> String {
        format!("VEC_01\t1\r\nBFC-450 Matrix File\r\n;x.BFC\r\n;sample x\r\n400\t420\t10\t3\t390\t10\r\nr:c:\t390\t400\t410\r\n{rows}EOD\r\n")
    }

    // A well-formed file parses with its grid and values in row-major order (exact: they are
    // copied from the text).
    #[test]
    fn parses_a_small_file() {
        let f = BfcFile::parse(
            &tiny("400\t0.1\t0.5\t0\r\n410\t0.2\t0\t0.6\r\n420\t-0.01\t0.3\t0\r\n"),
            "x.BFC",
        )
        .unwrap();
        assert_eq!(f.sample, "sample x");
        assert_eq!(f.emission_nm, vec![400.0, 410.0, 420.0]);
        assert_eq!(f.excitation_nm, vec![390.0, 400.0, 410.0]);
        assert_eq!(f.values[4], 0.0);
        assert_eq!(f.values[5], 0.6);
        assert_eq!(f.values[6], -0.01);
    }

    // Errors name the file, the line and the field.
    #[test]
    fn errors_name_file_line_and_field() {
        let e = BfcFile::parse(
            &tiny("400\t0.1\t0.5\t0\r\n410\t0.2\tabc\t0.6\r\n420\t0\t0.3\t0\r\n"),
            "x.BFC",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.starts_with("x.BFC:8:") && e.contains("field 3") && e.contains("400 nm"),
            "{e}"
        );
        let e = BfcFile::parse(&tiny("400\t0.1\t0.5\t0\r\n410\t0.2\t0\t0.6\r\n"), "x.BFC")
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.BFC:9:") && e.contains("420"), "{e}");
        let e = BfcFile::parse("hello\nworld\n", "y.BFC")
            .unwrap_err()
            .to_string();
        assert!(e.contains("y.BFC:1:") && e.contains("BFC-450"), "{e}");
        let e = BfcFile::parse(
            &tiny("").replace("r:c:\t390\t400\t410", "r:c:\t390\t400"),
            "z",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("z:6:") && e.contains("2 excitation"), "{e}");
    }
}
