//! `spectrace bench speed`: spectrace against the anchors (Mitsuba 3, LuxCore) on the scene
//! suite in scenes/bench/, fair by construction (docs/performance.md):
//!
//! - every scene is written once, as a spectrace scene, and exported to the anchors
//!   (`spectrace bench export`, [`crate::analysis::bench_scene`]): the same triangles, spectra
//!   and camera everywhere;
//! - every anchor runs in each of its documented configurations (Mitsuba 3's four samplers,
//!   LuxCore's BIDIRCPU with three samplers and BIDIRVMCPU, each with Russian roulette at its
//!   default and off; `scripts/anchors/anchor_render.py configs`), and spectrace is compared
//!   with the best of them;
//! - the reference is a long Mitsuba 3 render in two independent halves, never a spectrace
//!   render; its own noise (from the halves) is reported and allowed for in the fit;
//! - one timer for all: sampling start to image in memory; scene loading, BVH and JIT are
//!   reported beside it;
//! - a non-finite pixel is an error;
//! - each renderer renders at three or more budgets; MSE = a/t + b is fitted
//!   ([`crate::analysis::bench_fit`]): `a` is its inverse efficiency, `b` a floor; a renderer
//!   with a significant floor is reported as biased, not ranked;
//! - the error is split into regions (lamp images, caustic core, rest) and fitted per region;
//! - the CPU model and vector extensions head the output.
//!
//! Writes DIR/speed.md (the tables) and DIR/points.csv (every render). Paths default to the
//! repository layout: run it from the repository root.

use crate::analysis::bench_fit::{
    cpu_description, fit_inverse_time, mean_check, reference_variance, view_masks, Fit,
    ReferenceHalves, RegionSplit, Regions, MEAN_Z_LIMIT, REGION_NAMES,
};
use crate::analysis::bench_scene::export_scene;
use crate::analysis::RgbImage;
use crate::cli::render::{default_settings, load_scene};
use crate::integrator::{render_with, IntegratorKind, SampleBudget};
use crate::scene::{BuiltinFactory, Scene};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The suite: name and scene file (relative to the repository root).
pub const SUITE: [(&str, &str); 6] = [
    ("cornell", "scenes/cornell_box.ron"),
    ("glass_sphere", "scenes/bench/glass_sphere.ron"),
    ("glass_sphere_mesh", "scenes/bench/glass_sphere_mesh.ron"),
    ("spectral_caustic", "scenes/bench/spectral_caustic.ron"),
    ("glossy_metals", "scenes/bench/glossy_metals.ron"),
    ("window_room", "scenes/bench/window_room.ron"),
];

/// Every anchor configuration (as `anchor_render.py configs` lists them).
pub const ANCHOR_CONFIGS: [&str; 16] = [
    "mitsuba-independent",
    "mitsuba-independent-rroff",
    "mitsuba-multijitter",
    "mitsuba-multijitter-rroff",
    "mitsuba-orthogonal",
    "mitsuba-orthogonal-rroff",
    "mitsuba-ldsampler",
    "mitsuba-ldsampler-rroff",
    "luxcore-bidir-sobol",
    "luxcore-bidir-sobol-rroff",
    "luxcore-bidir-random",
    "luxcore-bidir-random-rroff",
    "luxcore-bidir-metropolis",
    "luxcore-bidir-metropolis-rroff",
    "luxcore-bidirvm",
    "luxcore-bidirvm-rroff",
];

/// Arguments of `spectrace bench speed`.
#[derive(clap::Args, Debug, Clone)]
pub struct SpeedArgs {
    /// Quick mode, for checking that everything runs: budgets 0.25, 0.5 and 1 s, one seed, a
    /// 256-spp reference (noisy: its noise is reported and allowed for, but the ratios are not
    /// figures to quote). Explicit --budgets/--seeds/--reference-spp win.
    #[arg(long)]
    pub quick: bool,
    /// Comma-separated sampling budgets per render, seconds (at least three). Default 4,8,16.
    #[arg(long, value_delimiter = ',')]
    pub budgets: Option<Vec<f64>>,
    /// Independent runs (seeds) per renderer, budget and scene. Default 2.
    #[arg(long)]
    pub seeds: Option<u32>,
    /// Worker threads of every renderer.
    #[arg(long, default_value_t = 2)]
    pub threads: usize,
    /// Comma-separated suite scene names (see `--list`) or scene files. Default: the suite.
    #[arg(long, value_delimiter = ',')]
    pub scenes: Option<Vec<String>>,
    /// Comma-separated spectrace integrators: bdpt, pt, lt.
    #[arg(long, value_delimiter = ',', default_value = "bdpt,pt,lt")]
    pub integrators: Vec<String>,
    /// Comma-separated anchor configurations (default: all; see `--list`).
    #[arg(long, value_delimiter = ',')]
    pub configs: Option<Vec<String>>,
    /// Python interpreter with mitsuba, pyluxcore, numpy and openexr; default
    /// $SPECTRACE_ANCHOR_PYTHON, else python3.
    #[arg(long)]
    pub python: Option<PathBuf>,
    /// The anchor script.
    #[arg(long, default_value = "scripts/anchors/anchor_render.py")]
    pub anchor_script: PathBuf,
    /// Render spectrace only (against existing references).
    #[arg(long)]
    pub no_anchors: bool,
    /// Directory of references: NAME.exr and its independent parts NAME_part1.exr, … (or
    /// NAME_half1.exr, NAME_half2.exr) (Mitsuba 3). Missing ones are rendered into
    /// OUT/references with --reference-spp.
    #[arg(long, default_value = "scenes/bench/references")]
    pub references: PathBuf,
    /// Samples per pixel of a reference rendered here (all its parts together). Default 16384;
    /// 256 with --quick.
    #[arg(long)]
    pub reference_spp: Option<u32>,
    /// Output directory.
    #[arg(long, default_value = "speed-out")]
    pub out: PathBuf,
    /// First seed; run k uses seed + k, for every renderer.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// List the suite and the anchor configurations and exit.
    #[arg(long)]
    pub list: bool,
}

impl SpeedArgs {
    fn budgets(&self) -> Vec<f64> {
        self.budgets.clone().unwrap_or_else(|| {
            if self.quick {
                vec![0.25, 0.5, 1.0]
            } else {
                vec![4.0, 8.0, 16.0]
            }
        })
    }
    fn seeds(&self) -> u32 {
        self.seeds.unwrap_or(if self.quick { 1 } else { 2 })
    }
    fn reference_spp(&self) -> u32 {
        self.reference_spp
            .unwrap_or(if self.quick { 256 } else { 16384 })
    }
    fn python(&self) -> PathBuf {
        self.python.clone().unwrap_or_else(|| {
            std::env::var_os("SPECTRACE_ANCHOR_PYTHON")
                .map_or_else(|| "python3".into(), PathBuf::from)
        })
    }
}

/// One render at one budget.
#[derive(Clone, Debug)]
struct Point {
    scene: String,
    config: String,
    renderer: String,
    anchor: bool,
    seed: u64,
    budget: f64,
    /// Samples per pixel (fractional for LuxCore's short runs: samples over pixels).
    spp: f64,
    seconds: f64,
    load_seconds: f64,
    jit_seconds: f64,
    split: RegionSplit,
}

/// The reference of one scene and what is known of its noise.
struct Reference {
    /// Mean of every part: the whole image's reference.
    image: RgbImage,
    /// Mean of the even-numbered parts: each region's reference (`ReferenceHalves`).
    compared: RgbImage,
    spp: String,
    /// Variance of the reference per value: whole image (all parts) and per region (the
    /// even-numbered parts).
    var_total: f64,
    var_region: [f64; 3],
}

/// What one `bench speed` run renders: the budgets, spectrace's integrators, the anchor
/// configurations and the scenes, checked.
struct SpeedPlan {
    budgets: Vec<f64>,
    kinds: Vec<(IntegratorKind, &'static str)>,
    configs: Vec<String>,
    scenes: Vec<(String, PathBuf)>,
}

/// One scene made ready: loaded, exported to the anchors, its reference and regions.
struct SceneSetup {
    name: String,
    scene: Scene,
    load_seconds: f64,
    exported: PathBuf,
    regions: Regions,
    reference: Reference,
}

/// Run `spectrace bench speed`.
pub fn run_speed(args: &SpeedArgs) -> Result<(), String> {
    if args.list {
        print_list();
        return Ok(());
    }
    let plan = speed_plan(args)?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let cpu = cpu_description();
    println!("CPU: {cpu}");
    let calibration = match film_factor(args) {
        Ok(f) => format!(
            "Mitsuba 3's film checked: an equal-energy emitter renders at {:.5} / {:.5} / {:.5} \
             (R, G, B) of the CIE integral of its spectrum (`anchor_render.py colour-factor`; \
             within {FILM_TOLERANCE} of 1). Every anchor image and reference is in the colour \
             convention of `scripts/anchors/observer.py`, spectrace's own.",
            f[0], f[1], f[2]
        ),
        Err(FilmCheck::Off(why)) => return Err(why),
        Err(FilmCheck::NotRun(why)) => format!(
            "Mitsuba 3's film not checked ({why}); the references' headers say their colour \
             convention."
        ),
    };
    println!("{calibration}");
    let started = Instant::now();
    let mut points: Vec<Point> = Vec::new();
    let mut notes: Vec<String> = Vec::new();
    let mut references = Vec::new();
    // Every reference found is checked before anything renders: one refused later would end
    // the run after the earlier scenes' renders.
    for (name, path) in &plan.scenes {
        let found = args.references.join(format!("{name}.exr"));
        if path.exists() && found.exists() {
            check_reference_colour(&found)?;
        }
    }
    for (name, path) in &plan.scenes {
        if !path.exists() {
            let note = format!("{name}: {} not found, skipped", path.display());
            println!("{note}");
            notes.push(note);
            continue;
        }
        let setup = set_up_scene(args, name, path)?;
        let mut failed: Vec<String> = Vec::new();
        for k in 0..u64::from(args.seeds()) {
            let seed = args.seed + k;
            points.extend(own_points(args, &plan, &setup, seed)?);
            if !args.no_anchors {
                let found = anchor_points(args, &plan, &setup, seed, &mut failed, &mut notes)?;
                points.extend(found);
            }
        }
        let pixels = setup.regions.pixels();
        references.push((setup.name, setup.reference, pixels));
    }
    let elapsed = started.elapsed().as_secs_f64();
    let estimate = full_run_estimate(&points, args, elapsed, plan.scenes.len());
    let md = report(
        &points,
        &references,
        args,
        (&cpu, &calibration),
        &notes,
        &estimate,
    );
    println!("\n{md}");
    write_results(args, &md, &points)
}

/// `--list`: the suite's scenes and the anchor configurations.
fn print_list() {
    println!("scenes:");
    for (n, p) in SUITE {
        println!("  {n:18} {p}");
    }
    println!("anchor configurations:\n  {}", ANCHOR_CONFIGS.join("\n  "));
}

/// The run's plan from the arguments, each list checked.
fn speed_plan(args: &SpeedArgs) -> Result<SpeedPlan, String> {
    let budgets = args.budgets();
    if budgets.len() < 3 || budgets.iter().any(|b| !(b.is_finite() && *b > 0.0)) {
        return Err(format!(
            "--budgets needs three or more positive numbers of seconds (the fit MSE = a/t + b has \
             two parameters), got {budgets:?}"
        ));
    }
    if args.threads == 0 {
        return Err("--threads must be at least 1".into());
    }
    if args.seeds() == 0 {
        return Err("--seeds must be at least 1".into());
    }
    Ok(SpeedPlan {
        budgets,
        kinds: integrator_kinds(&args.integrators)?,
        configs: anchor_configs(args.configs.as_deref())?,
        scenes: suite_scenes(args.scenes.as_deref())?,
    })
}

/// `--integrators`: spectrace's integrators and their labels.
fn integrator_kinds(names: &[String]) -> Result<Vec<(IntegratorKind, &'static str)>, String> {
    names
        .iter()
        .map(|name| match name.as_str() {
            "pt" => Ok((IntegratorKind::Pt, "spectrace-pt")),
            "bdpt" => Ok((IntegratorKind::Bdpt, "spectrace-bdpt")),
            "lt" => Ok((IntegratorKind::Lt, "spectrace-lt")),
            other => Err(format!(
                "unknown integrator '{other}' in --integrators (known: bdpt, pt, lt)"
            )),
        })
        .collect()
}

/// `--configs`: the anchor configurations (all by default).
fn anchor_configs(given: Option<&[String]>) -> Result<Vec<String>, String> {
    match given {
        Some(c) => {
            for name in c {
                if !ANCHOR_CONFIGS.contains(&name.as_str()) {
                    return Err(format!(
                        "unknown anchor configuration '{name}' in --configs (see --list)"
                    ));
                }
            }
            Ok(c.to_vec())
        }
        None => Ok(ANCHOR_CONFIGS.iter().map(|s| s.to_string()).collect()),
    }
}

/// `--scenes`: suite names or .ron files (the whole suite by default).
fn suite_scenes(given: Option<&[String]>) -> Result<Vec<(String, PathBuf)>, String> {
    let Some(list) = given else {
        return Ok(SUITE
            .iter()
            .map(|(n, p)| (n.to_string(), PathBuf::from(p)))
            .collect());
    };
    list.iter()
        .map(|s| match SUITE.iter().find(|(n, _)| n == s) {
            Some((n, p)) => Ok((n.to_string(), PathBuf::from(p))),
            None if s.ends_with(".ron") => Ok((
                Path::new(s)
                    .file_stem()
                    .map_or("scene".into(), |x| x.to_string_lossy().to_string()),
                PathBuf::from(s),
            )),
            None => Err(format!(
                "unknown scene '{s}' in --scenes (a suite name, see --list, or a .ron file)"
            )),
        })
        .collect()
}

/// Export the scene to the anchors, load it (the render pipeline's scene step, timed), and
/// find its reference and regions; prints the reference's noise and the regions' sizes.
fn set_up_scene(args: &SpeedArgs, name: &str, path: &Path) -> Result<SceneSetup, String> {
    let export_dir = args.out.join("scenes").join(name);
    let exported = export_scene(path, &export_dir)?;
    let t0 = Instant::now();
    let scene = load_scene(
        Some(path),
        None,
        &[],
        &Default::default(),
        &[&BuiltinFactory],
    )
    .map_err(|e| format!("{name}: {e}"))?;
    let load_seconds = t0.elapsed().as_secs_f64();
    let (emitter, shiny, _, _) = view_masks(&scene)?;
    let (image, parts, spp) = reference(args, name, &exported.path)?;
    // The regions from the odd-numbered parts, each region compared with the even-numbered
    // ones (why: `ReferenceHalves`), the whole image with all of them.
    let halves = ReferenceHalves::new(&parts).map_err(|e| format!("{name}: {e}"))?;
    let regions = Regions::from_masks(&emitter, &shiny, &halves.regions_from)
        .map_err(|e| format!("{name}: {e}"))?;
    let counted = regions.counted();
    let var_total = reference_variance(&parts, &counted);
    let mut var_region = [0.0; 3];
    for (r, v) in var_region.iter_mut().enumerate() {
        let mask: Vec<bool> = regions.region.iter().map(|x| *x == Some(r)).collect();
        *v = reference_variance(&parts, &mask) * halves.compared_variance_factor;
    }
    println!(
        "{name}: reference {spp}, {} parts (RMSE of its own noise {:.5}; the regions drawn \
         from the odd-numbered parts, each compared with the even-numbered ones); regions: {}",
        parts.len(),
        var_total.sqrt(),
        REGION_NAMES
            .iter()
            .zip(regions.pixels())
            .map(|(n, p)| format!("{n} {p} px"))
            .collect::<Vec<_>>()
            .join(", ")
    );
    Ok(SceneSetup {
        name: name.to_string(),
        scene,
        load_seconds,
        exported: exported.path,
        regions,
        reference: Reference {
            image,
            compared: halves.compared,
            spp,
            var_total,
            var_region,
        },
    })
}

/// spectrace's renders of one scene with one seed: every integrator at every budget, each
/// written as an EXR, measured against the reference and printed.
fn own_points(
    args: &SpeedArgs,
    plan: &SpeedPlan,
    setup: &SceneSetup,
    seed: u64,
) -> Result<Vec<Point>, String> {
    let (name, scene) = (&setup.name, &setup.scene);
    let mut points = Vec::new();
    for &(kind, label) in &plan.kinds {
        for (i, &b) in plan.budgets.iter().enumerate() {
            let settings = default_settings(
                SampleBudget::Time(Duration::from_secs_f64(b)),
                seed * 1000 + i as u64,
                Some(args.threads),
                scene.options.max_depth,
            );
            let out = render_with(scene, &settings, kind, false, &|_, _| {}, None)
                .map_err(|e| format!("{name} {label}: {e}"))?;
            let img = RgbImage::from_xyz(&out.result.image, &scene.options.rgb_space);
            let file = args.out.join(format!("{name}_{label}_s{seed}_b{i}.exr"));
            crate::film::write_exr(&file, &out.result.image, &scene.options.rgb_space)
                .map_err(|e| format!("{}: {e}", file.display()))?;
            let split = setup
                .regions
                .split(&img, &setup.reference.compared, &setup.reference.image)
                .map_err(|e| format!("{name} {label} at {b} s: {e}"))?;
            let p = Point {
                scene: name.clone(),
                config: label.into(),
                renderer: format!("spectrace {}", env!("CARGO_PKG_VERSION")),
                anchor: false,
                seed,
                budget: b,
                spp: f64::from(out.result.spp),
                seconds: out.result.elapsed.as_secs_f64(),
                load_seconds: setup.load_seconds,
                jit_seconds: 0.0,
                split,
            };
            print_point(&p);
            points.push(p);
        }
    }
    Ok(points)
}

/// The anchors' renders of one scene with one seed, in every configuration not yet `failed`;
/// a configuration that fails is noted and not tried again for this scene.
fn anchor_points(
    args: &SpeedArgs,
    plan: &SpeedPlan,
    setup: &SceneSetup,
    seed: u64,
    failed: &mut Vec<String>,
    notes: &mut Vec<String>,
) -> Result<Vec<Point>, String> {
    let name = &setup.name;
    let mut points = Vec::new();
    for config in &plan.configs {
        if failed.contains(config) {
            continue;
        }
        let lines = match run_anchor(args, &setup.exported, config, &plan.budgets, seed, name) {
            Ok(lines) => lines,
            Err(why) => {
                let note = format!("{name}: {config} skipped: {why}");
                println!("{note}");
                notes.push(note);
                failed.push(config.clone());
                continue;
            }
        };
        for (renderer, file, budget, spp, secs, load, jit) in lines {
            let img = RgbImage::read_exr(&file).map_err(|e| e.to_string())?;
            let split = setup
                .regions
                .split(&img, &setup.reference.compared, &setup.reference.image)
                .map_err(|e| format!("{name} {config} at {budget} s: {e}"))?;
            let p = Point {
                scene: name.clone(),
                config: config.clone(),
                renderer,
                anchor: true,
                seed,
                budget,
                spp,
                seconds: secs,
                load_seconds: load,
                jit_seconds: jit,
                split,
            };
            print_point(&p);
            points.push(p);
        }
    }
    Ok(points)
}

/// DIR/speed.md and DIR/points.csv.
fn write_results(args: &SpeedArgs, md: &str, points: &[Point]) -> Result<(), String> {
    let path = args.out.join("speed.md");
    std::fs::write(&path, md).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let csv_path = args.out.join("points.csv");
    std::fs::write(&csv_path, points_csv(points))
        .map_err(|e| format!("cannot write {}: {e}", csv_path.display()))?;
    println!("wrote {} and {}", path.display(), csv_path.display());
    Ok(())
}

/// The scene's reference (mean, its independent parts, description): from --references, else
/// rendered with Mitsuba 3 into OUT/references. The parts are NAME_part1.exr, NAME_part2.exr, …
/// (or, from older runs, NAME_half1.exr and NAME_half2.exr).
fn reference(
    args: &SpeedArgs,
    name: &str,
    scene_json: &Path,
) -> Result<(RgbImage, Vec<RgbImage>, String), String> {
    let read = |dir: &Path| -> Option<Result<(RgbImage, Vec<RgbImage>), String>> {
        let path = |s: &str| dir.join(format!("{name}{s}.exr"));
        let f = |s: &str| RgbImage::read_exr(&path(s)).ok();
        let mean = f("")?;
        let mut parts: Vec<RgbImage> = (1..).map_while(|k| f(&format!("_part{k}"))).collect();
        if parts.len() < 2 {
            parts = vec![f("_half1")?, f("_half2")?];
        }
        Some(check_reference_colour(&path("")).map(|()| (mean, parts)))
    };
    if let Some(found) = read(&args.references) {
        let (a, parts) = found?;
        let desc = format!(
            "from {}",
            args.references.join(format!("{name}.exr")).display()
        );
        return Ok((a, parts, desc));
    }
    let dir = args.out.join("references");
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let spp = args.reference_spp();
    println!("{name}: rendering a {spp}-spp Mitsuba 3 reference in eight parts …");
    let prefix = dir.join(name);
    run_anchor_script(
        args,
        "reference",
        &[
            "--scene-json".as_ref(),
            scene_json.as_os_str(),
            "--spp".as_ref(),
            spp.to_string().as_ref(),
            "--out-prefix".as_ref(),
            prefix.as_os_str(),
        ],
    )
    .map_err(|f| {
        f.describe(|status, last| {
            format!(
                "{name}: no reference in {} and Mitsuba 3 could not render one ({status}): {}",
                args.references.display(),
                last.unwrap_or("")
            )
        })
    })?;
    let (a, parts) =
        read(&dir).ok_or_else(|| format!("{name}: the reference was not written"))??;
    Ok((
        a,
        parts,
        format!("Mitsuba 3 independent, {spp} spp, rendered here"),
    ))
}

/// The header attribute in which a reference states its colour convention, and the statement
/// the bench takes: `COLOUR_ATTRIBUTE` and `COLOUR` of `scripts/anchors/observer.py` (a test
/// checks that the two agree).
const REFERENCE_COLOUR_ATTRIBUTE: &str = "spectraceBenchColour";
const REFERENCE_COLOUR: &str =
    "CIE 1931 2-degree, 1 nm table, XYZ over the integral of y-bar, linear sRGB (D65)";

/// A reference is used only if its header states the bench's colour convention: one made
/// through Mitsuba's `hdrfilm` (its 5 nm colour-matching table and its own normalisation) is
/// 0.1% brighter everywhere and off by up to 0.4% more per channel under line spectra, which
/// the means test would blame on the renderers.
fn check_reference_colour(path: &Path) -> Result<(), String> {
    let stated = RgbImage::read_exr_text_attribute(path, REFERENCE_COLOUR_ATTRIBUTE)
        .map_err(|e| e.to_string())?;
    if stated.as_deref() == Some(REFERENCE_COLOUR) {
        return Ok(());
    }
    let says = match stated {
        Some(c) => format!("states the colour convention \"{c}\""),
        None => format!("does not state its colour convention ({REFERENCE_COLOUR_ATTRIBUTE})"),
    };
    Err(format!(
        "{}: its header {says}; the bench's is \"{REFERENCE_COLOUR}\" \
         (scripts/anchors/observer.py). A reference rendered through Mitsuba's hdrfilm differs by \
         0.1% or more; render it again with `anchor_render.py reference` (docs/performance.md)",
        path.display()
    ))
}

/// How far Mitsuba's film may convert an equal-energy emitter from the CIE integral, per
/// channel. The film records the integrals themselves (`scripts/anchors/observer.py`), so the
/// measurement (16 × 16,384 spp on 64 pixels) scatters by about 1e-4 from its wavelength
/// sampling; Mitsuba's `hdrfilm`, with its own normalisation, sits at 1.0009–1.0010.
const FILM_TOLERANCE: f64 = 5e-4;

/// Why Mitsuba's film was not accepted: the check could not run, or its factor is off.
enum FilmCheck {
    NotRun(String),
    Off(String),
}

/// Mitsuba 3's spectrum-to-RGB conversion over the CIE integral, per channel, from the anchor
/// script's `colour-factor` (an equal-energy emitter filling the view): within
/// [`FILM_TOLERANCE`] of 1, else the anchors' images are not in the bench's colour convention.
fn film_factor(args: &SpeedArgs) -> Result<[f64; 3], FilmCheck> {
    let out = run_anchor_script(args, "colour-factor", &[]).map_err(|f| {
        FilmCheck::NotRun(f.describe(|status, last| format!("{status}: {}", last.unwrap_or(""))))
    })?;
    let f =
        parse_colour_factor(&String::from_utf8_lossy(&out.stdout)).map_err(FilmCheck::NotRun)?;
    check_film_factor(f).map_err(FilmCheck::Off)
}

/// `f` if every channel is within [`FILM_TOLERANCE`] of 1.
fn check_film_factor(f: [f64; 3]) -> Result<[f64; 3], String> {
    if f.iter().all(|x| (x - 1.0).abs() <= FILM_TOLERANCE) {
        Ok(f)
    } else {
        Err(format!(
            "Mitsuba 3's film renders an equal-energy emitter at {:.5} / {:.5} / {:.5} of the CIE \
             integral, more than {FILM_TOLERANCE} from 1: its images would not be in the colour \
             convention of the references and of spectrace (scripts/anchors/observer.py)",
            f[0], f[1], f[2]
        ))
    }
}

/// How a run of the anchor script failed: it could not start (the message), or it exited with
/// a status, its stderr's last line (if any) saying why.
enum ScriptFailure {
    NotStarted(String),
    Exited(std::process::ExitStatus, Option<String>),
}

impl ScriptFailure {
    /// The message: a start failure as it is, an exit as `exited` words it for the caller.
    fn describe(
        self,
        exited: impl FnOnce(std::process::ExitStatus, Option<&str>) -> String,
    ) -> String {
        match self {
            Self::NotStarted(message) => message,
            Self::Exited(status, last) => exited(status, last.as_deref()),
        }
    }
}

/// Runs `python anchor_script COMMAND ARGS… --threads N` (every command of the script takes
/// the bench's thread count): its output when it exits successfully.
fn run_anchor_script(
    args: &SpeedArgs,
    command: &str,
    command_args: &[&std::ffi::OsStr],
) -> Result<std::process::Output, ScriptFailure> {
    let out = std::process::Command::new(args.python())
        .arg(&args.anchor_script)
        .arg(command)
        .args(command_args)
        .arg("--threads")
        .arg(args.threads.to_string())
        .output()
        .map_err(|e| {
            ScriptFailure::NotStarted(format!("cannot run {}: {e}", args.python().display()))
        })?;
    if out.status.success() {
        Ok(out)
    } else {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let last = stderr.lines().last().map(str::to_string);
        Err(ScriptFailure::Exited(out.status, last))
    }
}

/// The `factor` of the script's JSON line: three finite values.
fn parse_colour_factor(stdout: &str) -> Result<[f64; 3], String> {
    let line = stdout
        .lines()
        .rev()
        .find(|l| l.trim_start().starts_with('{'))
        .ok_or("the script printed no result line")?;
    let v: serde_json::Value =
        serde_json::from_str(line).map_err(|e| format!("its result line is not JSON: {e}"))?;
    let f = v["factor"]
        .as_array()
        .filter(|a| a.len() == 3)
        .ok_or("its result has no three-value `factor`")?;
    let mut out = [0.0; 3];
    for (o, x) in out.iter_mut().zip(f) {
        *o = x.as_f64().ok_or("a factor is not a number")?;
    }
    if out.iter().all(|x| x.is_finite()) {
        Ok(out)
    } else {
        Err(format!("a factor is not finite: {out:?}"))
    }
}

type AnchorLine = (String, PathBuf, f64, f64, f64, f64, f64);

/// Runs one anchor configuration at every budget; its result lines or why it failed.
fn run_anchor(
    args: &SpeedArgs,
    scene_json: &Path,
    config: &str,
    budgets: &[f64],
    seed: u64,
    scene: &str,
) -> Result<Vec<AnchorLine>, String> {
    if !args.anchor_script.exists() {
        return Err(format!(
            "{} not found (run from the repository root or pass --anchor-script)",
            args.anchor_script.display()
        ));
    }
    let budget_list: Vec<String> = budgets.iter().map(|b| b.to_string()).collect();
    let prefix = args.out.join(format!("{scene}_{config}_s{seed}"));
    let output = run_anchor_script(
        args,
        "render",
        &[
            "--scene-json".as_ref(),
            scene_json.as_os_str(),
            "--config".as_ref(),
            config.as_ref(),
            "--budgets".as_ref(),
            budget_list.join(",").as_ref(),
            "--seed".as_ref(),
            seed.to_string().as_ref(),
            "--out-prefix".as_ref(),
            prefix.as_os_str(),
        ],
    )
    .map_err(|f| {
        f.describe(|status, last| format!("{status} ({})", last.unwrap_or("no message")))
    })?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let mut out = Vec::new();
    // Mitsuba's log goes to stdout too, and may leave a colour escape before a result line.
    for line in stdout
        .lines()
        .filter_map(|l| l.find("{\"config\"").map(|i| &l[i..]))
    {
        let v: serde_json::Value =
            serde_json::from_str(line).map_err(|e| format!("unreadable result line: {e}"))?;
        let f = |k: &str| v[k].as_f64().ok_or(format!("result line without {k}"));
        out.push((
            v["renderer"].as_str().unwrap_or("?").to_string(),
            PathBuf::from(v["file"].as_str().ok_or("result line without file")?),
            f("budget")?,
            f("spp")?,
            f("seconds")?,
            f("load_seconds")?,
            f("jit_seconds")?,
        ));
    }
    if out.len() != budgets.len() {
        return Err(format!(
            "{} result lines for {} budgets",
            out.len(),
            budgets.len()
        ));
    }
    Ok(out)
}

fn print_point(p: &Point) {
    println!(
        "{:18} {:32} seed {:2} budget {:6.2} s: {:9.2} spp in {:7.3} s (load {:.2} s, JIT {:.2} s), RMSE {:.5}",
        p.scene,
        p.config,
        p.seed,
        p.budget,
        p.spp,
        p.seconds,
        p.load_seconds,
        p.jit_seconds,
        p.split.total_mse().sqrt()
    );
}

fn points_csv(points: &[Point]) -> String {
    let mut s = String::from(
        "scene,config,renderer,seed,budget_s,spp,seconds,load_s,jit_s,mse,mse_lamp_images,mse_caustic_core,mse_rest\n",
    );
    for p in points {
        let _ = writeln!(
            s,
            "{},{},\"{}\",{},{},{},{:.5},{:.4},{:.4},{:e},{:e},{:e},{:e}",
            p.scene,
            p.config,
            p.renderer.replace('"', "'"),
            p.seed,
            p.budget,
            p.spp,
            p.seconds,
            p.load_seconds,
            p.jit_seconds,
            p.split.total_mse(),
            p.split.mse(0),
            p.split.mse(1),
            p.split.mse(2)
        );
    }
    s
}

/// The fit of one configuration on one scene: the whole image (`None` region) or a region.
fn fit_of(points: &[&Point], region: Option<usize>, ref_var: f64) -> Option<Fit> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .map(|p| {
            (
                p.seconds,
                region.map_or(p.split.total_mse(), |r| p.split.mse(r)),
            )
        })
        .collect();
    fit_inverse_time(&pts, ref_var)
}

/// `value ± se` with two significant digits of the standard error (`–` without one).
fn pm(value: f64, se: f64) -> String {
    if !se.is_finite() || se <= 0.0 {
        return format!("{value:.3e} ± –");
    }
    format!("{value:.2e} ± {se:.1e}")
}

/// The verdict on one configuration's renders against the reference's variance `var`: its fit,
/// and whether it converges to another image, by a significant floor or by a mean off the
/// reference by more than [`MEAN_Z_LIMIT`]
/// standard errors. With one seed the floor's test has one degree of freedom and is weak; the
/// means are tested on every pixel at once.
struct Verdict {
    fit: Option<Fit>,
    floor: bool,
    mean_off: bool,
}

impl Verdict {
    fn biased(&self) -> bool {
        self.floor || self.mean_off
    }
    /// "biased (floor)", "biased (mean)", "biased (floor, mean)" or "unbiased".
    fn text(&self) -> &'static str {
        match (self.floor, self.mean_off) {
            (true, true) => "biased (floor, mean)",
            (true, false) => "biased (floor)",
            (false, true) => "biased (mean)",
            (false, false) => "unbiased",
        }
    }
}

fn verdict(points: &[&Point], region: Option<usize>, var: f64) -> Verdict {
    let fit = fit_of(points, region, var);
    let splits: Vec<&RegionSplit> = points.iter().map(|p| &p.split).collect();
    Verdict {
        floor: fit.is_some_and(|f| f.biased(var)),
        mean_off: mean_check(&splits, region, var).is_some_and(|m| !m.within()),
        fit,
    }
}

fn report(
    points: &[Point],
    references: &[(String, Reference, [usize; 3])],
    args: &SpeedArgs,
    (cpu, calibration): (&str, &str),
    notes: &[String],
    estimate: &str,
) -> String {
    let mut s = String::new();
    let budgets = args.budgets();
    let _ = writeln!(s, "CPU: {cpu}\n\n{calibration}\n");
    let _ = writeln!(
        s,
        "Budgets {:?} s, {} seed(s), {} threads per renderer. Seconds = sampling start to image \
         in memory (load/BVH and JIT beside). Fit MSE = a/t + b per configuration over all its \
         renders (linear sRGB, directly seen emitters left out); a = MSE·s of the noise \
         (efficiency 1/a), b = floor, never below the reference's own variance (\"held\" there \
         where the free fit put it lower, as when error falls faster than 1/t, and only a \
         fitted); \"biased\" = b minus the reference's own variance above \
         Student's t (95%, the fit's degrees of freedom) standard errors and a tenth of a/t \
         at the longest budget (floor), or the mean more than {MEAN_Z_LIMIT} standard errors \
         off the reference (mean; see the means table). Ratio = a of the best unbiased anchor \
         configuration / a of the row (> 1: more efficient than the best anchor).\n",
        budgets,
        args.seeds(),
        args.threads
    );
    for (name, reference, pixels) in references {
        let scene_points: Vec<&Point> = points.iter().filter(|p| &p.scene == name).collect();
        let _ = writeln!(
            s,
            "### {name}\n\nReference: {}, {}×{} px; its own noise RMSE {:.2e} (whole, all parts), \
             per region {} (the even-numbered parts). Regions: {} (drawn from the odd-numbered \
             parts).\n",
            reference.spp,
            reference.image.width,
            reference.image.height,
            reference.var_total.sqrt(),
            reference
                .var_region
                .iter()
                .map(|v| format!("{:.1e}", v.sqrt()))
                .collect::<Vec<_>>()
                .join(" / "),
            REGION_NAMES
                .iter()
                .zip(pixels)
                .map(|(n, p)| format!("{n} {p} px"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        let mut configs: Vec<&str> = Vec::new();
        for p in &scene_points {
            if !configs.contains(&p.config.as_str()) {
                configs.push(&p.config);
            }
        }
        let group = |c: &str| -> Vec<&Point> {
            scene_points
                .iter()
                .copied()
                .filter(|p| p.config == c)
                .collect()
        };
        // The best unbiased anchor configuration, whole image and per region: its a.
        let best = |region: Option<usize>, var: f64| -> Option<(String, f64)> {
            configs
                .iter()
                .filter(|c| group(c).first().is_some_and(|p| p.anchor))
                .filter_map(|c| {
                    let v = verdict(&group(c), region, var);
                    match v.fit {
                        Some(f) if !v.biased() && f.a > 0.0 => Some((c.to_string(), f.a)),
                        _ => None,
                    }
                })
                .min_by(|a, b| a.1.total_cmp(&b.1))
        };
        let best_all = best(None, reference.var_total);
        let best_region: Vec<Option<(String, f64)>> = (0..3)
            .map(|r| best(Some(r), reference.var_region[r]))
            .collect();
        let _ = writeln!(
            s,
            "| configuration | renderer | spp at {} s | load s | JIT s | a (MSE·s) | b (MSE) | verdict | × best anchor | {} |",
            budgets.last().copied().unwrap_or(0.0),
            REGION_NAMES
                .iter()
                .map(|n| format!("{n}: × best"))
                .collect::<Vec<_>>()
                .join(" | ")
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|---|");
        for c in &configs {
            let g = group(c);
            let last_budget = budgets.last().copied().unwrap_or(0.0);
            let at_last: Vec<&&Point> = g.iter().filter(|p| p.budget == last_budget).collect();
            let spp = at_last.iter().map(|p| p.spp).sum::<f64>() / at_last.len().max(1) as f64;
            let load = g.iter().map(|p| p.load_seconds).sum::<f64>() / g.len().max(1) as f64;
            let jit = g.iter().map(|p| p.jit_seconds).sum::<f64>() / g.len().max(1) as f64;
            let v = verdict(&g, None, reference.var_total);
            let ratio_cell = |v: &Verdict, best: &Option<(String, f64)>| -> String {
                match (&v.fit, best) {
                    (None, _) => "no fit".into(),
                    (Some(_), _) if v.biased() => "biased".into(),
                    (Some(f), Some((bc, ba))) if bc == c => {
                        format!("1 (best, a {ba:.1e})", ba = f.a.min(*ba))
                    }
                    (Some(f), Some((_, ba))) if f.a > 0.0 => format!("{:.2}", ba / f.a),
                    (Some(_), Some(_)) => "a ≤ 0".into(),
                    (Some(_), None) => "no unbiased anchor".into(),
                }
            };
            let (a, b) = match &v.fit {
                Some(f) if f.floor_held => (pm(f.a, f.se_a), format!("{:.2e} (held)", f.b)),
                Some(f) => (pm(f.a, f.se_a), pm(f.b, f.se_b)),
                None => ("–".into(), "–".into()),
            };
            let verdict_text = match &v.fit {
                None => "no fit",
                Some(_) => v.text(),
            };
            let regions: Vec<String> = (0..3)
                .map(|r| {
                    if pixels[r] == 0 {
                        return "–".into();
                    }
                    ratio_cell(
                        &verdict(&g, Some(r), reference.var_region[r]),
                        &best_region[r],
                    )
                })
                .collect();
            let _ = writeln!(
                s,
                "| {c} | {} | {spp:.0} | {load:.2} | {jit:.2} | {a} | {b} | {verdict_text} | {} | {} |",
                g[0].renderer,
                ratio_cell(&v, &best_all),
                regions.join(" | ")
            );
        }
        let _ = writeln!(
            s,
            "\nBest unbiased anchor: {}.\n",
            best_all.map_or("none".into(), |b| b.0)
        );
        means_table(&mut s, &configs, &group, reference, pixels);
    }
    for n in notes {
        let _ = writeln!(s, "- {n}");
    }
    let _ = writeln!(s, "\n{estimate}");
    s
}

/// Per configuration and region, its renders' pooled mean against the reference's
/// ([`mean_check`]): the relative offset and z; a mark where |z| exceeds [`MEAN_Z_LIMIT`].
fn means_table<'p>(
    s: &mut String,
    configs: &[&str],
    group: &dyn Fn(&str) -> Vec<&'p Point>,
    reference: &Reference,
    pixels: &[usize; 3],
) {
    let _ = writeln!(
        s,
        "Means: every render of a configuration pooled, (render − reference) / reference and z = \
         that difference over its standard error (render noise and the reference's own); ✗ \
         where |z| > {MEAN_Z_LIMIT}.\n\n\
         | configuration | whole | {} |\n|---|---|---|---|---|",
        REGION_NAMES.join(" | ")
    );
    let cell = |splits: &[&RegionSplit], region: Option<usize>, var: f64| -> String {
        match mean_check(splits, region, var) {
            Some(m) => format!(
                "{:+.2}% (z {:+.1}){}",
                100.0 * m.relative,
                m.z,
                if m.within() { "" } else { " ✗" }
            ),
            None => "–".into(),
        }
    };
    for c in configs {
        let g = group(c);
        let splits: Vec<&RegionSplit> = g.iter().map(|p| &p.split).collect();
        let regions: Vec<String> = (0..3)
            .map(|r| {
                if pixels[r] == 0 {
                    "–".into()
                } else {
                    cell(&splits, Some(r), reference.var_region[r])
                }
            })
            .collect();
        let _ = writeln!(
            s,
            "| {c} | {} | {} |",
            cell(&splits, None, reference.var_total),
            regions.join(" | ")
        );
    }
    let _ = writeln!(s);
}

/// How long the full run (default budgets and seeds, every configuration and scene) would take,
/// from this run's per-render overheads (wall time not spent sampling).
fn full_run_estimate(points: &[Point], args: &SpeedArgs, elapsed: f64, scenes: usize) -> String {
    let sampled: f64 = points.iter().map(|p| p.seconds).sum();
    let renders = points.len().max(1) as f64;
    let overhead_per_render = ((elapsed - sampled) / renders).max(0.0);
    let full_budgets = [4.0, 8.0, 16.0];
    let per_config_seed = full_budgets.iter().sum::<f64>() + 3.0 * overhead_per_render;
    let configs = (ANCHOR_CONFIGS.len() + 3) as f64;
    let run = per_config_seed * configs * 2.0 * SUITE.len() as f64;
    // References: 16384 spp per scene at the rate Mitsuba's independent sampler showed here.
    let rate = points
        .iter()
        .filter(|p| p.config == "mitsuba-independent" && p.seconds > 0.0)
        .map(|p| p.spp / p.seconds)
        .fold(0.0, f64::max);
    let refs = if rate > 0.0 {
        format!(
            "{:.1} h for the six 16,384-spp references",
            16384.0 / rate * SUITE.len() as f64 / 3600.0
        )
    } else {
        "the references' time unknown (no mitsuba-independent render in this run)".into()
    };
    format!(
        "This run: {:.0} s wall for {} renders over {} scene(s) ({:.1} s overhead per render). \
         Full run (`spectrace bench speed`, budgets 4, 8, 16 s, 2 seeds, {} configurations, {} \
         scenes, {} threads): about {:.1} h of renders plus {refs}.",
        elapsed,
        points.len(),
        scenes,
        overhead_per_render,
        configs,
        SUITE.len(),
        args.threads,
        run / 3600.0
    )
}

/// Arguments of `spectrace bench export`.
#[derive(clap::Args, Debug, Clone)]
pub struct ExportArgs {
    /// The scene file (RON).
    pub scene: PathBuf,
    /// Output directory: scene.json and one PLY per object.
    #[arg(long)]
    pub out: PathBuf,
}

/// Run `spectrace bench export`.
pub fn run_export(args: &ExportArgs) -> Result<(), String> {
    let e = export_scene(&args.scene, &args.out)?;
    println!(
        "wrote {} ({} shapes, {} materials)",
        e.path.display(),
        e.json["shapes"].as_array().map_or(0, Vec::len),
        e.json["materials"].as_object().map_or(0, |m| m.len())
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(clap::Parser)]
    struct Cli {
        #[command(flatten)]
        args: SpeedArgs,
    }

    fn parse(extra: &[&str]) -> SpeedArgs {
        let mut argv = vec!["bench-speed"];
        argv.extend_from_slice(extra);
        Cli::parse_from(argv).args
    }

    // Bad input is refused before anything is rendered, with an error naming the option or the
    // item: fewer than three budgets, a non-positive budget, zero threads or seeds, an unknown
    // scene, integrator or anchor configuration.
    #[test]
    fn bad_arguments_are_named() {
        let dir = std::env::temp_dir().join("spectrace-bench-speed-args");
        let out = dir.to_string_lossy().to_string();
        let e = run_speed(&parse(&["--budgets", "1,2", "--out", &out])).unwrap_err();
        assert!(e.contains("--budgets"), "{e}");
        let e = run_speed(&parse(&["--budgets=1,-2,3", "--out", &out])).unwrap_err();
        assert!(e.contains("--budgets"), "{e}");
        let e = run_speed(&parse(&["--threads", "0", "--out", &out])).unwrap_err();
        assert!(e.contains("--threads"), "{e}");
        let e = run_speed(&parse(&["--seeds", "0", "--out", &out])).unwrap_err();
        assert!(e.contains("--seeds"), "{e}");
        let e = run_speed(&parse(&["--scenes", "kitchen", "--out", &out])).unwrap_err();
        assert!(e.contains("kitchen"), "{e}");
        let e = run_speed(&parse(&["--integrators", "mlt", "--out", &out])).unwrap_err();
        assert!(e.contains("mlt"), "{e}");
        let e = run_speed(&parse(&["--configs", "mitsuba-sobol", "--out", &out])).unwrap_err();
        assert!(e.contains("mitsuba-sobol"), "{e}");
    }

    // The anchor configurations listed here are exactly those the script knows (its `configs`
    // command); checked only where a Python 3 is available (CI has one, without the renderers:
    // `configs` imports neither).
    #[test]
    fn configurations_match_the_script() {
        let script =
            Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/anchors/anchor_render.py");
        let out = match std::process::Command::new("python3")
            .arg(&script)
            .arg("configs")
            .output()
        {
            Ok(o) if o.status.success() => o,
            _ => {
                println!("skipped: python3 cannot run {}", script.display());
                return;
            }
        };
        let listed: Vec<String> = String::from_utf8_lossy(&out.stdout)
            .lines()
            .map(str::to_string)
            .collect();
        assert_eq!(listed, ANCHOR_CONFIGS.to_vec());
    }

    fn point(config: &str, anchor: bool, seconds: f64, mse: f64) -> Point {
        Point {
            scene: "s".into(),
            config: config.into(),
            renderer: "r".into(),
            anchor,
            seed: 0,
            budget: seconds,
            spp: 1.0,
            seconds,
            load_seconds: 0.0,
            jit_seconds: 0.0,
            split: RegionSplit {
                // 10⁴ pixels of reference value 1.
                sse: [0.0, 0.0, 3e4 * mse],
                values: [0, 0, 30_000],
                sum_ref: [0.0, 0.0, 3e4],
                total_sse: 3e4 * mse,
                total_sum_ref: 3e4,
                ..Default::default()
            },
        }
    }

    // The film's factor is read from the script's last JSON line (anything else is refused
    // with the reason) and accepted within FILM_TOLERANCE of 1: the film with the 1 nm bands
    // measured 1.00006 / 0.99989 / 1.00007; Mitsuba's hdrfilm, 1.00103 / 1.00099 / 1.00089,
    // is refused.
    #[test]
    fn film_factor_is_parsed_and_checked() {
        let ok =
            "log line\n{\"renderer\": \"m\", \"factor\": [1.00006, 0.99989, 1.00007], \"spp\": 1}\n";
        let f = parse_colour_factor(ok).unwrap();
        assert_eq!(f, [1.00006, 0.99989, 1.00007]);
        assert!(check_film_factor(f).is_ok());
        let e = check_film_factor([1.00103, 1.00099, 1.00089]).unwrap_err();
        assert!(e.contains("1.00103") && e.contains("observer.py"), "{e}");
        let e = parse_colour_factor("{\"factor\": [1.0, 1.0]}").unwrap_err();
        assert!(e.contains("three-value"), "{e}");
        assert!(parse_colour_factor("{\"factor\": [1.0, 1.0, NaN]}").is_err());
        assert!(parse_colour_factor("no json").is_err());
    }

    /// The report of `pts` (budgets 1, 2, 4, 8 s) on one scene "s" with an exact one-pixel
    /// reference in the rest region.
    fn test_report(pts: &[Point]) -> String {
        let image = RgbImage {
            width: 1,
            height: 1,
            rgb: vec![[0.0; 3]],
        };
        let reference = Reference {
            compared: image.clone(),
            image,
            spp: "test".into(),
            var_total: 0.0,
            var_region: [0.0; 3],
        };
        let args = parse(&["--budgets", "1,2,4,8"]);
        report(
            pts,
            &[("s".into(), reference, [0, 0, 1])],
            &args,
            ("cpu", "calibration"),
            &[],
            "",
        )
    }

    /// The first table row of configuration `c` in `md`.
    fn table_row(md: &str, c: &str) -> String {
        md.lines()
            .find(|l| l.starts_with(&format!("| {c} |")))
            .unwrap_or_else(|| panic!("{md}"))
            .to_string()
    }

    // The report ranks against the best *unbiased* anchor: anchor A has a = 1 and a floor of
    // 0.2 (biased), anchor B a = 2 with no floor, spectrace a = 1 with no floor: spectrace is
    // 2.00× the best anchor (B), and A is listed as biased, not as the best.
    #[test]
    fn report_ranks_against_the_best_unbiased_anchor() {
        let mut pts = Vec::new();
        for t in [1.0, 2.0, 4.0, 8.0] {
            let mut a = point("A", true, t, 1.0 / t + 0.2);
            // A's floor is an offset of its mean: √0.2 ≈ 0.45 on a reference of 1.
            a.split.sum_diff = [0.0, 0.0, 3e4 * 0.2f64.sqrt()];
            a.split.total_sum_diff = 3e4 * 0.2f64.sqrt();
            pts.push(a);
            pts.push(point("B", true, t, 2.0 / t));
            pts.push(point("spectrace-bdpt", false, t, 1.0 / t));
        }
        let md = test_report(&pts);
        let row = |c: &str| table_row(&md, c);
        assert!(row("A").contains("biased (floor, mean)"), "{md}");
        assert!(row("B").contains("1 (best"), "{md}");
        assert!(row("spectrace-bdpt").contains("| 2.00 |"), "{md}");
        assert!(md.contains("Best unbiased anchor: B"), "{md}");
        // The means table: B and spectrace sit on the reference, A is 45% off, ~100 standard
        // errors over 10⁴ pixels (marked).
        let means = |c: &str| {
            md.lines()
                .filter(|l| l.starts_with(&format!("| {c} |")))
                .nth(1)
                .unwrap_or_else(|| panic!("{md}"))
                .to_string()
        };
        assert!(means("B").contains("+0.00% (z +0.0)"), "{md}");
        assert!(
            means("A").contains("+44.72%") && means("A").contains('✗'),
            "{md}"
        );
    }

    // The verdict also tests the means. Anchors "luxcore-c" and "mitsuba-d" have the
    // smallest a (0.5) and no floor, but their means are 1% off: 0.01 over a pooled standard
    // error of about 0.0016 (10⁴ pixels, MSE 0.5/t over 1–8 s), z ≈ 6 > 4, so both are "biased
    // (mean)" and not ranked, whatever the renderer; B (a = 2) is the best, and spectrace
    // (a = 1) 2.00× it. Without the mean test "luxcore-c" would rank first.
    #[test]
    fn report_tests_means() {
        let mut pts = Vec::new();
        for t in [1.0, 2.0, 4.0, 8.0] {
            for name in ["luxcore-c", "mitsuba-d"] {
                let mut p = point(name, true, t, 0.5 / t);
                p.split.sum_diff = [0.0, 0.0, 3e4 * 0.01];
                p.split.total_sum_diff = 3e4 * 0.01;
                pts.push(p);
            }
            pts.push(point("B", true, t, 2.0 / t));
            pts.push(point("spectrace-bdpt", false, t, 1.0 / t));
        }
        let md = test_report(&pts);
        let row = |c: &str| table_row(&md, c);
        assert!(row("luxcore-c").contains("biased (mean)"), "{md}");
        assert!(row("mitsuba-d").contains("biased (mean)"), "{md}");
        assert!(row("spectrace-bdpt").contains("| 2.00 |"), "{md}");
        assert!(md.contains("Best unbiased anchor: B"), "{md}");
    }

    /// A one-pixel EXR at `path`, its header stating `colour` (if any) as a reference would.
    fn write_reference(path: &Path, colour: Option<&str>) {
        use exr::prelude::*;
        let mut layer = Layer::new(
            (1, 1),
            LayerAttributes::default(),
            Encoding::FAST_LOSSLESS,
            SpecificChannels::rgb(|_| (0.5f32, 0.25f32, 0.125f32)),
        );
        if let Some(c) = colour {
            layer.attributes.other.insert(
                Text::from(REFERENCE_COLOUR_ATTRIBUTE),
                AttributeValue::Text(Text::from(c)),
            );
        }
        Image::from_layer(layer).write().to_file(path).unwrap();
    }

    // A reference is taken only when its header states the bench's colour convention; one
    // without the statement (rendered through hdrfilm) or with another is refused, naming the
    // file and the convention.
    #[test]
    fn references_must_state_the_colour_convention() {
        let dir = std::env::temp_dir().join("spectrace-bench-reference-colour");
        std::fs::create_dir_all(&dir).unwrap();
        let ok = dir.join("ok.exr");
        write_reference(&ok, Some(REFERENCE_COLOUR));
        assert_eq!(check_reference_colour(&ok), Ok(()));
        let old = dir.join("old.exr");
        write_reference(&old, None);
        let e = check_reference_colour(&old).unwrap_err();
        assert!(e.contains("old.exr") && e.contains("does not state"), "{e}");
        let other = dir.join("other.exr");
        write_reference(&other, Some("CIE 1931, 5 nm"));
        let e = check_reference_colour(&other).unwrap_err();
        assert!(
            e.contains("\"CIE 1931, 5 nm\"") && e.contains(REFERENCE_COLOUR),
            "{e}"
        );
        assert!(check_reference_colour(&dir.join("missing.exr")).is_err());
    }

    // The convention is written once on each side: the script's observer.py states the same
    // attribute and words as REFERENCE_COLOUR_ATTRIBUTE and REFERENCE_COLOUR, and every
    // committed reference (and part) states it.
    #[test]
    fn committed_references_state_the_script_colour_convention() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let script = std::fs::read_to_string(root.join("scripts/anchors/observer.py")).unwrap();
        assert!(
            script.contains(&format!(
                "COLOUR_ATTRIBUTE = \"{REFERENCE_COLOUR_ATTRIBUTE}\""
            )),
            "observer.py's COLOUR_ATTRIBUTE differs"
        );
        assert!(
            script.contains(&format!("COLOUR = \"{REFERENCE_COLOUR}\"")),
            "observer.py's COLOUR differs"
        );
        let refs = root.join("scenes/bench/references");
        let mut n = 0;
        for entry in std::fs::read_dir(&refs).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "exr") {
                check_reference_colour(&path).unwrap();
                n += 1;
            }
        }
        assert!(n >= 6, "{n} references in {}", refs.display());
    }
}
