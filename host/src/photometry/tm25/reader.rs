//! Reading TM-25-13 ray files (layout and rules in [`super`]): [`parse_header`] reads the
//! header of a byte slice and the [`RayLayout`] of its records, [`RayFile`] maps a file and
//! hands out its rays one record at a time. Nothing is allocated in proportion to a count the
//! file states before the bytes it implies are known to be there, so a lying header costs no
//! memory; every error names the file and the section.

use crate::photometry::PhotometryError;
use std::path::{Path, PathBuf};

/// Size of the fixed header: file header block 256, flags 32, nine text fields 36 000 bytes.
pub const FIXED_HEADER_BYTES: usize = 256 + 32 + 9 * 4000;

/// The nine text fields of section 4.7.3, in file order.
pub const TEXT_FIELDS: [&str; 9] = [
    "name of the light source",
    "manufacturer",
    "creator of the light source model",
    "creator of the ray file",
    "measurement equipment or simulation software",
    "camera",
    "light source operation",
    "additional information",
    "data reference",
];

/// Spectral data identifier (4.7.1.9).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectralId {
    /// 0: no spectral data.
    None,
    /// 1: every ray has the header's single wavelength.
    Single,
    /// 2: each ray has its own wavelength column.
    PerRay,
    /// 3: one spectral table for every ray.
    Table,
    /// 4: each ray names its table by a 1-based index column.
    Indexed,
}

impl SpectralId {
    /// The identifier's number in the file.
    pub fn code(self) -> i32 {
        match self {
            Self::None => 0,
            Self::Single => 1,
            Self::PerRay => 2,
            Self::Table => 3,
            Self::Indexed => 4,
        }
    }

    /// What it means, for reports.
    pub fn describe(self) -> &'static str {
        match self {
            Self::None => "no spectral data",
            Self::Single => "one wavelength for every ray",
            Self::PerRay => "a wavelength per ray",
            Self::Table => "one spectral table for every ray",
            Self::Indexed => "a spectral table per ray (index column)",
        }
    }
}

/// The known-data flags (4.7.2.3–8); position and direction are always present.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct KnownData {
    /// Radiant flux column (W).
    pub radiant: bool,
    /// Wavelength column (nm).
    pub wavelength: bool,
    /// Luminous flux column (lm).
    pub luminous: bool,
    /// Stokes S1..S3 and polarisation ellipse (6 columns).
    pub stokes: bool,
    /// Tristimulus X and Z (2 columns).
    pub tristimulus: bool,
    /// Spectrum index column.
    pub spectrum_index: bool,
}

/// The header of a TM-25 file.
#[derive(Clone, Debug, PartialEq)]
pub struct Tm25Header {
    /// File version (2013).
    pub version: i32,
    /// Creation method: 0 simulation, 1 measurement (other values are kept with a warning).
    pub creation_method: i32,
    /// Total luminous flux, lm (NaN when the file does not say).
    pub luminous_flux_lm: f32,
    /// Total radiant flux, W (NaN when the file does not say).
    pub radiant_flux_w: f32,
    /// Number of rays.
    pub n_rays: u64,
    /// Creation date and time as written.
    pub date: String,
    /// Ray start position code (4.7.1.8).
    pub start_position: i32,
    /// Spectral data identifier.
    pub spectral_id: SpectralId,
    /// The single wavelength, nm (identifier 1).
    pub single_wavelength_nm: f32,
    /// Wavelength range of the spectral data, nm.
    pub lambda_min_nm: f32,
    /// Upper end of that range, nm.
    pub lambda_max_nm: f32,
    /// Which columns the records have.
    pub flags: KnownData,
    /// The nine text fields ([`TEXT_FIELDS`]).
    pub texts: [String; 9],
    /// Spectral tables, `(nm, weight)` pairs each, in file order (table 1 first).
    pub spectra: Vec<Vec<(f32, f32)>>,
    /// Names of the additional columns.
    pub column_names: Vec<String>,
    /// The additional text block.
    pub additional_text: String,
    /// Legal but doubtful things noticed.
    pub warnings: Vec<String>,
}

/// Where each column sits in a record (index in floats), and where the records start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RayLayout {
    /// Byte offset of the first record.
    pub offset: usize,
    /// Floats per record.
    pub columns: usize,
    /// Radiant flux column.
    pub radiant: Option<usize>,
    /// Wavelength column.
    pub wavelength: Option<usize>,
    /// Luminous flux column.
    pub luminous: Option<usize>,
    /// Spectrum index column.
    pub spectrum_index: Option<usize>,
}

impl RayLayout {
    /// The columns the flags switch on, in the standard's order, and how many additional ones.
    pub fn of(flags: &KnownData, additional: usize, offset: usize) -> Self {
        let mut next = 6;
        let mut take = |on: bool, n: usize| {
            let at = on.then_some(next);
            if on {
                next += n;
            }
            at
        };
        let radiant = take(flags.radiant, 1);
        let wavelength = take(flags.wavelength, 1);
        let luminous = take(flags.luminous, 1);
        take(flags.stokes, 6);
        take(flags.tristimulus, 2);
        let spectrum_index = take(flags.spectrum_index, 1);
        RayLayout {
            offset,
            columns: next + additional,
            radiant,
            wavelength,
            luminous,
            spectrum_index,
        }
    }

    /// Bytes per record.
    pub fn record_bytes(&self) -> usize {
        4 * self.columns
    }

    /// Record `i` of `bytes` (the whole file). The caller has checked that the file holds it
    /// ([`parse_header`] checks that every record the header counts is there).
    pub fn ray(&self, bytes: &[u8], i: u64) -> RawRay {
        let start = self.offset + i as usize * self.record_bytes();
        let rec = &bytes[start..start + self.record_bytes()];
        let f = |c: usize| {
            f32::from_le_bytes([rec[4 * c], rec[4 * c + 1], rec[4 * c + 2], rec[4 * c + 3]])
        };
        RawRay {
            position_mm: [f(0), f(1), f(2)],
            direction: [f(3), f(4), f(5)],
            radiant_w: self.radiant.map(f),
            wavelength_nm: self.wavelength.map(f),
            luminous_lm: self.luminous.map(f),
            spectrum_index: self.spectrum_index.map(f),
        }
    }
}

/// One ray record as stored (the columns the renderer uses).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RawRay {
    /// Start point, in the file's length unit (mm).
    pub position_mm: [f32; 3],
    /// Direction (unit in a valid file).
    pub direction: [f32; 3],
    /// Radiant flux, W.
    pub radiant_w: Option<f32>,
    /// Wavelength, nm.
    pub wavelength_nm: Option<f32>,
    /// Luminous flux, lm.
    pub luminous_lm: Option<f32>,
    /// 1-based spectral table index.
    pub spectrum_index: Option<f32>,
}

/// A cursor over the header bytes that turns a short read into an error naming the section.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
    path: &'a Path,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize, section: &str) -> Result<&'a [u8], PhotometryError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        match end {
            Some(end) => {
                let s = &self.bytes[self.at..end];
                self.at = end;
                Ok(s)
            }
            None => Err(PhotometryError::file(
                self.path,
                section,
                format!(
                    "the file ends at byte {} but this section needs {n} bytes from byte {}: \
                     truncated or not a TM-25 file",
                    self.bytes.len(),
                    self.at
                ),
            )),
        }
    }
    fn i32(&mut self, section: &str) -> Result<i32, PhotometryError> {
        let b = self.take(4, section)?;
        Ok(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn f32(&mut self, section: &str) -> Result<f32, PhotometryError> {
        let b = self.take(4, section)?;
        Ok(f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }
    fn u64(&mut self, section: &str) -> Result<u64, PhotometryError> {
        let b = self.take(8, section)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(u64::from_le_bytes(a))
    }
    /// An error in `section` of this file.
    fn error(&self, section: &str, message: impl Into<String>) -> PhotometryError {
        PhotometryError::file(self.path, section, message)
    }
    fn utf32(&mut self, n_bytes: usize, section: &str) -> Result<String, PhotometryError> {
        let b = self.take(n_bytes, section)?;
        let mut s = String::new();
        for c in b.chunks_exact(4) {
            let u = u32::from_le_bytes([c[0], c[1], c[2], c[3]]);
            if u == 0 {
                break;
            }
            match char::from_u32(u) {
                Some(ch) => s.push(ch),
                None => {
                    return Err(PhotometryError::file(
                        self.path,
                        section,
                        format!("0x{u:x} is not a Unicode code point (UTF-32 text expected)"),
                    ))
                }
            }
        }
        Ok(s.trim_end().to_string())
    }
}

fn flag(c: &mut Cursor, section: &str) -> Result<bool, PhotometryError> {
    match c.i32(section)? {
        0 => Ok(false),
        1 => Ok(true),
        v => Err(PhotometryError::file(
            c.path,
            section,
            format!("must be 0 or 1, is {v}"),
        )),
    }
}

/// Parse the header of the TM-25 file `bytes` (the whole file) and check that it holds every
/// record the header counts; `path` names it in errors. Rays are not read (see
/// [`RayFile::check_rays`]).
pub fn parse_header(bytes: &[u8], path: &Path) -> Result<(Tm25Header, RayLayout), PhotometryError> {
    let mut c = Cursor { bytes, at: 0, path };
    let mut warnings = Vec::new();
    let version = read_version(&mut c)?;
    let source = read_source(&mut c, &mut warnings)?;
    let counts = read_spectral_counts(&mut c)?;
    let flags = read_flags(&mut c, counts.spectral_id, &mut warnings)?;
    let mut texts: [String; 9] = Default::default();
    for (i, t) in texts.iter_mut().enumerate() {
        *t = c.utf32(4000, &format!("4.7.3.{} {}", i + 1, TEXT_FIELDS[i]))?;
    }
    debug_assert_eq!(c.at, FIXED_HEADER_BYTES);
    let spectra = read_spectral_tables(&mut c, counts.n_spectra)?;
    let column_names = read_column_labels(&mut c, counts.n_additional)?;
    let additional_text = c.utf32(counts.text_size as usize, "4.7.6 additional text")?;
    let layout = RayLayout::of(&flags, counts.n_additional as usize, c.at);
    check_record_count(&c, &layout, source.n_rays)?;
    if source.n_rays == 0 {
        warnings.push("the file has no rays".into());
    }
    Ok((
        Tm25Header {
            version,
            creation_method: source.creation_method,
            luminous_flux_lm: source.luminous_flux_lm,
            radiant_flux_w: source.radiant_flux_w,
            n_rays: source.n_rays,
            date: source.date,
            start_position: source.start_position,
            spectral_id: counts.spectral_id,
            single_wavelength_nm: counts.single_wavelength_nm,
            lambda_min_nm: counts.lambda_min_nm,
            lambda_max_nm: counts.lambda_max_nm,
            flags,
            texts,
            spectra,
            column_names,
            additional_text,
            warnings,
        },
        layout,
    ))
}

/// 4.7.1.1–2: the file type `TM25` and the version, which must be 2013.
fn read_version(c: &mut Cursor) -> Result<i32, PhotometryError> {
    if c.take(4, "4.7.1.1 file type")? != b"TM25" {
        return Err(c.error(
            "4.7.1.1 file type",
            "the file does not start with `TM25`: not a TM-25 ray file",
        ));
    }
    let version = c.i32("4.7.1.2 version")?;
    if version != 2013 {
        return Err(c.error(
            "4.7.1.2 version",
            match version {
                2020 => {
                    "version 2020 (ANSI/IES TM-25-20) is not read: the 2020 revision's changes \
                         to the layout are not public, so its files cannot be read safely; \
                         TM-25-13 files (version 2013) are"
                        .to_string()
                }
                v => format!("version {v} is not known (TM-25-13 files say 2013)"),
            },
        ));
    }
    Ok(version)
}

/// 4.7.1.3–8: how the file was made, its totals and its number of rays.
struct Source {
    creation_method: i32,
    luminous_flux_lm: f32,
    radiant_flux_w: f32,
    n_rays: u64,
    date: String,
    start_position: i32,
}

/// Read 4.7.1.3–8; the fluxes must be ≥ 0 or NaN.
fn read_source(c: &mut Cursor, warnings: &mut Vec<String>) -> Result<Source, PhotometryError> {
    let creation_method = c.i32("4.7.1.3 creation method")?;
    if !(creation_method == 0 || creation_method == 1) {
        warnings.push(format!(
            "creation method {creation_method} (4.7.1.3) is neither 0 (simulation) nor 1 (measurement)"
        ));
    }
    let luminous_flux_lm = c.f32("4.7.1.4 luminous flux")?;
    let radiant_flux_w = c.f32("4.7.1.5 radiant flux")?;
    for (v, s) in [
        (luminous_flux_lm, "4.7.1.4 luminous flux"),
        (radiant_flux_w, "4.7.1.5 radiant flux"),
    ] {
        if !(v.is_nan() || (v >= 0.0 && v.is_finite())) {
            return Err(c.error(s, format!("{v}: must be ≥ 0 or NaN (unknown)")));
        }
    }
    let n_rays = c.u64("4.7.1.6 number of rays")?;
    let date_bytes = c.take(28, "4.7.1.7 date")?;
    let date = String::from_utf8_lossy(date_bytes.split(|&b| b == 0).next().unwrap_or(&[]))
        .trim()
        .to_string();
    let start_position = c.i32("4.7.1.8 ray start position")?;
    Ok(Source {
        creation_method,
        luminous_flux_lm,
        radiant_flux_w,
        n_rays,
        date,
        start_position,
    })
}

/// 4.7.1.9–15: the spectral data identifier and what it needs, and the sizes of the parts
/// after the fixed header.
struct SpectralCounts {
    spectral_id: SpectralId,
    single_wavelength_nm: f32,
    lambda_min_nm: f32,
    lambda_max_nm: f32,
    /// Number of spectral tables (≥ 0).
    n_spectra: i32,
    /// Number of additional ray data items (≥ 0).
    n_additional: i32,
    /// Size of the additional text block, bytes (a multiple of 32).
    text_size: i32,
}

/// Read and check 4.7.1.9–15, then skip the reserved bytes (4.7.1.16).
fn read_spectral_counts(c: &mut Cursor) -> Result<SpectralCounts, PhotometryError> {
    let id = c.i32("4.7.1.9 spectral data identifier")?;
    let spectral_id = match id {
        0 => SpectralId::None,
        1 => SpectralId::Single,
        2 => SpectralId::PerRay,
        3 => SpectralId::Table,
        4 => SpectralId::Indexed,
        v => {
            return Err(c.error(
                "4.7.1.9 spectral data identifier",
                format!("{v}: must be 0 to 4"),
            ))
        }
    };
    let single_wavelength_nm = c.f32("4.7.1.10 single wavelength")?;
    if spectral_id == SpectralId::Single
        && !(single_wavelength_nm > 0.0 && single_wavelength_nm.is_finite())
    {
        return Err(c.error(
            "4.7.1.10 single wavelength",
            format!("{single_wavelength_nm}: identifier 1 needs a wavelength > 0 nm"),
        ));
    }
    let lambda_min_nm = c.f32("4.7.1.11 minimum wavelength")?;
    let lambda_max_nm = c.f32("4.7.1.12 maximum wavelength")?;
    let n_spectra = c.i32("4.7.1.13 number of spectral tables")?;
    let n_additional = c.i32("4.7.1.14 number of additional ray data items")?;
    let text_size = c.i32("4.7.1.15 size of the additional text block")?;
    if n_spectra < 0 {
        return Err(c.error(
            "4.7.1.13 number of spectral tables",
            format!("{n_spectra} < 0"),
        ));
    }
    if matches!(spectral_id, SpectralId::Table | SpectralId::Indexed) && n_spectra == 0 {
        return Err(c.error(
            "4.7.1.13 number of spectral tables",
            format!("spectral data identifier {id} needs spectral tables, the file has none"),
        ));
    }
    if n_additional < 0 {
        return Err(c.error(
            "4.7.1.14 number of additional ray data items",
            format!("{n_additional} < 0"),
        ));
    }
    if text_size < 0 || text_size % 32 != 0 {
        return Err(c.error(
            "4.7.1.15 size of the additional text block",
            format!("{text_size}: must be a multiple of 32 bytes, ≥ 0"),
        ));
    }
    c.take(168, "4.7.1.16 reserved")?;
    Ok(SpectralCounts {
        spectral_id,
        single_wavelength_nm,
        lambda_min_nm,
        lambda_max_nm,
        n_spectra,
        n_additional,
        text_size,
    })
}

/// 4.7.2: the known-data flags, checked against the standard's rules and the identifier.
fn read_flags(
    c: &mut Cursor,
    spectral_id: SpectralId,
    warnings: &mut Vec<String>,
) -> Result<KnownData, PhotometryError> {
    if c.i32("4.7.2.1 position flag")? != 1 {
        return Err(c.error("4.7.2.1 position flag", "must be 1"));
    }
    if c.i32("4.7.2.2 direction flag")? != 1 {
        return Err(c.error("4.7.2.2 direction flag", "must be 1"));
    }
    let flags = KnownData {
        radiant: flag(c, "4.7.2.3 radiant flux flag")?,
        wavelength: flag(c, "4.7.2.4 wavelength flag")?,
        luminous: flag(c, "4.7.2.5 luminous flux flag")?,
        stokes: flag(c, "4.7.2.6 Stokes flag")?,
        tristimulus: flag(c, "4.7.2.7 tristimulus flag")?,
        spectrum_index: flag(c, "4.7.2.8 spectrum index flag")?,
    };
    check_flags(&flags, spectral_id).map_err(|m| c.error("4.7.2 known data flags", m))?;
    if flags.wavelength && spectral_id != SpectralId::PerRay {
        warnings.push(format!(
            "a wavelength column is present but the spectral data identifier is {}, not 2; \
             the column is used",
            spectral_id.code()
        ));
    }
    Ok(flags)
}

/// 4.7.4: `n_spectra` spectral tables and the padding to 32 bytes after them. Each count is
/// checked against the bytes left before anything is kept.
fn read_spectral_tables(
    c: &mut Cursor,
    n_spectra: i32,
) -> Result<Vec<Vec<(f32, f32)>>, PhotometryError> {
    let mut spectra = Vec::new();
    let table_start = c.at;
    for t in 1..=n_spectra {
        let section = format!("4.7.4 spectral table {t}");
        let np = c.i32(&section)?;
        let left = (c.bytes.len() - c.at) / 8;
        if np <= 0 || np as usize > left {
            return Err(c.error(
                &section,
                format!(
                    "{np} wavelength–weight pairs: must be > 0 and fit in the file ({left} would)"
                ),
            ));
        }
        let raw = c.take(8 * np as usize, &section)?;
        let mut table = Vec::with_capacity(np as usize);
        for p in raw.chunks_exact(8) {
            let l = f32::from_le_bytes([p[0], p[1], p[2], p[3]]);
            let w = f32::from_le_bytes([p[4], p[5], p[6], p[7]]);
            if !(l > 0.0 && l.is_finite() && w >= 0.0 && w.is_finite()) {
                return Err(c.error(
                    &section,
                    format!("pair ({l} nm, {w}): wavelengths must be > 0 and weights ≥ 0, finite"),
                ));
            }
            table.push((l, w));
        }
        if table.windows(2).any(|w| !(w[1].0 > w[0].0)) {
            return Err(c.error(&section, "wavelengths must increase"));
        }
        if !table.iter().any(|p| p.1 > 0.0) {
            return Err(c.error(&section, "every weight is 0"));
        }
        spectra.push(table);
    }
    let table_bytes = c.at - table_start;
    if !table_bytes.is_multiple_of(32) {
        c.take(
            32 - table_bytes % 32,
            "4.7.4 spectral tables (padding to 32 bytes)",
        )?;
    }
    Ok(spectra)
}

/// 4.7.5: the labels of the `n_additional` additional columns, 512 bytes each.
fn read_column_labels(c: &mut Cursor, n_additional: i32) -> Result<Vec<String>, PhotometryError> {
    let left = (c.bytes.len() - c.at) / 512;
    if n_additional as usize > left {
        return Err(c.error(
            "4.7.5 additional column labels",
            format!("{n_additional} labels of 512 bytes do not fit in the file"),
        ));
    }
    let mut column_names = Vec::new();
    for i in 0..n_additional {
        column_names.push(c.utf32(512, &format!("4.7.5 additional column label {}", i + 1))?);
    }
    Ok(column_names)
}

/// Every counted record must be there after the cursor; surplus bytes are refused too (the
/// layout would be misread, or another format).
fn check_record_count(c: &Cursor, layout: &RayLayout, n_rays: u64) -> Result<(), PhotometryError> {
    let have = (c.bytes.len() - c.at) as u128;
    let need = n_rays as u128 * layout.record_bytes() as u128;
    if have < need {
        return Err(c.error(
            "4.7.1.6 number of rays",
            format!(
                "the header counts {n_rays} rays of {} bytes ({need} bytes from byte {}), the file \
                 holds {} whole records: truncated, or the header lies",
                layout.record_bytes(),
                c.at,
                have / layout.record_bytes() as u128
            ),
        ));
    }
    if have > need {
        return Err(c.error(
            "4.7.7 ray data",
            format!(
                "{} bytes after the {n_rays} records the header counts ({} bytes each): the \
                 header does not describe this file",
                have - need,
                layout.record_bytes()
            ),
        ));
    }
    Ok(())
}

/// The standard's rules on flag combinations (module docs of [`super`]).
fn check_flags(f: &KnownData, id: SpectralId) -> Result<(), String> {
    if !(f.radiant || f.luminous) {
        return Err("neither radiant nor luminous flux: a ray file must carry one".into());
    }
    if id == SpectralId::PerRay && !f.wavelength {
        return Err("spectral data identifier 2 needs the wavelength flag".into());
    }
    if matches!(id, SpectralId::PerRay | SpectralId::Indexed) && (!f.radiant || f.luminous) {
        return Err(format!(
            "spectral data identifier {} needs radiant flux and no luminous flux",
            id.code()
        ));
    }
    if f.stokes && !f.radiant {
        return Err("Stokes parameters need radiant flux".into());
    }
    if f.tristimulus && !(f.luminous && id == SpectralId::None) {
        return Err("tristimulus values need luminous flux and spectral data identifier 0".into());
    }
    if f.spectrum_index != (id == SpectralId::Indexed) {
        return Err(
            "the spectrum index flag must be set exactly for spectral data identifier 4".into(),
        );
    }
    Ok(())
}

/// A record that cannot be a ray: the message says which value.
pub fn check_ray(r: &RawRay, n_spectra: usize) -> Result<(), String> {
    if !r.position_mm.iter().all(|v| v.is_finite()) {
        return Err(format!("start point {:?} is not finite", r.position_mm));
    }
    if !r.direction.iter().all(|v| v.is_finite()) {
        return Err(format!("direction {:?} is not finite", r.direction));
    }
    let len2: f32 = r.direction.iter().map(|v| v * v).sum();
    if !(len2 > 1e-12) {
        return Err(format!("direction {:?} has length 0", r.direction));
    }
    for (v, what) in [
        (r.radiant_w, "radiant flux"),
        (r.luminous_lm, "luminous flux"),
    ] {
        if let Some(v) = v {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(format!("{what} {v}: must be finite and ≥ 0"));
            }
        }
    }
    if let Some(l) = r.wavelength_nm {
        if !(l > 0.0 && l.is_finite()) {
            return Err(format!("wavelength {l} nm: must be > 0"));
        }
    }
    if let Some(i) = r.spectrum_index {
        if !(i >= 1.0 && i <= n_spectra as f32 && i.fract() == 0.0) {
            return Err(format!(
                "spectrum index {i}: must be a whole number from 1 to {n_spectra}"
            ));
        }
    }
    Ok(())
}

/// The bytes of a ray file: mapped, or held (files given as bytes, tests).
enum Data {
    Mapped(memmap2::Mmap),
    Owned(Vec<u8>),
}

/// A TM-25 file: its header and its records, read in place.
pub struct RayFile {
    data: Data,
    /// The header.
    pub header: Tm25Header,
    /// Where the records are.
    pub layout: RayLayout,
    /// The file.
    pub path: PathBuf,
}

impl std::fmt::Debug for RayFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RayFile")
            .field("path", &self.path)
            .field("n_rays", &self.header.n_rays)
            .finish()
    }
}

impl RayFile {
    /// Map `path` and read its header (the rays stay in the file until asked for).
    pub fn open(path: &Path) -> Result<Self, PhotometryError> {
        let file = std::fs::File::open(path)
            .map_err(|e| PhotometryError::file(path, "file", format!("cannot open: {e}")))?;
        let len = file
            .metadata()
            .map_err(|e| PhotometryError::file(path, "file", format!("cannot stat: {e}")))?
            .len();
        if len < FIXED_HEADER_BYTES as u64 {
            // Small enough to read; also avoids mapping an empty file.
            let bytes = std::fs::read(path)
                .map_err(|e| PhotometryError::file(path, "file", format!("cannot read: {e}")))?;
            return Self::from_bytes(bytes, path);
        }
        // SAFETY: the map is read-only and private to this process; the file must not be
        // truncated by another process while it is mapped (a read past the new end would
        // fault), which is the documented condition of reading a ray file in place.
        let map = unsafe { memmap2::Mmap::map(&file) }
            .map_err(|e| PhotometryError::file(path, "file", format!("cannot map: {e}")))?;
        let (header, layout) = parse_header(&map, path)?;
        Ok(Self {
            data: Data::Mapped(map),
            header,
            layout,
            path: path.to_path_buf(),
        })
    }

    /// A ray file held in memory (`path` names it in errors).
    pub fn from_bytes(bytes: Vec<u8>, path: &Path) -> Result<Self, PhotometryError> {
        let (header, layout) = parse_header(&bytes, path)?;
        Ok(Self {
            data: Data::Owned(bytes),
            header,
            layout,
            path: path.to_path_buf(),
        })
    }

    /// The file's bytes.
    pub fn bytes(&self) -> &[u8] {
        match &self.data {
            Data::Mapped(m) => m,
            Data::Owned(v) => v,
        }
    }

    /// Number of rays.
    pub fn n_rays(&self) -> u64 {
        self.header.n_rays
    }

    /// Ray `i` (< [`n_rays`](Self::n_rays)), as stored.
    pub fn ray(&self, i: u64) -> RawRay {
        self.layout.ray(self.bytes(), i)
    }

    /// Check every record ([`check_ray`]); the error names the file and the first bad ray.
    pub fn check_rays(&self) -> Result<(), PhotometryError> {
        let n = self.header.spectra.len();
        for i in 0..self.n_rays() {
            check_ray(&self.ray(i), n).map_err(|m| {
                PhotometryError::file(&self.path, format!("4.7.7 ray {}", i + 1), m)
            })?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::writer::{write_tm25, Tm25Spectrum, WriteHeader, WriteRay};
    use super::*;

    fn real_file() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/rays/cylinder_10k_lighttools.TM25RAY")
    }

    /// The shipped LightTools file: every header field as a hex dump reads it (values checked
    /// independently with a Python reader of the same layout), 10 000 records of 7 floats
    /// (luminous flux only), directions of unit length (f32: 1e-6), and the rays' luminous flux
    /// summing to 10 000 lm (each ray ≈ 1 lm; f64 sum, 1e-3 lm) while the header says 1 lm.
    #[test]
    fn the_lighttools_file_reads() {
        let f = RayFile::open(&real_file()).unwrap();
        let h = &f.header;
        assert_eq!(h.n_rays, 10_000);
        assert_eq!(h.spectral_id, SpectralId::None);
        assert_eq!(h.luminous_flux_lm, 1.0);
        assert_eq!(h.radiant_flux_w, 0.0);
        assert!(h.flags.luminous && !h.flags.radiant && !h.flags.wavelength);
        assert_eq!(f.layout.columns, 7);
        assert_eq!(f.layout.offset, FIXED_HEADER_BYTES);
        assert_eq!(h.texts[3], "LightTools 8.7.0");
        f.check_rays().unwrap();
        let mut sum = 0.0f64;
        for i in 0..f.n_rays() {
            let r = f.ray(i);
            let l: f32 = r.direction.iter().map(|v| v * v).sum::<f32>().sqrt();
            assert!((l - 1.0).abs() < 1e-6, "ray {i}: |k| = {l}");
            sum += r.luminous_lm.unwrap() as f64;
        }
        assert!((sum - 10_000.0).abs() < 1e-3, "{sum}");
    }

    fn small_file(n: u64, write_n: usize) -> Vec<u8> {
        let h = WriteHeader {
            luminous_flux_lm: f32::NAN,
            radiant_flux_w: 1.0,
            date: String::new(),
            texts: Default::default(),
            spectrum: Tm25Spectrum::PerRay,
        };
        let rays = (0..write_n).map(|i| WriteRay {
            position_mm: [0.0, 0.0, i as f32],
            direction: [0.0, 0.0, 1.0],
            flux_w: 0.25,
            wavelength_nm: 550.0,
        });
        let mut out = Vec::new();
        // The writer refuses a count mismatch after writing; keep what it wrote.
        let _ = write_tm25(&mut out, &h, n, rays);
        out
    }

    fn err_of(bytes: Vec<u8>) -> String {
        match RayFile::from_bytes(bytes, Path::new("bad.TM25RAY")) {
            Ok(f) => match f.check_rays() {
                Ok(()) => panic!("accepted"),
                Err(e) => e.to_string(),
            },
            Err(e) => e.to_string(),
        }
    }

    /// Bad input: each fault gives an error naming the file and the section or ray.
    #[test]
    fn bad_files_are_refused_with_the_fault_named() {
        let good = small_file(4, 4);
        assert!(RayFile::from_bytes(good.clone(), Path::new("g"))
            .unwrap()
            .check_rays()
            .is_ok());
        // Truncated inside the header and inside the rays.
        let e = err_of(good[..1000].to_vec());
        assert!(e.contains("bad.TM25RAY") && e.contains("truncated"), "{e}");
        let e = err_of(good[..good.len() - 3].to_vec());
        assert!(
            e.contains("4.7.1.6") && e.contains("3 whole records"),
            "{e}"
        );
        // A header claiming more rays than present, and one claiming a huge count: no
        // allocation follows the count.
        let e = err_of(small_file(9, 4));
        assert!(e.contains("counts 9 rays"), "{e}");
        let mut huge = good.clone();
        huge[20..28].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(err_of(huge).contains("counts 18446744073709551615 rays"));
        // Surplus bytes.
        let mut long = good.clone();
        long.extend_from_slice(&[0; 8]);
        assert!(err_of(long).contains("8 bytes after"));
        // Unknown version, wrong magic.
        let mut v = good.clone();
        v[4..8].copy_from_slice(&2020i32.to_le_bytes());
        assert!(err_of(v).contains("version 2020 (ANSI/IES TM-25-20) is not read"));
        let mut m = good.clone();
        m[0] = b'X';
        assert!(err_of(m).contains("not a TM-25"));
        // Forbidden flag combinations: identifier 2 with luminous flux; a flag of 2;
        // tristimulus without luminous flux.
        let mut f = good.clone();
        f[256 + 16..256 + 20].copy_from_slice(&1i32.to_le_bytes());
        assert!(err_of(f).contains("identifier 2 needs radiant flux and no luminous"));
        let mut f = good.clone();
        f[256 + 20..256 + 24].copy_from_slice(&2i32.to_le_bytes());
        assert!(err_of(f).contains("Stokes flag: must be 0 or 1"));
        let mut f = good.clone();
        f[256 + 24..256 + 28].copy_from_slice(&1i32.to_le_bytes());
        assert!(err_of(f).contains("tristimulus"));
        // Spectral identifier 5.
        let mut f = good.clone();
        f[60..64].copy_from_slice(&5i32.to_le_bytes());
        assert!(err_of(f).contains("must be 0 to 4"));
        // A NaN ray and a zero-length direction, named by their 1-based number.
        let rec = |i: usize| FIXED_HEADER_BYTES + 32 * i;
        let mut f = good.clone();
        f[rec(2)..rec(2) + 4].copy_from_slice(&f32::NAN.to_le_bytes());
        let e = err_of(f);
        assert!(e.contains("ray 3") && e.contains("not finite"), "{e}");
        let mut f = good.clone();
        f[rec(1) + 20..rec(1) + 24].copy_from_slice(&0f32.to_le_bytes());
        let e = err_of(f);
        assert!(e.contains("ray 2") && e.contains("length 0"), "{e}");
        // A spectral table count larger than the file: refused before any allocation.
        let mut f = good.clone();
        f[60..64].copy_from_slice(&3i32.to_le_bytes());
        f[256 + 12..256 + 16].copy_from_slice(&0i32.to_le_bytes());
        f[76..80].copy_from_slice(&1i32.to_le_bytes());
        f[FIXED_HEADER_BYTES..FIXED_HEADER_BYTES + 4].copy_from_slice(&i32::MAX.to_le_bytes());
        assert!(err_of(f).contains("spectral table 1"));
    }
}
