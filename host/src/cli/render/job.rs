//! A render decided before it starts (step 2 of the pipeline in [`super`]): the arguments
//! (those stored in the state file for `--resume`), the scene, the render plan, the sample
//! budget and range, the settings key and fingerprint, and the integrator settings, every flag
//! checked against the others and against the resumed state.

use super::args::{RenderArgs, StoredRender};
use super::scene::load;
use crate::cli::output_paths::{output_paths, OutputPaths};
use crate::film::spectral::SpectralBins;
use crate::film::{state_file::fnv1a64, RenderState, SliceSpec};
use crate::integrator::{EffectsRequest, RenderPlan};
use crate::integrator::{
    IntegratorKind, PathTracer, RenderSettings, SampleBudget, WavelengthSampling,
};
use crate::scene::Scene;
use crate::scene_file::ObjectFactory;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// One render, decided: what to render, from which sample to which, with which settings.
pub struct RenderJob {
    /// The arguments (the stored ones for `--resume`, with this run's threads and quiet).
    pub args: RenderArgs,
    /// The state resumed from, and its file.
    pub resume: Option<(PathBuf, RenderState)>,
    /// Where the EXR and PNG go.
    pub outputs: OutputPaths,
    /// The scene, built.
    pub scene: Scene,
    /// Seconds spent loading the scene.
    pub load_s: f64,
    /// The render plan: wavelength handling and effects on or off.
    pub plan: RenderPlan,
    /// `--spectral-exr`'s bins.
    pub spectral_bins: Option<SpectralBins>,
    /// `--slice K/M`.
    pub slice: Option<SliceSpec>,
    /// The whole render's samples per pixel (`None` for a time budget).
    pub total_spp: Option<u32>,
    /// The sample indices this job covers (`None` for a time budget).
    pub range: Option<Range<u32>>,
    /// The first sample index rendered now (past the resumed state's).
    pub first_sample: u32,
    /// The settings key ([`RenderArgs::settings_key`]) and the fingerprint of it with the scene file.
    pub key: String,
    pub fingerprint: u64,
    /// The integrator's settings.
    pub settings: RenderSettings,
}

impl RenderJob {
    /// The job of `args`, the scene built with `factories`; the plan's notes go to stderr
    /// unless `--quiet`.
    pub fn new(args: &RenderArgs, factories: &[&dyn ObjectFactory]) -> Result<Self, String> {
        let (args, resume) = match &args.resume {
            Some(path) => resumed_args(args, path)?,
            None => (args.clone(), None),
        };
        let outputs = output_paths(&args.output, args.png.as_deref())?;
        let t_load = Instant::now();
        let scene = load(&args, factories)?;
        let load_s = t_load.elapsed().as_secs_f64();
        let request = EffectsRequest::parse(args.effects, &args.effect)?;
        let plan = RenderPlan::new(&scene, &request);
        if !args.quiet {
            for n in plan.notes() {
                eprintln!("spectrace: {n}");
            }
        }
        let budget = sample_budget(&args, &scene)?;
        check_integrator_flags(&args)?;
        let spectral_bins = spectral_bins(&args, &scene, resume.as_ref())?;
        let slice = args.slice.as_deref().map(SliceSpec::parse).transpose()?;
        let total_spp = match budget {
            SampleBudget::Spp(n) => Some(n),
            _ => None,
        };
        check_slice(slice, total_spp)?;
        let max_depth = args.max_depth.unwrap_or(scene.options.max_depth);
        let key = args.settings_key(
            &scene,
            max_depth,
            &wavelength_density(&args, &plan, &scene)?,
        );
        let fingerprint = fingerprint(&args, &key)?;
        let range = total_spp.map(|n| slice.unwrap_or(SliceSpec::WHOLE).range(n));
        let mut first_sample = range.as_ref().map_or(0, |r| r.start);
        if let Some((path, st)) = &resume {
            check_resumed_state(path, st, fingerprint, &key)?;
            first_sample = st.done_until;
        }
        let budget = match (&range, resume.is_some() || slice.is_some()) {
            (Some(r), true) => SampleBudget::Range {
                start: first_sample,
                end: r.end,
            },
            _ => budget,
        };
        let settings = render_settings(&args, budget, max_depth);
        Ok(Self {
            args,
            resume,
            outputs,
            scene,
            load_s,
            plan,
            spectral_bins,
            slice,
            total_spp,
            range,
            first_sample,
            key,
            fingerprint,
            settings,
        })
    }

    /// True when the resumed state already holds every sample of the range.
    pub fn already_done(&self) -> bool {
        self.range
            .as_ref()
            .is_some_and(|r| self.first_sample >= r.end)
    }

    /// The camera's image size in pixels.
    pub fn resolution(&self) -> Result<(u32, u32), String> {
        Ok(self
            .scene
            .cameras
            .get(self.args.camera.as_deref())
            .map_err(|e| e.to_string())?
            .camera
            .resolution())
    }
}

/// `--spp N`, `--time SECONDS` or the scene's sample count.
fn sample_budget(args: &RenderArgs, scene: &Scene) -> Result<SampleBudget, String> {
    Ok(match (super::args::time_budget(args.time)?, args.spp) {
        (Some(t), _) => SampleBudget::Time(t),
        (None, Some(0)) => return Err("--spp must be at least 1".into()),
        (None, Some(n)) => SampleBudget::Spp(n),
        (None, None) => SampleBudget::Spp(scene.options.spp),
    })
}

/// The wavelength flags that only the path tracer takes.
fn check_integrator_flags(args: &RenderArgs) -> Result<(), String> {
    if args.integrator != IntegratorKind::Pt && args.wavelengths_per_path.is_some() {
        return Err(format!(
            "--wavelengths-per-path applies to --integrator pt only (got --integrator {})",
            args.integrator
        ));
    }
    if let Some(w) = args.wavelength_sampling.filter(|w| {
        args.integrator != IntegratorKind::Pt
            && !matches!(
                w,
                WavelengthSampling::Product
                    | WavelengthSampling::Visible
                    | WavelengthSampling::Uniform
            )
    }) {
        return Err(format!(
            "--wavelength-sampling {w} applies to --integrator pt only; --integrator {} takes \
             product, uniform or visible (the observer-plus-emission mixture)",
            args.integrator
        ));
    }
    Ok(())
}

/// `--spectral-exr`'s bins, checked against the memory available and the resumed state.
fn spectral_bins(
    args: &RenderArgs,
    scene: &Scene,
    resume: Option<&(PathBuf, RenderState)>,
) -> Result<Option<SpectralBins>, String> {
    if args.spectral_exr.is_none() {
        return Ok(None);
    }
    let b = SpectralBins::parse(&args.bins)?;
    let (w, h) = scene
        .cameras
        .get(args.camera.as_deref())
        .map_err(|e| e.to_string())?
        .camera
        .resolution();
    crate::film::spectral_film::check_memory(b, w, h, crate::limits::available_memory_bytes())?;
    if let Some((path, st)) = resume {
        if st.film.spectral.as_ref().map(|s| s.bins) != Some(b) {
            return Err(format!(
                "{}: the state holds no spectral sums at --bins {} (written by another \
                 spectrace?); render again instead",
                path.display(),
                b.spec()
            ));
        }
    }
    Ok(Some(b))
}

/// More slices than samples would leave some empty.
fn check_slice(slice: Option<SliceSpec>, total_spp: Option<u32>) -> Result<(), String> {
    if let (Some(s), Some(n)) = (slice, total_spp) {
        if s.count > n {
            return Err(format!(
                "--slice {s}: {} slices of a {n} spp render would leave some empty; use at \
                 most {n} slices",
                s.count
            ));
        }
    }
    Ok(())
}

/// The fingerprint of the scene file's bytes and the settings key.
fn fingerprint(args: &RenderArgs, key: &str) -> Result<u64, String> {
    let scene_bytes = match &args.scene {
        Some(p) => std::fs::read(p).map_err(|e| format!("cannot read {}: {e}", p.display()))?,
        None => Vec::new(),
    };
    Ok(fnv1a64(&[&scene_bytes, key.as_bytes()]))
}

/// A resumed state continues only the render it was written by.
fn check_resumed_state(
    path: &Path,
    st: &RenderState,
    fingerprint: u64,
    key: &str,
) -> Result<(), String> {
    if st.fingerprint != fingerprint || st.settings != key {
        return Err(format!(
            "{}: the scene file or settings changed since this state was written \
             (fingerprint {:016x}, now {fingerprint:016x}{}); render again instead",
            path.display(),
            st.fingerprint,
            settings_difference(&st.settings, key)
        ));
    }
    Ok(())
}

/// The integrator settings of a render with every flag at its default (no camera chosen,
/// the default wavelength and sample sampling): what `bench` renders with.
pub fn default_settings(
    budget: SampleBudget,
    seed: u64,
    threads: Option<usize>,
    max_depth: u32,
) -> RenderSettings {
    RenderSettings {
        sampler: Default::default(),
        budget,
        seed,
        threads,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth,
            ..PathTracer::default()
        },
    }
}

/// The integrator settings of `args`.
fn render_settings(args: &RenderArgs, budget: SampleBudget, max_depth: u32) -> RenderSettings {
    RenderSettings {
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
    }
}

/// The name of the wavelength density a render of `scene` under `plan` draws from (the
/// settings fingerprint's `wavelength_density`): the path tracer's lanes as
/// [`PathWavelengthSampler`](crate::integrator::wavelengths::groups::PathWavelengthSampler)
/// resolves them, bdpt's and lt's pairs as
/// [`PairWavelengths`](crate::integrator::wavelengths::pairs::PairWavelengths) does.
fn wavelength_density(
    args: &RenderArgs,
    plan: &RenderPlan,
    scene: &Scene,
) -> Result<String, String> {
    let sampling = args.wavelength_sampling.unwrap_or_default();
    Ok(if args.integrator == IntegratorKind::Pt {
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
    })
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
