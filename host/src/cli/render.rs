//! `spectrace render [SCENE] [-o FILE.exr] [--png FILE.png] [--spp N | --time SECONDS] [--seed N]
//! [--threads N] [--camera NAME]`: render a scene file, or the embedded measured Cornell box when
//! no scene is given, with a progress bar and a summary.

use crate::film::{write_exr, write_png, XyzImage};
use crate::integrator::{render, PathTracer, RenderSettings, SampleBudget};
use crate::scene::{load_scene_file_with, ObjectFactory, Scene};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Arguments of `spectrace render`.
#[derive(clap::Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene file (RON). Without it the embedded measured Cornell box is rendered.
    pub scene: Option<PathBuf>,
    /// OpenEXR output (R, G, B linear + X, Y, Z).
    #[arg(short = 'o', long = "output", default_value = "render.exr")]
    pub output: PathBuf,
    /// sRGB PNG preview (default: the EXR name with .png).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Samples per pixel (default: the scene's, 64 for the Cornell box).
    #[arg(long, conflicts_with = "time")]
    pub spp: Option<u32>,
    /// Render for this many seconds instead of a fixed sample count.
    #[arg(long)]
    pub time: Option<f64>,
    /// Random seed; the same seed gives the same image for any thread count.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Camera name (default: the scene's first camera).
    #[arg(long)]
    pub camera: Option<String>,
    /// Maximum path depth (default: the scene's, 64).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Light transport algorithm: bdpt (bidirectional, MIS), pt (path tracing) or lt (light
    /// tracing).
    #[arg(long, default_value = "bdpt")]
    pub integrator: crate::integrator::IntegratorKind,
    /// Path tracing only: wavelengths carried by one camera path, 1 or a multiple of 4 up to
    /// 16 (default 4).
    #[arg(long = "wavelengths-per-path")]
    pub wavelengths_per_path: Option<u32>,
    /// Path tracing only: how camera paths draw wavelengths: visible (observer importance,
    /// default), uniform, or light (the scene's emission SPDs).
    #[arg(long = "wavelength-sampling")]
    pub wavelength_sampling: Option<crate::integrator::WavelengthSampling>,
    /// Debug (bdpt): write each (s, t) strategy's weighted contribution as its own EXR here.
    #[arg(long = "strategy-images")]
    pub strategy_images: Option<PathBuf>,
    /// Plugin libraries whose types the scene may use.
    #[command(flatten)]
    pub plugins: super::plugin_args::PluginArgs,
    /// Spectral representation switches (step spectra, RGB-uplifted reflectances, observer step).
    #[command(flatten)]
    pub representation: super::representation_args::RepresentationArgs,
}

/// Load the scene named by `args` (or the default) with the given factories.
pub fn load(args: &RenderArgs, factories: &[&dyn ObjectFactory]) -> Result<Scene, String> {
    let repr = args.representation.options()?;
    match &args.scene {
        Some(p) => load_scene_file_with(p, factories, &repr),
        None => crate::scene::cornell::cornell_box_with(factories, &repr),
    }
    .map_err(|e| e.to_string())
}

/// Run `spectrace render` with the built-in types and the plugins named in `args`.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    let registry = std::sync::Arc::new(args.plugins.registry(false)?);
    let faults = crate::plugin::adapter::PluginFaults::new();
    let plugins = crate::plugin::factory::PluginFactory::new(registry, faults.clone());
    // One way in: the registry builds every type, built-in, plugin or blob.
    let result = run_with_factories(args, &[&plugins]);
    // Plugin calls that failed during rendering contributed nothing; say so, with the first cause.
    if let Some(first) = faults.first() {
        return Err(format!(
            "{} plugin call(s) failed during rendering (their samples contributed nothing; the \
             image was still written); first: {first}",
            faults.count()
        ));
    }
    result
}

/// Run `spectrace render`, building scene items with `factories` (the registry's factory, or
/// [`crate::scene::BuiltinFactory`] alone).
pub fn run_with_factories(
    args: &RenderArgs,
    factories: &[&dyn ObjectFactory],
) -> Result<(), String> {
    let t_load = std::time::Instant::now();
    let scene = load(args, factories)?;
    let load_s = t_load.elapsed().as_secs_f64();
    let budget = match (args.spp, args.time) {
        (_, Some(t)) if t.is_finite() && t > 0.0 => SampleBudget::Time(Duration::from_secs_f64(t)),
        (_, Some(t)) => {
            return Err(format!(
                "--time must be a positive number of seconds, got {t}"
            ))
        }
        (Some(0), _) => return Err("--spp must be at least 1".into()),
        (Some(n), _) => SampleBudget::Spp(n),
        (None, None) => SampleBudget::Spp(scene.options.spp),
    };
    if args.integrator != crate::integrator::IntegratorKind::Pt
        && (args.wavelengths_per_path.is_some() || args.wavelength_sampling.is_some())
    {
        return Err(format!(
            "--wavelengths-per-path and --wavelength-sampling apply to --integrator pt only \
             (got --integrator {})",
            args.integrator
        ));
    }
    let settings = RenderSettings {
        budget,
        seed: args.seed,
        threads: args.threads,
        camera: args.camera.clone(),
        tile_size: 16,
        tracer: PathTracer {
            max_depth: args.max_depth.unwrap_or(scene.options.max_depth),
            wavelengths: args.wavelength_sampling.unwrap_or_default(),
            wavelengths_per_path: args.wavelengths_per_path.unwrap_or(4),
            ..PathTracer::default()
        },
    };
    let bar = if args.quiet {
        indicatif::ProgressBar::hidden()
    } else {
        let b = indicatif::ProgressBar::new(1);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] [{bar:40}] {percent:>3}% tiles, eta {eta}",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar())
            .progress_chars("=> "),
        );
        b
    };
    let progress = |done: u64, total: u64| {
        bar.set_length(total);
        bar.set_position(done);
    };
    let cancel = super::interrupt::interrupt_flag();
    let _ = render;
    let output = crate::integrator::render_with(
        &scene,
        &settings,
        args.integrator,
        args.strategy_images.is_some(),
        &progress,
        Some(cancel),
    )
    .map_err(|e| e.to_string())?;
    let result = &output.result;
    bar.finish_and_clear();
    println!("integrator {}:", args.integrator);
    for line in crate::integrator::strategy_summary(&scene, args.integrator) {
        println!("  {line}");
    }
    if args.integrator == crate::integrator::IntegratorKind::Pt {
        let (sampling, n) = (
            settings.tracer.wavelengths,
            settings.tracer.wavelengths_per_path,
        );
        let fell_back = sampling == crate::integrator::WavelengthSampling::LightSpd
            && crate::integrator::wavelength_groups::PathWavelengthSampler::new(
                &scene, sampling, n,
            )
            .is_ok_and(|s| s.light_spd_fell_back());
        println!(
            "  wavelengths: {n} per path, {}",
            if fell_back {
                "light-SPD sampling requested but no light has an evaluable spectrum: visible-importance used".to_string()
            } else {
                match sampling {
                    crate::integrator::WavelengthSampling::Visible => "visible-importance sampling",
                    crate::integrator::WavelengthSampling::Uniform => "uniform sampling",
                    crate::integrator::WavelengthSampling::LightSpd => {
                        "light-SPD importance sampling"
                    }
                }
                .to_string()
            }
        );
    }
    if let Some(dir) = &args.strategy_images {
        for w in crate::integrator::select::write_strategy_images(dir, &output, &scene)? {
            println!("  wrote {}", w.display());
        }
    }

    let png = args
        .png
        .clone()
        .unwrap_or_else(|| args.output.with_extension("png"));
    let written = save(&result.image, &args.output, &png, &scene)?;

    let secs = result.elapsed.as_secs_f64().max(1e-9);
    let rgb = scene.options.rgb_space.xyz_to_rgb(result.image.mean_xyz());
    println!(
        "rendered {}×{} at {} spp ({} samples) in {:.2} s (scene load {:.2} s, {} threads)",
        result.image.width,
        result.image.height,
        result.spp,
        result.samples,
        secs,
        load_s,
        args.threads.unwrap_or_else(rayon::current_num_threads),
    );
    println!(
        "  {:.3} M samples/s, {:.3} M rays/s, mean linear {} ({:.5}, {:.5}, {:.5}), non-finite pixels: {}",
        result.samples as f64 / secs / 1e6,
        result.rays as f64 / secs / 1e6,
        scene.options.rgb_space_name,
        rgb[0],
        rgb[1],
        rgb[2],
        result.image.non_finite_count()
    );
    for w in written {
        println!("  wrote {}", w.display());
    }
    for w in scene.warnings() {
        println!("  warning: {w}");
    }
    Ok(())
}

/// Write the EXR and PNG. If the EXR cannot be written where asked, the work is not lost: it
/// goes to a rescue file in the temp directory and the error says where.
fn save(image: &XyzImage, exr: &Path, png: &Path, scene: &Scene) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    let mut errors = Vec::new();
    match write_exr(exr, image, &scene.options.rgb_space) {
        Ok(()) => written.push(exr.to_path_buf()),
        Err(e) => {
            let rescue =
                std::env::temp_dir().join(format!("spectrace-rescue-{}.exr", std::process::id()));
            match write_exr(&rescue, image, &scene.options.rgb_space) {
                Ok(()) => errors.push(format!("{e}; the image was saved to {}", rescue.display())),
                Err(e2) => errors.push(format!("{e}; rescue copy failed too: {e2}")),
            }
        }
    }
    match write_png(png, image, scene.options.png_exposure) {
        Ok(()) => written.push(png.to_path_buf()),
        Err(e) => errors.push(e.to_string()),
    }
    if errors.is_empty() {
        Ok(written)
    } else {
        for w in &written {
            eprintln!("spectrace: wrote {}", w.display());
        }
        Err(errors.join("; "))
    }
}
