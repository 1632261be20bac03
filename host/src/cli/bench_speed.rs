//! `spectrace bench speed [--budget SECONDS] [--seeds N] [--threads N] [--python PY] [--out DIR]`:
//! the Cornell box and the glass-sphere caustic rendered for the same wall-clock budget by
//! spectrace's path tracer and BDPT and by the anchors (Mitsuba 3's spectral path tracer,
//! LuxCore's BIDIRCPU and PATHCPU, through `scripts/anchors/anchor_render.py`), every image
//! compared with one long reference per scene (directly visible light left out, as
//! `spectrace compare` does).
//!
//! Every renderer renders every scene `--seeds` times (seeds `--seed`, `--seed + 1`, …; the runs
//! of one seed are made one after the other for all renderers, so a change of the machine's
//! load is spread over all of them). The efficiency of a renderer is `1 / mean(MSE·seconds)`
//! over its runs: for an unbiased renderer the expected MSE falls as 1/time, so the mean of
//! `MSE·seconds` estimates its inverse efficiency whatever the budget, and its standard error
//! over the runs gives the efficiency's. One run's MSE is not enough where rare, very bright
//! samples decide it (the lamp seen through the glass ball of the caustic scene): the mean over
//! runs counts them at their true rate, and the standard error says how well it is known.
//! Prints and writes DIR/speed.md: per run the spp, seconds and RMSE; per renderer the mean,
//! the efficiency with its standard error and the ratio to the best anchor with the ratio's
//! standard error; for the caustic also the efficiency per region ([`CausticRegions`]).
//! An anchor that cannot be installed or run is reported and skipped.
//!
//! Paths default to the repository layout, so run it from the repository root (or pass them).

use super::speed_regions::{CausticRegions, RegionSplit, REGION_GROUPS};
use crate::analysis::{compare_images_excluding, CompareOptions, RgbImage};
use crate::integrator::{render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget};
use crate::scene::SceneSource;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Arguments of `spectrace bench speed`.
#[derive(clap::Args, Debug, Clone)]
pub struct SpeedArgs {
    /// Wall-clock budget of every render (one renderer, scene and seed), in seconds.
    #[arg(long, default_value_t = 10.0)]
    pub budget: f64,
    /// Independent runs (seeds) per renderer and scene; the whole benchmark takes about
    /// seeds × budget × 5 renderers × scenes. The efficiency's standard error needs at least 2.
    #[arg(long, default_value_t = 4)]
    pub seeds: u32,
    /// Worker threads of every renderer.
    #[arg(long, default_value_t = 2)]
    pub threads: usize,
    /// Comma-separated scenes: cornell, caustic.
    #[arg(long, value_delimiter = ',', default_value = "cornell,caustic")]
    pub scenes: Vec<String>,
    /// Comma-separated spectrace integrators to run: pt, bdpt.
    #[arg(long, value_delimiter = ',', default_value = "pt,bdpt")]
    pub integrators: Vec<String>,
    /// Python interpreter with mitsuba and pyluxcore installed (see the anchor script); default
    /// $SPECTRACE_ANCHOR_PYTHON, else python3.
    #[arg(long)]
    pub python: Option<PathBuf>,
    /// The anchor script.
    #[arg(long, default_value = "scripts/anchors/anchor_render.py")]
    pub anchor_script: PathBuf,
    /// Render spectrace only.
    #[arg(long)]
    pub no_anchors: bool,
    /// The caustic scene file.
    #[arg(long, default_value = "scenes/caustic.ron")]
    pub caustic_scene: PathBuf,
    /// Reference of the Cornell box (Mitsuba 3, 10,240 spp).
    #[arg(long, default_value = "host/data/reference/cbox_reference_mitsuba.exr")]
    pub cornell_reference: PathBuf,
    /// Reference of the caustic (spectrace BDPT, 16,384 spp, checked against Mitsuba 3 in
    /// docs/accuracy.md; lower noise in the caustic than the path-traced Mitsuba reference).
    #[arg(
        long,
        default_value = "docs/figures/caustic/reference_bdpt_16384spp.exr"
    )]
    pub caustic_reference: PathBuf,
    /// Output directory for the images and speed.md.
    #[arg(long, default_value = "speed-out")]
    pub out: PathBuf,
    /// First seed; run k uses seed + k, for spectrace and the anchors alike.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// One measured render.
#[derive(Clone, Debug)]
struct SpeedRow {
    scene: String,
    renderer: String,
    integrator: String,
    anchor: bool,
    seed: u64,
    spp: u32,
    seconds: f64,
    pixels: usize,
    rmse: f64,
    /// Squared error per region (caustic scene only).
    regions: Option<RegionSplit>,
}

impl SpeedRow {
    fn samples_per_second(&self) -> f64 {
        self.spp as f64 * self.pixels as f64 / self.seconds.max(1e-9)
    }
    /// Equal-time efficiency of this run alone: error variance falls as 1/time, so
    /// 1/(RMSE²·t) is independent of the budget for an unbiased renderer.
    #[cfg(test)]
    fn efficiency(&self) -> f64 {
        1.0 / (self.rmse * self.rmse * self.seconds.max(1e-9))
    }
}

/// Mean and standard error of the mean of `x` (standard error NaN for fewer than 2 values).
fn mean_se(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    if x.len() < 2 {
        return (mean, f64::NAN);
    }
    let var = x.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// An efficiency `1/m` from the mean `m` of a renderer's per-run `MSE·seconds`, with its
/// relative standard error (that of `m`, to first order).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Efficiency {
    value: f64,
    rel_se: f64,
}

impl Efficiency {
    fn from_products(mse_seconds: &[f64]) -> Self {
        let (m, se) = mean_se(mse_seconds);
        Self {
            value: 1.0 / m,
            rel_se: se / m,
        }
    }
    /// `self / other` and the ratio's standard error (relative errors added in quadrature:
    /// the runs of two renderers are independent).
    fn ratio(&self, other: &Efficiency) -> (f64, f64) {
        let r = self.value / other.value;
        (r, r * self.rel_se.hypot(other.rel_se))
    }
}

/// All runs of one renderer and integrator on one scene.
struct Summary<'a> {
    runs: Vec<&'a SpeedRow>,
}

impl Summary<'_> {
    fn first(&self) -> &SpeedRow {
        self.runs[0]
    }
    fn mean(&self, f: impl Fn(&SpeedRow) -> f64) -> f64 {
        self.runs.iter().map(|r| f(r)).sum::<f64>() / self.runs.len() as f64
    }
    /// Efficiency from every run's MSE·seconds.
    fn efficiency(&self) -> Efficiency {
        let p: Vec<f64> = self
            .runs
            .iter()
            .map(|r| r.rmse * r.rmse * r.seconds)
            .collect();
        Efficiency::from_products(&p)
    }
    /// Efficiency of the regions of `REGION_GROUPS[i]` alone (caustic scene).
    fn region_efficiency(&self, i: usize) -> Option<Efficiency> {
        let group = REGION_GROUPS[i].1;
        let p: Option<Vec<f64>> = self
            .runs
            .iter()
            .map(|r| r.regions.map(|g| g.group_mse(group) * r.seconds))
            .collect();
        p.map(|p| Efficiency::from_products(&p))
    }
}

/// Rows grouped by (scene, renderer, integrator), in the order they first appear.
fn summaries(rows: &[SpeedRow]) -> Vec<Summary<'_>> {
    let mut out: Vec<Summary> = Vec::new();
    for r in rows {
        let same = |s: &&mut Summary| {
            let f = s.first();
            (f.scene == r.scene) && (f.renderer == r.renderer) && (f.integrator == r.integrator)
        };
        match out.iter_mut().find(|s| same(s)) {
            Some(s) => s.runs.push(r),
            None => out.push(Summary { runs: vec![r] }),
        }
    }
    out
}

/// The anchor renders of every scene: (renderer, engine/variant arguments).
const ANCHORS: [(&str, &str, &str); 3] = [
    ("mitsuba", "--variant", "llvm_ad_spectral"),
    ("luxcore", "--engine", "BIDIRCPU"),
    ("luxcore", "--engine", "PATHCPU"),
];

/// Run `spectrace bench speed`.
pub fn run_speed(args: &SpeedArgs) -> Result<(), String> {
    if !(args.budget.is_finite() && args.budget > 0.0) {
        return Err(format!(
            "--budget must be a positive number of seconds, got {}",
            args.budget
        ));
    }
    if args.threads == 0 {
        return Err("--threads must be at least 1".into());
    }
    if args.seeds == 0 {
        return Err("--seeds must be at least 1 (2 or more for a standard error)".into());
    }
    for name in &args.scenes {
        if !matches!(name.as_str(), "cornell" | "caustic") {
            return Err(format!(
                "unknown scene '{name}' in --scenes (known: cornell, caustic)"
            ));
        }
    }
    let mut kinds = Vec::new();
    for name in &args.integrators {
        kinds.push(match name.as_str() {
            "pt" => (IntegratorKind::Pt, "pt"),
            "bdpt" => (IntegratorKind::Bdpt, "bdpt"),
            other => {
                return Err(format!(
                    "unknown integrator '{other}' in --integrators (known: pt, bdpt)"
                ))
            }
        });
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let mut rows = Vec::new();
    let mut notes = Vec::new();
    for scene_name in &args.scenes {
        let (source, reference_path) = match scene_name.as_str() {
            "cornell" => (SceneSource::from_path(None), &args.cornell_reference),
            _ => (
                SceneSource::from_path(Some(args.caustic_scene.clone())),
                &args.caustic_reference,
            ),
        };
        let reference = RgbImage::read_exr(reference_path).map_err(|e| {
            format!("{e} (run from the repository root or pass the reference's path)")
        })?;
        let regions = (scene_name == "caustic").then(|| CausticRegions::new(&reference));
        let scene = source
            .build(&Default::default())
            .map_err(|e| format!("{scene_name}: {e}"))?;
        // Anchors that failed once are not tried again for the other seeds.
        let mut skipped = vec![false; ANCHORS.len()];
        for k in 0..u64::from(args.seeds) {
            let seed = args.seed + k;
            for &(kind, label) in &kinds {
                let settings = RenderSettings {
                    sampler: Default::default(),
                    budget: SampleBudget::Time(Duration::from_secs_f64(args.budget)),
                    seed,
                    threads: Some(args.threads),
                    camera: None,
                    tile_size: 16,
                    tracer: PathTracer {
                        max_depth: scene.options.max_depth,
                        ..PathTracer::default()
                    },
                };
                let out = render_with(&scene, &settings, kind, false, &|_, _| {}, None)
                    .map_err(|e| format!("{scene_name} {label}: {e}"))?;
                let img = RgbImage::from_xyz(&out.result.image, &scene.options.rgb_space);
                let path = args
                    .out
                    .join(format!("{scene_name}_spectrace_{label}_seed{seed}.exr"));
                crate::film::write_exr(&path, &out.result.image, &scene.options.rgb_space)
                    .map_err(|e| format!("{}: {e}", path.display()))?;
                let row = SpeedRow {
                    scene: scene_name.clone(),
                    renderer: format!("spectrace {}", env!("CARGO_PKG_VERSION")),
                    integrator: label.into(),
                    anchor: false,
                    seed,
                    spp: out.result.spp,
                    seconds: out.result.elapsed.as_secs_f64(),
                    pixels: img.width as usize * img.height as usize,
                    rmse: rmse(&img, &reference, scene_name)?,
                    regions: regions.as_ref().map(|g| g.split(&img, &reference)),
                };
                print_row(&row);
                rows.push(row);
            }
            if args.no_anchors {
                continue;
            }
            for (a, (renderer, flag, value)) in ANCHORS.into_iter().enumerate() {
                if skipped[a] {
                    continue;
                }
                let path = args
                    .out
                    .join(format!("{scene_name}_{renderer}_{value}_seed{seed}.exr"));
                match run_anchor(args, scene_name, renderer, flag, value, seed, &path) {
                    Ok((spp, seconds, renderer, integrator)) => {
                        let img = RgbImage::read_exr(&path).map_err(|e| e.to_string())?;
                        let row = SpeedRow {
                            scene: scene_name.clone(),
                            renderer,
                            integrator,
                            anchor: true,
                            seed,
                            spp,
                            seconds,
                            pixels: img.width as usize * img.height as usize,
                            rmse: rmse(&img, &reference, scene_name)?,
                            regions: regions.as_ref().map(|g| g.split(&img, &reference)),
                        };
                        print_row(&row);
                        rows.push(row);
                    }
                    Err(why) => {
                        let note = format!("{scene_name}: {renderer} {value} skipped: {why}");
                        println!("{note}");
                        notes.push(note);
                        skipped[a] = true;
                    }
                }
            }
        }
    }
    let table = table(&rows, args, &notes);
    println!("\n{table}");
    let md = args.out.join("speed.md");
    std::fs::write(&md, &table).map_err(|e| format!("cannot write {}: {e}", md.display()))?;
    println!("wrote {}", md.display());
    Ok(())
}

fn rmse(img: &RgbImage, reference: &RgbImage, scene: &str) -> Result<f64, String> {
    if (img.width, img.height) != (reference.width, reference.height) {
        return Err(format!(
            "{scene}: the render is {}×{} but the reference is {}×{}",
            img.width, img.height, reference.width, reference.height
        ));
    }
    let (c, _) = compare_images_excluding(
        img,
        reference,
        CompareOptions {
            exclude_light: true,
        },
        None,
    );
    Ok(c.rmse)
}

fn print_row(r: &SpeedRow) {
    println!(
        "{:8} {:22} {:28} seed {:3} {:6} spp {:7.2} s {:7.3} Msamples/s  RMSE {:.5}",
        r.scene,
        r.renderer,
        r.integrator,
        r.seed,
        r.spp,
        r.seconds,
        r.samples_per_second() / 1e6,
        r.rmse
    );
}

/// Runs the anchor script; returns (spp, seconds, renderer, integrator) or why it was skipped.
fn run_anchor(
    args: &SpeedArgs,
    scene: &str,
    renderer: &str,
    flag: &str,
    value: &str,
    seed: u64,
    out: &Path,
) -> Result<(u32, f64, String, String), String> {
    if !args.anchor_script.exists() {
        return Err(format!(
            "{} not found (run from the repository root or pass --anchor-script)",
            args.anchor_script.display()
        ));
    }
    let python = args.python.clone().unwrap_or_else(|| {
        std::env::var_os("SPECTRACE_ANCHOR_PYTHON").map_or_else(|| "python3".into(), PathBuf::from)
    });
    let output = std::process::Command::new(&python)
        .arg(&args.anchor_script)
        .args(["--renderer", renderer, "--scene", scene, flag, value])
        .arg("--seconds")
        .arg(args.budget.to_string())
        .arg("--threads")
        .arg(args.threads.to_string())
        .arg("--seed")
        .arg(seed.to_string())
        .arg("--out")
        .arg(out)
        .output()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    let stderr = String::from_utf8_lossy(&output.stderr);
    if !output.status.success() {
        let last = stderr.lines().last().unwrap_or("no message");
        return Err(format!("{} ({last})", output.status));
    }
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line = stdout
        .lines()
        .rev()
        .find(|l| l.trim_start().starts_with('{'))
        .ok_or_else(|| "the anchor script printed no result line".to_string())?;
    let v: serde_json::Value =
        serde_json::from_str(line).map_err(|e| format!("unreadable result line: {e}"))?;
    let spp = v["spp"].as_u64().ok_or("result line without spp")? as u32;
    let seconds = v["seconds"].as_f64().ok_or("result line without seconds")?;
    let text = |k: &str| v[k].as_str().unwrap_or("?").to_string();
    Ok((spp, seconds, text("renderer"), text("integrator")))
}

/// `value ± se` with the precision the standard error allows (two significant digits of it);
/// "value ± –" without a standard error.
fn pm(value: f64, se: f64) -> String {
    if !se.is_finite() || se <= 0.0 {
        return format!("{value:.3} ± –");
    }
    let digits = (1 - se.log10().floor() as i32).clamp(0, 6) as usize;
    format!("{value:.digits$} ± {se:.digits$}")
}

/// The best anchor on `scene` (by the region `region`, or the whole image): its index in
/// `sums` and its efficiency.
fn best_anchor(
    sums: &[Summary],
    scene: &str,
    region: Option<usize>,
) -> Option<(usize, Efficiency)> {
    sums.iter()
        .enumerate()
        .filter(|(_, s)| s.first().anchor && s.first().scene == scene)
        .filter_map(|(k, s)| match region {
            Some(i) => s.region_efficiency(i).map(|e| (k, e)),
            None => Some((k, s.efficiency())),
        })
        .max_by(|a, b| a.1.value.total_cmp(&b.1.value))
}

/// Summary `k`'s efficiency `eff` as a multiple of the best anchor's, with its standard error;
/// "1 (best)" for the best anchor itself, "–" without anchors.
fn ratio_cell(k: usize, eff: Option<Efficiency>, best: Option<(usize, Efficiency)>) -> String {
    match (eff, best) {
        (_, Some((b, _))) if b == k => "1 (best)".into(),
        (Some(e), Some((_, b))) => {
            let (r, se) = e.ratio(&b);
            pm(r, se)
        }
        _ => "–".into(),
    }
}

/// The Markdown tables: per run; per renderer the efficiency from all its runs and its ratio
/// to the best anchor's; for the caustic, the same per region.
fn table(rows: &[SpeedRow], args: &SpeedArgs, notes: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Budget {} s per render, {} threads, {} seed(s) per renderer from seed {}; RMSE in linear \
         sRGB against the scene's reference, directly visible light excluded. Efficiency = \
         1/mean(RMSE²·seconds) over a renderer's runs, ± one standard error (from the spread of \
         RMSE²·seconds over the runs); the ratio's standard error adds both relative errors in \
         quadrature.\n",
        args.budget, args.threads, args.seeds, args.seed
    );
    let sums = summaries(rows);
    let _ = writeln!(
        s,
        "| scene | renderer | integrator | runs | spp (mean) | seconds (mean) | Msamples/s | \
         RMSE per run | √(mean MSE) | efficiency | × best anchor |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
    for (k, sum) in sums.iter().enumerate() {
        let f = sum.first();
        let eff = sum.efficiency();
        let ratio = ratio_cell(k, Some(eff), best_anchor(&sums, &f.scene, None));
        let per_run: Vec<String> = sum.runs.iter().map(|r| format!("{:.5}", r.rmse)).collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.0} | {:.2} | {:.3} | {} | {:.5} | {} | {} |",
            f.scene,
            f.renderer,
            f.integrator,
            sum.runs.len(),
            sum.mean(|r| r.spp as f64),
            sum.mean(|r| r.seconds),
            sum.mean(SpeedRow::samples_per_second) / 1e6,
            per_run.join(", "),
            sum.mean(|r| r.rmse * r.rmse).sqrt(),
            pm(eff.value, eff.value * eff.rel_se),
            ratio
        );
    }
    if sums.iter().any(|x| x.first().regions.is_some()) {
        let _ = writeln!(
            s,
            "\nCaustic by region (docs/performance.md, \"The caustic\"; regions from the reference \
             alone): share of the squared error (mean over runs) and the efficiency of the region \
             alone as a multiple of the best anchor's on that region.\n"
        );
        let names: Vec<&str> = REGION_GROUPS.iter().map(|g| g.0).collect();
        let _ = writeln!(s, "| renderer | integrator | {} |", names.join(" | "));
        let _ = writeln!(s, "|---|---|{}", "---|".repeat(names.len()));
        for (k, sum) in sums.iter().enumerate() {
            let f = sum.first();
            if f.regions.is_none() {
                continue;
            }
            let cells: Vec<String> = (0..REGION_GROUPS.len())
                .map(|i| {
                    let share = sum.mean(|r| {
                        r.regions
                            .unwrap_or_default()
                            .group_share(REGION_GROUPS[i].1)
                    });
                    let best = best_anchor(&sums, &f.scene, Some(i));
                    let ratio = if best.is_some() {
                        format!(", {}", ratio_cell(k, sum.region_efficiency(i), best))
                    } else {
                        String::new()
                    };
                    format!("{:.0}%{ratio}", 100.0 * share)
                })
                .collect();
            let _ = writeln!(
                s,
                "| {} | {} | {} |",
                f.renderer,
                f.integrator,
                cells.join(" | ")
            );
        }
    }
    for n in notes {
        let _ = writeln!(s, "\n- {n}");
    }
    s
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

    // Bad input is refused before anything is rendered, with an error naming the option or
    // the item: a non-positive budget, zero threads, an unknown scene or integrator name, no seeds.
    #[test]
    fn bad_arguments_are_named() {
        let dir = std::env::temp_dir().join("spectrace-bench-speed-args");
        let out = dir.to_string_lossy().to_string();
        let e = run_speed(&parse(&["--budget=-1", "--out", &out])).unwrap_err();
        assert!(e.contains("--budget"), "{e}");
        let e = run_speed(&parse(&["--threads", "0", "--out", &out])).unwrap_err();
        assert!(e.contains("--threads"), "{e}");
        let e = run_speed(&parse(&["--scenes", "kitchen", "--out", &out])).unwrap_err();
        assert!(e.contains("kitchen"), "{e}");
        let e = run_speed(&parse(&["--integrators", "mlt", "--out", &out])).unwrap_err();
        assert!(e.contains("mlt"), "{e}");
        let e = run_speed(&parse(&["--seeds", "0", "--out", &out])).unwrap_err();
        assert!(e.contains("--seeds"), "{e}");
    }

    // Efficiency is 1/(RMSE²·t): halving the RMSE at the same time quadruples it; samples/s
    // counts every pixel's samples. Exact arithmetic on chosen numbers.
    #[test]
    fn efficiency_and_rate() {
        let row = |rmse: f64| SpeedRow {
            scene: "s".into(),
            renderer: "r".into(),
            integrator: "i".into(),
            anchor: false,
            seed: 0,
            spp: 10,
            seconds: 2.0,
            pixels: 100,
            rmse,
            regions: None,
        };
        assert_eq!(row(0.5).efficiency(), 2.0);
        assert_eq!(row(0.25).efficiency(), 8.0);
        assert_eq!(row(0.5).samples_per_second(), 500.0);
    }

    // The efficiency of several runs is 1/mean(MSE·t), not the mean of the runs' efficiencies
    // (which one lucky run without an outlier would decide), and its standard error is the
    // sample standard deviation of MSE·t over √n, relative to the mean. Runs with MSE·t = 1
    // and 3: mean 2, sd √2, SE 1 → efficiency 0.5 with relative SE 0.5. The ratio of two such
    // efficiencies has relative SE √(0.5² + 0.5²). Exact arithmetic on chosen numbers
    // (1e-12: rounding of the square roots).
    #[test]
    fn efficiency_over_runs_and_its_standard_error() {
        let e = Efficiency::from_products(&[1.0, 3.0]);
        assert_eq!(e.value, 0.5);
        assert!((e.rel_se - 0.5).abs() < 1e-12, "{e:?}");
        let (r, se) = e.ratio(&Efficiency {
            value: 0.25,
            rel_se: 0.5,
        });
        assert_eq!(r, 2.0);
        assert!((se - 2.0 * 0.5f64.hypot(0.5)).abs() < 1e-12, "{se}");
        // One run: no standard error, shown as such.
        let one = Efficiency::from_products(&[4.0]);
        assert_eq!(one.value, 0.25);
        assert!(one.rel_se.is_nan());
        assert_eq!(pm(0.25, f64::NAN), "0.250 ± –");
        assert_eq!(pm(1.2344, 0.0321), "1.234 ± 0.032");
    }
}
