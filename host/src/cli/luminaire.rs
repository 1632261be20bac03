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
//! LM-63-2019 or EULUMDAT; reading OUT gives the same candela table. FILE may also be a light
//! blob, and `--scene S --light NAME` exports a light of a scene: a `luminaire` light exports
//! its table (with `flux_lm` and `multiplier` applied, the tilt table kept); any other light is
//! measured first, as `bake` does.
//!
//! `spectrace luminaire bake SCENE --light NAME -o OUT.blob [--step DEG] [--samples N] [--point]`
//! measures a light of a scene like a goniophotometer (see [`crate::light::measure::goniometer`]):
//! its spectrum, a type C intensity table every `--step` degrees (default 2.5) and its size
//! (the box of the points it emits from), and writes a blob that renders without the light's
//! plugin: a `near_field_luminaire` emitting the table from that box (see
//! [`crate::light::near_field`]) when the box has a face of non-zero area, so that close to a
//! large panel the baked light lights as the panel does; a point `luminaire` when the light
//! emits from a point or a line, or with `--point`.
//! NAME is a light of the scene's `lights` or an object with an emissive material.

use super::plugin_args::PluginArgs;
use crate::builtin::light::luminaire::{exported_luminaire, LuminaireParams};
use crate::builtin::light::near_field::{self, NearFieldParams};
use crate::builtin::spectral::Spectrum;
use crate::light::measure::goniometer::{measure, GoniometerSettings, Measurement};
use crate::light::near_field::NearFieldLight;
use crate::light::Light;
use crate::photometry::eulumdat_writer::write_eulumdat;
use crate::photometry::ies_writer::write_ies_2019;
use crate::photometry::{load_luminaire, Luminaire, PhotometricType};
use crate::plugin::blob::{Blob, BUILTIN_PLUGIN};
use crate::plugin::factory::{Built, PluginFactory};
use crate::scene_file::{FactoryContext, ObjectFactory};
use spectrace_plugin_api::ObjectKind;
use std::path::{Path, PathBuf};
use std::sync::Arc;

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
    /// Write a luminaire file, a light blob or a light of a scene as IES LM-63-2019 or EULUMDAT.
    Export(ExportArgs),
    /// Measure a light of a scene (any kind, plugin lights included) and save it as a blob of
    /// a `near_field_luminaire` (or, for a point-like light or with --point, a `luminaire`):
    /// spectrum, goniometric table, luminous opening.
    Bake(BakeArgs),
}

/// How finely to measure a light.
#[derive(clap::Args, Debug, Clone)]
pub struct MeasureArgs {
    /// Angular step of the measured table, degrees (divides 180).
    #[arg(long, default_value_t = 2.5)]
    pub step: f64,
    /// Samples per direction (lights that can be evaluated; default 64) or beams in all
    /// (lights that only hand out beams; default 4000000).
    #[arg(long)]
    pub samples: Option<u64>,
}

/// Arguments of `spectrace luminaire bake`.
#[derive(clap::Args, Debug)]
pub struct BakeArgs {
    /// The scene file.
    pub scene: PathBuf,
    /// Name of the light (or emissive object) to measure.
    #[arg(long)]
    pub light: String,
    /// Output blob.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    /// Measurement resolution.
    pub measure: MeasureArgs,
    /// Write a point luminaire even when the light has a luminous opening (its far field only:
    /// close to a large emitter it lights as a point would).
    #[arg(long)]
    pub point: bool,
    #[command(flatten)]
    /// Plugins to load.
    pub plugins: PluginArgs,
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
    /// The luminaire to read (.ies or .ldt), or a light blob (.blob).
    #[arg(required_unless_present = "scene")]
    pub file: Option<PathBuf>,
    /// Export a light of this scene instead (with --light).
    #[arg(long, conflicts_with = "file", requires = "light")]
    pub scene: Option<PathBuf>,
    /// Name of the light (or emissive object) of --scene.
    #[arg(long, requires = "scene")]
    pub light: Option<String>,
    /// Output format.
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Output file.
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    /// Measurement resolution (lights that are not luminaires).
    pub measure: MeasureArgs,
    #[command(flatten)]
    /// Plugins to load.
    pub plugins: PluginArgs,
}

impl MeasureArgs {
    fn settings(&self, beams_only: bool) -> GoniometerSettings {
        GoniometerSettings {
            step_deg: self.step,
            samples: self
                .samples
                .unwrap_or(if beams_only { 4_000_000 } else { 64 }),
            seed: 1,
        }
    }
}

/// A light to export or bake: a `luminaire` light's parameters (its table is exported as is),
/// or any light (measured).
enum Source {
    Luminaire(Box<LuminaireParams>, FactoryContext),
    Light(Arc<dyn Light>),
}

fn factory(plugins: &PluginArgs) -> Result<PluginFactory, String> {
    let registry = Arc::new(plugins.registry(false)?);
    Ok(PluginFactory::new(
        registry,
        crate::plugin::adapter::PluginFaults::new(),
    ))
}

/// The light `name` of the scene file `path`: a listed light or an emissive object.
/// With `export_table`, a `near_field_luminaire` gives its table as it is (for `export`); else
/// it is built and measured like any light (for `bake`, which keeps its opening).
fn scene_light(
    path: &Path,
    name: &str,
    factory: &PluginFactory,
    export_table: bool,
) -> Result<Source, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    let desc = crate::scene::parse_scene_str(&text, path).map_err(|e| e.to_string())?;
    let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    if let Some(item) = desc.lights.iter().find(|l| l.name == name) {
        if item.type_name == "luminaire" {
            let p: LuminaireParams = crate::builtin::from_value(&item.params)
                .map_err(|e| format!("{}: light `{name}`: {e}", path.display()))?;
            let ctx = factory.context(&base, format!("light `{name}`"));
            return Ok(Source::Luminaire(Box::new(p), ctx));
        }
        if item.type_name == near_field::TYPE.name && export_table {
            let p: NearFieldParams = crate::builtin::from_value(&item.params)
                .map_err(|e| format!("{}: light `{name}`: {e}", path.display()))?;
            let ctx = factory.context(&base, format!("light `{name}`"));
            return Ok(Source::Luminaire(Box::new(point_params(&p)), ctx));
        }
    }
    let factories: [&dyn ObjectFactory; 1] = [factory];
    let scene = crate::scene::load_scene_file(path, &factories).map_err(|e| e.to_string())?;
    let lights = scene.lights.lights();
    let areas = lights.iter().filter(|l| l.object().is_some()).count();
    if let Some(i) = desc.lights.iter().position(|l| l.name == name) {
        return Ok(Source::Light(lights[areas + i].clone()));
    }
    let emissive = lights.iter().find(|l| {
        l.object()
            .and_then(|o| scene.objects.get(o))
            .is_some_and(|o| o.name == name)
    });
    match emissive {
        Some(l) => Ok(Source::Light(l.clone())),
        None => {
            let mut names: Vec<String> = desc.lights.iter().map(|l| l.name.clone()).collect();
            names.extend(
                lights
                    .iter()
                    .filter_map(|l| l.object().and_then(|o| scene.objects.get(o)))
                    .map(|o| o.name.clone()),
            );
            Err(format!(
                "{}: no light or emissive object named `{name}` (lights: {})",
                path.display(),
                names.join(", ")
            ))
        }
    }
}

/// The point luminaire of a near-field luminaire's parameters (the same table, frame and
/// factors; the opening dropped): what `export` writes of it.
fn point_params(p: &NearFieldParams) -> LuminaireParams {
    LuminaireParams {
        file: p.file.clone(),
        table: p.table.clone(),
        position: p.position,
        aim: p.aim,
        c0: p.c0,
        spd: p.spd.clone(),
        flux_lm: p.flux_lm,
        multiplier: p.multiplier,
        tilt_deg: p.tilt_deg,
    }
}

/// The light a blob holds.
fn blob_light(path: &Path, factory: &PluginFactory) -> Result<Source, String> {
    let blob = Blob::read_file(path).map_err(|e| e.to_string())?;
    if blob.kind != ObjectKind::Light {
        return Err(format!(
            "{}: holds a {}, not a light",
            path.display(),
            blob.kind
        ));
    }
    if blob.plugin == BUILTIN_PLUGIN && blob.type_name == "luminaire" {
        let (p, _): (LuminaireParams, usize) =
            bincode::serde::decode_from_slice(&blob.payload, bincode::config::standard())
                .map_err(|e| format!("{}: bad luminaire state: {e}", path.display()))?;
        let ctx = factory.context(Path::new("."), format!("blob {}", path.display()));
        return Ok(Source::Luminaire(Box::new(p), ctx));
    }
    if blob.plugin == BUILTIN_PLUGIN && blob.type_name == near_field::TYPE.name {
        let (p, _): (NearFieldParams, usize) =
            bincode::serde::decode_from_slice(&blob.payload, bincode::config::standard())
                .map_err(|e| format!("{}: bad near-field luminaire state: {e}", path.display()))?;
        let ctx = factory.context(Path::new("."), format!("blob {}", path.display()));
        return Ok(Source::Luminaire(Box::new(point_params(&p)), ctx));
    }
    match blob
        .instantiate(factory)
        .map_err(|e| format!("{}: {e}", path.display()))?
    {
        Built::Light(l) => Ok(Source::Light(l)),
        _ => Err(format!("{}: not a light", path.display())),
    }
}

fn measured(light: &dyn Light, m: &MeasureArgs) -> Result<Measurement, String> {
    let beams = light.flags().contains(crate::light::LightFlags::BEAMS_ONLY);
    measure(light, &m.settings(beams))
}

/// Run `spectrace luminaire export`.
pub fn export(args: &ExportArgs) -> Result<(), String> {
    let (lum, source, what) = match (&args.file, &args.scene, &args.light) {
        (Some(file), _, _) if file.extension().is_some_and(|e| e == "blob") => {
            let f = factory(&args.plugins)?;
            let src = blob_light(file, &f)?;
            let name = file.display().to_string();
            let lum = source_luminaire(src, &args.measure, &name)?;
            (lum, name.clone(), name)
        }
        (Some(file), _, _) => {
            let lum = load_luminaire(file).map_err(|e| e.to_string())?;
            let source = file.file_name().map_or_else(
                || file.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            (lum, source, file.display().to_string())
        }
        (None, Some(scene), Some(light)) => {
            let f = factory(&args.plugins)?;
            let src = scene_light(scene, light, &f, true)?;
            let name = format!("light `{light}` of {}", scene.display());
            let lum = source_luminaire(src, &args.measure, &name)?;
            (lum, name.clone(), name)
        }
        _ => return Err("luminaire export: give a FILE, or --scene and --light".into()),
    };
    let text = match args.format {
        ExportFormat::Ies => write_ies_2019(&lum, &source),
        ExportFormat::Ldt => write_eulumdat(&lum, &source)
            .map_err(|e| format!("{what}: cannot write EULUMDAT: {e}"))?,
    };
    std::fs::write(&args.output, text)
        .map_err(|e| format!("cannot write {}: {e}", args.output.display()))?;
    if lum.tilt.is_some() && args.format == ExportFormat::Ldt {
        eprintln!(
            "warning: {what}: EULUMDAT has no lamp tilt table; the tilt data was not written"
        );
    }
    Ok(())
}

/// The table of a light: a luminaire's own, any other light's measured.
fn source_luminaire(src: Source, m: &MeasureArgs, name: &str) -> Result<Luminaire, String> {
    match src {
        Source::Luminaire(p, ctx) => {
            exported_luminaire(&p, &ctx).map_err(|e| format!("{name}: {e}"))
        }
        Source::Light(l) => {
            let m = measured(l.as_ref(), m).map_err(|e| format!("{name}: {e}"))?;
            Ok(m.luminaire)
        }
    }
}

/// Run `spectrace luminaire bake`.
pub fn bake(args: &BakeArgs) -> Result<(), String> {
    let f = factory(&args.plugins)?;
    let name = format!("light `{}` of {}", args.light, args.scene.display());
    let light: Arc<dyn Light> = match scene_light(&args.scene, &args.light, &f, false)? {
        Source::Light(l) => l,
        Source::Luminaire(p, ctx) => Arc::new(
            crate::builtin::light::luminaire::build_luminaire(&p, &ctx)
                .map_err(|e| format!("{name}: {e}"))?,
        ),
    };
    let m = measured(light.as_ref(), &args.measure).map_err(|e| format!("{name}: {e}"))?;
    let source = format!(
        "baked from light `{}` of {}",
        args.light,
        args.scene.file_name().map_or_else(
            || args.scene.display().to_string(),
            |n| n.to_string_lossy().into_owned()
        )
    );
    let near = !args.point && NearFieldLight::has_opening(m.size);
    let blob = baked_blob(&m, &source, near)?;
    // The blob must load with the built-in types alone (no plugin).
    let builtins = PluginFactory::new(
        Arc::new(crate::plugin::builtin_registry()),
        crate::plugin::adapter::PluginFaults::new(),
    );
    let baked = match blob.instantiate(&builtins)? {
        Built::Light(l) => l,
        _ => return Err("the baked blob is not a light".into()),
    };
    blob.write_file(&args.output).map_err(|e| e.to_string())?;
    let k = crate::photometry::efficacy::luminous_efficacy_lm_per_w(baked.spd().as_ref());
    println!("baked             {name}");
    println!(
        "grid              type C, {}° steps ({} × {} angles)",
        args.measure.step,
        m.luminaire.h_deg.len(),
        m.luminaire.v_deg.len()
    );
    println!("stated power      {:.6} W", m.stated_power_w);
    println!(
        "measured flux     {:.6} W, {:.3} lm ({:+.3} % of the stated power)",
        m.flux_w,
        m.flux_lm,
        100.0 * (m.flux_w / m.stated_power_w - 1.0)
    );
    println!(
        "baked light       {:.6} W, {:.3} lm",
        baked.power(),
        baked.power() * k
    );
    println!(
        "emitter           centre ({:.4}, {:.4}, {:.4}) m, size {:.4} × {:.4} × {:.4} m (x, z, y)",
        m.centre[0], m.centre[1], m.centre[2], m.size[0], m.size[1], m.size[2]
    );
    if near {
        println!(
            "emits from        its opening: a near_field_luminaire of {:.4} × {:.4} × {:.4} m",
            m.size[0], m.size[1], m.size[2]
        );
    } else if args.point {
        println!("emits from        a point (--point): a luminaire");
    } else {
        println!(
            "emits from        a point: a luminaire (the emitter has no face of non-zero area)"
        );
    }
    println!("wrote             {}", args.output.display());
    Ok(())
}

/// The blob of a measured light: a `near_field_luminaire` emitting the table from the measured
/// box (`near`), else a point `luminaire`. Lengths in metres (the scene's unit is converted when
/// the scene is built), the frame the world's (the goniometer measures in it).
fn baked_blob(m: &Measurement, source: &str, near: bool) -> Result<Blob, String> {
    let table = Some(m.table(source));
    let spd = Some(Spectrum::Pairs(m.spectrum.clone()));
    let encode = |r: Result<Vec<u8>, bincode::error::EncodeError>| {
        r.map_err(|e| format!("cannot encode the baked light: {e}"))
    };
    let (ty, payload) = if near {
        let p = NearFieldParams {
            file: None,
            table,
            position: m.centre,
            aim: None,
            c0: None,
            spd,
            flux_lm: None,
            multiplier: None,
            tilt_deg: None,
            size_m: Some(m.size),
        };
        let bytes = bincode::serde::encode_to_vec(&p, bincode::config::standard());
        (near_field::TYPE, encode(bytes)?)
    } else {
        let p = LuminaireParams {
            file: None,
            table,
            position: m.centre,
            aim: None,
            c0: None,
            spd,
            flux_lm: None,
            multiplier: None,
            tilt_deg: None,
        };
        let bytes = bincode::serde::encode_to_vec(&p, bincode::config::standard());
        (crate::builtin::light::luminaire::TYPE, encode(bytes)?)
    };
    Ok(Blob {
        kind: ObjectKind::Light,
        plugin: BUILTIN_PLUGIN.to_string(),
        plugin_version: env!("CARGO_PKG_VERSION").to_string(),
        type_name: ty.name.to_string(),
        type_version: ty.version,
        payload,
    })
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
    match &args.command {
        Some(LuminaireCommand::Export(e)) => return export(e),
        Some(LuminaireCommand::Bake(b)) => return bake(b),
        None => {}
    }
    let Some(path) = &args.file else {
        return Err("luminaire: give a file (.ies or .ldt), or `luminaire export`".into());
    };
    if path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gldf"))
    {
        return super::gldf::info(path, args.json);
    }
    let lum = load_luminaire(path).map_err(|e| e.to_string())?;
    let file = path.display().to_string();
    warn_about(&lum, &file);
    if args.json {
        println!("{}", report_json(&lum, &file, &args.at));
        return Ok(());
    }
    print_report(&lum, &file, &args.at);
    Ok(())
}

/// Warnings a reader of `file` should see: the reader's own, a table of zeros, a luminaire
/// giving more than its lamps' flux.
fn warn_about(lum: &Luminaire, file: &str) {
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
}

/// The luminaire's summary as text; `at`: extra (h, v) directions, degrees.
fn print_report(lum: &Luminaire, file: &str, at: &[(f64, f64)]) {
    let flux = lum.flux_lm();
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
    for &(h, v) in at {
        println!("cd at h={h} v={v}  {:.3}", lum.candela_at(h, v));
    }
}
