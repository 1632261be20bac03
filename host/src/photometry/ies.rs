//! IES LM-63 reader (1986, 1991, 1995, 2002 and 2019 headers).
//!
//! Written here because no crate fits: `lidrs` is stalled and reads type C only, and the
//! `eulumdat` crate (which also reads IES) is AGPL, which this project cannot take.
//!
//! What it reads, in file order:
//! | part | content |
//! |---|---|
//! | version line | `IESNA:LM-63-1995`, `IESNA:LM-63-2002`, `IES:LM-63-2019`, `IESNA91`, the non-standard `IESNA95`; none (or anything else) means LM-63-1986 and the line is free text. Leading blanks are allowed. |
//! | header | `[KEYWORD] value` lines (`[MORE]` continues the previous one) and free text, up to `TILT=` |
//! | `TILT=` | `NONE`; `INCLUDE` (tilt data follows); or a file name, read relative to the IES file |
//! | tilt data | lamp-to-luminaire geometry, number of pairs, angles, multiplying factors |
//! | 10 numbers | lamps, lumens per lamp (−1: absolute photometry), candela multiplier, number of vertical and horizontal angles, photometric type (1 C, 2 B, 3 A), units (1 ft, 2 m), width, length, height |
//! | 3 numbers | ballast factor; ballast-lamp photometric factor (1986/1991, a multiplier), "future use" (1995/2002, not applied), file generation type (2019, **not** a multiplier); input watts |
//! | angles | vertical angles, then horizontal angles |
//! | candela | one block of vertical values per horizontal angle |
//!
//! Numbers may be wrapped at any width and separated by blanks or commas. Bytes are read as
//! Latin-1 (real files carry 0xA0 in keyword lines). Anything after the candela table (for
//! example `END` and a DOS end-of-file byte) is ignored with a warning when it is not `END`.

use super::error::PhotometryError;
use super::luminaire::{
    IesVersion, LampSet, Luminaire, Multiplier, PhotometricType, SourceFormat, Symmetry, TiltTable,
};
use super::number_stream::NumberStream;
use std::path::Path;

/// Feet to metres.
const FOOT_M: f64 = 0.3048;

/// Parse the LM-63 file at `path` whose bytes are `bytes`.
pub fn parse_ies(bytes: &[u8], path: &Path) -> Result<Luminaire, PhotometryError> {
    let text = latin1(bytes);
    let lines = lines_of(&text);
    let mut warnings = Vec::new();

    let (version, header_start) = read_version(&lines, path, &mut warnings)?;
    let head = read_header(&lines, header_start, path)?;
    let mut nums = NumberStream::new(path, &lines[head.tilt_line + 1..], head.tilt_line + 2);
    let tilt = read_tilt_of(&head, &mut nums, path)?;
    let n = read_numbers(&mut nums, path, version)?;
    let (multipliers, scale) = multipliers_of(&n, version, path, &mut warnings)?;
    let mut table = read_table(&mut nums, n.nv, n.nh, scale, path)?;
    warn_trailing(&nums, &mut warnings);
    table.make_ascending(path)?;
    let symmetry = symmetry_of(
        n.ptype,
        &table.h,
        &table.v,
        path,
        &table.h_lines,
        &table.v_lines,
        &mut warnings,
    )?;

    let absolute = n.absolute();
    let lamp = LampSet {
        count: n.n_lamps,
        lumens: (!absolute).then_some(n.lumens_per_lamp),
        description: head.lamp_description,
        watts: (n.watts > 0.0).then_some(n.watts),
    };
    Ok(Luminaire {
        format: SourceFormat::Ies(version),
        photometric_type: n.ptype,
        symmetry,
        h_deg: table.h,
        v_deg: table.v,
        candela: table.cd,
        lamps: vec![lamp],
        multipliers,
        absolute,
        rated_lamp_lumens: (!absolute).then_some(n.n_lamps as f64 * n.lumens_per_lamp),
        size_m: n.size.map(|s| s * n.unit_m),
        tilt,
        header: head.header,
        warnings,
    })
}

/// The version from the first line that is not empty, and the index of the first header line
/// (the version line itself for LM-63-1986, whose first line is free text).
fn read_version(
    lines: &[&str],
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<(IesVersion, usize), PhotometryError> {
    let first = lines
        .iter()
        .position(|l| !l.trim().is_empty())
        .ok_or_else(|| PhotometryError::file(path, "file", "is empty"))?;
    let version_text = lines[first].trim().to_ascii_uppercase();
    Ok(match version_text.as_str() {
        "IESNA:LM-63-1995" => (IesVersion::Lm63_1995, first + 1),
        "IESNA:LM-63-2002" => (IesVersion::Lm63_2002, first + 1),
        "IES:LM-63-2019" => (IesVersion::Lm63_2019, first + 1),
        "IESNA91" | "IESNA:LM-63-1991" => (IesVersion::Lm63_1991, first + 1),
        "IESNA95" => {
            warnings.push(format!(
                "line {}: non-standard version line `IESNA95`, read as LM-63-1995",
                first + 1
            ));
            (IesVersion::Lm63_1995, first + 1)
        }
        v if v.starts_with("IESNA") || v.starts_with("IES:") => {
            warnings.push(format!(
                "line {}: unknown version line `{}`, read as LM-63-2002",
                first + 1,
                lines[first].trim()
            ));
            (IesVersion::Lm63_2002, first + 1)
        }
        _ => (IesVersion::Lm63_1986, first),
    })
}

/// The header lines up to `TILT=`.
struct Header {
    /// `[KEYWORD] value` lines (with `[MORE]` joined) and free text.
    header: Vec<String>,
    /// The first `[LAMP]` value.
    lamp_description: String,
    /// Index of the `TILT=` line.
    tilt_line: usize,
    /// What follows `TILT=`.
    tilt_value: String,
}

/// Keyword and free-text lines from `start` up to the `TILT=` line.
fn read_header(lines: &[&str], start: usize, path: &Path) -> Result<Header, PhotometryError> {
    let mut header: Vec<String> = Vec::new();
    let mut lamp_description = String::new();
    let mut tilt_line = None;
    for (i, line) in lines.iter().enumerate().skip(start) {
        let t = line.trim();
        if t.get(..5).is_some_and(|p| p.eq_ignore_ascii_case("TILT=")) {
            tilt_line = Some(i);
            break;
        }
        if let Some(rest) = t.strip_prefix('[') {
            if let Some(end) = rest.find(']') {
                let key = rest[..end].trim().to_string();
                let value = rest[end + 1..].trim().to_string();
                if key.eq_ignore_ascii_case("MORE") {
                    if let Some(prev) = header.last_mut() {
                        prev.push(' ');
                        prev.push_str(&value);
                    }
                } else {
                    if key.eq_ignore_ascii_case("LAMP") && lamp_description.is_empty() {
                        lamp_description = value.clone();
                    }
                    header.push(format!("[{key}] {value}"));
                }
                continue;
            }
        }
        if !t.is_empty() {
            header.push(t.to_string());
        }
    }
    let tilt_line = tilt_line.ok_or_else(|| {
        PhotometryError::file(
            path,
            "TILT=",
            "no `TILT=` line: this is not an IES LM-63 file",
        )
    })?;
    let tilt_value = lines[tilt_line].trim()[5..].trim().to_string();
    Ok(Header {
        header,
        lamp_description,
        tilt_line,
        tilt_value,
    })
}

/// The tilt table `TILT=` names: none, the data that follows in `nums`, or a file beside `path`.
fn read_tilt_of(
    head: &Header,
    nums: &mut NumberStream,
    path: &Path,
) -> Result<Option<TiltTable>, PhotometryError> {
    match head.tilt_value.to_ascii_uppercase().as_str() {
        "NONE" => Ok(None),
        "INCLUDE" => Ok(Some(read_tilt(nums, path, "INCLUDE".to_string())?)),
        "" => Err(PhotometryError::at(
            path,
            head.tilt_line + 1,
            "TILT=",
            "no value; expected NONE, INCLUDE or a tilt file name",
        )),
        _ => {
            let tilt_path = path
                .parent()
                .unwrap_or(Path::new("."))
                .join(&head.tilt_value);
            let limit = crate::limits::LUMINAIRE_FILE_MAX_BYTES;
            let read = crate::limits::read_limited(&tilt_path, limit, "tilt file");
            let bytes = read.map_err(|e| {
                PhotometryError::at(
                    path,
                    head.tilt_line + 1,
                    "TILT=",
                    format!("cannot read tilt file {}: {e}", tilt_path.display()),
                )
            })?;
            let text = latin1(&bytes);
            let tlines = lines_of(&text);
            let mut tnums = NumberStream::new(&tilt_path, &tlines, 1);
            Ok(Some(read_tilt(
                &mut tnums,
                &tilt_path,
                tilt_path.display().to_string(),
            )?))
        }
    }
}

/// The 10 + 3 numbers after the tilt data, checked.
struct Numbers {
    n_lamps: i64,
    /// −1 for absolute photometry.
    lumens_per_lamp: f64,
    candela_multiplier: f64,
    nv: usize,
    nh: usize,
    ptype: PhotometricType,
    /// Metres per file unit.
    unit_m: f64,
    /// Luminous opening width, length, height in file units.
    size: [f64; 3],
    ballast_factor: f64,
    /// Line of the ballast factor (and of the field after it).
    bf_line: usize,
    /// Name of the second of the three numbers, which depends on the version.
    second_name: &'static str,
    second: f64,
    watts: f64,
}

impl Numbers {
    /// Whether the file gives absolute photometry (lumens per lamp −1).
    fn absolute(&self) -> bool {
        self.lumens_per_lamp == -1.0
    }
}

/// Read the 10 + 3 numbers, then check them.
fn read_numbers(
    nums: &mut NumberStream,
    path: &Path,
    version: IesVersion,
) -> Result<Numbers, PhotometryError> {
    let lamps_line = nums.line_of_next();
    let n_lamps = nums.integer("number of lamps")?;
    let lumens_line = nums.line_of_next();
    let lumens_per_lamp = nums.number("lumens per lamp")?;
    let mult_line = nums.line_of_next();
    let candela_multiplier = nums.number("candela multiplier")?;
    let nv_line = nums.line_of_next();
    let nv = nums.integer("number of vertical angles")?;
    let nh_line = nums.line_of_next();
    let nh = nums.integer("number of horizontal angles")?;
    let type_line = nums.line_of_next();
    let ptype = match nums.integer("photometric type")? {
        1 => PhotometricType::C,
        2 => PhotometricType::B,
        3 => PhotometricType::A,
        other => {
            return Err(PhotometryError::at(
                path,
                type_line,
                "photometric type",
                format!("{other}; expected 1 (type C), 2 (type B) or 3 (type A)"),
            ))
        }
    };
    let units_line = nums.line_of_next();
    let unit_m = match nums.integer("units type")? {
        1 => FOOT_M,
        2 => 1.0,
        other => {
            return Err(PhotometryError::at(
                path,
                units_line,
                "units type",
                format!("{other}; expected 1 (feet) or 2 (metres)"),
            ))
        }
    };
    let width = nums.number("luminous opening width")?;
    let length = nums.number("luminous opening length")?;
    let height = nums.number("luminous opening height")?;
    let bf_line = nums.line_of_next();
    let ballast_factor = nums.number("ballast factor")?;
    let second_name = match version {
        IesVersion::Lm63_1986 | IesVersion::Lm63_1991 => "ballast-lamp photometric factor",
        IesVersion::Lm63_1995 | IesVersion::Lm63_2002 => "future use",
        IesVersion::Lm63_2019 => "file generation type",
    };
    let second = nums.number(second_name)?;
    let watts = nums.number("input watts")?;

    let out_of_range = |line: usize, field: &str, message: String| {
        Err(PhotometryError::at(path, line, field, message))
    };
    if n_lamps < 1 {
        let message = format!("{n_lamps}; at least 1 expected");
        return out_of_range(lamps_line, "number of lamps", message);
    }
    if lumens_per_lamp != -1.0 && !(lumens_per_lamp > 0.0) {
        let message =
            format!("{lumens_per_lamp}; expected a positive number or -1 (absolute photometry)");
        return out_of_range(lumens_line, "lumens per lamp", message);
    }
    if !(candela_multiplier > 0.0) {
        let message = format!("{candela_multiplier}; must be positive");
        return out_of_range(mult_line, "candela multiplier", message);
    }
    if !(ballast_factor > 0.0) {
        let message = format!("{ballast_factor}; must be positive");
        return out_of_range(bf_line, "ballast factor", message);
    }
    if !(1..=100_000).contains(&nv) {
        let message = format!("{nv}; expected 1 to 100000");
        return out_of_range(nv_line, "number of vertical angles", message);
    }
    if !(1..=100_000).contains(&nh) {
        let message = format!("{nh}; expected 1 to 100000");
        return out_of_range(nh_line, "number of horizontal angles", message);
    }
    Ok(Numbers {
        n_lamps,
        lumens_per_lamp,
        candela_multiplier,
        nv: nv as usize,
        nh: nh as usize,
        ptype,
        unit_m,
        size: [width, length, height],
        ballast_factor,
        bf_line,
        second_name,
        second,
        watts,
    })
}

/// The multipliers the file declares (which of them apply depends on the version) and the
/// product of those applied.
fn multipliers_of(
    n: &Numbers,
    version: IesVersion,
    path: &Path,
    warnings: &mut Vec<String>,
) -> Result<(Vec<Multiplier>, f64), PhotometryError> {
    let mut multipliers = vec![
        Multiplier {
            name: "candela multiplier",
            value: n.candela_multiplier,
            applied: true,
        },
        Multiplier {
            name: "ballast factor",
            value: n.ballast_factor,
            applied: true,
        },
    ];
    let (second_name, second) = (n.second_name, n.second);
    let second_applied = matches!(version, IesVersion::Lm63_1986 | IesVersion::Lm63_1991);
    if !second_applied && second != 1.0 && version != IesVersion::Lm63_2019 {
        warnings.push(format!(
            "the {second_name} field is {second}, not 1; it is not a multiplier in {} and is ignored",
            SourceFormat::Ies(version).name()
        ));
    }
    if !(second > 0.0) && second_applied {
        return Err(PhotometryError::at(
            path,
            n.bf_line,
            second_name,
            format!("{second}; must be positive"),
        ));
    }
    multipliers.push(Multiplier {
        name: second_name,
        value: second,
        applied: second_applied,
    });
    let scale: f64 = multipliers
        .iter()
        .filter(|m| m.applied)
        .map(|m| m.value)
        .product();
    Ok((multipliers, scale))
}

/// The angles and the candela table, with the line each angle was read from.
struct Table {
    v: Vec<f64>,
    v_lines: Vec<usize>,
    h: Vec<f64>,
    h_lines: Vec<usize>,
    /// One block of `v.len()` values per horizontal angle, multipliers applied (cd).
    cd: Vec<f64>,
}

/// `n` angles named `what` and the line of each.
fn read_angles(
    nums: &mut NumberStream,
    n: usize,
    what: &str,
) -> Result<(Vec<f64>, Vec<usize>), PhotometryError> {
    let mut out = Vec::with_capacity(n);
    let mut line_numbers = Vec::with_capacity(n);
    for i in 0..n {
        line_numbers.push(nums.line_of_next());
        out.push(nums.number(&format!("{what} angle {}", i + 1))?);
    }
    Ok((out, line_numbers))
}

/// Vertical angles, horizontal angles and the candela values (times `scale`), refusing negative
/// candela.
fn read_table(
    nums: &mut NumberStream,
    nv: usize,
    nh: usize,
    scale: f64,
    path: &Path,
) -> Result<Table, PhotometryError> {
    let (v, v_lines) = read_angles(nums, nv, "vertical")?;
    let (h, h_lines) = read_angles(nums, nh, "horizontal")?;
    let mut cd = Vec::with_capacity(nv * nh);
    for ih in 0..nh {
        for iv in 0..nv {
            let line = nums.line_of_next();
            let field = format!(
                "candela (horizontal angle {}, vertical angle {})",
                ih + 1,
                iv + 1
            );
            let value = nums.number(&field)?;
            if value < 0.0 {
                return Err(PhotometryError::at(
                    path,
                    line,
                    field,
                    format!("{value} is negative"),
                ));
            }
            cd.push(value * scale);
        }
    }
    Ok(Table {
        v,
        v_lines,
        h,
        h_lines,
        cd,
    })
}

impl Table {
    /// Ascending angles: a descending list is reversed together with the table (its lines
    /// stay in file order, as the checks that follow only report the ends).
    fn make_ascending(&mut self, path: &Path) -> Result<(), PhotometryError> {
        let v_desc = check_monotonic(&self.v, &self.v_lines, path, "vertical angle")?;
        let h_desc = check_monotonic(&self.h, &self.h_lines, path, "horizontal angle")?;
        let nv = self.v.len();
        if v_desc {
            self.v.reverse();
            for row in self.cd.chunks_mut(nv) {
                row.reverse();
            }
        }
        if h_desc {
            self.h.reverse();
            let mut rows: Vec<Vec<f64>> = self.cd.chunks(nv).map(|c| c.to_vec()).collect();
            rows.reverse();
            self.cd = rows.concat();
        }
        Ok(())
    }
}

/// A warning for anything after the candela table other than `END`.
fn warn_trailing(nums: &NumberStream, warnings: &mut Vec<String>) {
    let (trailing, trailing_line) = nums.rest();
    let junk: Vec<&str> = trailing
        .iter()
        .copied()
        .filter(|t| !t.eq_ignore_ascii_case("END"))
        .collect();
    if !junk.is_empty() {
        warnings.push(format!(
            "line {trailing_line}: {} value(s) after the candela table ignored (first `{}`)",
            junk.len(),
            junk[0]
        ));
    }
}

/// Latin-1 decoding: every byte is the code point of the same value (never fails).
pub(crate) fn latin1(bytes: &[u8]) -> String {
    bytes.iter().map(|&b| b as char).collect()
}

/// The lines of `text`, LF or CRLF ended.
pub(crate) fn lines_of(text: &str) -> Vec<&str> {
    text.split('\n').map(|l| l.trim_end_matches('\r')).collect()
}

/// Tilt data: geometry, number of pairs, angles, factors.
fn read_tilt(
    nums: &mut NumberStream,
    path: &Path,
    source: String,
) -> Result<TiltTable, PhotometryError> {
    let geo_line = nums.line_of_next();
    let geometry = nums.integer("lamp-to-luminaire geometry")?;
    if !(1..=3).contains(&geometry) {
        return Err(PhotometryError::at(
            path,
            geo_line,
            "lamp-to-luminaire geometry",
            format!("{geometry}; expected 1, 2 or 3"),
        ));
    }
    let n_line = nums.line_of_next();
    let n = nums.integer("number of tilt angle/factor pairs")?;
    if !(1..=10_000).contains(&n) {
        return Err(PhotometryError::at(
            path,
            n_line,
            "number of tilt angle/factor pairs",
            format!("{n}; expected 1 to 10000"),
        ));
    }
    let mut angles = Vec::new();
    for i in 0..n {
        angles.push(nums.number(&format!("tilt angle {}", i + 1))?);
    }
    let mut factors = Vec::new();
    for i in 0..n {
        factors.push(nums.number(&format!("tilt factor {}", i + 1))?);
    }
    Ok(TiltTable {
        geometry,
        angles_deg: angles,
        factors,
        source,
    })
}

/// Whether `xs` is strictly descending (`true`) or ascending (`false`); error otherwise.
fn check_monotonic(
    xs: &[f64],
    lines: &[usize],
    path: &Path,
    what: &str,
) -> Result<bool, PhotometryError> {
    if xs.len() < 2 {
        return Ok(false);
    }
    let desc = xs[1] < xs[0];
    for i in 1..xs.len() {
        let ok = if desc {
            xs[i] < xs[i - 1]
        } else {
            xs[i] > xs[i - 1]
        };
        if !ok {
            return Err(PhotometryError::at(
                path,
                lines[i],
                format!("{what} {}", i + 1),
                format!(
                    "{} after {}: angles must strictly increase (or strictly decrease)",
                    xs[i],
                    xs[i - 1]
                ),
            ));
        }
    }
    Ok(desc)
}

/// LM-63's symmetry rules from the first and last horizontal angles.
fn symmetry_of(
    ptype: PhotometricType,
    h: &[f64],
    v: &[f64],
    path: &Path,
    h_lines: &[usize],
    v_lines: &[usize],
    warnings: &mut Vec<String>,
) -> Result<Symmetry, PhotometryError> {
    let (h0, h1) = (h[0], h[h.len() - 1]);
    let (v0, v1) = (v[0], v[v.len() - 1]);
    let near = |a: f64, b: f64| (a - b).abs() < 1e-6;
    match ptype {
        PhotometricType::C => {
            if v0 < -1e-6 || v1 > 180.0 + 1e-6 {
                return Err(PhotometryError::at(
                    path,
                    v_lines[if v0 < 0.0 { 0 } else { v.len() - 1 }],
                    "vertical angles",
                    format!("{v0}..{v1}; type C vertical angles lie in 0..180"),
                ));
            }
            if !(near(v0, 0.0) || near(v0, 90.0)) || !(near(v1, 90.0) || near(v1, 180.0)) {
                warnings.push(format!(
                    "vertical angles {v0}..{v1}: LM-63 expects 0 or 90 to 90 or 180; no light outside"
                ));
            }
            if h.len() == 1 {
                return Ok(Symmetry::Axial);
            }
            if near(h0, 0.0) && near(h1, 90.0) {
                Ok(Symmetry::Quadrant)
            } else if near(h0, 0.0) && near(h1, 180.0) {
                Ok(Symmetry::BilateralC0C180)
            } else if near(h0, 90.0) && near(h1, 270.0) {
                Ok(Symmetry::BilateralC90C270)
            } else if h0 >= -1e-6 && h1 <= 360.0 + 1e-6 && h1 - h0 > 180.0 {
                Ok(Symmetry::None)
            } else {
                Err(PhotometryError::at(
                    path,
                    h_lines[h.len() - 1],
                    "horizontal angles",
                    format!(
                        "{h0}..{h1} match no LM-63 symmetry (0; 0..90; 0..180; 90..270; 0..360)"
                    ),
                ))
            }
        }
        PhotometricType::A | PhotometricType::B => {
            for (a, line, what) in [
                (h0, h_lines[0], "horizontal angles"),
                (h1, h_lines[h.len() - 1], "horizontal angles"),
                (v0, v_lines[0], "vertical angles"),
                (v1, v_lines[v.len() - 1], "vertical angles"),
            ] {
                if !(-90.0 - 1e-6..=90.0 + 1e-6).contains(&a) {
                    return Err(PhotometryError::at(
                        path,
                        line,
                        what,
                        format!("{a}: type A and B angles lie in -90..90"),
                    ));
                }
            }
            if near(h0, 0.0) && h.len() > 1 {
                Ok(Symmetry::LateralH)
            } else if near(h0, -90.0) && near(h1, 90.0) {
                Ok(Symmetry::None)
            } else if h.len() == 1 {
                Err(PhotometryError::at(
                    path,
                    h_lines[0],
                    "horizontal angles",
                    "one horizontal angle: types A and B have no axial symmetry",
                ))
            } else {
                warnings.push(format!(
                    "horizontal angles {h0}..{h1}: LM-63 expects -90..90 or 0..90; no light outside"
                ));
                Ok(Symmetry::None)
            }
        }
    }
}
