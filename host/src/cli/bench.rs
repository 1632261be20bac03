//! `spectrace bench accuracy [SCENE] --reference REF.exr --budget SECONDS [--configs a,b,...]
//! [--out DIR]`: error against time for each renderer configuration; writes DIR/accuracy.csv,
//! log–log plots of RMSE and mean ΔE00 against time (SVG and PNG) with the fitted slope per
//! configuration, and DIR/summary.md.

use crate::analysis::accuracy_bench::{
    available_configs, converged, loglog_fit, run_accuracy_bench, select_configs, time_to_reach,
    to_csv, unavailable_configs, AccuracyConfig, AccuracyPoint, BenchSettings, SceneProvider,
};
use crate::analysis::plot::{plot_loglog, PlotLabels, Series};
use crate::analysis::RgbImage;
use crate::scene::SceneSource;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// `spectrace bench …` benchmarks.
#[derive(clap::Subcommand, Debug, Clone)]
pub enum BenchCommand {
    /// Error versus time of renderer configurations against a reference image.
    Accuracy(AccuracyArgs),
    /// Equal-time efficiency of spectrace against Mitsuba 3 and LuxCore on the bench's scene
    /// suite, per region, with their means against Mitsuba references (see docs/performance.md).
    Speed(super::bench_speed::SpeedArgs),
    /// Write a scene for the anchors (scene.json and PLY files; see `bench speed`).
    Export(super::bench_speed::ExportArgs),
    /// The cost of each effect: every bundled scene with `--effects auto`, `all` and each of
    /// its effects switched off (time per sample, mean Y; see docs/effects.md).
    Effects(super::bench_effects::EffectsBenchArgs),
}

/// Arguments of `spectrace bench accuracy`.
#[derive(clap::Args, Debug, Clone)]
pub struct AccuracyArgs {
    /// Scene file (RON). Without it the embedded measured Cornell box is rendered.
    pub scene: Option<PathBuf>,
    /// Reference OpenEXR (linear sRGB R, G, B) of the same scene and size.
    #[arg(long, required_unless_present = "list")]
    pub reference: Option<PathBuf>,
    /// Time budget per configuration, in seconds.
    #[arg(long, required_unless_present = "list")]
    pub budget: Option<f64>,
    /// Comma-separated configuration names (default: all available).
    #[arg(long, value_delimiter = ',')]
    pub configs: Option<Vec<String>>,
    /// Output directory for the CSV, plots and summary.
    #[arg(long, default_value = "accuracy-out")]
    pub out: PathBuf,
    /// Largest samples per pixel tried.
    #[arg(long, default_value_t = 4096)]
    pub max_spp: u32,
    /// Mean ΔE00 to report the time to reach.
    #[arg(long, default_value_t = 1.0)]
    pub target_delta_e: f64,
    /// RMSE to report the time to reach.
    #[arg(long, default_value_t = 0.01)]
    pub target_rmse: f64,
    /// Seed of every render.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = crate::limits::parse_threads)]
    pub threads: Option<usize>,
    /// List the configurations and exit.
    #[arg(long)]
    pub list: bool,
    /// Also leave out the pixels that show specular surfaces (glass, mirrors), whose sub-pixel
    /// images of small lights dominate whole-image errors for a long time; the rest of the image
    /// is where diffuse light and caustics are judged.
    #[arg(long)]
    pub exclude_specular: bool,
}

/// Run `spectrace bench …`.
pub fn run(cmd: &BenchCommand) -> Result<(), String> {
    match cmd {
        BenchCommand::Accuracy(a) => run_accuracy(a),
        BenchCommand::Speed(a) => super::bench_speed::run_speed(a),
        BenchCommand::Export(a) => super::bench_speed::run_export(a),
        BenchCommand::Effects(a) => super::bench_effects::run_bench(a),
    }
}

fn run_accuracy(args: &AccuracyArgs) -> Result<(), String> {
    let source = SceneSource::from_path(args.scene.clone());
    // The scene as written: its depth sets the configurations' default, and it is the one the
    // default-representation configurations render.
    let scene = source
        .build(&Default::default())
        .map_err(|e| e.to_string())?;
    let all = available_configs(scene.options.max_depth);
    if args.list {
        for c in &all {
            println!("{:18} {}", c.name, c.trade_off);
        }
        for (n, why) in unavailable_configs() {
            println!("not yet available: {n}: {why}");
        }
        return Ok(());
    }
    let budget = args.budget.unwrap_or(f64::NAN);
    if !(budget.is_finite() && budget > 0.0) {
        return Err(format!(
            "--budget must be a positive number of seconds, got {budget}"
        ));
    }
    let reference_path = args.reference.clone().unwrap_or_default();
    let configs = select_configs(all, args.configs.as_deref())?;
    let reference = RgbImage::read_exr(&reference_path).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let settings = BenchSettings {
        budget: Duration::from_secs_f64(budget),
        max_spp: args.max_spp.max(1),
        seed: args.seed,
        threads: args.threads,
        exclude_specular: args.exclude_specular,
    };
    println!("config              spp   seconds  Msamples/s      RMSE   ΔE00 mean  ΔE00 p99");
    let show = |p: &AccuracyPoint| {
        println!(
            "{:17} {:4} {:9.3} {:11.3} {:9.5} {:11.4} {:9.4}",
            p.config,
            p.spp,
            p.seconds,
            p.samples_per_second / 1e6,
            p.rmse,
            p.delta_e_mean,
            p.delta_e_p99
        );
    };
    let scenes = PrebuiltDefault {
        scene: &scene,
        source: &source,
    };
    let points = run_accuracy_bench(&scenes, &reference, &configs, &settings, &show)
        .map_err(|e| e.to_string())?;
    let written = write_outputs(args, &configs, &points)?;
    for w in written {
        println!("wrote {}", w.display());
    }
    Ok(())
}

/// The already loaded scene for the default representation, rebuilt from `source` otherwise.
struct PrebuiltDefault<'a> {
    scene: &'a crate::scene::Scene,
    source: &'a SceneSource,
}

impl SceneProvider for PrebuiltDefault<'_> {
    fn scene_with(
        &self,
        representation: &crate::scene_file::RepresentationOptions,
    ) -> Result<crate::scene::Scene, String> {
        if representation.is_default() {
            Ok(self.scene.clone())
        } else {
            self.source.scene_with(representation)
        }
    }
}

fn write_file(path: &Path, text: &str) -> Result<PathBuf, String> {
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path.to_path_buf())
}

/// Slope label of one configuration for one metric.
fn slope(points: &[AccuracyPoint], config: &str, metric: fn(&AccuracyPoint) -> f64) -> Option<f64> {
    let pts: Vec<(f64, f64)> = converged(points, config)
        .iter()
        .map(|p| (p.seconds, metric(p)))
        .collect();
    loglog_fit(&pts).map(|(m, _)| m)
}

fn write_outputs(
    args: &AccuracyArgs,
    configs: &[AccuracyConfig],
    points: &[AccuracyPoint],
) -> Result<Vec<PathBuf>, String> {
    let out = &args.out;
    let mut written = vec![write_file(&out.join("accuracy.csv"), &to_csv(points))?];
    let rmse: fn(&AccuracyPoint) -> f64 = |p| p.rmse;
    let de: fn(&AccuracyPoint) -> f64 = |p| p.delta_e_mean;
    let scene_name = SceneSource::from_path(args.scene.clone()).describe();
    for (metric, file, ylabel) in [
        (
            rmse,
            "rmse_vs_time",
            if args.exclude_specular {
                "RMSE vs reference (linear sRGB, light and specular pixels excluded)"
            } else {
                "RMSE vs reference (linear sRGB, light excluded)"
            },
        ),
        (
            de,
            "delta_e_vs_time",
            if args.exclude_specular {
                "mean CIEDE2000 vs reference (light and specular pixels excluded)"
            } else {
                "mean CIEDE2000 vs reference (light excluded)"
            },
        ),
    ] {
        let series: Vec<Series> = configs
            .iter()
            .map(|c| Series {
                label: match slope(points, &c.name, metric) {
                    Some(m) => format!("{} (slope {m:.2})", c.name),
                    None => c.name.clone(),
                },
                points: points
                    .iter()
                    .filter(|p| p.config == c.name)
                    .map(|p| (p.seconds, metric(p)))
                    .collect(),
            })
            .collect();
        let labels = PlotLabels {
            title: format!("{scene_name}: error vs render time"),
            x: "render time (s)".into(),
            y: ylabel.into(),
        };
        let (svg, png) = (
            out.join(format!("{file}.svg")),
            out.join(format!("{file}.png")),
        );
        plot_loglog(&series, &labels, &svg, &png).map_err(|e| e.to_string())?;
        written.push(svg);
        written.push(png);
    }
    written.push(write_file(
        &out.join("summary.md"),
        &summary(args, configs, points),
    )?);
    Ok(written)
}

/// The Markdown summary: per configuration the slopes (fitted on points ≥ 4 spp), the
/// samples/s, the final errors and the time to reach the targets.
fn summary(args: &AccuracyArgs, configs: &[AccuracyConfig], points: &[AccuracyPoint]) -> String {
    let rmse: fn(&AccuracyPoint) -> f64 = |p| p.rmse;
    let de: fn(&AccuracyPoint) -> f64 = |p| p.delta_e_mean;
    let fmt_slope = |s: Option<f64>| s.map_or("–".to_string(), |m| format!("{m:.2}"));
    // Measured time if reached; otherwise the fitted power law's estimate, marked "≈ … (fit)".
    let reach = |config: &str, metric: fn(&AccuracyPoint) -> f64, target: f64| {
        if let Some((t, spp)) = time_to_reach(points, config, metric, target) {
            return format!("{t:.2} s ({spp} spp)");
        }
        let pts: Vec<(f64, f64)> = converged(points, config)
            .iter()
            .map(|p| (p.seconds, metric(p)))
            .collect();
        match loglog_fit(&pts) {
            Some((m, b)) if m < -0.05 => {
                format!("≈ {:.0} s (fit)", 10f64.powf((target.log10() - b) / m))
            }
            _ => "not reached".to_string(),
        }
    };
    let mut s = String::new();
    let _ = writeln!(
        s,
        "| config | Msamples/s | slope RMSE | slope ΔE00 | last spp | RMSE | ΔE00 mean | ΔE00 p99 | \
         time to ΔE00 mean ≤ {} | time to RMSE ≤ {} |",
        args.target_delta_e, args.target_rmse
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for c in configs {
        let mine: Vec<&AccuracyPoint> = points.iter().filter(|p| p.config == c.name).collect();
        let Some(last) = mine.last() else { continue };
        let sps = mine
            .iter()
            .map(|p| p.samples_per_second)
            .fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "| {} | {:.3} | {} | {} | {} | {:.5} | {:.3} | {:.3} | {} | {} |",
            c.name,
            sps / 1e6,
            fmt_slope(slope(points, &c.name, rmse)),
            fmt_slope(slope(points, &c.name, de)),
            last.spp,
            last.rmse,
            last.delta_e_mean,
            last.delta_e_p99,
            reach(&c.name, de, args.target_delta_e),
            reach(&c.name, rmse, args.target_rmse),
        );
    }
    let _ = writeln!(s);
    for c in configs {
        let _ = writeln!(s, "- **{}**: {}", c.name, c.trade_off);
    }
    let _ = writeln!(s);
    for (n, why) in unavailable_configs() {
        let _ = writeln!(s, "- not yet available: {n} ({why})");
    }
    s
}
