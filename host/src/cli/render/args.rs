//! The arguments of `spectrace render` (step 1 of the pipeline in [`super`]): the flags, the
//! command line stored in state files for `--resume`, and the settings key every part of one
//! render must share.

use crate::film::SliceSpec;
use crate::scene::Scene;
use std::path::{Path, PathBuf};

/// Arguments of `spectrace render`.
#[derive(clap::Args, Debug, Clone)]
pub struct RenderArgs {
    /// Scene file: RON, or a Mitsuba 3 XML scene (.xml, converted on loading; see `convert`).
    /// Without it the embedded measured Cornell box is rendered.
    pub scene: Option<PathBuf>,
    /// Set a parameter of a Mitsuba XML scene, as Mitsuba's `-D name=value`.
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub define: Vec<String>,
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
    pub effects: crate::integrator::EffectsMode,
    /// Force one effect on or off, NAME=on|off (repeatable): dispersion, fluorescence,
    /// thin-film, narrowband-emission (alias line-emission), flat-path-colour, manifold,
    /// camera-chain, visibility-guide (pt's and bdpt's s = 1 learned light points; see docs/effects.md). Also
    /// light-subpaths=auto|Q: the fraction of bdpt's camera samples that trace light subpaths,
    /// auto (chosen by a short pilot, the default) or Q in [0, 1] (1, 0.5, 1/8, …; 0: every
    /// camera sample path traced, an error where that would lose light); and
    /// light-subpath-count=auto|N: how many light subpaths such a camera sample traces, auto
    /// (the same pilot: 1, 2, 4 or 8 where delta surfaces make caustics, else 1) or N in
    /// [1, 64].
    #[arg(long = "effect", value_name = "NAME=on|off")]
    pub effect: Vec<String>,
    /// Debug (bdpt): write each (s, t) strategy's weighted contribution as its own EXR here.
    #[arg(long = "strategy-images")]
    pub strategy_images: Option<PathBuf>,
    /// Plugin libraries whose types the scene may use.
    #[command(flatten)]
    pub plugins: crate::cli::plugin_args::PluginArgs,
    /// Spectral representation switches (step spectra, RGB-uplifted reflectances, observer step).
    #[command(flatten)]
    pub representation: crate::cli::representation_args::RepresentationArgs,
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
pub(super) struct StoredRender {
    #[command(flatten)]
    pub(super) args: RenderArgs,
}

/// A path made absolute against the current directory (left alone if that fails).
pub(super) fn absolute(p: &Path) -> PathBuf {
    std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf())
}

impl RenderArgs {
    /// The command line that renders the same image (absolute paths), as stored in state files
    /// for `--resume`. Leaves out --threads, --quiet, --resume and the testing hook.
    pub fn to_command_line(&self) -> Vec<String> {
        let mut a = Vec::new();
        self.push_image_flags(&mut a);
        self.push_input_flags(&mut a);
        if self.diagnostic_layer {
            a.push("--diagnostic-layer".into());
        }
        if let Some(s) = &self.scene {
            a.push(absolute(s).display().to_string());
        }
        a
    }

    /// The flags of [`to_command_line`](Self::to_command_line) that shape the image: outputs,
    /// samples, seed, camera, depth, integrator, exposure, resolution, wavelengths, sampler.
    fn push_image_flags(&self, a: &mut Vec<String>) {
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
    }

    /// The flags of [`to_command_line`](Self::to_command_line) that name inputs and extra
    /// outputs: strategy images, sensors, plugins, representation, slice, state, spectral EXR.
    fn push_input_flags(&self, a: &mut Vec<String>) {
        let mut push = |k: &str, v: String| {
            a.push(k.to_string());
            a.push(v);
        };
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
    }

    /// Everything but the seed and the sample count that changes the image, as `name=value`
    /// pairs: what the parts of one render must share.
    ///
    /// `density` is the wavelength density the render draws from (what `--wavelength-sampling`
    /// resolves to for this scene): recorded because a default may change between versions
    /// (bdpt and lt once drew from the observer-plus-emission mixture), and a part drawn from
    /// another density would not make the uninterrupted render.
    pub(super) fn settings_key(&self, scene: &Scene, max_depth: u32, density: &str) -> String {
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
        match crate::integrator::EffectsRequest::parse(self.effects, &self.effect) {
            Ok(r) if r == crate::integrator::EffectsRequest::default() => String::new(),
            Ok(r) => format!(" effects={}", r.key()),
            Err(e) => format!(" effects=invalid({e})"),
        }
    }

    /// Where the state file goes.
    pub(super) fn state_path(&self, slice: Option<SliceSpec>) -> PathBuf {
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

/// `--time SECONDS` as a duration: a positive, finite number of seconds (`render`, `reference`).
pub fn time_budget(seconds: Option<f64>) -> Result<Option<std::time::Duration>, String> {
    match seconds {
        Some(t) if t.is_finite() && t > 0.0 => Ok(Some(std::time::Duration::from_secs_f64(t))),
        Some(t) => Err(format!(
            "--time must be a positive number of seconds, got {t}"
        )),
        None => Ok(None),
    }
}
