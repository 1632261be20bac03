//! GLDF (Global Lighting Data Format, DIAL and Relux, gldf.io): a zip container whose
//! `product.xml` describes a luminaire product, its variants and their emitters, and refers to
//! photometry files (EULUMDAT or IES, folder `ldc/`), spectra (`spectrum/`, or inline),
//! geometry and images. Read here: what a renderer needs to light a scene with a variant's
//! emitter, its photometry and its light source's spectrum.
//!
//! Structure read (element names of the format's XSD, 1.0.0-rc.1 to rc.3, as its documentation
//! on gldf.io describes them):
//! - `GeneralDefinitions/Files/File` (`id`, `contentType`, `type` = `localFileName` | `url`,
//!   text = the file name inside the folder named by the first part of `contentType`);
//! - `Photometries/Photometry` (`id`) with `PhotometryFileReference fileId`;
//! - `Spectrums/Spectrum` (`id`) with `Intensity wavelength="nm"` values or a
//!   `SpectrumFileReference fileId` (a text file of `nm value` lines);
//! - `LightSources/FixedLightSource | ChangeableLightSource` (`id`) with `Name`,
//!   `SpectrumReference spectrumId`, `ColorInformation` (`CorrelatedColorTemperature`,
//!   `ColorRenderingIndex`) and `RatedLuminousFlux`;
//! - `Emitters/Emitter` (`id`) with `FixedLightEmitter | ChangeableLightEmitter`:
//!   `PhotometryReference photometryId`, `LightSourceReference fixedLightSourceId |
//!   changeableLightSourceId`, `RatedLuminousFlux`;
//! - `ProductDefinitions/ProductMetaData/Name`, `Variants/Variant` (`id`, `Name`) and every
//!   `EmitterReference emitterId` below the variant.
//!
//! Safety (a container is untrusted input): entries are looked up by exact name, never
//! extracted to disk; a container with an entry whose name is absolute, has a `..` component
//! or a backslash is refused; at most [`MAX_ENTRIES`] entries; every read stops at
//! [`MAX_ENTRY_BYTES`] of decompressed data whatever the entry's header claims, and the whole
//! container at [`MAX_TOTAL_BYTES`] (zip bombs); XML with a DTD is refused (no entity
//! expansion: roxmltree's default), and files of `type="url"` are not fetched.

use super::luminaire::Luminaire;
use super::PhotometryError;
use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Most entries a container may have.
pub const MAX_ENTRIES: usize = 10_000;
/// Most bytes one entry may decompress to (photometry files are kilobytes, product.xml
/// rarely a megabyte).
pub const MAX_ENTRY_BYTES: u64 = 64 << 20;
/// Most bytes read from one container in all.
pub const MAX_TOTAL_BYTES: u64 = 256 << 20;

/// A light source of the container.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightSource {
    /// Its id.
    pub id: String,
    /// Its name (first locale).
    pub name: String,
    /// Referenced spectrum id.
    pub spectrum: Option<String>,
    /// Stated CCT, K.
    pub cct_k: Option<f64>,
    /// Stated CRI (Ra).
    pub cri: Option<f64>,
}

/// An emitter of the container.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Emitter {
    /// Its id.
    pub id: String,
    /// Entry name of its photometry file in the zip (`ldc/…`), when local.
    pub photometry: Option<String>,
    /// Its light source id.
    pub light_source: Option<String>,
    /// Rated luminous flux, lm.
    pub rated_flux_lm: Option<f64>,
}

/// A product variant.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Variant {
    /// Its id.
    pub id: String,
    /// Its name (first locale).
    pub name: String,
    /// Emitter ids it references, in document order.
    pub emitters: Vec<String>,
}

/// A GLDF container as read (see the module docs).
#[derive(Debug)]
pub struct Gldf {
    /// The container file.
    pub path: PathBuf,
    /// Product name (first locale).
    pub product: String,
    /// Manufacturer from the header.
    pub manufacturer: String,
    /// Variants.
    pub variants: Vec<Variant>,
    /// Emitters by id.
    pub emitters: Vec<Emitter>,
    /// Light sources.
    pub light_sources: Vec<LightSource>,
    /// Spectra by id: `(nm, value)` ascending.
    pub spectra: HashMap<String, Vec<(f64, f64)>>,
    /// Things that are legal but probably not what the author meant.
    pub warnings: Vec<String>,
    archive: zip::ZipArchive<std::io::Cursor<Vec<u8>>>,
    read_total: u64,
}

fn err(path: &Path, field: &str, msg: impl Into<String>) -> PhotometryError {
    PhotometryError::file(path, field, msg)
}

/// True for an entry name that stays inside the container.
fn safe_name(name: &str) -> bool {
    !(name.starts_with('/')
        || name.contains('\\')
        || name.contains('\0')
        || name.split('/').any(|c| c == "..")
        || name.get(1..2) == Some(":"))
}

/// Text of the first `Locale` child of `node`'s child `tag`.
fn locale(node: roxmltree::Node, tag: &str) -> String {
    child(node, tag)
        .and_then(|n| n.children().find(|c| c.has_tag_name("Locale")))
        .and_then(|l| l.text())
        .unwrap_or("")
        .trim()
        .to_string()
}

fn child<'a, 'i>(node: roxmltree::Node<'a, 'i>, tag: &str) -> Option<roxmltree::Node<'a, 'i>> {
    node.children().find(|c| c.has_tag_name(tag))
}

fn number(node: Option<roxmltree::Node>) -> Option<f64> {
    node.and_then(|n| n.text())
        .and_then(|t| t.trim().parse().ok())
        .filter(|v: &f64| v.is_finite())
}

/// File id → (content type, zip entry of a local file; `None` for a URL).
type DeclaredFiles = HashMap<String, (String, Option<String>)>;

/// The files `GeneralDefinitions` declares; a local name that leaves its folder is refused.
fn declared_files(gd: roxmltree::Node, path: &Path) -> Result<DeclaredFiles, PhotometryError> {
    let mut files = DeclaredFiles::new();
    let Some(fs) = child(gd, "Files") else {
        return Ok(files);
    };
    for f in fs.children().filter(|c| c.has_tag_name("File")) {
        let id = f.attribute("id").unwrap_or("").to_string();
        let ct = f.attribute("contentType").unwrap_or("").to_string();
        let name = f.text().unwrap_or("").trim().to_string();
        let local = f.attribute("type") == Some("localFileName");
        let folder = ct.split('/').next().unwrap_or("");
        let entry = local.then(|| format!("{folder}/{name}"));
        if let Some(e) = &entry {
            if !safe_name(e) || name.contains('/') {
                return Err(err(
                    path,
                    "product.xml",
                    format!("File `{id}`: name `{name}` leaves its folder; refused"),
                ));
            }
        }
        files.insert(id, (ct, entry));
    }
    Ok(files)
}

/// Parse a spectrum text file: `nm value` per line (blank or tab separated; `#` comments).
pub fn parse_spectrum_text(text: &str) -> Result<Vec<(f64, f64)>, String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut it = line
            .split(|c: char| c.is_whitespace() || c == ';' || c == ',')
            .filter(|s| !s.is_empty());
        let (Some(a), Some(b)) = (it.next(), it.next()) else {
            return Err(format!("line {}: expected `wavelength value`", i + 1));
        };
        let (Ok(l), Ok(v)) = (a.parse::<f64>(), b.parse::<f64>()) else {
            return Err(format!("line {}: `{line}` is not two numbers", i + 1));
        };
        out.push((l, v));
    }
    check_spectrum(&out)?;
    Ok(out)
}

fn check_spectrum(s: &[(f64, f64)]) -> Result<(), String> {
    if s.len() < 2 {
        return Err("a spectrum needs at least two wavelengths".into());
    }
    if s.iter()
        .any(|p| !(p.0 > 0.0 && p.0.is_finite() && p.1 >= 0.0 && p.1.is_finite()))
    {
        return Err("wavelengths must be > 0 nm and intensities finite and ≥ 0".into());
    }
    if s.windows(2).any(|w| !(w[1].0 > w[0].0)) {
        return Err("wavelengths must increase".into());
    }
    if !s.iter().any(|p| p.1 > 0.0) {
        return Err("every intensity is 0".into());
    }
    Ok(())
}

impl Gldf {
    /// Read the container at `path` (limits in the module docs).
    pub fn open(path: &Path) -> Result<Self, PhotometryError> {
        let bytes = crate::limits::read_limited(path, MAX_TOTAL_BYTES, "GLDF container")
            .map_err(|e| err(path, "file", format!("cannot read: {e}")))?;
        Self::from_bytes(bytes, path)
    }

    /// Read a container held in memory (`path` names it in errors).
    pub fn from_bytes(bytes: Vec<u8>, path: &Path) -> Result<Self, PhotometryError> {
        let archive = zip::ZipArchive::new(std::io::Cursor::new(bytes))
            .map_err(|e| err(path, "zip", format!("not a readable zip container: {e}")))?;
        if archive.len() > MAX_ENTRIES {
            return Err(err(
                path,
                "zip",
                format!(
                    "{} entries, more than the limit of {MAX_ENTRIES}",
                    archive.len()
                ),
            ));
        }
        for name in archive.file_names() {
            if !safe_name(name) {
                return Err(err(
                    path,
                    "zip",
                    format!("entry `{name}` points outside the container (absolute path, `..` or `\\`); refused"),
                ));
            }
        }
        let mut g = Gldf {
            path: path.to_path_buf(),
            product: String::new(),
            manufacturer: String::new(),
            variants: vec![],
            emitters: vec![],
            light_sources: vec![],
            spectra: HashMap::new(),
            warnings: vec![],
            archive,
            read_total: 0,
        };
        let xml = g.entry("product.xml")?;
        let text =
            String::from_utf8(xml).map_err(|_| err(path, "product.xml", "not UTF-8 text"))?;
        g.parse_product(&text)?;
        Ok(g)
    }

    /// The decompressed bytes of entry `name`, bounded by the limits.
    pub fn entry(&mut self, name: &str) -> Result<Vec<u8>, PhotometryError> {
        let path = self.path.clone();
        if !safe_name(name) {
            return Err(err(&path, name, "refers outside the container"));
        }
        let mut f = self
            .archive
            .by_name(name)
            .map_err(|e| err(&path, name, format!("not in the container: {e}")))?;
        let left = MAX_TOTAL_BYTES.saturating_sub(self.read_total);
        let limit = MAX_ENTRY_BYTES.min(left);
        let mut out = Vec::new();
        (&mut f)
            .take(limit + 1)
            .read_to_end(&mut out)
            .map_err(|e| err(&path, name, format!("cannot decompress: {e}")))?;
        if out.len() as u64 > limit {
            return Err(err(
                &path,
                name,
                format!("decompresses to more than {limit} bytes (the limit per entry and container): refused as a zip bomb"),
            ));
        }
        self.read_total += out.len() as u64;
        Ok(out)
    }

    fn parse_product(&mut self, text: &str) -> Result<(), PhotometryError> {
        let path = self.path.clone();
        let doc = roxmltree::Document::parse(text).map_err(|e| {
            err(
                &path,
                "product.xml",
                format!("not well-formed XML (a DTD or entity is refused): {e}"),
            )
        })?;
        let root = doc.root_element();
        if !root.has_tag_name("Root") {
            return Err(err(
                &path,
                "product.xml",
                format!("root element `{}`, expected `Root`", root.tag_name().name()),
            ));
        }
        self.manufacturer = child(root, "Header")
            .and_then(|h| child(h, "Manufacturer"))
            .and_then(|m| m.text())
            .unwrap_or("")
            .trim()
            .to_string();
        let gd = child(root, "GeneralDefinitions")
            .ok_or_else(|| err(&path, "product.xml", "no GeneralDefinitions"))?;
        let files = declared_files(gd, &path)?;
        let photometries = self.read_photometries(gd, &files);
        let spectrum_files = self.read_spectra(gd, &files)?;
        self.read_light_sources(gd);
        self.read_emitters(gd, &photometries);
        self.read_variants(root);
        for (id, entry) in spectrum_files {
            let bytes = self.entry(&entry)?;
            let text = String::from_utf8_lossy(&bytes);
            let s = parse_spectrum_text(&text).map_err(|m| err(&path, &entry, m))?;
            self.spectra.insert(id, s);
        }
        Ok(())
    }

    /// Photometry id → its file's zip entry (a URL or an undeclared file is a warning).
    fn read_photometries(
        &mut self,
        gd: roxmltree::Node,
        files: &DeclaredFiles,
    ) -> HashMap<String, String> {
        let mut photometries: HashMap<String, String> = HashMap::new();
        let Some(ps) = child(gd, "Photometries") else {
            return photometries;
        };
        for p in ps.children().filter(|c| c.has_tag_name("Photometry")) {
            let id = p.attribute("id").unwrap_or("").to_string();
            if let Some(fid) =
                child(p, "PhotometryFileReference").and_then(|r| r.attribute("fileId"))
            {
                match files.get(fid) {
                    Some((_, Some(entry))) => {
                        photometries.insert(id, entry.clone());
                    }
                    Some((_, None)) => self
                        .warnings
                        .push(format!("photometry `{id}`: its file is a URL, not fetched")),
                    None => self
                        .warnings
                        .push(format!("photometry `{id}`: file `{fid}` is not declared")),
                }
            }
        }
        photometries
    }

    /// The spectra given inline (checked and kept); returns those given as files in the
    /// container, (spectrum id, zip entry), read once the whole product is known.
    fn read_spectra(
        &mut self,
        gd: roxmltree::Node,
        files: &DeclaredFiles,
    ) -> Result<Vec<(String, String)>, PhotometryError> {
        let mut spectrum_files = Vec::new();
        let Some(ss) = child(gd, "Spectrums") else {
            return Ok(spectrum_files);
        };
        for s in ss.children().filter(|c| c.has_tag_name("Spectrum")) {
            let id = s.attribute("id").unwrap_or("").to_string();
            let values: Vec<(f64, f64)> = s
                .children()
                .filter(|c| c.has_tag_name("Intensity"))
                .filter_map(|c| {
                    Some((
                        c.attribute("wavelength")?.trim().parse().ok()?,
                        number(Some(c))?,
                    ))
                })
                .collect();
            if !values.is_empty() {
                check_spectrum(&values)
                    .map_err(|m| err(&self.path, &format!("product.xml spectrum `{id}`"), m))?;
                self.spectra.insert(id, values);
            } else if let Some(fid) =
                child(s, "SpectrumFileReference").and_then(|r| r.attribute("fileId"))
            {
                match files.get(fid) {
                    Some((_, Some(entry))) => spectrum_files.push((id, entry.clone())),
                    _ => self.warnings.push(format!(
                        "spectrum `{id}`: file `{fid}` is not in the container"
                    )),
                }
            }
        }
        Ok(spectrum_files)
    }

    /// The fixed and changeable light sources.
    fn read_light_sources(&mut self, gd: roxmltree::Node) {
        let Some(ls) = child(gd, "LightSources") else {
            return;
        };
        for l in ls.children().filter(|c| {
            c.has_tag_name("FixedLightSource") || c.has_tag_name("ChangeableLightSource")
        }) {
            let ci = child(l, "ColorInformation");
            self.light_sources.push(LightSource {
                id: l.attribute("id").unwrap_or("").to_string(),
                name: locale(l, "Name"),
                spectrum: child(l, "SpectrumReference")
                    .and_then(|r| r.attribute("spectrumId"))
                    .map(str::to_string),
                cct_k: ci.and_then(|c| number(child(c, "CorrelatedColorTemperature"))),
                cri: ci.and_then(|c| number(child(c, "ColorRenderingIndex"))),
            });
        }
    }

    /// The light emitters, each with its photometry's zip entry and its light source; sensors
    /// are left out with a warning.
    fn read_emitters(&mut self, gd: roxmltree::Node, photometries: &HashMap<String, String>) {
        let Some(es) = child(gd, "Emitters") else {
            return;
        };
        for e in es.children().filter(|c| c.has_tag_name("Emitter")) {
            let id = e.attribute("id").unwrap_or("").to_string();
            let Some(le) = e.children().find(|c| {
                c.has_tag_name("FixedLightEmitter") || c.has_tag_name("ChangeableLightEmitter")
            }) else {
                self.warnings.push(format!("emitter `{id}`: not a fixed or changeable light emitter (sensors are not lights)"));
                continue;
            };
            let photometry = child(le, "PhotometryReference")
                .and_then(|r| r.attribute("photometryId"))
                .and_then(|p| photometries.get(p).cloned());
            let light_source = child(le, "LightSourceReference").and_then(|r| {
                r.attribute("fixedLightSourceId")
                    .or(r.attribute("changeableLightSourceId"))
                    .map(str::to_string)
            });
            self.emitters.push(Emitter {
                id,
                photometry,
                light_source,
                rated_flux_lm: number(child(le, "RatedLuminousFlux")),
            });
        }
    }

    /// The product's name and its variants with the emitters each uses.
    fn read_variants(&mut self, root: roxmltree::Node) {
        let Some(pd) = child(root, "ProductDefinitions") else {
            return;
        };
        if let Some(m) = child(pd, "ProductMetaData") {
            self.product = locale(m, "Name");
        }
        if let Some(vs) = child(pd, "Variants") {
            for v in vs.children().filter(|c| c.has_tag_name("Variant")) {
                let emitters = v
                    .descendants()
                    .filter(|d| d.has_tag_name("EmitterReference"))
                    .filter_map(|d| d.attribute("emitterId").map(str::to_string))
                    .collect();
                self.variants.push(Variant {
                    id: v.attribute("id").unwrap_or("").to_string(),
                    name: locale(v, "Name"),
                    emitters,
                });
            }
        }
    }

    /// The emitter `id`.
    pub fn emitter(&self, id: &str) -> Option<&Emitter> {
        self.emitters.iter().find(|e| e.id == id)
    }

    /// The light source of an emitter.
    pub fn light_source_of(&self, e: &Emitter) -> Option<&LightSource> {
        let id = e.light_source.as_deref()?;
        self.light_sources.iter().find(|l| l.id == id)
    }

    /// The spectrum `(nm, value)` of an emitter's light source, when the container has one.
    pub fn spectrum_of(&self, e: &Emitter) -> Option<&Vec<(f64, f64)>> {
        self.spectra
            .get(self.light_source_of(e)?.spectrum.as_deref()?)
    }

    /// The photometry of an emitter, read from the container (IES or EULUMDAT by extension).
    pub fn luminaire_of(&mut self, e: &Emitter) -> Result<Luminaire, PhotometryError> {
        let path = self.path.clone();
        let entry = e.photometry.clone().ok_or_else(|| {
            err(
                &path,
                &format!("emitter `{}`", e.id),
                "has no photometry file in the container",
            )
        })?;
        let bytes = self.entry(&entry)?;
        let inner = PathBuf::from(format!("{}!{entry}", path.display()));
        let lower = entry.to_ascii_lowercase();
        if lower.ends_with(".ies") {
            super::ies::parse_ies(&bytes, &inner)
        } else {
            super::eulumdat::parse_eulumdat(&bytes, &inner)
        }
    }

    /// The variant `id` (or the first when `None`), and its emitter `emitter` (or its first).
    pub fn choose(
        &self,
        variant: Option<&str>,
        emitter: Option<&str>,
    ) -> Result<(Variant, Emitter), String> {
        let v = match variant {
            Some(id) => self.variants.iter().find(|v| v.id == id).ok_or_else(|| {
                format!(
                    "no variant `{id}` (variants: {})",
                    self.variants
                        .iter()
                        .map(|v| v.id.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })?,
            None => self
                .variants
                .first()
                .ok_or("the container has no variant")?,
        };
        let eid = match emitter {
            Some(id) if v.emitters.iter().any(|e| e == id) => id.to_string(),
            Some(id) => {
                return Err(format!(
                    "variant `{}` has no emitter `{id}` (it has: {})",
                    v.id,
                    v.emitters.join(", ")
                ))
            }
            None => v
                .emitters
                .iter()
                .find(|e| self.emitter(e).is_some())
                .cloned()
                .ok_or_else(|| format!("variant `{}` references no light emitter", v.id))?,
        };
        let e = self
            .emitter(&eid)
            .ok_or_else(|| format!("emitter `{eid}` is not defined"))?;
        Ok((v.clone(), e.clone()))
    }
}
