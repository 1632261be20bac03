//! Long, resumable reference renders: the image is built from passes of a fixed number of
//! samples per pixel; after each pass the f64 sums go to the sidecar state file
//! ([`ReferenceState`]) and the EXR is rewritten, so stopping (Ctrl-C, time budget) loses at
//! most the pass in flight and resuming continues exactly where it stopped.
//!
//! Pass `k` renders with seed `mix64(base_seed ⊕ mix64(k + 1))`: every pass draws fresh,
//! independent sample streams, and the seeds depend only on `k`, so `N` passes followed by a
//! resumed `N` passes give bitwise the same sums as `2N` passes in one run (the sums are added
//! in the same pass order). (A renderer-side "first sample index" would let passes continue one
//! low-discrepancy sequence instead; the render driver does not expose one.)

use super::{AnalysisError, ReferenceState};
use crate::film::write_exr;
use crate::integrator::{render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget};
use crate::sampler::mix64;
use crate::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How to run (or continue) a reference render.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceSettings {
    /// Samples per pixel of one pass (the unit that is saved; ignored when resuming).
    pub pass_spp: u32,
    /// Base seed (ignored when resuming: the state's is used).
    pub seed: u64,
    /// Light transport algorithm.
    pub integrator: IntegratorKind,
    /// Path tracer settings (depth, Russian roulette).
    pub tracer: PathTracer,
    /// Worker threads (`None`: one per core).
    pub threads: Option<usize>,
    /// Stop once this many samples per pixel are accumulated in total.
    pub target_spp: Option<u64>,
    /// Time budget of this run: no pass starts after it, and a pass still running when it ends
    /// is stopped within the tiles in flight and dropped.
    pub time: Option<Duration>,
    /// Description of the scene (file path or "default Cornell box"), part of the state's key.
    pub scene_name: String,
}

impl ReferenceSettings {
    /// The key stored in the state: everything that must not change between runs.
    pub fn key(&self) -> String {
        format!(
            "scene={}; integrator={}; max_depth={}; rr_depth={}",
            self.scene_name, self.integrator, self.tracer.max_depth, self.tracer.rr_depth
        )
    }
}

/// The state file beside `output`: `output` with `.state` appended.
pub fn state_path(output: &Path) -> PathBuf {
    let mut s = output.as_os_str().to_owned();
    s.push(".state");
    PathBuf::from(s)
}

/// The seed of pass `k` (see the module docs).
pub fn pass_seed(base_seed: u64, pass: u64) -> u64 {
    mix64(base_seed ^ mix64(pass.wrapping_add(1)))
}

/// What a run did.
#[derive(Clone, Debug, PartialEq)]
pub struct ReferenceOutcome {
    /// The accumulated state (also on disk).
    pub state: ReferenceState,
    /// Passes added in this run.
    pub passes_added: u64,
    /// Passes resumed from disk.
    pub passes_resumed: u64,
    /// Camera samples per second over this run's passes.
    pub samples_per_second: f64,
    /// True if the run ended because `cancel` was set.
    pub interrupted: bool,
    /// True if the time budget ran out during a pass, which was then stopped and dropped; the
    /// seconds that pass had run.
    pub pass_dropped_at_time_limit: Option<f64>,
}

/// Render `scene` progressively into `output` (EXR) and its state file, resuming from the state
/// file if it exists and matches. Stops at `target_spp`, after `time`, or when `cancel` is set
/// (the pass in flight is then dropped: its pixels would have unequal sample counts).
/// `on_pass` is told the state after each saved pass.
pub fn run_reference(
    scene: &Scene,
    output: &Path,
    settings: &ReferenceSettings,
    cancel: Option<&AtomicBool>,
    on_pass: &dyn Fn(&ReferenceState),
) -> Result<ReferenceOutcome, AnalysisError> {
    if settings.pass_spp == 0 {
        return Err(AnalysisError::Render(
            "pass size must be at least 1 spp".into(),
        ));
    }
    let (width, height) = scene
        .cameras
        .get(None)
        .map(|c| c.camera.resolution())
        .map_err(AnalysisError::Render)?;
    let spath = state_path(output);
    let mut state = open_state(&spath, settings, width, height)?;
    let resumed = state.passes;
    let start = Instant::now();
    let mut samples = 0u64;
    let mut interrupted = false;
    let mut dropped_at_limit = None;
    // A pass is stopped by `stop`, which a watcher sets when the user cancels or the time budget
    // ends: without it a pass of 1024 spp started just before the budget ran out overran it by
    // a whole pass.
    let stop = AtomicBool::new(false);
    let finished = AtomicBool::new(false);
    let deadline = settings.time.map(|t| start + t);
    let user_cancelled = || cancel.is_some_and(|c| c.load(Ordering::SeqCst));
    std::thread::scope(|scope| -> Result<(), AnalysisError> {
        if deadline.is_some() || cancel.is_some() {
            scope.spawn(|| {
                while !finished.load(Ordering::SeqCst) {
                    if user_cancelled() || deadline.is_some_and(|d| Instant::now() >= d) {
                        stop.store(true, Ordering::SeqCst);
                        break;
                    }
                    std::thread::sleep(Duration::from_millis(5));
                }
            });
        }
        let result = (|| {
            loop {
                if settings.target_spp.is_some_and(|t| state.spp() >= t) {
                    break;
                }
                if settings.time.is_some_and(|t| start.elapsed() >= t) {
                    break;
                }
                if user_cancelled() {
                    interrupted = true;
                    break;
                }
                let render_settings = pass_settings(&state, settings);
                let pass_start = Instant::now();
                let out = render_with(
                    scene,
                    &render_settings,
                    settings.integrator,
                    false,
                    &|_, _| {},
                    Some(&stop),
                )
                .map_err(|e| AnalysisError::Render(e.to_string()))?;
                if stop.load(Ordering::SeqCst) || out.result.spp != state.pass_spp {
                    if user_cancelled() {
                        interrupted = true;
                    } else {
                        dropped_at_limit = Some(pass_start.elapsed().as_secs_f64());
                    }
                    break;
                }
                samples += out.result.samples;
                add_pass(&mut state, &out.result.image.xyz);
                state.save(&spath)?;
                write_exr(output, &state.image(), &scene.options.rgb_space).map_err(|e| {
                    AnalysisError::Write {
                        path: output.to_path_buf(),
                        message: e.to_string(),
                    }
                })?;
                on_pass(&state);
            }
            Ok(())
        })();
        finished.store(true, Ordering::SeqCst);
        result
    })?;
    let secs = start.elapsed().as_secs_f64().max(1e-9);
    Ok(ReferenceOutcome {
        passes_added: state.passes - resumed,
        passes_resumed: resumed,
        samples_per_second: samples as f64 / secs,
        interrupted,
        pass_dropped_at_time_limit: dropped_at_limit,
        state,
    })
}

/// The state file at `spath` when it exists (it must come from the same render settings and
/// resolution), else a new state.
fn open_state(
    spath: &Path,
    settings: &ReferenceSettings,
    width: u32,
    height: u32,
) -> Result<ReferenceState, AnalysisError> {
    let key = settings.key();
    if !spath.exists() {
        return Ok(ReferenceState::new(
            width,
            height,
            settings.seed,
            settings.pass_spp,
            key,
        ));
    }
    let s = ReferenceState::load(spath)?;
    if s.key != key || (s.width, s.height) != (width, height) {
        return Err(AnalysisError::Content {
            path: spath.to_path_buf(),
            message: format!(
                "was made by a different render ({}, {}×{}); this run is ({key}, \
                 {width}×{height}); delete the file or choose another output name",
                s.key, s.width, s.height
            ),
        });
    }
    Ok(s)
}

/// The render settings of the state's next pass: its own seed, `pass_spp` samples.
fn pass_settings(state: &ReferenceState, settings: &ReferenceSettings) -> RenderSettings {
    RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(state.pass_spp),
        seed: pass_seed(state.base_seed, state.passes),
        threads: settings.threads,
        camera: None,
        tile_size: 16,
        tracer: settings.tracer,
    }
}

/// Add a finished pass's image (`xyz` per pixel, a mean over `pass_spp` samples) to the sums.
fn add_pass(state: &mut ReferenceState, xyz: &[[f64; 3]]) {
    let n = state.pass_spp as f64;
    for (s, m) in state.sums.iter_mut().zip(xyz) {
        for c in 0..3 {
            s[c] += m[c] * n;
        }
    }
    state.passes += 1;
}
