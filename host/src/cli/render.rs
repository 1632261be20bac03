//! `spectrace render [SCENE] [-o FILE.exr] [--png FILE.png] [--spp N | --time SECONDS] [--seed N]
//! [--threads N] [--camera NAME] [--slice K/M] [--state FILE] [--resume FILE]
//! [--diagnostic-layer] [--spectral-exr S.exr [--bins START:END:STEP]]`: render a scene file, or the embedded measured Cornell box when no scene
//! is given, with a progress bar and a summary.
//!
//! Slices and checkpoints (see `docs/distributed.md`): `--slice K/M` renders only the sample
//! indices `⌊(K−1)·N/M⌋..⌊K·N/M⌋` of every pixel and writes the exact film to a state file
//! (no image) for `spectrace merge`. Ctrl-C or SIGTERM during a sample-count render writes the
//! image of the whole passes done and the same kind of state file; `--resume FILE` continues it
//! to the image an uninterrupted run would have made, bit for bit.

use crate::film::{
    state_file::fnv1a64, write_exr_with_layers, write_png, FilmState, RenderState, SliceSpec,
    XyzImage,
};
use crate::integrator::{render, PathTracer, RenderSettings, SampleBudget};
use crate::scene::{load_scene_file_with, ObjectFactory, Scene};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Arguments of `spectrace render`.
#[derive(clap::Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene file (RON). Without it the embedded measured Cornell box is rendered.
    pub scene: Option<PathBuf>,
    /// OpenEXR output (R, G, B linear + X, Y, Z); a name ending in .png writes only the PNG.
    #[arg(short = 'o', long = "output", default_value = "render.exr")]
    pub output: PathBuf,
    /// sRGB PNG preview (default: the EXR name with .png).
    #[arg(long)]
    pub png: Option<PathBuf>,
    /// Samples per pixel (default: the scene's, 64 for the Cornell box).
    #[arg(long, conflicts_with = "time", value_parser = crate::limits::parse_spp)]
    pub spp: Option<u32>,
    /// Render for this many seconds instead of a fixed sample count; a pass still running at
    /// the end is stopped after the tiles in flight and dropped (the summary says so).
    #[arg(long)]
    pub time: Option<f64>,
    /// Random seed; the same seed gives the same image for any thread count.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Worker threads (default: one per core).
    #[arg(long, value_parser = crate::limits::parse_threads)]
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
    /// PNG exposure in EV: the PNG shows the image × 2^EV (the EXR is never scaled). Overrides
    /// the scene's `png_exposure`; without either, an image that would be nearly black or
    /// mostly clipped gets an automatic exposure, said in the summary.
    #[arg(long, value_name = "EV", allow_negative_numbers = true, value_parser = parse_ev)]
    pub exposure: Option<f64>,
    /// Image size WxH in pixels, replacing every camera's `resolution` (the field of view
    /// along the camera's `fov_axis` is kept; the other follows the aspect ratio).
    #[arg(long, value_name = "WxH", value_parser = parse_resolution)]
    pub resolution: Option<(u32, u32)>,
    /// Light transport algorithm: bdpt (bidirectional, MIS), pt (path tracing) or lt (light
    /// tracing).
    #[arg(long, default_value = "bdpt")]
    pub integrator: crate::integrator::IntegratorKind,
    /// Path tracing only: wavelengths carried by one camera path, 1 or a multiple of 4 up to
    /// 16 (default 4).
    #[arg(long = "wavelengths-per-path")]
    pub wavelengths_per_path: Option<u32>,
    /// How camera paths draw wavelengths: product (observer importance times the square root
    /// of the lights' emission, plus ¼ observer importance; the default), visible (observer
    /// importance), uniform, or light (the scene's emission SPDs). bdpt and lt take product,
    /// uniform or visible (for them: half observer importance, half the lights' spectra).
    #[arg(long = "wavelength-sampling")]
    pub wavelength_sampling: Option<crate::integrator::WavelengthSampling>,
    /// Numbers of camera samples and light paths: sobol (shuffled, Owen-scrambled Sobol'
    /// points for each sample's first dimensions, the default) or independent (PCG32).
    #[arg(long)]
    pub sampler: Option<crate::integrator::SamplerKind>,
    /// Effects to simulate: auto (what the scene analysis finds, the default) or all (every
    /// switchable effect's machinery, found or not).
    #[arg(long, value_enum, default_value = "auto")]
    pub effects: crate::effects::EffectsMode,
    /// Force one effect on or off, NAME=on|off (repeatable): dispersion, fluorescence,
    /// thin-film, narrowband-emission (alias line-emission), flat-path-colour.
    #[arg(long = "effect", value_name = "NAME=on|off")]
    pub effect: Vec<String>,
    /// Debug (bdpt): write each (s, t) strategy's weighted contribution as its own EXR here.
    #[arg(long = "strategy-images")]
    pub strategy_images: Option<PathBuf>,
    /// Plugin libraries whose types the scene may use.
    #[command(flatten)]
    pub plugins: super::plugin_args::PluginArgs,
    /// Spectral representation switches (step spectra, RGB-uplifted reflectances, observer step).
    #[command(flatten)]
    pub representation: super::representation_args::RepresentationArgs,
    /// Render only slice K of M (1 ≤ K ≤ M) of the sample indices and write its state file
    /// (see --state) for `spectrace merge` instead of an image.
    #[arg(long, value_name = "K/M", conflicts_with = "time")]
    pub slice: Option<String>,
    /// State file of a slice or of an interrupted render (default: OUTPUT.state, for a slice
    /// OUTPUT.slice-K-of-M.state).
    #[arg(long, value_name = "FILE")]
    pub state: Option<PathBuf>,
    /// Continue an interrupted render or slice from its state file, with the settings stored
    /// in it (only --threads and --quiet may be given anew).
    #[arg(long, value_name = "FILE")]
    pub resume: Option<PathBuf>,
    /// Add a `rejected` channel to the EXR: per pixel, the samples the film refused (NaN,
    /// infinite or negative).
    #[arg(long = "diagnostic-layer")]
    pub diagnostic_layer: bool,
    /// Also write the spectral radiance per pixel (W/(m²·sr·nm) at the --bins nodes, tent
    /// weighted; XYZ by the trapezoid rule, see docs/spectral.md) as an OpenEXR in the
    /// Fichet–Pacanowski–Wilkie 2021 layout (`S0.<λ>nm`). Slices and checkpoints carry its
    /// exact sums; `spectrace merge` writes the merged one.
    #[arg(long = "spectral-exr", value_name = "OUT.exr")]
    pub spectral_exr: Option<PathBuf>,
    /// Wavelength nodes of --spectral-exr, START:END:STEP in nm (360:830:1 reproduces the
    /// film's XYZ of a CIE observer exactly).
    #[arg(
        long,
        value_name = "START:END:STEP",
        default_value = "380:780:5",
        requires = "spectral_exr"
    )]
    pub bins: String,
    /// Write each scene sensor's illuminance as DIR/NAME.csv (x,y,z,lux,stderr) and a
    /// false-colour DIR/NAME.png with isolux contours.
    #[arg(long = "sensors-out", value_name = "DIR")]
    pub sensors_out: Option<PathBuf>,
    /// Write the image's luminance per pixel (cd/m²) as a CSV (x,y,cd_m2).
    #[arg(long = "luminance-out", value_name = "F.csv")]
    pub luminance_out: Option<PathBuf>,
    /// Testing hook: stop as if interrupted once this many progress units (tiles or light-path
    /// chunks) are done.
    #[arg(long = "stop-after-units", hide = true)]
    pub stop_after_units: Option<u64>,
    /// Testing hook: once this many progress units are done, print `waiting for a signal` to
    /// stderr and wait (at most 60 s) for Ctrl-C or SIGTERM, so a test can signal mid-render.
    #[arg(long = "wait-for-signal-after-units", hide = true)]
    pub wait_for_signal_after_units: Option<u64>,
}

/// `spectrace render` arguments wrapped for re-parsing a stored command line.
#[derive(clap::Parser, Debug)]
struct StoredRender {
    #[command(flatten)]
    args: RenderArgs,
}

/// A path made absolute against the current directory (left alone if that fails).
fn absolute(p: &Path) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}

impl RenderArgs {
    /// The command line that renders the same image (absolute paths), as stored in state files
    /// for `--resume`. Leaves out --threads, --quiet, --resume and the testing hook.
    pub fn to_command_line(&self) -> Vec<String> {
        let mut a = Vec::new();
        let mut push = |k: &str, v: String| {
            a.push(k.to_string());
            a.push(v);
        };
        push("-o", absolute(&self.output).display().to_string());
        if let Some(p) = &self.png {
            push("--png", absolute(p).display().to_string());
        }
        if let Some(n) = self.spp {
            push("--spp", n.to_string());
        }
        push("--seed", self.seed.to_string());
        if let Some(c) = &self.camera {
            push("--camera", c.clone());
        }
        if let Some(d) = self.max_depth {
            push("--max-depth", d.to_string());
        }
        push("--integrator", self.integrator.to_string());
        if let Some(ev) = self.exposure {
            push("--exposure", ev.to_string());
        }
        if let Some((w, h)) = self.resolution {
            push("--resolution", format!("{w}x{h}"));
        }
        if let Some(n) = self.wavelengths_per_path {
            push("--wavelengths-per-path", n.to_string());
        }
        if let Some(w) = self.wavelength_sampling {
            push("--wavelength-sampling", w.to_string());
        }
        if let Some(k) = self.sampler {
            push("--sampler", k.to_string());
        }
        if let Some(d) = &self.strategy_images {
            push("--strategy-images", absolute(d).display().to_string());
        }
        if let Some(d) = &self.sensors_out {
            push("--sensors-out", absolute(d).display().to_string());
        }
        if let Some(f) = &self.luminance_out {
            push("--luminance-out", absolute(f).display().to_string());
        }
        for l in &self.plugins.libraries {
            push("--plugin", absolute(l).display().to_string());
        }
        for d in &self.plugins.directories {
            push("--plugins", absolute(d).display().to_string());
        }
        let r = &self.representation;
        if let Some(v) = &r.spd_interpolation {
            push("--spd-interpolation", v.clone());
        }
        if let Some(v) = &r.reflectance {
            push("--reflectance", v.clone());
        }
        if let Some(v) = r.observer_step {
            push("--observer-step", v.to_string());
        }
        if let Some(s) = &self.slice {
            push("--slice", s.clone());
        }
        if let Some(s) = &self.state {
            push("--state", absolute(s).display().to_string());
        }
        if let Some(p) = &self.spectral_exr {
            push("--spectral-exr", absolute(p).display().to_string());
            push("--bins", self.bins.clone());
        }
        if self.diagnostic_layer {
            a.push("--diagnostic-layer".into());
        }
        if let Some(s) = &self.scene {
            a.push(absolute(s).display().to_string());
        }
        a
    }

    /// Everything but the seed and the sample count that changes the image, as `name=value`
    /// pairs: what the parts of one render must share.
    ///
    /// `density` is the wavelength density the render draws from (what `--wavelength-sampling`
    /// resolves to for this scene): recorded because a default may change between versions
    /// (bdpt and lt once drew from the observer-plus-emission mixture), and a part drawn from
    /// another density would not make the uninterrupted render.
    fn settings_key(&self, scene: &Scene, max_depth: u32, density: &str) -> String {
        let r = &self.representation;
        format!(
            "integrator={} max_depth={max_depth} wavelengths_per_path={:?} \
             wavelength_sampling={:?} wavelength_density={density} camera={:?} \
             spd_interpolation={:?} reflectance={:?} \
             observer_step={:?} plugins={:?} plugin_dirs={:?} observer={} rgb_space={}{}{}",
            self.integrator,
            self.wavelengths_per_path,
            self.wavelength_sampling.map(|w| w.to_string()),
            self.camera,
            r.spd_interpolation,
            r.reflectance,
            r.observer_step,
            self.plugins
                .libraries
                .iter()
                .map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned()))
                .collect::<Vec<_>>(),
            self.plugins.directories.len(),
            scene.observer.name(),
            scene.options.rgb_space_name,
            // Only when given, so state files written before the flag existed still match.
            self.resolution
                .map_or(String::new(), |(w, h)| format!(" resolution={w}x{h}")),
            self.effects_key(),
        ) + &self.sampler_key()
    }

    /// The sampler in the settings fingerprint; empty for the default (Sobol'), so checkpoints
    /// written before `--sampler` existed still resume.
    fn sampler_key(&self) -> String {
        match self.sampler.unwrap_or_default() {
            crate::integrator::SamplerKind::Sobol => String::new(),
            k => format!(" sampler={k}"),
        }
    }

    /// The effects request in the settings fingerprint; empty for the default (`auto`, nothing
    /// forced), so checkpoints written before `--effects` existed still resume.
    fn effects_key(&self) -> String {
        match crate::effects::EffectsRequest::parse(self.effects, &self.effect) {
            Ok(r) if r == crate::effects::EffectsRequest::default() => String::new(),
            Ok(r) => format!(" effects={}", r.key()),
            Err(e) => format!(" effects=invalid({e})"),
        }
    }

    /// Where the state file goes.
    fn state_path(&self, slice: Option<SliceSpec>) -> PathBuf {
        if let Some(p) = &self.state {
            return p.clone();
        }
        let mut name = self.output.as_os_str().to_owned();
        if let Some(s) = slice {
            name.push(format!(".slice-{}-of-{}", s.index, s.count));
        }
        name.push(".state");
        PathBuf::from(name)
    }
}

/// Load the scene named by `args` (or the default) with the given factories.
pub fn load(args: &RenderArgs, factories: &[&dyn ObjectFactory]) -> Result<Scene, String> {
    let repr = args.representation.options()?;
    let Some((w, h)) = args.resolution else {
        return match &args.scene {
            Some(p) => load_scene_file_with(p, factories, &repr),
            None => crate::scene::cornell::cornell_box_with(factories, &repr),
        }
        .map_err(|e| e.to_string());
    };
    // --resolution: every camera's `resolution` replaced before the scene is built.
    let (mut desc, base, file) = match &args.scene {
        Some(p) => (
            crate::scene::read_scene_file(p).map_err(|e| e.to_string())?,
            p.parent().unwrap_or(Path::new(".")).to_path_buf(),
            p.clone(),
        ),
        None => (
            crate::scene::cornell_box_description().map_err(|e| e.to_string())?,
            PathBuf::from("."),
            PathBuf::from("<embedded cornell box>"),
        ),
    };
    for c in &mut desc.cameras {
        let size: ron::Value = ron::from_str(&format!("({w}, {h})")).map_err(|e| e.to_string())?;
        match &mut c.params {
            ron::Value::Map(m) => {
                m.insert(ron::Value::String("resolution".into()), size);
            }
            p @ ron::Value::Unit => {
                let mut m = ron::Map::new();
                m.insert(ron::Value::String("resolution".into()), size);
                *p = ron::Value::Map(m);
            }
            _ => {}
        }
    }
    crate::scene::build_scene_with(&desc, &base, &file, factories, &repr).map_err(|e| e.to_string())
}

/// An exposure in EV: finite, within ±100 (2^100 already turns any renderable value white).
pub fn parse_ev(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(ev) if ev.is_finite() && ev.abs() <= 100.0 => Ok(ev),
        _ => Err(format!(
            "expected an exposure in EV between -100 and 100, got `{s}`"
        )),
    }
}

/// `WxH` (e.g. `640x480`), each 1..65536 pixels.
pub fn parse_resolution(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("expected WIDTHxHEIGHT in pixels, e.g. 640x480, got `{s}`");
    let (w, h) = s.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    let w: u32 = w.trim().parse().map_err(|_| bad())?;
    let h: u32 = h.trim().parse().map_err(|_| bad())?;
    if !(1..=65536).contains(&w) || !(1..=65536).contains(&h) {
        return Err(format!("each side must be 1..65536 pixels, got {w}x{h}"));
    }
    Ok((w, h))
}

/// The PNG's exposure multiplier and, when it was picked automatically, a line for the summary.
fn png_exposure(args: &RenderArgs, scene: &Scene, image: &XyzImage) -> (f64, Option<String>) {
    if let Some(ev) = args.exposure {
        return (2f64.powf(ev), None);
    }
    if scene.options.png_exposure_given {
        return (scene.options.png_exposure, None);
    }
    match crate::film::exposure::auto_exposure(image) {
        Some(a) => (
            a.multiplier,
            Some(format!(
                "PNG exposure chosen automatically: {:+.1} EV (×{:.4e}), because at 0 EV the image \
                 would be {}; the EXR is unscaled; set it with --exposure EV or `png_exposure`",
                a.ev(),
                a.multiplier,
                if a.was_dark {
                    "nearly black"
                } else {
                    "mostly clipped"
                }
            )),
        ),
        None => (scene.options.png_exposure, None),
    }
}

/// Run `spectrace render` with the built-in types and the plugins named in `args`.
pub fn run(args: &RenderArgs) -> Result<(), String> {
    let registry = std::sync::Arc::new(args.plugins.registry(false)?);
    let faults = crate::plugin::adapter::PluginFaults::new();
    let plugins = crate::plugin::factory::PluginFactory::new(registry, faults.clone());
    // One way in: the registry builds every type, built-in, plugin or blob.
    let result = run_with_factories(args, &[&plugins]);
    // Plugin calls that failed or returned unusable values contributed nothing; say so, once per
    // call site or reason, with counts.
    result?;
    for line in faults.outcome()? {
        println!("  warning: plugin {line}");
    }
    Ok(())
}

/// The name of the wavelength density a render of `scene` under `plan` draws from (the
/// settings fingerprint's `wavelength_density`): the path tracer's lanes as
/// [`PathWavelengthSampler`](crate::integrator::wavelengths::groups::PathWavelengthSampler)
/// resolves them, bdpt's and lt's pairs as
/// [`PairWavelengths`](crate::integrator::wavelengths::pairs::PairWavelengths) does.
fn wavelength_density(
    args: &RenderArgs,
    plan: &crate::effects::RenderPlan,
    scene: &Scene,
) -> Result<String, String> {
    let sampling = args.wavelength_sampling.unwrap_or_default();
    Ok(
        if args.integrator == crate::integrator::IntegratorKind::Pt {
            crate::integrator::wavelengths::groups::PathWavelengthSampler::new(
                plan,
                sampling,
                args.wavelengths_per_path.unwrap_or(4),
                scene.objects.fluorescence(),
            )?
            .sampling()
            .to_string()
        } else {
            let planned = plan.scene(scene);
            crate::integrator::wavelengths::pairs::PairWavelengths::new(plan, &planned, sampling)
                .key()
                .to_string()
        },
    )
}

/// The `name=value` settings that differ between a state's key and this render's, for the
/// refusal message (empty when only the scene file changed).
fn settings_difference(was: &str, now: &str) -> String {
    let (was_set, now_set): (Vec<&str>, Vec<&str>) =
        (was.split(' ').collect(), now.split(' ').collect());
    let only = |a: &[&str], b: &[&str]| {
        a.iter()
            .filter(|t| !b.contains(t))
            .copied()
            .collect::<Vec<_>>()
            .join(" ")
    };
    let (gone, new) = (only(&was_set, &now_set), only(&now_set, &was_set));
    match (gone.is_empty(), new.is_empty()) {
        (true, true) => String::new(),
        (false, true) => format!("; the state also has `{gone}`"),
        (true, false) => format!("; now `{new}`, which the state does not record"),
        (false, false) => format!("; the state has `{gone}`, now `{new}`"),
    }
}

/// Run `spectrace render`, building scene items with `factories` (the registry's factory, or
/// [`crate::scene::BuiltinFactory`] alone).
pub fn run_with_factories(
    args: &RenderArgs,
    factories: &[&dyn ObjectFactory],
) -> Result<(), String> {
    let (args, resume) = match &args.resume {
        Some(path) => resumed_args(args, path)?,
        None => (args.clone(), None),
    };
    let args = &args;
    let outputs = super::output_paths::output_paths(&args.output, args.png.as_deref())?;
    let t_load = std::time::Instant::now();
    let scene = load(args, factories)?;
    let load_s = t_load.elapsed().as_secs_f64();
    // The render plan, decided once: wavelength handling and effects on or off.
    let request = crate::effects::EffectsRequest::parse(args.effects, &args.effect)?;
    let plan = crate::effects::RenderPlan::new(&scene, &request);
    if !args.quiet {
        for n in plan.notes() {
            eprintln!("spectrace: {n}");
        }
    }
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
        && args.wavelengths_per_path.is_some()
    {
        return Err(format!(
            "--wavelengths-per-path applies to --integrator pt only (got --integrator {})",
            args.integrator
        ));
    }
    if let Some(w) = args.wavelength_sampling.filter(|w| {
        args.integrator != crate::integrator::IntegratorKind::Pt
            && !matches!(
                w,
                crate::integrator::WavelengthSampling::Product
                    | crate::integrator::WavelengthSampling::Visible
                    | crate::integrator::WavelengthSampling::Uniform
            )
    }) {
        return Err(format!(
            "--wavelength-sampling {w} applies to --integrator pt only; --integrator {} takes \
             product, uniform or visible (the observer-plus-emission mixture)",
            args.integrator
        ));
    }
    let spectral_bins = match &args.spectral_exr {
        Some(_) => {
            let b = crate::film::spectral::SpectralBins::parse(&args.bins)?;
            let (w, h) = scene
                .cameras
                .get(args.camera.as_deref())
                .map_err(|e| e.to_string())?
                .camera
                .resolution();
            crate::film::spectral_film::check_memory(
                b,
                w,
                h,
                crate::limits::available_memory_bytes(),
            )?;
            Some(b)
        }
        None => None,
    };
    if let (Some((path, st)), Some(b)) = (&resume, spectral_bins) {
        if st.film.spectral.as_ref().map(|s| s.bins) != Some(b) {
            return Err(format!(
                "{}: the state holds no spectral sums at --bins {} (written by another \
                 spectrace?); render again instead",
                path.display(),
                b.spec()
            ));
        }
    }
    let slice = args.slice.as_deref().map(SliceSpec::parse).transpose()?;
    let total_spp = match budget {
        SampleBudget::Spp(n) => Some(n),
        _ => None,
    };
    if let (Some(s), Some(n)) = (slice, total_spp) {
        if s.count > n {
            return Err(format!(
                "--slice {s}: {} slices of a {n} spp render would leave some empty; use at \
                 most {n} slices",
                s.count
            ));
        }
    }
    let max_depth = args.max_depth.unwrap_or(scene.options.max_depth);
    let key = args.settings_key(&scene, max_depth, &wavelength_density(args, &plan, &scene)?);
    let scene_bytes = match &args.scene {
        Some(p) => std::fs::read(p).map_err(|e| format!("cannot read {}: {e}", p.display()))?,
        None => Vec::new(),
    };
    let fingerprint = fnv1a64(&[&scene_bytes, key.as_bytes()]);
    let range = total_spp.map(|n| slice.unwrap_or(SliceSpec::WHOLE).range(n));
    let mut first_sample = range.as_ref().map_or(0, |r| r.start);
    if let Some((path, st)) = &resume {
        if st.fingerprint != fingerprint || st.settings != key {
            return Err(format!(
                "{}: the scene file or settings changed since this state was written \
                 (fingerprint {:016x}, now {fingerprint:016x}{}); render again instead",
                path.display(),
                st.fingerprint,
                settings_difference(&st.settings, &key)
            ));
        }
        first_sample = st.done_until;
    }
    let budget = match (&range, resume.is_some() || slice.is_some()) {
        (Some(r), true) => SampleBudget::Range {
            start: first_sample,
            end: r.end,
        },
        _ => budget,
    };
    let settings = RenderSettings {
        budget,
        seed: args.seed,
        threads: args.threads,
        camera: args.camera.clone(),
        tile_size: 16,
        tracer: PathTracer {
            max_depth,
            wavelengths: args.wavelength_sampling.unwrap_or_default(),
            wavelengths_per_path: args.wavelengths_per_path.unwrap_or(4),
            ..PathTracer::default()
        },
        sampler: args.sampler.unwrap_or_default(),
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
    // Ctrl-C/SIGTERM (or the testing hook) stop the render through one flag.
    let interrupt = super::interrupt::interrupt_flag();
    let stop = std::sync::atomic::AtomicBool::new(false);
    let waited = std::sync::atomic::AtomicBool::new(false);
    let progress = |done: u64, total: u64| {
        bar.set_length(total);
        bar.set_position(done);
        if args.wait_for_signal_after_units.is_some_and(|k| done >= k)
            && !waited.swap(true, std::sync::atomic::Ordering::SeqCst)
        {
            eprintln!("waiting for a signal");
            let t = std::time::Instant::now();
            while !interrupt.load(std::sync::atomic::Ordering::SeqCst)
                && t.elapsed() < Duration::from_secs(60)
            {
                std::thread::sleep(Duration::from_millis(5));
            }
        }
        if interrupt.load(std::sync::atomic::Ordering::Relaxed)
            || args.stop_after_units.is_some_and(|k| done >= k)
        {
            stop.store(true, std::sync::atomic::Ordering::Relaxed);
        }
    };
    let _ = render;
    let already_done = range.as_ref().is_some_and(|r| first_sample >= r.end);
    let mut output = if already_done {
        None
    } else {
        Some(
            crate::integrator::select::render_planned_with_options(
                &scene,
                &plan,
                &settings,
                args.integrator,
                crate::integrator::IntegratorOptions {
                    strategy_images: args.strategy_images.is_some(),
                    spectral: spectral_bins,
                },
                &progress,
                Some(&stop),
            )
            .map_err(|e| e.to_string())?,
        )
    };
    let stopped = stop.load(std::sync::atomic::Ordering::Relaxed);
    // The whole film: the resumed state's plus this run's (exact, so the same bits as one run).
    let (w, h) = scene
        .cameras
        .get(args.camera.as_deref())
        .map_err(|e| e.to_string())?
        .camera
        .resolution();
    let mut new_spp = 0;
    let this_run = match &mut output {
        Some(o) => {
            new_spp = o.result.spp;
            std::mem::replace(&mut o.film, FilmState::new(0, 0, false))
        }
        None => FilmState::new(w, h, false),
    };
    let film = match resume {
        Some((_, st)) => {
            let mut f = st.film;
            f.merge(&this_run);
            f
        }
        None => this_run,
    };
    // A slice, or an unfinished render (the checkpoint), is saved; a finished whole render
    // needs no state file.
    let done_until = first_sample + new_spp;
    if let Some(r) = range
        .as_ref()
        .filter(|r| slice.is_some() || done_until != r.end)
    {
        let state = RenderState {
            scene: args.scene.as_deref().map(absolute),
            fingerprint,
            settings: key.clone(),
            args: {
                // The sample count goes into the stored command line even when it came from
                // the scene, so --resume aims at the same N.
                let mut a = args.to_command_line();
                if args.spp.is_none() {
                    a.extend(["--spp".to_string(), total_spp.unwrap_or(0).to_string()]);
                }
                a
            },
            seed: args.seed,
            spp_total: total_spp.unwrap_or(0),
            slice: slice.unwrap_or(SliceSpec::WHOLE),
            done_until,
            rgb_space: scene.options.rgb_space_name.clone(),
            png_exposure: scene.options.png_exposure,
            film,
        };
        let film = &state.film;
        let state_path = args.state_path(slice);
        let complete = state.is_complete();
        state.save(&state_path).map_err(|e| e.to_string())?;
        if let Some(s) = slice {
            bar.finish_and_clear();
            for line in film.rejected.summary() {
                println!("  {line}");
            }
            if !complete {
                return Err(format!(
                    "interrupted: slice {s} holds samples {}..{} of {}..{}; state written to \
                     {}; continue with `spectrace render --resume {}`",
                    r.start,
                    state.done_until,
                    r.start,
                    r.end,
                    state_path.display(),
                    state_path.display()
                ));
            }
            println!(
                "slice {s}: samples {}..{} of every pixel ({} spp in all), {} rendered now; wrote {}",
                r.start,
                r.end,
                state.spp_total,
                new_spp,
                state_path.display()
            );
            return Ok(());
        }
        {
            bar.finish_and_clear();
            let image = film.image();
            let mut written = save(&image, &outputs, &scene, extra_layers(args, film), args)?;
            if let Some((p, _)) = write_spectral(args, film, &image, &scene)? {
                written.push(p);
            }
            for wr in written {
                println!(
                    "  wrote {} (partial: {} spp)",
                    wr.display(),
                    state.done_until
                );
            }
            return Err(format!(
                "interrupted after {} of {} spp; checkpoint written to {}; continue with \
                 `spectrace render --resume {}`",
                state.done_until,
                state.spp_total,
                state_path.display(),
                state_path.display()
            ));
        }
    }
    // The image comes from the whole film (resumed part included).
    if let Some(o) = &mut output {
        o.result.image = film.image();
        o.result.spp = range
            .as_ref()
            .map_or(o.result.spp, |r| first_sample + new_spp - r.start);
    }
    let Some(output) = output else {
        let image = film.image();
        for wr in save(&image, &outputs, &scene, extra_layers(args, &film), args)? {
            println!("  wrote {}", wr.display());
        }
        if let Some((_, line)) = write_spectral(args, &film, &image, &scene)? {
            println!("{line}");
        }
        return Ok(());
    };
    let result = &output.result;
    bar.finish_and_clear();
    println!("integrator {}:", args.integrator);
    for line in crate::integrator::strategy_summary(&scene, args.integrator) {
        println!("  {line}");
    }
    println!("  {}", plan.summary_line());
    for n in plan.notes() {
        println!("  {n}");
    }
    println!(
        "  sampler: {}",
        match settings.sampler {
            crate::integrator::SamplerKind::Sobol => {
                "sobol (shuffled, Owen-scrambled Sobol' points for the first dimensions of each sample)"
            }
            crate::integrator::SamplerKind::Independent => "independent (PCG32)",
        }
    );
    if args.integrator == crate::integrator::IntegratorKind::Pt {
        let (sampling, n) = (
            settings.tracer.wavelengths,
            settings.tracer.wavelengths_per_path,
        );
        let sampler = crate::integrator::wavelengths::groups::PathWavelengthSampler::new(
            &plan,
            sampling,
            n,
            scene.objects.fluorescence(),
        );
        let fell_back = sampling == crate::integrator::WavelengthSampling::LightSpd
            && sampler.as_ref().is_ok_and(|s| s.light_spd_fell_back());
        let refused = sampler
            .as_ref()
            .is_ok_and(|s| s.light_spd_refused_for_fluorescence());
        println!(
            "  wavelengths: {n} per path, {}",
            if refused {
                "light-SPD sampling requested but the scene fluoresces (light appears where no light emits): visible-importance used".to_string()
            } else if fell_back {
                "light-SPD sampling requested but no light has an evaluable spectrum: visible-importance used".to_string()
            } else {
                let used = sampler.as_ref().map_or(sampling, |s| s.sampling());
                match used {
                    crate::integrator::WavelengthSampling::Visible
                        if plan.emission_wavelengths()
                            && plan.mixture().emission_weight() >= 1.0 =>
                    {
                        "all from the lights' spectra (render plan: all emission is narrowband)"
                    }
                    crate::integrator::WavelengthSampling::Visible
                        if plan.emission_wavelengths() =>
                    {
                        "half visible-importance, half from the lights' spectra (render plan)"
                    }
                    crate::integrator::WavelengthSampling::Visible
                        if sampling == crate::integrator::WavelengthSampling::Product =>
                    {
                        "visible-importance sampling (observer × emission does not apply: no evaluable light, or fluorescence)"
                    }
                    crate::integrator::WavelengthSampling::Visible => "visible-importance sampling",
                    crate::integrator::WavelengthSampling::Product => {
                        "observer × √emission importance (¾) with visible importance (¼)"
                    }
                    crate::integrator::WavelengthSampling::Uniform => "uniform sampling",
                    crate::integrator::WavelengthSampling::LightSpd => {
                        "light-SPD importance sampling"
                    }
                }
                .to_string()
            }
        );
    } else {
        // bdpt and lt: the density the render drew its pairs from (the plan's cached table).
        let planned = plan.scene(&scene);
        let pair = crate::integrator::wavelengths::pairs::PairWavelengths::new(
            &plan,
            &planned,
            settings.tracer.wavelengths,
        );
        println!("  wavelengths: one set per path pair, {}", pair.describe());
    }
    if let Some(dir) = &args.strategy_images {
        for w in crate::integrator::select::write_strategy_images(dir, &output, &scene)? {
            println!("  wrote {}", w.display());
        }
    }

    let written = save(
        &result.image,
        &outputs,
        &scene,
        extra_layers(args, &film),
        args,
    )?;
    let exposure_note = png_exposure(args, &scene, &result.image).1;
    if let Some((_, line)) = write_spectral(args, &film, &result.image, &scene)? {
        println!("{line}");
    }

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
    // A black image is never what the user meant: say so, with what the plan knows about why.
    if result.image.non_finite_count() == 0 && result.image.xyz.iter().all(|p| p[1] == 0.0) {
        use crate::effects::Effect;
        let effects = plan.effects();
        let why = match args.integrator {
            crate::integrator::IntegratorKind::Lt if effects.contains(Effect::DeltaBsdfs) => {
                " light tracing cannot show specular surfaces the camera sees directly \
                 (this scene has some); try --integrator bdpt or pt"
            }
            crate::integrator::IntegratorKind::Pt if effects.contains(Effect::DeltaLights) => {
                " the path tracer cannot reach a point, spot or directional light through a \
                 specular surface (only next-event estimation finds them); try --integrator bdpt"
            }
            _ => " check that a light reaches what the camera sees (`spectrace explain`)",
        };
        println!("  warning: the image is black (every pixel 0):{why}");
    }
    if let Some(d) = result.dropped_pass {
        println!(
            "  time budget: the pass of {} spp running at its end was stopped {:.2} s in and \
             dropped; the image holds the {} spp of the whole passes",
            d.spp,
            d.after.as_secs_f64(),
            result.spp
        );
    }
    for line in film.rejected.summary() {
        println!("  {line}");
    }
    for w in written {
        println!("  wrote {}", w.display());
    }
    if let Some(note) = exposure_note {
        println!("  {note}");
    }
    if scene.options.length_unit != crate::scene::LengthUnit::Metre {
        println!(
            "  scene units: {} (lengths converted to metres when the scene was built)",
            scene.options.length_unit
        );
    }
    if let Some(path) = &args.luminance_out {
        super::sensors::write_luminance(&scene, &result.image, path)?;
    }
    if !stopped {
        super::sensors::measure_sensors(
            &scene,
            &settings,
            args.integrator,
            total_spp.unwrap_or(scene.options.spp),
            args.sensors_out.as_deref(),
        )?;
    }
    for w in scene.warnings() {
        println!("  warning: {w}");
    }
    if stopped && range.is_none() {
        return Err(format!(
            "interrupted: the image holds the {} spp rendered before the stop (a time budget \
             has no checkpoint; render with --spp to be able to resume)",
            result.spp
        ));
    }
    Ok(())
}

/// Write `--spectral-exr` from the film's spectral sums, if asked for; returns the file and a
/// summary line comparing the XYZ integrated from it with the film's `image`.
fn write_spectral(
    args: &RenderArgs,
    film: &FilmState,
    image: &XyzImage,
    scene: &Scene,
) -> Result<Option<(PathBuf, String)>, String> {
    let (Some(path), Some(spectral)) = (&args.spectral_exr, film.spectral_image()) else {
        return Ok(None);
    };
    spectral.write_exr(path)?;
    let line = spectral_summary(path, &spectral, image, scene.observer.as_ref());
    Ok(Some((path.clone(), line)))
}

/// One line: the spectral file, its nodes, and its mean XYZ by the trapezoid rule against the
/// film's (relative differences).
pub fn spectral_summary(
    path: &Path,
    spectral: &crate::film::spectral::SpectralImage,
    image: &XyzImage,
    observer: &dyn crate::color::Observer,
) -> String {
    let from_nodes = spectral.to_xyz(observer);
    let n = image.xyz.len().max(1) as f64;
    let mean = |v: &[[f64; 3]], c: usize| v.iter().map(|p| p[c]).sum::<f64>() / n;
    let rel: Vec<String> = (0..3)
        .map(|c| {
            let (a, b) = (mean(&from_nodes, c), mean(&image.xyz, c));
            if b != 0.0 {
                format!("{:+.1e}", (a - b) / b)
            } else {
                "n/a".into()
            }
        })
        .collect();
    let w = &spectral.wavelengths;
    format!(
        "  wrote {} ({} nodes {}–{} nm every {} nm); mean Y from the nodes {:.6}, film Y {:.6}; \
         relative difference X {} Y {} Z {} (rounding when the nodes are the observer's 1 nm \
         grid over its whole range, else the interpolation between nodes and the light \
         outside them)",
        path.display(),
        w.len(),
        w.first().copied().unwrap_or(0.0),
        w.last().copied().unwrap_or(0.0),
        spectral.step,
        mean(&from_nodes, 1),
        mean(&image.xyz, 1),
        rel[0],
        rel[1],
        rel[2]
    )
}

/// The optional diagnostic channels of the EXR.
fn extra_layers(args: &RenderArgs, film: &FilmState) -> Vec<(String, Vec<f32>)> {
    if !args.diagnostic_layer {
        return Vec::new();
    }
    let (w, h) = film.resolution();
    vec![(
        "rejected".to_string(),
        film.rejected.layer(w as usize * h as usize),
    )]
}

/// For `--resume FILE`: the stored command line (with this run's --threads, --quiet and the
/// testing hook) and the state.
fn resumed_args(
    args: &RenderArgs,
    path: &Path,
) -> Result<(RenderArgs, Option<(PathBuf, RenderState)>), String> {
    if args.scene.is_some()
        || args.spp.is_some()
        || args.time.is_some()
        || args.slice.is_some()
        || args.state.is_some()
    {
        return Err(format!(
            "--resume {} takes the scene, samples, slice and state file from that file; give \
             only --threads and --quiet with it",
            path.display()
        ));
    }
    let state = RenderState::load(path).map_err(|e| e.to_string())?;
    use clap::Parser;
    let mut stored = StoredRender::try_parse_from(
        std::iter::once("render".to_string()).chain(state.args.iter().cloned()),
    )
    .map_err(|e| {
        format!(
            "{}: the stored command line does not parse: {e}",
            path.display()
        )
    })?
    .args;
    stored.threads = args.threads;
    stored.quiet = args.quiet;
    stored.stop_after_units = args.stop_after_units;
    stored.wait_for_signal_after_units = args.wait_for_signal_after_units;
    stored.state = Some(path.to_path_buf());
    if stored.seed != state.seed || stored.spp != Some(state.spp_total) {
        return Err(format!(
            "{}: the stored command line does not match the state (seed, spp)",
            path.display()
        ));
    }
    Ok((stored, Some((path.to_path_buf(), state))))
}

/// Write the EXR and PNG. If the EXR cannot be written where asked, the work is not lost: it
/// goes to a rescue file in the temp directory and the error says where.
fn save(
    image: &XyzImage,
    outputs: &super::output_paths::OutputPaths,
    scene: &Scene,
    extra: Vec<(String, Vec<f32>)>,
    args: &RenderArgs,
) -> Result<Vec<PathBuf>, String> {
    save_image(
        image,
        outputs.exr.as_deref(),
        &outputs.png,
        &scene.options.rgb_space,
        png_exposure(args, scene, image).0,
        extra,
    )
}

/// [`save`] with the colour space and PNG exposure given (for `spectrace merge`); no EXR is
/// written when `exr` is `None` (`-o x.png`).
pub fn save_image(
    image: &XyzImage,
    exr: Option<&Path>,
    png: &Path,
    space: &crate::color::RgbColorSpace,
    png_exposure: f64,
    extra: Vec<(String, Vec<f32>)>,
) -> Result<Vec<PathBuf>, String> {
    let mut written = Vec::new();
    let mut errors = Vec::new();
    match exr.map(|exr| (exr, write_exr_with_layers(exr, image, space, extra.clone()))) {
        None => {}
        Some((exr, Ok(()))) => written.push(exr.to_path_buf()),
        Some((_, Err(e))) => {
            let rescue =
                std::env::temp_dir().join(format!("spectrace-rescue-{}.exr", std::process::id()));
            match write_exr_with_layers(&rescue, image, space, extra) {
                Ok(()) => errors.push(format!("{e}; the image was saved to {}", rescue.display())),
                Err(e2) => errors.push(format!("{e}; rescue copy failed too: {e2}")),
            }
        }
    }
    match write_png(png, image, png_exposure) {
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
