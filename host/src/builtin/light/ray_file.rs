//! `ray_file`: an IES TM-25 ray file (`.TM25RAY`) as a light (see
//! [`crate::light::ray_file`] and [`crate::photometry::tm25`]).
//!
//! | parameter        | unit        | default      | meaning |
//! |------------------|-------------|--------------|---------|
//! | `file`           | —           | —            | `.TM25RAY` file, relative to the scene file |
//! | `position`       | scene units | —            | where the file's origin (0, 0, 0) goes |
//! | `aim`            | —           | `(0, -1, 0)` | world direction of the file's +z axis (LED files emit along +z) |
//! | `x_axis`         | —           | `(1, 0, 0)`  | world direction of the file's +x axis, made perpendicular to `aim` |
//! | `file_unit`      | —           | `"mm"`       | length unit of the file's start points (TM-25: mm): `m`, `cm`, `mm`, `in`, `ft` |
//! | `flux_w`         | W           | the rays'    | total radiant flux: the rays are scaled to give it |
//! | `flux_lm`        | lm          | the rays'    | total luminous flux, the same with the spectrum's efficacy |
//! | `spd`            | —           | `"e"`        | spectrum of a file without spectral data (identifier 0); ignored otherwise |
//! | `max_rays`       | —           | `4000000`    | at most this many rays are drawn from (more: chosen by flux, systematic resampling) |
//! | `model`          | —           | `"beams"`    | `"beams"`: the rays themselves (light tracing and BDPT light paths only); `"near_field"`: a luminaire with a luminous opening built from the rays (their binned far field and the box of their start points), seen by every integrator and by sensors |
//! | `table_step_deg` | degrees     | `5`          | angular step of the `near_field` model's table (divides 180) |
//! | `sha256`         | —           | —            | the file's SHA-256 (hex): a file with another is refused |
//! | `data_base64`    | —           | —            | the file's bytes in base64, instead of reading `file` (then only its name) |
//!
//! Flux: radiant flux per ray (W) when the file has it; otherwise its luminous flux (lm)
//! divided by the luminous efficacy of the ray's spectrum (its single wavelength, its table, or
//! `spd`). The total is the rays' sum; both it and the header's total are printed, and a header
//! total that differs by more than 1 % ([`HEADER_MISMATCH`]) is warned about, since the rays
//! are the data. The light's spectrum: the file's table (identifier 3), its line (1), the
//! flux-weighted histogram of the rays' wavelengths at 1 nm (2), the flux-weighted mix of its
//! tables (4), or `spd` (0).
//!
//! At build the chosen model is stated on standard error (`ray_file: … beams only …`), with
//! the header's flux next to the rays' sum.
//!
//! Blobs (`spectrace blob pack`): a file of at most [`EMBED_LIMIT_BYTES`] is embedded
//! (`data_base64`, with its `sha256`), so the blob renders after the file is gone; a larger one
//! is referred to by absolute path and SHA-256 (said on standard error at pack time), so the
//! blob renders only where that very file is, and a changed file is refused by name.

use super::light_spd;
use crate::builtin::spectral::Spectrum;
use crate::builtin::{check, from_value, param_err, state_fns, Build, BuiltinType, Embed};
use crate::light::measure::goniometer::{measure, GoniometerSettings};
use crate::light::near_field::NearFieldLight;
use crate::light::ray_file::{file_spectra, RayFileLight, RaySpectrum};
use crate::light::{Light, LuminaireLight};
use crate::photometry::efficacy::luminous_efficacy_lm_per_w;
use crate::photometry::tm25::{RayFile, SpectralId, Tm25Header};
use crate::scene_file::pin::sha256_hex;
use crate::scene_file::type_doc::Param;
use crate::scene_file::units::LengthUnit;
use crate::scene_file::{FactoryContext, FactoryError};
use crate::spectrum::{parse_spd_spec, Interpolation, Spd, TabulatedSpd};
use base64::engine::general_purpose::STANDARD as BASE64;
use base64::Engine as _;
use glam::Vec3A;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The type.
pub const TYPE: BuiltinType = BuiltinType {
    name: "ray_file",
    aliases: &["tm25"],
    version: 1,
    description: "IES TM-25 ray file: the measured or simulated rays of a source, as beams or a near-field luminaire",
    params: &[
        Param::required("file", "", ".TM25RAY file, relative to the scene file"),
        Param::required("position", "scene units", "where the file's origin goes, (x, y, z)"),
        Param::optional("aim", "", "(0, -1, 0)", "world direction of the file's +z axis"),
        Param::optional(
            "x_axis",
            "",
            "(1, 0, 0)",
            "world direction of the file's +x axis, made perpendicular to aim",
        ),
        Param::optional("file_unit", "", "\"mm\"", "length unit of the file: m, cm, mm, in, ft"),
        Param::optional("flux_w", "W", "the rays'", "total radiant flux; the rays are scaled to it"),
        Param::optional("flux_lm", "lm", "the rays'", "total luminous flux; the rays are scaled to it"),
        Param::optional(
            "spd",
            "",
            "\"e\"",
            "spectrum of a file without spectral data (identifier 0)",
        ),
        Param::optional("max_rays", "", "4000000", "rays drawn from at most (chosen by flux)"),
        Param::optional(
            "model",
            "",
            "\"beams\"",
            "\"beams\" (light tracing, BDPT light paths) or \"near_field\" (connectable luminaire)",
        ),
        Param::optional("table_step_deg", "degrees", "5", "near_field table step"),
        Param::optional("sha256", "", "—", "the file's SHA-256 (hex); another file is refused"),
        Param::optional(
            "data_base64",
            "",
            "—",
            "the file's bytes in base64 instead of reading `file` (what blobs store)",
        ),
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: Some(state_fns::<RayFileParams>()),
};

/// Largest ray file a blob embeds, bytes (16 MiB: about 600 000 rays of 28 bytes; base64 makes
/// the payload 4/3 of that, well under the blob payload limit of 64 MiB). Larger files are
/// referred to by path and SHA-256.
pub const EMBED_LIMIT_BYTES: u64 = 16 << 20;

/// Parameters of [`TYPE`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RayFileParams {
    /// The file.
    pub file: String,
    /// Where its origin goes, scene units.
    pub position: [f64; 3],
    /// World direction of its +z.
    #[serde(default)]
    pub aim: Option<[f64; 3]>,
    /// World direction of its +x.
    #[serde(default)]
    pub x_axis: Option<[f64; 3]>,
    /// Its length unit.
    #[serde(default)]
    pub file_unit: Option<String>,
    /// Radiant flux override, W.
    #[serde(default)]
    pub flux_w: Option<f64>,
    /// Luminous flux override, lm.
    #[serde(default)]
    pub flux_lm: Option<f64>,
    /// Spectrum for files without one.
    #[serde(default)]
    pub spd: Option<Spectrum>,
    /// Most rays drawn from.
    #[serde(default)]
    pub max_rays: Option<u64>,
    /// `beams` or `near_field`.
    #[serde(default)]
    pub model: Option<String>,
    /// Table step of the near-field model, degrees.
    #[serde(default)]
    pub table_step_deg: Option<f64>,
    /// SHA-256 of the file, hex.
    #[serde(default)]
    pub sha256: Option<String>,
    /// The file's bytes, base64 (standard alphabet, padded).
    #[serde(default)]
    pub data_base64: Option<String>,
}

impl Embed for RayFileParams {
    /// A file up to [`EMBED_LIMIT_BYTES`] goes into the blob; a larger one is pinned by absolute
    /// path and SHA-256.
    fn embed(&mut self, ctx: &FactoryContext) -> Result<(), FactoryError> {
        self.spd.embed(ctx)?;
        if self.data_base64.is_some() {
            return Ok(());
        }
        let path = ctx.resolve(&self.file);
        let file = RayFile::open(&path).map_err(|e| param_err("file", e))?;
        let hash = sha256_hex(file.bytes());
        check_sha256(self.sha256.as_deref(), &hash, &path.display().to_string())?;
        self.sha256 = Some(hash.clone());
        let len = file.bytes().len() as u64;
        if len <= EMBED_LIMIT_BYTES {
            self.data_base64 = Some(BASE64.encode(file.bytes()));
            self.file = path
                .file_name()
                .map_or_else(|| self.file.clone(), |n| n.to_string_lossy().into_owned());
        } else {
            let abs = std::path::absolute(&path).unwrap_or(path.clone());
            eprintln!(
                "note: {}: {:.1} MiB is over the {} MiB a blob embeds; the blob refers to it by \
                 path and SHA-256 {hash} and renders only where that file is",
                abs.display(),
                len as f64 / (1u64 << 20) as f64,
                EMBED_LIMIT_BYTES >> 20
            );
            self.file = abs.to_string_lossy().into_owned();
        }
        Ok(())
    }
}

/// Refuse a file whose SHA-256 `got` is not the `want`ed one (when one is given).
fn check_sha256(want: Option<&str>, got: &str, what: &str) -> Result<(), FactoryError> {
    match want {
        Some(w) if !w.trim().eq_ignore_ascii_case(got) => Err(param_err(
            "sha256",
            format!(
                "{what} has SHA-256 {got}, not the pinned {}: a different file from the one \
                 the light was made with",
                w.trim()
            ),
        )),
        _ => Ok(()),
    }
}

/// The ray file `p` names: decoded from `data_base64`, or mapped from `file`; checked against
/// `sha256` when given.
fn open_file(p: &RayFileParams, ctx: &FactoryContext) -> Result<(RayFile, PathBuf), FactoryError> {
    match &p.data_base64 {
        Some(data) => {
            let label = PathBuf::from(format!("{} (embedded)", p.file));
            // Bounded: base64 of at most the blob payload limit.
            let bytes = BASE64
                .decode(data.trim())
                .map_err(|e| param_err("data_base64", format!("not base64: {e}")))?;
            if let Some(want) = &p.sha256 {
                check_sha256(
                    Some(want),
                    &sha256_hex(&bytes),
                    &label.display().to_string(),
                )?;
            }
            let file =
                RayFile::from_bytes(bytes, &label).map_err(|e| param_err("data_base64", e))?;
            Ok((file, label))
        }
        None => {
            let path = ctx.resolve(&p.file);
            let file = RayFile::open(&path).map_err(|e| param_err("file", e))?;
            if let Some(want) = &p.sha256 {
                check_sha256(
                    Some(want),
                    &sha256_hex(file.bytes()),
                    &path.display().to_string(),
                )?;
            }
            Ok((file, path))
        }
    }
}

/// World directions of the file's x, y, z axes.
pub fn file_axes(
    aim: Option<[f64; 3]>,
    x_axis: Option<[f64; 3]>,
) -> Result<[Vec3A; 3], FactoryError> {
    let z = match aim {
        Some(a) => check::direction("aim", a)?.normalize(),
        None => Vec3A::NEG_Y,
    };
    let x0 = match x_axis {
        Some(x) => check::direction("x_axis", x)?.normalize(),
        None if z.x.abs() < 0.9 => Vec3A::X,
        None => Vec3A::NEG_Z,
    };
    let x = x0 - z * x0.dot(z);
    if !(x.length() > 1e-4) {
        return Err(param_err("x_axis", "is parallel to `aim`"));
    }
    let x = x.normalize();
    Ok([x, z.cross(x), z])
}

/// The spectrum of a ray file's rays and the light's overall SPD (see the module docs).
fn spectra(
    file: &RayFile,
    p: &RayFileParams,
    ctx: &FactoryContext,
) -> Result<(RaySpectrum, Arc<dyn Spd>), FactoryError> {
    let h = &file.header;
    let tables = file_spectra(file).map_err(|e| param_err("file", e))?;
    let fluxes = |f: &mut dyn FnMut(&crate::photometry::tm25::RawRay, f64)| {
        for i in 0..file.n_rays() {
            let r = file.ray(i);
            let w = r.radiant_w.or(r.luminous_lm).unwrap_or(0.0) as f64;
            f(&r, w);
        }
    };
    let hist = |bins: &[f64], lo: usize, name: &str| -> Result<Arc<dyn Spd>, FactoryError> {
        let first = bins.iter().position(|&b| b > 0.0).ok_or_else(|| {
            param_err(
                "file",
                "the rays carry no flux at any wavelength in 200..2000 nm",
            )
        })?;
        let last = bins.iter().rposition(|&b| b > 0.0).unwrap_or(first);
        let (a, b) = (first.saturating_sub(1), (last + 1).min(bins.len() - 1));
        let nm: Vec<f64> = (a..=b).map(|i| (lo + i) as f64 + 0.5).collect();
        let v: Vec<f64> = (a..=b).map(|i| bins[i]).collect();
        let s = TabulatedSpd::new(name, &nm, &v, Interpolation::Linear)
            .map_err(|e| param_err("file", e))?;
        Ok(Arc::new(s))
    };
    Ok(match h.spectral_id {
        SpectralId::None if h.flags.wavelength => {
            let mut bins = vec![0.0; 1800];
            fluxes(&mut |r, w| {
                if let Some(l) = r.wavelength_nm {
                    let i = l.floor() as i64 - 200;
                    if (0..1800).contains(&i) {
                        bins[i as usize] += w;
                    }
                }
            });
            (RaySpectrum::PerRay, hist(&bins, 200, "rays' wavelengths")?)
        }
        SpectralId::None => {
            let spd = match &p.spd {
                Some(_) => light_spd(&p.spd, ctx)?,
                None => Arc::new(parse_spd_spec("e").map_err(|e| param_err("spd", e))?),
            };
            (RaySpectrum::Shared(spd.clone()), spd)
        }
        SpectralId::Single => {
            let l = h.single_wavelength_nm as f64;
            let spd: Arc<dyn Spd> =
                Arc::new(parse_spd_spec(&format!("line:{l}")).map_err(|e| param_err("file", e))?);
            (RaySpectrum::Single(l), spd)
        }
        SpectralId::PerRay => {
            let mut bins = vec![0.0; 1800];
            fluxes(&mut |r, w| {
                let i = r.wavelength_nm.unwrap_or(0.0).floor() as i64 - 200;
                if (0..1800).contains(&i) {
                    bins[i as usize] += w;
                }
            });
            (RaySpectrum::PerRay, hist(&bins, 200, "rays' wavelengths")?)
        }
        SpectralId::Table => (RaySpectrum::Shared(tables[0].clone()), tables[0].clone()),
        SpectralId::Indexed => {
            let mut per = vec![0.0; tables.len()];
            fluxes(&mut |r, w| {
                let k = r.spectrum_index.unwrap_or(1.0) as usize;
                if let Some(x) = per.get_mut(k.saturating_sub(1)) {
                    *x += w;
                }
            });
            let mut bins = vec![0.0; 1800];
            for (t, w) in tables.iter().zip(&per) {
                for (i, b) in bins.iter_mut().enumerate() {
                    *b += w * t.value(200.0 + i as f64 + 0.5);
                }
            }
            (
                RaySpectrum::Indexed(tables),
                hist(&bins, 200, "mix of the spectral tables")?,
            )
        }
    })
}

/// Header totals and rays' sums differing by more than this (relative) are reported. 1 %: a
/// header total is a summary that makers round (three significant figures is 0.5 % at worst),
/// while files whose header and rays disagree do so grossly (the LightTools example: 1 lm
/// against 10 000 lm).
pub const HEADER_MISMATCH: f64 = 0.01;

/// The warning for a header total (`header`, NaN or 0 when not given) that disagrees with the
/// rays' sum by more than [`HEADER_MISMATCH`]: which one the light uses and why.
pub fn header_mismatch(header: f32, rays: f64, unit: &str) -> Option<String> {
    let h = header as f64;
    if !(h > 0.0) || ((rays / h) - 1.0).abs() <= HEADER_MISMATCH {
        return None;
    }
    Some(format!(
        "the header's total flux is {header} {unit} but the rays sum to {rays:.6} {unit} \
         ({:+.1} %); the light uses the rays' sum (the rays are the data, the header a summary; \
         `flux_w` / `flux_lm` set another total)",
        100.0 * (rays / h - 1.0)
    ))
}

/// Build the light.
pub fn build(p: &RayFileParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    let (file, path) = open_file(p, ctx)?;
    let file = Arc::new(file);
    for w in &file.header.warnings {
        eprintln!("warning: {}: {w}", path.display());
    }
    let origin = check::position("position", p.position)?;
    let axes = file_axes(p.aim, p.x_axis)?;
    let unit = match &p.file_unit {
        Some(u) => LengthUnit::parse(u).map_err(|e| param_err("file_unit", e))?,
        None => LengthUnit::Millimetre,
    };
    let (spectrum, spd) = spectra(&file, p, ctx)?;
    let k = luminous_efficacy_lm_per_w(spd.as_ref());
    // W per stored flux unit for luminous-only files: 1/K of the ray's spectrum, the same for
    // every ray (identifiers 0, 1, 3: the standard forbids luminous flux with 2 and 4).
    let h = &file.header;
    let w_per_unit = if h.flags.radiant {
        1.0
    } else if k > 0.0 {
        1.0 / k
    } else {
        return Err(param_err(
            "spd",
            "the file gives luminous flux, and its spectrum has no visible part (efficacy 0 lm/W)",
        ));
    };
    let flux_of = |r: &crate::photometry::tm25::RawRay| -> f64 {
        r.radiant_w.or(r.luminous_lm).unwrap_or(0.0) as f64 * w_per_unit
    };
    let max_rays = p.max_rays.unwrap_or(4_000_000);
    if max_rays == 0 {
        return Err(param_err("max_rays", "must be ≥ 1"));
    }
    // The rays' total (RayFileLight::new checks every ray and names a bad one).
    let rays_w: f64 = (0..file.n_rays()).map(|i| flux_of(&file.ray(i))).sum();
    let rays_w = if rays_w > 0.0 && rays_w.is_finite() {
        rays_w
    } else {
        1.0
    };
    let scale = flux_scale(p, rays_w, k)?;
    report_flux(p, &file.header, &path, rays_w / w_per_unit);
    let light = RayFileLight::new(
        file.clone(),
        origin,
        axes,
        unit.metres(),
        flux_of,
        scale,
        spectrum,
        spd.clone(),
        max_rays,
    )
    .map_err(|e| param_err("file", e))?;
    match p.model.as_deref().unwrap_or("beams") {
        "beams" => {
            eprintln!(
                "ray_file {}: {} rays ({} drawn from), {:.6} W, {:.4} lm: beams only (light tracing \
                 and BDPT light paths; path tracing and sensors do not see it; model \"near_field\" \
                 makes it connectable)",
                path.display(),
                file.n_rays(),
                light.rays_used(),
                light.power(),
                light.power() * k
            );
            Ok(Arc::new(light))
        }
        "near_field" => near_field_model(&light, p.table_step_deg.unwrap_or(5.0), &path),
        other => Err(param_err(
            "model",
            format!("`{other}`: expected \"beams\" or \"near_field\""),
        )),
    }
}

/// The factor the rays' flux is multiplied by: 1, or the given `flux_w` / `flux_lm` over the
/// rays' total `rays_w` (W; `k` lm/W converts lumens).
fn flux_scale(p: &RayFileParams, rays_w: f64, k: f64) -> Result<f64, FactoryError> {
    Ok(match (p.flux_w, p.flux_lm) {
        (Some(_), Some(_)) => {
            return Err(param_err("flux_lm", "give `flux_w` or `flux_lm`, not both"))
        }
        (Some(w), None) => check::radiometric("flux_w", w, "W")? as f64 / rays_w,
        (None, Some(lm)) => check::radiometric("flux_lm", lm, "lm")? as f64 / (rays_w * k),
        (None, None) => 1.0,
    })
}

/// Print the header's total and the rays' sum (`rays_total`, in the file's flux unit) and which
/// the light emits; warn when they disagree.
fn report_flux(p: &RayFileParams, h: &Tm25Header, path: &Path, rays_total: f64) {
    // f32 as the file stores it (printed with its own shortest decimals).
    let header_f32 = if h.flags.radiant {
        h.radiant_flux_w
    } else {
        h.luminous_flux_lm
    };
    let header_total = header_f32 as f64;
    let unit_name = if h.flags.radiant { "W" } else { "lm" };
    let header_text = if header_total.is_nan() {
        "not given (NaN)".to_string()
    } else {
        format!("{header_f32} {unit_name}")
    };
    let used = match (p.flux_w, p.flux_lm) {
        (None, None) => "the rays' sum",
        _ => "the rays scaled to the given flux",
    };
    eprintln!(
        "ray_file {}: flux: header {header_text}, rays' sum {rays_total:.6} {unit_name}; the light \
         emits {used}",
        path.display()
    );
    if let Some(w) = header_mismatch(header_f32, rays_total, unit_name) {
        eprintln!("warning: {}: {w}", path.display());
    }
}

/// The `near_field` model of a ray-file light: its far-field table binned from the rays
/// (`step` degrees), emitted from the box of their start points (a point luminaire when the
/// box has no face of non-zero area).
fn near_field_model(
    light: &RayFileLight,
    step: f64,
    path: &Path,
) -> Result<Arc<dyn Light>, FactoryError> {
    let m = measure(
        light,
        &GoniometerSettings {
            step_deg: step,
            samples: 4_000_000,
            seed: 1,
        },
    )
    .map_err(|e| param_err("table_step_deg", e))?;
    let nm: Vec<f64> = m.spectrum.iter().map(|s| s.0).collect();
    let v: Vec<f64> = m.spectrum.iter().map(|s| s.1).collect();
    let mspd: Arc<dyn Spd> = Arc::new(
        TabulatedSpd::new("ray file spectrum", &nm, &v, Interpolation::Linear)
            .map_err(|e| param_err("file", e))?,
    );
    let mk = luminous_efficacy_lm_per_w(mspd.as_ref());
    let centre = Vec3A::new(m.centre[0] as f32, m.centre[1] as f32, m.centre[2] as f32);
    let ident = [Vec3A::X, Vec3A::Y, Vec3A::Z];
    eprintln!(
        "ray_file {}: near-field model: {step}° far-field table binned from 4000000 draws \
         of the rays, emitted from their start points' box {:.4} × {:.4} × {:.4} m (x, z, y) \
         at ({:.4}, {:.4}, {:.4}); {:.6} W",
        path.display(),
        m.size[0],
        m.size[1],
        m.size[2],
        centre.x,
        centre.y,
        centre.z,
        m.flux_w
    );
    if NearFieldLight::has_opening(m.size) {
        Ok(Arc::new(NearFieldLight::new(
            centre,
            ident,
            m.size,
            m.luminaire,
            mspd,
            mk,
        )))
    } else {
        Ok(Arc::new(LuminaireLight::new(
            centre,
            ident,
            m.luminaire,
            mspd,
            mk,
        )))
    }
}
