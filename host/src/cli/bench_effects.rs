//! `spectrace bench effects [--scenes a,b,…] [--integrators pt,bdpt] [--spp N] [--seeds K]
//! [--threads N] [--dir DIR] [--out FILE.md]`: what each effect costs. Every bundled scene is
//! rendered with `--effects auto` and `--effects all`, and with each switchable effect the scene
//! calls for forced off; each run is K seeds of N spp. Prints (and writes to FILE.md) one row per
//! run: the time per camera sample (µs; light paths for lt), its ratio to `auto`, the image-mean
//! Y with its standard error (from the seed spread) and the difference to `auto` in those
//! standard errors. `all` must agree with `auto` within noise (it only adds machinery for
//! absent effects); an effect switched off changes the image where the scene has it, and the
//! time column says what it cost.
//!
//! | option          | default                                                       | meaning                          |
//! |-----------------|---------------------------------------------------------------|----------------------------------|
//! | `--scenes`      | cornell,caustic,materials,spot_mirror,prism,thin_film,laser,line_lamps | bundled scenes (`cornell` is the embedded box) |
//! | `--integrators` | pt,bdpt                                                       | integrators run on each          |
//! | `--spp`         | 4                                                             | samples per pixel per seed       |
//! | `--seeds`       | 3                                                             | seeds per run (standard errors)  |
//! | `--dir`         | `scenes`                                                      | where the scene files are        |
//!
//! Timing is wall clock of the sampling loop on a possibly shared machine: compare ratios
//! within one run of the command, not across machines.

use crate::cli::render::{default_settings, load_scene};
use crate::integrator::select::render_planned;
use crate::integrator::{EffectsMode, EffectsRequest, RenderPlan, Switch};
use crate::integrator::{IntegratorKind, SampleBudget};
use crate::scene::{BuiltinFactory, Scene};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Arguments of `spectrace bench effects`.
#[derive(clap::Args, Debug, Clone)]
pub struct EffectsBenchArgs {
    /// Comma-separated bundled scenes (file stems in --dir; `cornell` is the embedded box).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "cornell,caustic,materials,spot_mirror,prism,thin_film,laser,line_lamps,fluorescence,sun_and_sky,luminaire,sensors_downlight"
    )]
    pub scenes: Vec<String>,
    /// Comma-separated integrators.
    #[arg(long, value_delimiter = ',', default_value = "pt,bdpt")]
    pub integrators: Vec<IntegratorKind>,
    /// Samples per pixel of each seed's render.
    #[arg(long, default_value_t = 4, value_parser = crate::limits::parse_spp)]
    pub spp: u32,
    /// Seeds per run (at least 2: the standard errors come from their spread).
    #[arg(long, default_value_t = 3)]
    pub seeds: u32,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = crate::limits::parse_threads)]
    pub threads: Option<usize>,
    /// Directory of the scene files.
    #[arg(long, default_value = "scenes")]
    pub dir: PathBuf,
    /// Also write the table (Markdown) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// One run: a scene, an integrator, an effects request, K seeds.
struct Run {
    label: String,
    us_per_sample: f64,
    mean_y: f64,
    se_y: f64,
}

fn load(name: &str, dir: &std::path::Path) -> Result<Scene, String> {
    if name == "cornell" {
        return crate::scene::default_scene().map_err(|e| e.to_string());
    }
    let path = dir.join(format!("{name}.ron"));
    load_scene(
        Some(&path),
        None,
        &[],
        &Default::default(),
        &[&BuiltinFactory],
    )
    .map_err(|e| format!("{}: {e}", path.display()))
}

fn run(
    scene: &Scene,
    request: &EffectsRequest,
    kind: IntegratorKind,
    args: &EffectsBenchArgs,
    label: String,
) -> Result<Run, String> {
    let plan = RenderPlan::new(scene, request);
    let (mut secs, mut samples) = (0.0f64, 0u64);
    let mut ys = Vec::new();
    for seed in 1..=args.seeds.max(2) as u64 {
        let budget = SampleBudget::Spp(args.spp);
        let settings = default_settings(budget, seed, args.threads, scene.options.max_depth);
        let out = render_planned(scene, &plan, &settings, kind, false, &|_, _| {}, None)
            .map_err(|e| e.to_string())?;
        secs += out.result.elapsed.as_secs_f64();
        samples += out.result.samples;
        ys.push(out.result.image.mean_xyz()[1]);
    }
    let k = ys.len() as f64;
    let mean = ys.iter().sum::<f64>() / k;
    let var = ys.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (k - 1.0);
    Ok(Run {
        label,
        us_per_sample: 1e6 * secs / samples.max(1) as f64,
        mean_y: mean,
        se_y: (var / k).sqrt(),
    })
}

/// Run `spectrace bench effects`.
pub fn run_bench(args: &EffectsBenchArgs) -> Result<(), String> {
    let mut table = String::from(
        "| scene | integrator | effects | µs/sample | time / auto | mean Y ± se | Δ vs auto (se) |\n\
         |---|---|---|---|---|---|---|\n",
    );
    println!(
        "effects bench: {} spp × {} seeds per run",
        args.spp,
        args.seeds.max(2)
    );
    for name in &args.scenes {
        let scene = load(name, &args.dir)?;
        let found = switchable_effects(&RenderPlan::auto(&scene));
        for &kind in &args.integrators {
            let mut auto: Option<Run> = None;
            for (label, req) in requests(&found) {
                let r = run(&scene, &req, kind, args, label)?;
                let row = table_row(name, kind, &r, auto.as_ref());
                print!("{row}");
                table.push_str(&row);
                if auto.is_none() {
                    auto = Some(r);
                }
            }
        }
    }
    if let Some(path) = &args.out {
        write_table(args, path, &table)?;
    }
    Ok(())
}

/// The switchable effects the scene calls for (each is also run forced off).
fn switchable_effects(auto_plan: &RenderPlan) -> Vec<Switch> {
    Switch::ALL
        .into_iter()
        .filter(|s| match s {
            Switch::Dispersion => auto_plan.dispersion(),
            Switch::Fluorescence => auto_plan.fluorescence(),
            Switch::ThinFilm => auto_plan.thin_film(),
            Switch::NarrowbandEmission => auto_plan.emission_wavelengths(),
            Switch::FlatPathColour => auto_plan.flat_path_colour(),
            Switch::Manifold => auto_plan.manifold(),
            Switch::CameraChain => auto_plan.camera_chain(),
            Switch::VisibilityGuide => auto_plan.visibility_guide() != Some(false),
        })
        .collect()
}

/// The runs of one scene and integrator: auto first (the baseline), all, then auto with each
/// found effect forced off.
fn requests(found: &[Switch]) -> Vec<(String, EffectsRequest)> {
    let mut requests = vec![
        ("auto".to_string(), EffectsRequest::default()),
        (
            "all".to_string(),
            EffectsRequest {
                mode: EffectsMode::All,
                forced: Vec::new(),
                ..Default::default()
            },
        ),
    ];
    for s in found {
        requests.push((
            format!("auto, {}=off", s.name()),
            EffectsRequest {
                mode: EffectsMode::Auto,
                forced: vec![(*s, false)],
                ..Default::default()
            },
        ));
    }
    requests
}

/// One table row: the run's cost and mean against the `auto` run (`None`: this is it).
fn table_row(name: &str, kind: IntegratorKind, r: &Run, auto: Option<&Run>) -> String {
    let base = auto.unwrap_or(r);
    let ratio = r.us_per_sample / base.us_per_sample;
    let se = (r.se_y.powi(2) + base.se_y.powi(2)).sqrt();
    let delta = if auto.is_none() {
        "—".to_string()
    } else if se > 0.0 {
        format!("{:+.1}", (r.mean_y - base.mean_y) / se)
    } else if r.mean_y == base.mean_y {
        "0 (identical)".to_string()
    } else {
        "≠ (no noise)".to_string()
    };
    format!(
        "| {name} | {kind} | {} | {:.2} | {ratio:.2} | {:.5} ± {:.5} | {delta} |\n",
        r.label, r.us_per_sample, r.mean_y, r.se_y
    )
}

/// `--out`: the table with the command that made it.
fn write_table(args: &EffectsBenchArgs, path: &Path, table: &str) -> Result<(), String> {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "<!-- spectrace bench effects --spp {} --seeds {} --integrators {} -->",
        args.spp,
        args.seeds.max(2),
        args.integrators
            .iter()
            .map(|k| k.name())
            .collect::<Vec<_>>()
            .join(",")
    );
    text.push_str(table);
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}
