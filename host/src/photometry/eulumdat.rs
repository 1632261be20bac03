//! EULUMDAT (`.ldt`) reader.
//!
//! Written here because no crate fits: the `eulumdat` crate is AGPL, which this project cannot
//! take, and `lidrs` is stalled. The layout is one field per line:
//! | line | field |
//! |---|---|
//! | 1 | company identification |
//! | 2 | Ityp (type indicator, 0–3) |
//! | 3 | Isym (symmetry indicator, 0–4) |
//! | 4–7 | Mc (C-planes in 0..360), Dc (C step, deg), Ng (intensities per plane), Dg (γ step, deg; 0 for uneven steps) |
//! | 8–12 | report number, luminaire name, luminaire number, file name, date/user |
//! | 13–21 | luminaire length/diameter, width, height, luminous area length/diameter, width, heights at C0, C90, C180, C270 (mm) |
//! | 22–25 | downward flux fraction (%), light output ratio LORL (%), conversion factor for intensities, tilt during measurement (deg) |
//! | 26 | n, the number of lamp sets |
//! | 26a–f ×n | per set: number of lamps (negative: absolute photometry), lamp type, total lamp flux (lm), colour, colour rendering, watts incl. ballast |
//! | 27 | 10 direct ratios |
//! | 28 | Mc C-angles (deg) |
//! | 29 | Ng γ-angles (deg) |
//! | 30 | intensities in cd/1000 lm, one stored C-plane after another |
//!
//! Stored C-planes by Isym: 0 all Mc; 1 one plane (C0); 2 C0..C180 (Mc/2 + 1); 3 C90..C270
//! (Mc/2 + 1, while the C-angle list still starts at 0); 4 C0..C90 (Mc/4 + 1).
//!
//! Candela = stored value × (flux of the first lamp set, lm) / 1000 × conversion factor: the
//! table refers to the first set (for absolute photometry that field is the luminaire's flux).
//! Numbers may use a decimal comma (`95,1`). Lines 28–30 are read as a stream of numbers, so a
//! file that puts several on a line still loads.

use super::error::PhotometryError;
use super::ies::{latin1, lines_of};
use super::luminaire::{LampSet, Luminaire, Multiplier, PhotometricType, SourceFormat, Symmetry};
use std::path::Path;

/// Lines of the file with a cursor; every read names its line and field on error.
struct Lines<'a> {
    path: &'a Path,
    lines: Vec<&'a str>,
    next: usize,
}

impl<'a> Lines<'a> {
    fn text(&mut self, field: &str) -> Result<(&'a str, usize), PhotometryError> {
        let i = self.next;
        let Some(line) = self.lines.get(i) else {
            return Err(PhotometryError::at(
                self.path,
                self.lines.len().max(1),
                field,
                "the file ends before this field",
            ));
        };
        self.next += 1;
        Ok((line.trim(), i + 1))
    }

    fn number(&mut self, field: &str) -> Result<f64, PhotometryError> {
        let (t, line) = self.text(field)?;
        parse_number(t).ok_or_else(|| {
            PhotometryError::at(self.path, line, field, format!("`{t}` is not a number"))
        })
    }

    fn integer(&mut self, field: &str) -> Result<(i64, usize), PhotometryError> {
        let line = self.next + 1;
        let v = self.number(field)?;
        if v.fract() != 0.0 || v.abs() > 1e9 {
            return Err(PhotometryError::at(
                self.path,
                line,
                field,
                format!("{v} is not a whole number"),
            ));
        }
        Ok((v as i64, line))
    }
}

/// A number with a decimal point or a decimal comma; `None` if it is not one.
fn parse_number(t: &str) -> Option<f64> {
    let t = t.trim();
    let v = if t.contains(',') && !t.contains('.') {
        t.replace(',', ".").parse::<f64>().ok()?
    } else {
        t.parse::<f64>().ok()?
    };
    v.is_finite().then_some(v)
}

/// Parse the EULUMDAT file at `path` whose bytes are `bytes`.
pub fn parse_eulumdat(bytes: &[u8], path: &Path) -> Result<Luminaire, PhotometryError> {
    let text = latin1(bytes);
    let lines = lines_of(&text);
    let mut r = Lines {
        path,
        lines,
        next: 0,
    };
    let mut warnings = Vec::new();
    let mut header = Vec::new();

    let counts = read_counts(&mut r, &mut header)?;
    let [length, width, height] = read_dimensions(&mut r)?;
    let conversion = read_factors(&mut r, &mut header)?;
    let lamps = read_lamp_sets(&mut r, &mut header)?;
    for k in 1..=10 {
        r.number(&format!("direct ratio {k}"))?;
    }
    let planes = stored_planes(&counts, path)?;
    let scale = lamps[0].lumens.unwrap_or(1000.0) / 1000.0 * conversion;
    let Table { c_all, g, cd } = read_table(&r, &counts, &planes, scale)?;
    let h: Vec<f64> = (0..planes.count).map(|p| c_all[planes.first + p]).collect();
    check_increasing(&c_all, path, "C-angles")?;
    check_increasing(&g, path, "gamma angles")?;
    let expected_first = match counts.isym {
        3 => 90.0,
        _ => 0.0,
    };
    if (h[0] - expected_first).abs() > 1e-6 {
        warnings.push(format!(
            "Isym {}: the first stored C-plane is C{} where C{expected_first} was expected",
            counts.isym, h[0]
        ));
    }
    if !(conversion > 0.0) {
        warnings.push(format!("conversion factor {conversion} is not positive"));
    }
    let absolute = lamps[0].count < 0;
    let multipliers = vec![
        Multiplier {
            name: "lamp flux / 1000 lm (set 1)",
            value: lamps[0].lumens.unwrap_or(1000.0) / 1000.0,
            applied: true,
        },
        Multiplier {
            name: "conversion factor",
            value: conversion,
            applied: true,
        },
    ];
    let rated: f64 = lamps[0].lumens.unwrap_or(0.0);
    Ok(Luminaire {
        format: SourceFormat::Eulumdat,
        photometric_type: PhotometricType::C,
        symmetry: planes.symmetry,
        h_deg: h,
        v_deg: g,
        candela: cd,
        lamps,
        multipliers,
        absolute,
        rated_lamp_lumens: (!absolute).then_some(rated),
        size_m: [width / 1000.0, length / 1000.0, height / 1000.0],
        tilt: None,
        header,
        warnings,
    })
}

/// Lines 2–7: the type and symmetry indicators and the size of the table, each with its line
/// (Mc and Ng are checked once the lamp sets are read, as the file's order has them).
struct Counts {
    isym: i64,
    isym_line: usize,
    mc: i64,
    mc_line: usize,
    ng: i64,
    ng_line: usize,
}

/// Lines 1–12: company, Ityp, Isym, Mc, Dc, Ng, Dg and the identification lines (into `header`).
fn read_counts(r: &mut Lines, header: &mut Vec<String>) -> Result<Counts, PhotometryError> {
    let path = r.path;
    let (company, _) = r.text("company identification")?;
    header.push(format!("company: {company}"));
    let (ityp, ityp_line) = r.integer("Ityp")?;
    if !(0..=3).contains(&ityp) {
        return Err(PhotometryError::at(
            path,
            ityp_line,
            "Ityp",
            format!("{ityp}; expected 0 to 3"),
        ));
    }
    let (isym, isym_line) = r.integer("Isym")?;
    if !(0..=4).contains(&isym) {
        return Err(PhotometryError::at(
            path,
            isym_line,
            "Isym",
            format!("{isym}; expected 0 to 4"),
        ));
    }
    let (mc, mc_line) = r.integer("Mc (number of C-planes)")?;
    let _dc = r.number("Dc (C-plane step)")?;
    let (ng, ng_line) = r.integer("Ng (intensities per C-plane)")?;
    let _dg = r.number("Dg (gamma step)")?;
    for field in [
        "measurement report number",
        "luminaire name",
        "luminaire number",
        "file name",
        "date/user",
    ] {
        let (t, _) = r.text(field)?;
        if !t.is_empty() {
            header.push(format!("{field}: {t}"));
        }
    }
    Ok(Counts {
        isym,
        isym_line,
        mc,
        mc_line,
        ng,
        ng_line,
    })
}

/// Lines 13–21: the luminaire's length, width and height (mm); the luminous area is skipped.
fn read_dimensions(r: &mut Lines) -> Result<[f64; 3], PhotometryError> {
    let length = r.number("luminaire length")?;
    let width = r.number("luminaire width")?;
    let height = r.number("luminaire height")?;
    for field in [
        "luminous area length",
        "luminous area width",
        "luminous area height C0",
        "luminous area height C90",
        "luminous area height C180",
        "luminous area height C270",
    ] {
        r.number(field)?;
    }
    Ok([length, width, height])
}

/// Lines 22–25 (into `header`); returns the conversion factor for intensities.
fn read_factors(r: &mut Lines, header: &mut Vec<String>) -> Result<f64, PhotometryError> {
    let dff = r.number("downward flux fraction")?;
    let lorl = r.number("light output ratio")?;
    let conversion = r.number("conversion factor")?;
    let tilt = r.number("tilt during measurement")?;
    header.push(format!("downward flux fraction: {dff} %"));
    header.push(format!("light output ratio: {lorl} %"));
    if tilt != 0.0 {
        header.push(format!("tilt during measurement: {tilt} deg"));
    }
    Ok(conversion)
}

/// Line 26 and the lamp sets 26a–f; the first set's flux must be positive.
fn read_lamp_sets(
    r: &mut Lines,
    header: &mut Vec<String>,
) -> Result<Vec<LampSet>, PhotometryError> {
    let path = r.path;
    let (n_sets, n_sets_line) = r.integer("number of lamp sets")?;
    if !(1..=1000).contains(&n_sets) {
        return Err(PhotometryError::at(
            path,
            n_sets_line,
            "number of lamp sets",
            format!("{n_sets}; expected 1 or more"),
        ));
    }
    let mut lamps = Vec::new();
    for s in 1..=n_sets {
        let (count, _) = r.integer(&format!("number of lamps (set {s})"))?;
        let (kind, _) = r.text(&format!("lamp type (set {s})"))?;
        let flux_line = r.next + 1;
        let flux = r.number(&format!("total lamp flux (set {s})"))?;
        let (colour, _) = r.text(&format!("colour (set {s})"))?;
        let (cri, _) = r.text(&format!("colour rendering (set {s})"))?;
        let watts = r.number(&format!("watts (set {s})"))?;
        if s == 1 && !(flux > 0.0) {
            return Err(PhotometryError::at(
                path,
                flux_line,
                "total lamp flux (set 1)",
                format!("{flux}; the intensities are per 1000 lm of it, so it must be positive"),
            ));
        }
        if !colour.is_empty() || !cri.is_empty() {
            header.push(format!(
                "lamp set {s}: colour {colour}, colour rendering {cri}"
            ));
        }
        lamps.push(LampSet {
            count,
            lumens: Some(flux),
            description: kind.to_string(),
            watts: (watts > 0.0).then_some(watts),
        });
    }
    Ok(lamps)
}

/// Which C-planes the file stores, by Isym.
struct Planes {
    symmetry: Symmetry,
    /// Index in the C-angle list of the first stored plane.
    first: usize,
    /// Number of stored planes.
    count: usize,
}

/// Check Mc and Ng and work out the stored C-planes from Isym.
fn stored_planes(c: &Counts, path: &Path) -> Result<Planes, PhotometryError> {
    if !(1..=100_000).contains(&c.mc) {
        return Err(PhotometryError::at(
            path,
            c.mc_line,
            "Mc (number of C-planes)",
            format!("{}; expected 1 or more", c.mc),
        ));
    }
    if !(1..=100_000).contains(&c.ng) {
        return Err(PhotometryError::at(
            path,
            c.ng_line,
            "Ng (intensities per C-plane)",
            format!("{}; expected 1 or more", c.ng),
        ));
    }
    let (mc, isym) = (c.mc as usize, c.isym);
    let (symmetry, first, count) = match isym {
        0 => (Symmetry::None, 0, mc),
        1 => (Symmetry::Axial, 0, 1),
        2 => (Symmetry::BilateralC0C180, 0, mc / 2 + 1),
        3 => (Symmetry::BilateralC90C270, mc / 4, mc / 2 + 1),
        4 => (Symmetry::Quadrant, 0, mc / 4 + 1),
        other => {
            return Err(PhotometryError::at(
                path,
                c.isym_line,
                "Isym",
                format!("{other}; expected 0 to 4"),
            ))
        }
    };
    if (isym == 2 || isym == 3) && mc % 2 != 0
        || isym == 4 && mc % 4 != 0
        || isym == 3 && mc % 4 != 0
    {
        return Err(PhotometryError::at(
            path,
            c.mc_line,
            "Mc (number of C-planes)",
            format!("{mc} C-planes cannot be split as Isym {isym} requires"),
        ));
    }
    Ok(Planes {
        symmetry,
        first,
        count,
    })
}

/// Lines 28–30: every C-angle, the γ-angles, and the stored intensities (cd).
struct Table {
    c_all: Vec<f64>,
    g: Vec<f64>,
    cd: Vec<f64>,
}

/// Lines 28–30 read as one stream of numbers: all C-angles, the γ-angles and the stored
/// intensities times `scale` (cd).
fn read_table(
    r: &Lines,
    c: &Counts,
    planes: &Planes,
    scale: f64,
) -> Result<Table, PhotometryError> {
    let path = r.path;
    let (mc, ng) = (c.mc as usize, c.ng as usize);
    let start = r.next;
    let mut stream: Vec<(String, usize)> = Vec::new();
    for (i, line) in r.lines[start..].iter().enumerate() {
        for t in line.split_whitespace() {
            stream.push((t.to_string(), start + i + 1));
        }
    }
    let mut pos = 0;
    let mut next = |field: &str| -> Result<f64, PhotometryError> {
        let Some((t, line)) = stream.get(pos) else {
            return Err(PhotometryError::at(
                path,
                r.lines.len(),
                field,
                "the file ends before this value",
            ));
        };
        pos += 1;
        parse_number(t).ok_or_else(|| {
            PhotometryError::at(path, *line, field, format!("`{t}` is not a number"))
        })
    };
    let mut c_all = Vec::with_capacity(mc);
    for i in 0..mc {
        c_all.push(next(&format!("C-angle {}", i + 1))?);
    }
    let mut g = Vec::with_capacity(ng);
    for i in 0..ng {
        g.push(next(&format!("gamma angle {}", i + 1))?);
    }
    let mut cd = Vec::with_capacity(planes.count * ng);
    for p in 0..planes.count {
        for j in 0..ng {
            let v = next(&format!(
                "intensity (stored C-plane {}, gamma angle {})",
                p + 1,
                j + 1
            ))?;
            cd.push(v * scale);
        }
    }
    Ok(Table { c_all, g, cd })
}

/// An error unless `xs` (the list named `what`) strictly increases.
fn check_increasing(xs: &[f64], path: &Path, what: &str) -> Result<(), PhotometryError> {
    for w in xs.windows(2) {
        if !(w[1] > w[0]) {
            return Err(PhotometryError::file(
                path,
                what,
                format!("{} after {}: {what} must increase", w[1], w[0]),
            ));
        }
    }
    Ok(())
}
