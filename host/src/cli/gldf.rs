//! `spectrace luminaire FILE.gldf [--json]`: what a GLDF container holds for rendering: the
//! product, its variants and their emitters, each emitter's photometry (flux integrated from
//! its table, rated flux) and its light source's spectrum with the CCT (Ohno) and CIE 13.3
//! Ra computed from it, next to the values the container states.

use crate::color::cri::color_rendering;
use crate::photometry::gldf::{Emitter, Gldf, LightSource};
use crate::spectrum::{Interpolation, TabulatedSpd};
use std::path::Path;

/// What the report says of one emitter: its flux from the table (or why not), its light
/// source, and the CCT and Ra of the container's spectrum.
struct EmitterReport {
    emitter: Emitter,
    flux: Result<f64, String>,
    source: Option<LightSource>,
    cct: Option<f64>,
    ra: Option<f64>,
}

/// Run the report.
pub fn info(path: &Path, json: bool) -> Result<(), String> {
    let mut g = Gldf::open(path).map_err(|e| e.to_string())?;
    let file = path.display().to_string();
    for w in &g.warnings {
        eprintln!("warning: {file}: {w}");
    }
    let mut emitters = Vec::new();
    for e in g.emitters.clone() {
        emitters.push(emitter_report(&mut g, e)?);
    }
    if json {
        print_json(&file, &g, &emitters);
    } else {
        print_text(&file, &g, &emitters);
    }
    Ok(())
}

/// The emitter's photometry and spectrum, measured.
fn emitter_report(g: &mut Gldf, e: Emitter) -> Result<EmitterReport, String> {
    let flux = g
        .luminaire_of(&e)
        .map(|l| l.flux_lm())
        .map_err(|e| e.to_string());
    let source = g.light_source_of(&e).cloned();
    let (cct, ra) = match g.spectrum_of(&e) {
        Some(s) => {
            let nm: Vec<f64> = s.iter().map(|p| p.0).collect();
            let v: Vec<f64> = s.iter().map(|p| p.1).collect();
            let spd = TabulatedSpd::new("container spectrum", &nm, &v, Interpolation::Linear)
                .map_err(|e| e.to_string())?;
            match color_rendering(&spd) {
                Some(c) => (Some(c.cct_k), Some(c.ra)),
                None => (None, None),
            }
        }
        None => (None, None),
    };
    Ok(EmitterReport {
        emitter: e,
        flux,
        source,
        cct,
        ra,
    })
}

/// `--json`: the report as one JSON object.
fn print_json(file: &str, g: &Gldf, emitters: &[EmitterReport]) {
    let vs: Vec<serde_json::Value> = g
        .variants
        .iter()
        .map(|v| serde_json::json!({"id": v.id, "name": v.name, "emitters": v.emitters}))
        .collect();
    let es: Vec<serde_json::Value> = emitters
        .iter()
        .map(|r| {
            let (e, flux, ls) = (&r.emitter, &r.flux, &r.source);
            serde_json::json!({
                "id": e.id, "photometry": e.photometry, "flux_lm": flux.as_ref().ok(),
                "photometry_error": flux.as_ref().err(), "rated_flux_lm": e.rated_flux_lm,
                "light_source": ls.as_ref().map(|l| l.id.clone()),
                "stated_cct_k": ls.as_ref().and_then(|l| l.cct_k), "stated_cri": ls.as_ref().and_then(|l| l.cri),
                "spectrum_cct_k": r.cct, "spectrum_ra": r.ra,
            })
        })
        .collect();
    println!(
        "{}",
        serde_json::json!({"file": file, "product": g.product, "manufacturer": g.manufacturer,
                           "variants": vs, "emitters": es, "warnings": g.warnings})
    );
}

/// The report as text: the product, its variants, then each emitter.
fn print_text(file: &str, g: &Gldf, emitters: &[EmitterReport]) {
    println!("file            {file}");
    println!("product         {}", g.product);
    println!("manufacturer    {}", g.manufacturer);
    for v in &g.variants {
        println!(
            "variant         `{}` {}: emitters {}",
            v.id,
            v.name,
            v.emitters.join(", ")
        );
    }
    for r in emitters {
        print_emitter(r);
    }
}

/// One emitter as text.
fn print_emitter(r: &EmitterReport) {
    let e = &r.emitter;
    println!("emitter         `{}`", e.id);
    println!(
        "  photometry    {}",
        e.photometry.as_deref().unwrap_or("none in the container")
    );
    match &r.flux {
        Ok(f) => println!(
            "  flux          {f:.1} lm (table){}",
            e.rated_flux_lm
                .map_or(String::new(), |r| format!(", rated {r} lm"))
        ),
        Err(m) => println!("  flux          unreadable: {m}"),
    }
    if let Some(l) = &r.source {
        println!("  light source  `{}` {}", l.id, l.name);
        println!(
            "  stated        CCT {}, CRI {}",
            l.cct_k.map_or("—".into(), |c| format!("{c} K")),
            l.cri.map_or("—".into(), |c| format!("{c}"))
        );
    }
    match (r.cct, r.ra) {
        (Some(c), Some(r)) => println!(
            "  spectrum      CCT {c:.0} K, Ra {r:.1} (computed from the container's spectrum)"
        ),
        _ => {
            println!("  spectrum      none in the container (a `gldf` light then needs `spd`)")
        }
    }
}
