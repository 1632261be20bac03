//! `spectrace rays`: IES TM-25 ray files.
//!
//! | command | what |
//! |---|---|
//! | `rays info FILE [--json]` | the header (version, creation method, fluxes, ray count, date, spectral identifier, flags, record size, the nine text fields), the rays' summed flux against the header's, the spectral tables, the start points' box and a far-field summary (relative intensity per 10° ring of γ from the file's +z, the half-intensity angle, the share of flux in the forward hemisphere) |
//! | `rays export SCENE --light NAME -N COUNT -o OUT.TM25RAY [--seed S]` | draws COUNT rays from a light of the scene (any kind: built-in, plugin, blob, luminaire, emissive object) and writes them as TM-25-13 in the world frame, start points in mm ([`crate::light::measure::tm25_export`]) |
//!
//! To put an exported file back where its light was: a `ray_file` light with
//! `position: (0, 0, 0), aim: (0, 0, 1), x_axis: (1, 0, 0)` (file frame = world frame).

use super::plugin_args::PluginArgs;
use crate::light::measure::tm25_export::export_light;
use crate::light::Light;
use crate::photometry::tm25::{RayFile, SpectralId, Tm25Header, TEXT_FIELDS};
use crate::plugin::factory::PluginFactory;
use crate::scene_file::ObjectFactory;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Subcommands of `spectrace rays`.
#[derive(clap::Subcommand, Debug)]
pub enum RaysCommand {
    /// Header, flux, ray count, spectral tables and far-field summary of a TM-25 ray file.
    Info(InfoArgs),
    /// Sample a light of a scene into a TM-25 ray file.
    Export(ExportArgs),
}

/// Arguments of `rays info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// The .TM25RAY file.
    pub file: PathBuf,
    /// One JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `rays export`.
#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Name of the light (or emissive object).
    #[arg(long)]
    pub light: String,
    /// Number of rays.
    #[arg(short = 'N', long = "rays", default_value_t = 1_000_000)]
    pub rays: u64,
    /// Output file.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Seed of the random numbers.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    #[command(flatten)]
    /// Plugins to load.
    pub plugins: PluginArgs,
}

/// Run `spectrace rays`.
pub fn run(cmd: &RaysCommand) -> Result<(), String> {
    match cmd {
        RaysCommand::Info(a) => info(a),
        RaysCommand::Export(a) => export(a),
    }
}

/// The far-field summary of a ray file: flux per 10° ring of γ (from +z), in W or lm.
pub struct FarFieldSummary {
    /// Relative intensity (flux / ring solid angle, max 1) per ring 0–10°, …, 170–180°.
    pub rings: [f64; 18],
    /// γ where the ring intensity falls below half its maximum, degrees.
    pub half_intensity_deg: f64,
    /// Share of the flux with kz > 0.
    pub forward_share: f64,
    /// Summed flux per column: radiant (W), luminous (lm).
    pub sums: (Option<f64>, Option<f64>),
    /// Start points' box, file units: min and max.
    pub bounds: ([f32; 3], [f32; 3]),
}

/// Compute the [`FarFieldSummary`] in one pass over the rays.
pub fn far_field_summary(f: &RayFile) -> FarFieldSummary {
    let mut ring = [0.0f64; 18];
    let (mut rad, mut lum, mut fwd, mut tot) = (0.0, 0.0, 0.0, 0.0);
    let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
    for i in 0..f.n_rays() {
        let r = f.ray(i);
        rad += r.radiant_w.unwrap_or(0.0) as f64;
        lum += r.luminous_lm.unwrap_or(0.0) as f64;
        let w = r.radiant_w.or(r.luminous_lm).unwrap_or(0.0) as f64;
        let len = r
            .direction
            .iter()
            .map(|v| (*v as f64).powi(2))
            .sum::<f64>()
            .sqrt();
        if !(len > 0.0 && w.is_finite()) {
            continue;
        }
        let g = (r.direction[2] as f64 / len)
            .clamp(-1.0, 1.0)
            .acos()
            .to_degrees();
        ring[((g / 10.0) as usize).min(17)] += w;
        tot += w;
        if r.direction[2] > 0.0 {
            fwd += w;
        }
        for a in 0..3 {
            lo[a] = lo[a].min(r.position_mm[a]);
            hi[a] = hi[a].max(r.position_mm[a]);
        }
    }
    let mut rings = [0.0; 18];
    for (k, v) in rings.iter_mut().enumerate() {
        let (a, b) = (
            (10.0 * k as f64).to_radians(),
            (10.0 * (k + 1) as f64).to_radians(),
        );
        *v = ring[k] / (2.0 * std::f64::consts::PI * (a.cos() - b.cos()));
    }
    let max = rings.iter().copied().fold(0.0, f64::max);
    if max > 0.0 {
        rings.iter_mut().for_each(|v| *v /= max);
    }
    let peak = rings.iter().position(|&v| v == 1.0).unwrap_or(0);
    let half = (peak..18)
        .find(|&k| rings[k] < 0.5)
        .map_or(180.0, |k| 10.0 * k as f64 + 5.0);
    FarFieldSummary {
        rings,
        half_intensity_deg: half,
        forward_share: if tot > 0.0 { fwd / tot } else { 0.0 },
        sums: (
            f.header.flags.radiant.then_some(rad),
            f.header.flags.luminous.then_some(lum),
        ),
        bounds: (lo, hi),
    }
}

fn info(a: &InfoArgs) -> Result<(), String> {
    let f = RayFile::open(&a.file).map_err(|e| e.to_string())?;
    f.check_rays().map_err(|e| e.to_string())?;
    let h = &f.header;
    let file = a.file.display().to_string();
    for w in &h.warnings {
        eprintln!("warning: {file}: {w}");
    }
    let s = far_field_summary(&f);
    let mismatch = |header: f32, sum: Option<f64>, unit: &str| {
        if let Some(sum) = sum {
            if let Some(w) = crate::builtin::light::ray_file::header_mismatch(header, sum, unit) {
                eprintln!("warning: {file}: {w}");
            }
        }
    };
    mismatch(h.radiant_flux_w, s.sums.0, "W");
    mismatch(h.luminous_flux_lm, s.sums.1, "lm");
    if a.json {
        print_json(&file, &f, &s);
    } else {
        print_text(&file, &f, &s);
    }
    Ok(())
}

/// `rays info --json`: the header, the rays' sums and the far field as one JSON object.
fn print_json(file: &str, f: &RayFile, s: &FarFieldSummary) {
    let h = &f.header;
    let fl = &h.flags;
    let spectra: Vec<serde_json::Value> = h
        .spectra
        .iter()
        .map(|t| {
            let peak = t.iter().copied().fold((0.0f32, 0.0f32), |m, p| if p.1 > m.1 { p } else { m });
            serde_json::json!({"points": t.len(), "min_nm": t[0].0, "max_nm": t[t.len() - 1].0, "peak_nm": peak.0})
        })
        .collect();
    let num = |v: f32| {
        if v.is_nan() {
            serde_json::Value::Null
        } else {
            serde_json::json!(v)
        }
    };
    println!(
        "{}",
        serde_json::json!({
            "file": file,
            "version": h.version,
            "creation_method": h.creation_method,
            "header_luminous_flux_lm": num(h.luminous_flux_lm),
            "header_radiant_flux_w": num(h.radiant_flux_w),
            "rays": h.n_rays,
            "date": h.date,
            "spectral_id": h.spectral_id.code(),
            "single_wavelength_nm": num(h.single_wavelength_nm),
            "flags": {"radiant": fl.radiant, "wavelength": fl.wavelength, "luminous": fl.luminous,
                      "stokes": fl.stokes, "tristimulus": fl.tristimulus, "spectrum_index": fl.spectrum_index},
            "record_bytes": f.layout.record_bytes(),
            "additional_columns": h.column_names,
            "texts": h.texts,
            "rays_radiant_flux_w": s.sums.0,
            "rays_luminous_flux_lm": s.sums.1,
            "spectra": spectra,
            "bounds_mm": [s.bounds.0, s.bounds.1],
            "far_field": {"ring_deg": 10, "relative_intensity": s.rings,
                          "half_intensity_deg": s.half_intensity_deg, "forward_share": s.forward_share},
            "warnings": h.warnings,
        })
    );
}

/// `rays info`: the header, the rays' sums, the columns and spectra, the far field.
fn print_text(file: &str, f: &RayFile, s: &FarFieldSummary) {
    print_header(file, f, s);
    print_columns_and_spectra(&f.header);
    print_far_field(s);
}

/// The header's fields and the fluxes the rays sum to.
fn print_header(file: &str, f: &RayFile, s: &FarFieldSummary) {
    let h = &f.header;
    println!("file               {file}");
    println!(
        "version            {} (creation method {}: {})",
        h.version,
        h.creation_method,
        match h.creation_method {
            0 => "simulation",
            1 => "measurement",
            _ => "unknown",
        }
    );
    println!(
        "rays               {} ({} bytes each)",
        h.n_rays,
        f.layout.record_bytes()
    );
    println!("date               {}", h.date);
    println!(
        "header flux        {} W, {} lm (NaN: not given)",
        h.radiant_flux_w, h.luminous_flux_lm
    );
    if let Some(w) = s.sums.0 {
        println!("rays' radiant flux {w:.6} W");
    }
    if let Some(lm) = s.sums.1 {
        println!("rays' luminous flux {lm:.6} lm");
    }
}

/// The record's columns, the spectrum, the spectral tables and the text fields.
fn print_columns_and_spectra(h: &Tm25Header) {
    let fl = &h.flags;
    let cols: Vec<&str> = [
        (fl.radiant, "radiant flux"),
        (fl.wavelength, "wavelength"),
        (fl.luminous, "luminous flux"),
        (fl.stokes, "Stokes (6)"),
        (fl.tristimulus, "tristimulus X Z"),
        (fl.spectrum_index, "spectrum index"),
    ]
    .iter()
    .filter(|c| c.0)
    .map(|c| c.1)
    .collect();
    println!(
        "columns            x y z kx ky kz, {}{}",
        cols.join(", "),
        if h.column_names.is_empty() {
            String::new()
        } else {
            format!(", additional: {}", h.column_names.join(", "))
        }
    );
    print!(
        "spectrum           {} ({})",
        h.spectral_id.code(),
        h.spectral_id.describe()
    );
    if h.spectral_id == SpectralId::Single {
        print!(": {} nm", h.single_wavelength_nm);
    }
    println!();
    for (i, t) in h.spectra.iter().enumerate() {
        let peak = t
            .iter()
            .copied()
            .fold((0.0f32, 0.0f32), |m, p| if p.1 > m.1 { p } else { m });
        println!(
            "spectral table {}   {} points, {} .. {} nm, peak at {} nm",
            i + 1,
            t.len(),
            t[0].0,
            t[t.len() - 1].0,
            peak.0
        );
    }
    for (k, t) in h.texts.iter().enumerate() {
        if !t.is_empty() {
            println!(
                "{:<19}{t}",
                format!("{}:", TEXT_FIELDS[k])
                    .chars()
                    .take(18)
                    .collect::<String>()
                    + " "
            );
        }
    }
}

/// Where the rays start and how their directions spread.
fn print_far_field(s: &FarFieldSummary) {
    println!(
        "start points (mm)  x {:.3} .. {:.3}, y {:.3} .. {:.3}, z {:.3} .. {:.3}",
        s.bounds.0[0], s.bounds.1[0], s.bounds.0[1], s.bounds.1[1], s.bounds.0[2], s.bounds.1[2]
    );
    println!(
        "far field          half intensity at γ ≈ {:.0}° from +z, {:.1} % of the flux forward (kz > 0)",
        s.half_intensity_deg,
        100.0 * s.forward_share
    );
    let rings: Vec<String> = s.rings.iter().map(|v| format!("{v:.2}")).collect();
    println!("relative intensity per 10° ring of γ: {}", rings.join(" "));
}

/// The light `name` of a scene: a listed light or an emissive object.
pub fn scene_light(
    path: &Path,
    name: &str,
    factory: &PluginFactory,
) -> Result<Arc<dyn Light>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let desc = crate::scene::parse_scene_str(&text, path).map_err(|e| e.to_string())?;
    let factories: [&dyn ObjectFactory; 1] = [factory];
    let scene = crate::scene::load_scene_file(path, &factories).map_err(|e| e.to_string())?;
    let lights = scene.lights.lights();
    let areas = lights.iter().filter(|l| l.object().is_some()).count();
    if let Some(i) = desc.lights.iter().position(|l| l.name == name) {
        return Ok(lights[areas + i].clone());
    }
    lights
        .iter()
        .find(|l| {
            l.object()
                .and_then(|o| scene.objects.get(o))
                .is_some_and(|o| o.name == name)
        })
        .cloned()
        .ok_or_else(|| {
            let names: Vec<&str> = desc.lights.iter().map(|l| l.name.as_str()).collect();
            format!(
                "{}: no light or emissive object named `{name}` (lights: {})",
                path.display(),
                names.join(", ")
            )
        })
}

fn export(a: &ExportArgs) -> Result<(), String> {
    let registry = Arc::new(a.plugins.registry(false)?);
    let factory = PluginFactory::new(registry, crate::plugin::adapter::PluginFaults::new());
    let light = scene_light(&a.scene, &a.light, &factory)?;
    let mut texts: [String; 9] = Default::default();
    texts[0] = format!("light `{}` of {}", a.light, a.scene.display());
    texts[3] = "spectrace".into();
    texts[4] = format!(
        "spectrace {} (Monte Carlo sampling of the light, seed {})",
        env!("CARGO_PKG_VERSION"),
        a.seed
    );
    texts[8] = "file frame = scene world frame, start points in mm".into();
    let file = std::fs::File::create(&a.output)
        .map_err(|e| format!("cannot write {}: {e}", a.output.display()))?;
    let mut out = std::io::BufWriter::with_capacity(1 << 20, file);
    let s = export_light(light.as_ref(), a.rays, a.seed, texts, &mut out)
        .map_err(|e| format!("{}: {e}", a.output.display()))?;
    println!("light              `{}` of {}", a.light, a.scene.display());
    println!(
        "rays               {} ({} empty draws written with flux 0)",
        s.rays, s.empty
    );
    println!(
        "flux               {:.6} W ({:+.3} % of the light's stated {:.6} W), {:.4} lm",
        s.flux_w,
        100.0 * (s.flux_w / s.stated_w - 1.0),
        s.stated_w,
        s.flux_lm
    );
    println!("spectrum           identifier {}", s.spectral_id);
    println!("wrote              {}", a.output.display());
    Ok(())
}
