//! `spectrace luminaire FILE [--at H,V ...] [--json]`: what a measured luminaire file (IES
//! LM-63 or EULUMDAT) says: the header read, the total flux integrated from the candela table
//! and the candela at chosen angles.
//!
//! | option | meaning |
//! |---|---|
//! | `FILE` | an `.ies` or `.ldt` file |
//! | `--at H,V` | file angles in degrees (type C: C-plane, γ from the nadir), repeatable |
//! | `--json` | one JSON object; keys include `flux_lm` and `samples: [{h, v, cd}]` |
//!
//! `spectrace luminaire export FILE --format ies|ldt -o OUT` writes the luminaire as IES
//! LM-63-2019 or EULUMDAT; reading OUT gives the same candela table.

use crate::photometry::eulumdat_writer::write_eulumdat;
use crate::photometry::ies_writer::write_ies_2019;
use crate::photometry::{load_luminaire, Luminaire, PhotometricType};
use std::path::PathBuf;

/// Arguments of `spectrace luminaire`.
#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true)]
pub struct LuminaireArgs {
    /// `export`: write the luminaire as IES LM-63-2019 or EULUMDAT.
    #[command(subcommand)]
    pub command: Option<LuminaireCommand>,
    /// An IES LM-63 (.ies) or EULUMDAT (.ldt) file.
    pub file: Option<PathBuf>,
    /// Angles `H,V` in degrees (type C: C-plane and gamma from the nadir) to print candela at.
    #[arg(long = "at", value_parser = parse_angles, value_name = "H,V")]
    pub at: Vec<(f64, f64)>,
    /// Print one JSON object (keys include flux_lm and samples: [{h, v, cd}]).
    #[arg(long)]
    pub json: bool,
}

/// Subcommands of `spectrace luminaire`.
#[derive(clap::Subcommand, Debug)]
pub enum LuminaireCommand {
    /// Write a luminaire file as IES LM-63-2019 or EULUMDAT.
    Export(ExportArgs),
}

/// Output formats of `spectrace luminaire export`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExportFormat {
    /// IES LM-63-2019.
    Ies,
    /// EULUMDAT.
    Ldt,
}

/// Arguments of `spectrace luminaire export`.
#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// The luminaire to read (.ies or .ldt).
    pub file: PathBuf,
    /// Output format.
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Output file.
    #[arg(short, long)]
    pub output: PathBuf,
}

/// Run `spectrace luminaire export`.
pub fn export(args: &ExportArgs) -> Result<(), String> {
    let lum = load_luminaire(&args.file).map_err(|e| e.to_string())?;
    let source = args.file.file_name().map_or_else(
        || args.file.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let text = match args.format {
        ExportFormat::Ies => write_ies_2019(&lum, &source),
        ExportFormat::Ldt => write_eulumdat(&lum, &source)
            .map_err(|e| format!("{}: cannot write EULUMDAT: {e}", args.file.display()))?,
    };
    std::fs::write(&args.output, text)
        .map_err(|e| format!("cannot write {}: {e}", args.output.display()))?;
    if lum.tilt.is_some() && args.format == ExportFormat::Ldt {
        eprintln!(
            "warning: {}: EULUMDAT has no lamp tilt table; the tilt data was not written",
            args.file.display()
        );
    }
    Ok(())
}

fn parse_angles(s: &str) -> Result<(f64, f64), String> {
    let bad = || format!("`{s}`: expected two angles in degrees as H,V (for example 0,45)");
    let (h, v) = s.split_once(',').ok_or_else(bad)?;
    let h: f64 = h.trim().parse().map_err(|_| bad())?;
    let v: f64 = v.trim().parse().map_err(|_| bad())?;
    if !h.is_finite() || !v.is_finite() {
        return Err(bad());
    }
    Ok((h, v))
}

fn type_name(t: PhotometricType) -> &'static str {
    match t {
        PhotometricType::A => "A",
        PhotometricType::B => "B",
        PhotometricType::C => "C",
    }
}

/// The JSON report of a luminaire and the candela at `at`.
pub fn report_json(lum: &Luminaire, file: &str, at: &[(f64, f64)]) -> serde_json::Value {
    let samples: Vec<serde_json::Value> = at
        .iter()
        .map(|&(h, v)| serde_json::json!({"h": h, "v": v, "cd": lum.candela_at(h, v)}))
        .collect();
    let lamps: Vec<serde_json::Value> = lum
        .lamps
        .iter()
        .map(|l| {
            serde_json::json!({
                "count": l.count,
                "lumens": l.lumens,
                "description": l.description,
                "watts": l.watts,
            })
        })
        .collect();
    let multipliers: Vec<serde_json::Value> = lum
        .multipliers
        .iter()
        .map(|m| serde_json::json!({"name": m.name, "value": m.value, "applied": m.applied}))
        .collect();
    let flux = lum.flux_lm();
    serde_json::json!({
        "file": file,
        "format": lum.format.name(),
        "photometric_type": type_name(lum.photometric_type),
        "symmetry": lum.symmetry.name(),
        "h_deg": lum.h_deg,
        "v_deg": lum.v_deg,
        "lamps": lamps,
        "multipliers": multipliers,
        "absolute_photometry": lum.absolute,
        "rated_lamp_lumens": lum.rated_lamp_lumens,
        "flux_lm": flux,
        "max_cd": lum.max_cd(),
        "size_m": lum.size_m,
        "tilt": lum.tilt.as_ref().map(|t| serde_json::json!({
            "geometry": t.geometry, "angles_deg": t.angles_deg, "factors": t.factors, "source": t.source
        })),
        "warnings": lum.warnings,
        "samples": samples,
    })
}

fn range(xs: &[f64]) -> String {
    match xs {
        [] => "none".to_string(),
        [a] => format!("{a} (1 angle)"),
        [a, .., b] => format!("{a} .. {b} ({} angles)", xs.len()),
    }
}

/// Run `spectrace luminaire`.
pub fn run(args: &LuminaireArgs) -> Result<(), String> {
    if let Some(LuminaireCommand::Export(e)) = &args.command {
        return export(e);
    }
    let Some(path) = &args.file else {
        return Err("luminaire: give a file (.ies or .ldt), or `luminaire export`".into());
    };
    let lum = load_luminaire(path).map_err(|e| e.to_string())?;
    let file = path.display().to_string();
    for w in &lum.warnings {
        eprintln!("warning: {file}: {w}");
    }
    let flux = lum.flux_lm();
    if !(flux > 0.0) {
        eprintln!("warning: {file}: every candela value is 0: this luminaire emits nothing");
    }
    if let Some(rated) = lum.rated_lamp_lumens {
        if flux > 1.05 * rated {
            eprintln!(
                "warning: {file}: the table integrates to {:.0} % of the rated lamp flux; a \
                 luminaire gives at most its lamps' flux (wrong multiplier or lumens?)",
                100.0 * flux / rated
            );
        }
    }
    if args.json {
        println!("{}", report_json(&lum, &file, &args.at));
        return Ok(());
    }
    println!("file              {file}");
    println!("format            {}", lum.format.name());
    println!("photometric type  {}", type_name(lum.photometric_type));
    println!("symmetry          {}", lum.symmetry.name());
    println!("h angles (deg)    {}", range(&lum.h_deg));
    println!("v angles (deg)    {}", range(&lum.v_deg));
    for (i, l) in lum.lamps.iter().enumerate() {
        let lumens = l
            .lumens
            .map_or("absolute photometry".to_string(), |v| format!("{v} lm"));
        let watts = l.watts.map_or(String::new(), |w| format!(", {w} W"));
        let desc = if l.description.is_empty() {
            String::new()
        } else {
            format!(", {}", l.description)
        };
        println!(
            "lamps (set {})     {} × {lumens}{watts}{desc}",
            i + 1,
            l.count
        );
    }
    for m in &lum.multipliers {
        let applied = if m.applied {
            "applied"
        } else {
            "not a multiplier"
        };
        println!("multiplier        {} = {} ({applied})", m.name, m.value);
    }
    if let Some(t) = &lum.tilt {
        println!(
            "tilt              {} pairs, geometry {}, from {}",
            t.angles_deg.len(),
            t.geometry,
            t.source
        );
    }
    println!("flux              {flux:.2} lm (trapezoid over the sphere)");
    if let Some(rated) = lum.rated_lamp_lumens {
        println!(
            "rated lamp flux   {rated} lm (luminaire efficiency {:.1} %)",
            100.0 * flux / rated
        );
    } else {
        println!("rated lamp flux   none (absolute photometry)");
    }
    println!("max intensity     {:.2} cd", lum.max_cd());
    for &(h, v) in &args.at {
        println!("cd at h={h} v={v}  {:.3}", lum.candela_at(h, v));
    }
    Ok(())
}
