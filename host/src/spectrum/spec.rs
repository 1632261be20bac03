//! The spectrum spec strings used by scene files and the CLI.
//!
//! Emission (normalized SPD), [`parse_spd_spec`]:
//! - a bundled name: `d65`, `a`, `fl11`, `led_b1`, `mercury`, `high_pressure_sodium`, …
//! - `blackbody:T` (kelvin, tabulated on 360–830 nm) or `blackbody:T:LO:HI` (nm);
//! - `gaussian:CENTRE:FWHM` (both nm; the width is the *full width at half maximum*);
//! - `line:LAMBDA` (a monochromatic delta line, nm);
//! - a CSV path (`wavelength_nm,value`), optionally `path.csv#COLUMN` (header name or 1-based
//!   value-column index) for multi-column files; `step:PATH` reads it with step interpolation;
//! - a weighted sum `0.7*d65 + 0.3*line:532` (weights are power fractions, renormalized).

use std::path::Path;

use super::builtin_spd::BuiltinSpd;
use super::bundled::{bundled_names, bundled_spd, bundled_table};
use super::csv_table::{read_csv_table, CsvTable};
use super::error::SpectrumError;
use super::tabulated_spd::{Interpolation, TabulatedSpd};

fn spec_err(spec: &str, what: impl Into<String>) -> SpectrumError {
    SpectrumError::Spec {
        spec: spec.to_string(),
        what: what.into(),
    }
}

fn number(spec: &str, field: &str, what: &str) -> Result<f64, SpectrumError> {
    field
        .trim()
        .parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| spec_err(spec, format!("{what} `{field}` is not a finite number")))
}

/// Split `path#column` into the path and the optional column selector.
fn split_column(s: &str) -> (&str, Option<&str>) {
    match s.rsplit_once('#') {
        Some((p, c)) if !c.is_empty() && !Path::new(s).exists() => (p, Some(c)),
        _ => (s, None),
    }
}

/// Pick one value column of `table` (from `file`) by header name or 1-based index.
pub fn select_column(
    table: &CsvTable,
    file: &str,
    column: Option<&str>,
) -> Result<Vec<f64>, SpectrumError> {
    let invalid = |what: String| SpectrumError::Invalid {
        file: file.to_string(),
        what,
    };
    let n = table.columns.len();
    let idx = match column {
        None if n == 1 => 0,
        None => {
            return Err(invalid(format!(
                "has {n} value columns; choose one with `{file}#NAME` or `#INDEX` (columns: {})",
                table
                    .header
                    .as_ref()
                    .map(|h| h.join(", "))
                    .unwrap_or_else(|| format!("1..{n}"))
            )))
        }
        Some(c) => match c.trim().parse::<usize>() {
            Ok(i) if (1..=n).contains(&i) => i - 1,
            Ok(i) => return Err(invalid(format!("column index {i} is not in 1..{n}"))),
            Err(_) => table
                .column_index(c.trim())
                .ok_or_else(|| invalid(format!("no column named `{c}`")))?,
        },
    };
    Ok(table.columns[idx].clone())
}

fn csv_spd(
    spec: &str,
    path_and_col: &str,
    interp: Interpolation,
) -> Result<BuiltinSpd, SpectrumError> {
    let (path, col) = split_column(path_and_col);
    if path.is_empty() {
        return Err(spec_err(spec, "empty file path"));
    }
    let table = read_csv_table(Path::new(path))?;
    let values = select_column(&table, path, col)?;
    TabulatedSpd::new(path, &table.wavelengths, &values, interp).map(BuiltinSpd::Tabulated)
}

/// Split an SPD-type spec `name(param: value, …)` into the type name and its RON parameter
/// text; a bare `name` gets `()` (defaults). This is the syntax plugins use to name another
/// plugin's SPD type through host services, and scenes use for the same in spec strings.
pub fn split_type_spec(spec: &str) -> (&str, &str) {
    let spec = spec.trim();
    match spec.find('(') {
        Some(i) if spec.ends_with(')') => (spec[..i].trim(), &spec[i..]),
        _ => (spec, "()"),
    }
}

/// Parse one emission spec (see the module docs) into a normalized SPD.
pub fn parse_spd_spec(spec: &str) -> Result<BuiltinSpd, SpectrumError> {
    parse_spd_spec_with(spec, Interpolation::Linear)
}

/// [`parse_spd_spec`] with `tables` as the reconstruction of measured tables (CSV files and
/// bundled spectra, also inside sums): `Step` gives the seed §5 piecewise-constant
/// representation. `step:PATH` is always a step table; analytic SPDs (blackbody, Gaussian) are
/// tabulated finely and stay linear; lines are unaffected.
pub fn parse_spd_spec_with(spec: &str, tables: Interpolation) -> Result<BuiltinSpd, SpectrumError> {
    let s = spec.trim();
    if s.is_empty() {
        return Err(spec_err(spec, "empty spectrum spec"));
    }
    if Path::new(s).is_file() {
        return csv_spd(spec, s, tables);
    }
    if s.contains('+') {
        let parts = s
            .split('+')
            .map(|term| {
                let term = term.trim();
                match term.split_once('*') {
                    Some((w, rest)) => Ok((
                        number(spec, w, "weight")?,
                        parse_spd_spec_with(rest, tables)?,
                    )),
                    None => Ok((1.0, parse_spd_spec_with(term, tables)?)),
                }
            })
            .collect::<Result<Vec<_>, SpectrumError>>()?;
        return BuiltinSpd::sum(parts);
    }
    if let Some((w, rest)) = s.split_once('*') {
        if let Ok(w) = number(spec, w, "weight") {
            return BuiltinSpd::sum(vec![(w, parse_spd_spec_with(rest, tables)?)]);
        }
    }
    let (kind, args) = s.split_once(':').unwrap_or((s, ""));
    let fields: Vec<&str> = args.split(':').collect();
    match kind.to_ascii_lowercase().as_str() {
        "blackbody" => match fields.as_slice() {
            [t] => BuiltinSpd::blackbody(number(spec, t, "temperature")?),
            [t, lo, hi] => TabulatedSpd::blackbody(
                number(spec, t, "temperature")?,
                number(spec, lo, "lower wavelength")?,
                number(spec, hi, "upper wavelength")?,
            )
            .map(BuiltinSpd::Tabulated),
            _ => Err(spec_err(
                spec,
                "expected blackbody:KELVIN or blackbody:KELVIN:LO_NM:HI_NM",
            )),
        },
        "gaussian" => match fields.as_slice() {
            [c, w] => BuiltinSpd::gaussian(number(spec, c, "centre")?, number(spec, w, "FWHM")?),
            _ => Err(spec_err(spec, "expected gaussian:CENTRE_NM:FWHM_NM")),
        },
        "line" => match fields.as_slice() {
            [l] => BuiltinSpd::line(number(spec, l, "wavelength")?),
            _ => Err(spec_err(spec, "expected line:LAMBDA_NM")),
        },
        "csv" => csv_spd(spec, args, tables),
        "step" => csv_spd(spec, args, Interpolation::Step),
        _ => {
            if tables == Interpolation::Linear {
                if let Some(found) = bundled_spd(s) {
                    return found.map(BuiltinSpd::Tabulated);
                }
            } else if let Some(found) = bundled_table(s) {
                return found
                    .and_then(|(t, file)| {
                        TabulatedSpd::new(file, &t.wavelengths, &t.columns[0], tables)
                    })
                    .map(BuiltinSpd::Tabulated);
            }
            if s.to_ascii_lowercase().ends_with(".csv") || s.contains('#') {
                return csv_spd(spec, s, tables);
            }
            Err(spec_err(
                spec,
                format!(
                    "not a file, a bundled spectrum, blackbody:K, gaussian:C:FWHM or line:NM; bundled names: {}",
                    bundled_names().collect::<Vec<_>>().join(", ")
                ),
            ))
        }
    }
}

/// Wavelengths (nm) and raw values of a table.
pub type RawTable = (Vec<f64>, Vec<f64>);

/// The raw (unnormalized) table behind a bundled name or CSV path, for use as a curve.
pub fn raw_table_for_spec(spec: &str) -> Option<Result<RawTable, SpectrumError>> {
    if let Some(found) = bundled_table(spec) {
        return Some(found.map(|(t, _)| (t.wavelengths, t.columns[0].clone())));
    }
    let (path, col) = split_column(spec);
    if Path::new(path).is_file() || path.to_ascii_lowercase().ends_with(".csv") {
        return Some(read_csv_table(Path::new(path)).and_then(|t| {
            let v = select_column(&t, path, col)?;
            Ok((t.wavelengths, v))
        }));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::Spd;

    // Each spec form must produce the described SPD; structural checks plus the FWHM half-point
    // (1e-4, the Gaussian's tabulation error) and sum weights (1e-12, one division).
    #[test]
    fn parses_each_form() {
        assert!(matches!(
            parse_spd_spec("d65").unwrap(),
            BuiltinSpd::Tabulated(_)
        ));
        assert!(matches!(
            parse_spd_spec("blackbody:2856").unwrap(),
            BuiltinSpd::Tabulated(_)
        ));
        let g = parse_spd_spec("gaussian:550:20").unwrap();
        assert!((g.value(560.0) / g.value(550.0) - 0.5).abs() < 1e-4);
        let l = parse_spd_spec("line:532").unwrap();
        assert!(l.is_delta());
        let s = parse_spd_spec("0.75*d65 + 0.25*line:532").unwrap();
        let lines = s.delta_lines();
        assert_eq!(lines.len(), 1);
        assert!((lines[0].weight - 0.25).abs() < 1e-12);
        assert!(
            (s.value(560.0) - 0.75 * parse_spd_spec("d65").unwrap().value(560.0)).abs() < 1e-12
        );
    }

    // Step tables (seed §5's piecewise-constant representation): the bundled D65 read with
    // `parse_spd_spec_with(.., Step)` holds each 5 nm entry on [λᵢ, λᵢ₊₁) (equal values, exact,
    // both are the same table entry over the same integral), differs from the linear reading
    // between nodes, and is normalized by the step sum Σ fᵢ·Δλ (left rectangles) instead of the
    // trapezoid sum: checked through value ratios to 1e-12 (two divisions). Sums pass the
    // choice on; `Linear` is exactly `parse_spd_spec`.
    #[test]
    fn step_tables_for_bundled_and_sums() {
        use crate::spectrum::bundled::bundled_table;
        let lin = parse_spd_spec("d65").unwrap();
        let step = parse_spd_spec_with("d65", Interpolation::Step).unwrap();
        assert_eq!(
            parse_spd_spec_with("d65", Interpolation::Linear).unwrap(),
            lin
        );
        assert_eq!(step.value(562.0), step.value(560.0));
        assert_eq!(step.value(564.9), step.value(560.0));
        assert!(step.value(565.0) != step.value(560.0));
        assert!((lin.value(562.0) - step.value(562.0)).abs() > 1e-6);
        let (t, _) = bundled_table("d65").unwrap().unwrap();
        let (x, f) = (&t.wavelengths, &t.columns[0]);
        let left_sum: f64 = (0..x.len() - 1).map(|i| f[i] * (x[i + 1] - x[i])).sum();
        let i560 = x.iter().position(|&l| l == 560.0).unwrap();
        assert!((step.value(562.0) * left_sum / f[i560] - 1.0).abs() < 1e-12);
        let sum = parse_spd_spec_with("0.5*d65 + 0.5*a", Interpolation::Step).unwrap();
        assert_eq!(sum.value(561.0), sum.value(564.0));
    }

    // Bad specs must be errors naming the spec, never panics.
    #[test]
    fn rejects_bad_specs() {
        for bad in [
            "",
            "blackbody:",
            "blackbody:-5",
            "gaussian:550",
            "line:abc",
            "nosuch",
            "x*d65+",
            "missing.csv",
        ] {
            let e = parse_spd_spec(bad);
            assert!(e.is_err(), "{bad}");
        }
        let msg = parse_spd_spec("missing.csv").unwrap_err().to_string();
        assert!(msg.contains("missing.csv"), "{msg}");
    }
}
