//! `spectrace color SPD [--observer …] [--illuminant SPD] [--json]`: the colour of a spectrum.
//!
//! Without `--illuminant`, SPD is an emitter (any emission spec: bundled name, CSV path,
//! `blackbody:K`, …) and XYZ is normalized to Y = 100. With `--illuminant`, SPD is a
//! reflectance (CSV path, `colorchecker:PATCH`, a number, …) seen under that illuminant with the
//! CIE factor k = 100/ΣSȳ. Linear sRGB is XYZ/100 through the sRGB matrix; for a reflectance the
//! illuminant's white is first Bradford-adapted to D65, for an emitter XYZ is used as is.

use crate::color::cct::{cct_duv, uv_1960};
use crate::color::cri::color_rendering;
use crate::color::rgb_space::SRGB;
use crate::color::xyz::{chromaticity, emitter_xyz, reflectance_xyz, spd_tristimulus};
use crate::color::{CieObserverKind, Observer};
use crate::spectrum::{parse_spd_spec, SpectralCurve};

/// Arguments of `spectrace color`.
#[derive(clap::Args, Debug)]
pub struct ColorArgs {
    /// The spectrum: a bundled name (d65, a, fl11, mercury, …), a CSV path, blackbody:K,
    /// gaussian:CENTRE:FWHM, line:NM; with --illuminant a reflectance (CSV path, colorchecker:PATCH, number).
    pub spd: String,
    /// Colour-matching functions: cie1931-2, cie1964-10, cie2015-2 or cie2015-10.
    #[arg(long, default_value = "cie1931-2", value_parser = parse_observer)]
    pub observer: CieObserverKind,
    /// Treat SPD as a reflectance under this illuminant (any emission spec).
    #[arg(long)]
    pub illuminant: Option<String>,
    /// Print one JSON object with the keys X, Y, Z, x, y, srgb_linear; for an emitter also
    /// cct_k, duv, cri_ra, cri_r (R1–R14), tm30_rf and tm30_rg.
    #[arg(long)]
    pub json: bool,
}

fn parse_observer(s: &str) -> Result<CieObserverKind, String> {
    CieObserverKind::from_name(s).ok_or_else(|| {
        format!("unknown observer `{s}`; choose cie1931-2, cie1964-10, cie2015-2 or cie2015-10")
    })
}

/// The computed colour of a spectrum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColorReport {
    /// Tristimulus values (Y = 100 for an emitter or the perfect white).
    pub xyz: [f64; 3],
    /// Chromaticity x, y.
    pub xy: (f64, f64),
    /// Linear sRGB (D65), XYZ/100 converted.
    pub srgb_linear: [f64; 3],
    /// Figures of a light source (emitters only; `None` for a reflectance).
    pub light: Option<LightFigures>,
}

/// Colour figures of a light source: CCT, Duv and colour rendering.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightFigures {
    /// Correlated colour temperature in K and Duv (Ohno), CIE 1931 2°; `None` when the
    /// chromaticity is too far from the Planckian locus for a CCT.
    pub cct_duv: Option<(f64, f64)>,
    /// CIE 13.3 colour rendering (Ra, R1–R14); `None` without a CCT.
    pub cri: Option<crate::color::cri::ColorRendering>,
    /// ANSI/IES TM-30 Rf and Rg; `None` without a CCT in 1000–25000 K.
    pub tm30: Option<crate::color::tm30::Tm30>,
}

/// Compute the colour described by `args`; errors name the bad spec or file.
pub fn compute(args: &ColorArgs) -> Result<ColorReport, String> {
    let observer = args.observer.get();
    let mut light = None;
    let (xyz, rgb_matrix) = match &args.illuminant {
        None => {
            let spd = parse_spd_spec(&args.spd).map_err(|e| e.to_string())?;
            let xyz = emitter_xyz(&spd, observer);
            if xyz[1] <= 0.0 {
                return Err(format!(
                    "`{}` has no power visible to the {} observer ({}–{} nm)",
                    args.spd,
                    observer.name(),
                    observer.range().0,
                    observer.range().1
                ));
            }
            // CCT, Duv and colour rendering are defined for the CIE 1931 2° observer whatever
            // --observer says.
            let xyz_2deg = emitter_xyz(&spd, CieObserverKind::Cie1931_2.get());
            let (u, v) = uv_1960(xyz_2deg);
            light = Some(LightFigures {
                cct_duv: cct_duv(u, v),
                cri: color_rendering(&spd),
                tm30: crate::color::tm30::tm30(&spd),
            });
            (xyz, SRGB.xyz_to_rgb_matrix())
        }
        Some(ill) => {
            let illuminant = parse_spd_spec(ill).map_err(|e| e.to_string())?;
            let curve = SpectralCurve::parse(&args.spd).map_err(|e| e.to_string())?;
            let white = spd_tristimulus(&illuminant, observer);
            if white[1] <= 0.0 {
                return Err(format!(
                    "illuminant `{ill}` has no power visible to the {} observer",
                    observer.name()
                ));
            }
            let xyz = reflectance_xyz(|l| curve.value(l), &illuminant, observer);
            (xyz, SRGB.xyz_to_rgb_matrix_from(white))
        }
    };
    let scaled = xyz.map(|v| v / 100.0);
    let srgb_linear = crate::color::matrix3::mul_vec(&rgb_matrix, scaled);
    Ok(ColorReport {
        xyz,
        xy: chromaticity(xyz),
        srgb_linear,
        light,
    })
}

/// Run `spectrace color`: print the report as text or JSON.
pub fn run(args: &ColorArgs) -> Result<(), String> {
    if is_bfc_path(&args.spd) {
        return run_bfc(args);
    }
    let r = compute(args)?;
    if args.json {
        let mut obj = serde_json::json!({
            "X": r.xyz[0],
            "Y": r.xyz[1],
            "Z": r.xyz[2],
            "x": r.xy.0,
            "y": r.xy.1,
            "srgb_linear": r.srgb_linear,
        });
        if let Some(l) = &r.light {
            obj["cct_k"] = serde_json::json!(l.cct_duv.map(|c| c.0));
            obj["duv"] = serde_json::json!(l.cct_duv.map(|c| c.1));
            obj["cri_ra"] = serde_json::json!(l.cri.map(|c| c.ra));
            obj["cri_r"] = serde_json::json!(l.cri.map(|c| c.r));
            obj["tm30_rf"] = serde_json::json!(l.tm30.map(|t| t.rf));
            obj["tm30_rg"] = serde_json::json!(l.tm30.map(|t| t.rg));
        }
        println!("{obj}");
    } else {
        println!("observer    {}", args.observer.name());
        println!(
            "X Y Z       {:.4} {:.4} {:.4}",
            r.xyz[0], r.xyz[1], r.xyz[2]
        );
        println!("x y         {:.5} {:.5}", r.xy.0, r.xy.1);
        println!(
            "sRGB linear {:.5} {:.5} {:.5}  (D65)",
            r.srgb_linear[0], r.srgb_linear[1], r.srgb_linear[2]
        );
        if let Some(l) = &r.light {
            match l.cct_duv {
                Some((t, duv)) => println!("CCT Duv     {t:.1} K {duv:+.5}  (Ohno, CIE 1931 2°)"),
                None => println!("CCT Duv     none: too far from the Planckian locus"),
            }
            if let Some(c) = &l.cri {
                println!("CRI Ra      {:.1}  (CIE 13.3)", c.ra);
                let rs: Vec<String> = c.r.iter().map(|v| format!("{v:.1}")).collect();
                println!("R1–R14      {}", rs.join(" "));
            }
            if let Some(t) = &l.tm30 {
                println!(
                    "TM-30       Rf {:.1} Rg {:.1}  (ANSI/IES TM-30-18)",
                    t.rf, t.rg
                );
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Fluorescent samples: `spectrace color FILE.BFC --illuminant NAME [--json]`

/// True when `spec` names a bispectral matrix file (`.BFC`, any case).
fn is_bfc_path(spec: &str) -> bool {
    std::path::Path::new(spec)
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("bfc"))
}

/// The colour of a bispectral matrix file under an illuminant: total, reflected and
/// fluoresced XYZ (perfect white diffuser Y = 100), plus what the cleaning rule removed and
/// the largest albedo. Errors name the file, line and field of bad data.
pub fn compute_bfc(
    args: &ColorArgs,
) -> Result<
    (
        crate::color::fluorescent_xyz::FluorescentXyz,
        crate::spectrum::bispectral_matrix::BispectralMatrix,
    ),
    String,
> {
    use crate::spectrum::bispectral_matrix::BispectralMatrix;
    let ill = args.illuminant.as_deref().ok_or_else(|| {
        format!(
            "`{}` is a fluorescent sample (bispectral matrix): give the light it is seen under with --illuminant (for example d65)",
            args.spd
        )
    })?;
    let illuminant = parse_spd_spec(ill).map_err(|e| e.to_string())?;
    let observer = args.observer.get();
    if !(spd_tristimulus(&illuminant, observer)[1] > 0.0) {
        return Err(format!(
            "illuminant `{ill}` has no power visible to the {} observer",
            observer.name()
        ));
    }
    let m = BispectralMatrix::read(std::path::Path::new(&args.spd)).map_err(|e| e.to_string())?;
    let c = crate::color::fluorescent_xyz::fluorescent_xyz(&m, &illuminant, observer);
    Ok((c, m))
}

fn run_bfc(args: &ColorArgs) -> Result<(), String> {
    let (c, m) = compute_bfc(args)?;
    let xy = |v: [f64; 3]| chromaticity(v);
    let (albedo, at) = m.max_albedo();
    let cleaning = m.cleaning();
    if args.json {
        let part = |v: [f64; 3]| serde_json::json!({"X": v[0], "Y": v[1], "Z": v[2], "x": xy(v).0, "y": xy(v).1});
        let obj = serde_json::json!({
            "X": c.total[0],
            "Y": c.total[1],
            "Z": c.total[2],
            "x": xy(c.total).0,
            "y": xy(c.total).1,
            "reflected": part(c.reflected),
            "fluoresced": part(c.fluoresced),
            "sample": m.sample(),
            "max_albedo": albedo,
            "max_albedo_excitation_nm": at,
        });
        println!("{obj}");
    } else {
        println!("sample      {}", m.sample());
        println!("observer    {}", args.observer.name());
        for (name, v) in [
            ("total", c.total),
            ("reflected", c.reflected),
            ("fluoresced", c.fluoresced),
        ] {
            println!(
                "{name:<11} X Y Z {:.4} {:.4} {:.4}  x y {:.5} {:.5}",
                v[0],
                v[1],
                v[2],
                xy(v).0,
                xy(v).1
            );
        }
        println!(
            "cleaning    {} negative reflectances, {} negative fluorescence entries, {} anti-Stokes entries (sum of positives {:.4}) set to 0",
            cleaning.negative_reflectance,
            cleaning.negative_fluorescence,
            cleaning.anti_stokes,
            cleaning.anti_stokes_sum
        );
        println!("max albedo  {albedo:.4} (reflected + re-radiated) at excitation {at} nm");
    }
    Ok(())
}
