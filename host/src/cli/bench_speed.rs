//! `spectrace bench speed [--budget SECONDS] [--threads N] [--python PY] [--out DIR]`: the
//! Cornell box and the glass-sphere caustic rendered for the same wall-clock budget by
//! spectrace's path tracer and BDPT and by the anchors (Mitsuba 3's spectral path tracer,
//! LuxCore's BIDIRCPU and PATHCPU, through `scripts/anchors/anchor_render.py`), every image
//! compared with one long reference per scene (directly visible light left out, as
//! `spectrace compare` does). Prints and writes DIR/speed.md, one row per render: renderer,
//! integrator, spp, seconds, samples/s, RMSE, efficiency `1/(RMSE²·seconds)` and its ratio to the
//! best anchor on that scene. An anchor that cannot be installed or run is reported and skipped.
//!
//! Paths default to the repository layout, so run it from the repository root (or pass them).

use crate::analysis::{compare_images_excluding, CompareOptions, RgbImage};
use crate::integrator::{render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget};
use crate::scene::SceneSource;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Arguments of `spectrace bench speed`.
#[derive(clap::Args, Debug, Clone)]
pub struct SpeedArgs {
    /// Wall-clock budget of every render, in seconds.
    #[arg(long, default_value_t = 10.0)]
    pub budget: f64,
    /// Worker threads of every renderer.
    #[arg(long, default_value_t = 2)]
    pub threads: usize,
    /// Comma-separated scenes: cornell, caustic.
    #[arg(long, value_delimiter = ',', default_value = "cornell,caustic")]
    pub scenes: Vec<String>,
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
    /// Seed of spectrace's renders (the anchors get it too).
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
    spp: u32,
    seconds: f64,
    pixels: usize,
    rmse: f64,
}

impl SpeedRow {
    fn samples_per_second(&self) -> f64 {
        self.spp as f64 * self.pixels as f64 / self.seconds.max(1e-9)
    }
    /// Equal-time efficiency: error variance falls as 1/time, so 1/(RMSE²·t) is independent of
    /// the budget for an unbiased renderer.
    fn efficiency(&self) -> f64 {
        1.0 / (self.rmse * self.rmse * self.seconds.max(1e-9))
    }
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
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let mut rows = Vec::new();
    let mut notes = Vec::new();
    for scene_name in &args.scenes {
        let (source, reference_path) = match scene_name.as_str() {
            "cornell" => (SceneSource::from_path(None), &args.cornell_reference),
            "caustic" => (
                SceneSource::from_path(Some(args.caustic_scene.clone())),
                &args.caustic_reference,
            ),
            other => {
                return Err(format!(
                    "unknown scene '{other}' in --scenes (known: cornell, caustic)"
                ))
            }
        };
        let reference = RgbImage::read_exr(reference_path).map_err(|e| {
            format!("{e} (run from the repository root or pass the reference's path)")
        })?;
        let scene = source
            .build(&Default::default())
            .map_err(|e| format!("{scene_name}: {e}"))?;
        for (kind, label) in [(IntegratorKind::Pt, "pt"), (IntegratorKind::Bdpt, "bdpt")] {
            let settings = RenderSettings {
                sampler: Default::default(),
                budget: SampleBudget::Time(Duration::from_secs_f64(args.budget)),
                seed: args.seed,
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
            let path = args.out.join(format!("{scene_name}_spectrace_{label}.exr"));
            crate::film::write_exr(&path, &out.result.image, &scene.options.rgb_space)
                .map_err(|e| format!("{}: {e}", path.display()))?;
            let row = SpeedRow {
                scene: scene_name.clone(),
                renderer: format!("spectrace {}", env!("CARGO_PKG_VERSION")),
                integrator: label.into(),
                anchor: false,
                spp: out.result.spp,
                seconds: out.result.elapsed.as_secs_f64(),
                pixels: img.width as usize * img.height as usize,
                rmse: rmse(&img, &reference, scene_name)?,
            };
            print_row(&row);
            rows.push(row);
        }
        if args.no_anchors {
            continue;
        }
        for (renderer, flag, value) in ANCHORS {
            let path = args
                .out
                .join(format!("{scene_name}_{renderer}_{value}.exr"));
            match run_anchor(args, scene_name, renderer, flag, value, &path) {
                Ok((spp, seconds, renderer, integrator)) => {
                    let img = RgbImage::read_exr(&path).map_err(|e| e.to_string())?;
                    let row = SpeedRow {
                        scene: scene_name.clone(),
                        renderer,
                        integrator,
                        anchor: true,
                        spp,
                        seconds,
                        pixels: img.width as usize * img.height as usize,
                        rmse: rmse(&img, &reference, scene_name)?,
                    };
                    print_row(&row);
                    rows.push(row);
                }
                Err(why) => {
                    let note = format!("{scene_name}: {renderer} {value} skipped: {why}");
                    println!("{note}");
                    notes.push(note);
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
        "{:8} {:22} {:28} {:6} spp {:7.2} s {:7.3} Msamples/s  RMSE {:.5}",
        r.scene,
        r.renderer,
        r.integrator,
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
        .arg(args.seed.to_string())
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

/// The Markdown table: per scene, each row's efficiency relative to the best anchor's.
fn table(rows: &[SpeedRow], args: &SpeedArgs, notes: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Budget {} s per render, {} threads; RMSE in linear sRGB against the scene's reference, \
         directly visible light excluded; efficiency = 1/(RMSE²·seconds).\n",
        args.budget, args.threads
    );
    let _ = writeln!(
        s,
        "| scene | renderer | integrator | spp | seconds | Msamples/s | RMSE | efficiency | × best anchor |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let best = rows
            .iter()
            .filter(|a| a.anchor && a.scene == r.scene)
            .map(SpeedRow::efficiency)
            .fold(None, |m: Option<f64>, e| Some(m.map_or(e, |m| m.max(e))));
        let ratio = best.map_or("–".to_string(), |b| format!("{:.2}", r.efficiency() / b));
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.2} | {:.3} | {:.5} | {:.0} | {} |",
            r.scene,
            r.renderer,
            r.integrator,
            r.spp,
            r.seconds,
            r.samples_per_second() / 1e6,
            r.rmse,
            r.efficiency(),
            ratio
        );
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
    // the item: a non-positive budget, zero threads, an unknown scene name.
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
            spp: 10,
            seconds: 2.0,
            pixels: 100,
            rmse,
        };
        assert_eq!(row(0.5).efficiency(), 2.0);
        assert_eq!(row(0.25).efficiency(), 8.0);
        assert_eq!(row(0.5).samples_per_second(), 500.0);
    }
}
