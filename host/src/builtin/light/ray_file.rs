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
//!
//! Flux: radiant flux per ray (W) when the file has it; otherwise its luminous flux (lm)
//! divided by the luminous efficacy of the ray's spectrum (its single wavelength, its table, or
//! `spd`). The total is the rays' sum; a header total that differs by more than 0.1 % is
//! reported, since the rays are the data. The light's spectrum: the file's table (identifier
//! 3), its line (1), the flux-weighted histogram of the rays' wavelengths at 1 nm (2), the
//! flux-weighted mix of its tables (4), or `spd` (0).
//!
//! At build the chosen model is stated on standard error (`ray_file: … beams only …`).

use super::light_spd;
use crate::builtin::spectral::Spectrum;
use crate::builtin::{check, from_value, param_err, Build, BuiltinType};
use crate::light::near_field::NearFieldLight;
use crate::light::ray_file::{file_spectra, RayFileLight, RaySpectrum};
use crate::light::{Light, LuminaireLight};
use crate::photometry::efficacy::luminous_efficacy_lm_per_w;
use crate::photometry::goniometer::{measure, GoniometerSettings};
use crate::photometry::tm25::{RayFile, SpectralId};
use crate::plugin::type_doc::Param;
use crate::scene::units::LengthUnit;
use crate::scene::{FactoryContext, FactoryError};
use crate::spectrum::{parse_spd_spec, Interpolation, Spd, TabulatedSpd};
use glam::Vec3A;
use serde::{Deserialize, Serialize};
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
    ],
    build: Build::Light(|v, ctx| build(&from_value(v)?, ctx)),
    state: None,
};

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

/// Build the light.
pub fn build(p: &RayFileParams, ctx: &FactoryContext) -> Result<Arc<dyn Light>, FactoryError> {
    let path = ctx.resolve(&p.file);
    let file = Arc::new(RayFile::open(&path).map_err(|e| param_err("file", e))?);
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
    let scale = match (p.flux_w, p.flux_lm) {
        (Some(_), Some(_)) => {
            return Err(param_err("flux_lm", "give `flux_w` or `flux_lm`, not both"))
        }
        (Some(w), None) => check::radiometric("flux_w", w, "W")? as f64 / rays_w,
        (None, Some(lm)) => check::radiometric("flux_lm", lm, "lm")? as f64 / (rays_w * k),
        (None, None) => 1.0,
    };
    let header_total = if h.flags.radiant {
        h.radiant_flux_w as f64
    } else {
        h.luminous_flux_lm as f64
    };
    let rays_total = rays_w / w_per_unit;
    if header_total > 0.0 && ((rays_total / header_total) - 1.0).abs() > 1e-3 {
        let unit = if h.flags.radiant { "W" } else { "lm" };
        eprintln!(
            "warning: {}: the header's total flux is {header_total} {unit} but the rays sum to \
             {rays_total:.6} {unit}; the rays' sum is used",
            path.display()
        );
    }
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
        "near_field" => {
            let step = p.table_step_deg.unwrap_or(5.0);
            let m = measure(
                &light,
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
                m.size[0], m.size[1], m.size[2], centre.x, centre.y, centre.z, m.flux_w
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
        other => Err(param_err(
            "model",
            format!("`{other}`: expected \"beams\" or \"near_field\""),
        )),
    }
}
