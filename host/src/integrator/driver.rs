//! What every integrator has in common: the [`Integrator`] trait (render a scene into the film),
//! its type information ([`IntegratorInfo`], with the parameter table in the form plugins use,
//! [`ParamDoc`]) and its [`Registration`] (information plus constructor). A new integrator is one
//! file implementing the trait and one entry in [`super::select::registered`].

use super::render::ProgressFn;
use super::{RenderError, RenderResult, RenderSettings};
use crate::film::XyzImage;
use crate::integrator::plan::RenderPlan;
use crate::light::LightFlags;
use crate::scene::Scene;
use spectrace_plugin_api::ParamDoc;
use std::sync::atomic::AtomicBool;

/// Name, version, description and parameter table of an integrator type.
#[derive(Clone, Copy, Debug)]
pub struct IntegratorInfo {
    /// Name as given to `--integrator`.
    pub name: &'static str,
    /// Other accepted names.
    pub aliases: &'static [&'static str],
    /// Version of its parameter set; bumps whenever the parameters change.
    pub version: u32,
    /// One line on what it is.
    pub description: &'static str,
    /// The render settings it reads, with units and defaults.
    pub params: &'static [ParamDoc],
}

impl IntegratorInfo {
    /// True when `name` (any case) is this integrator's name or one of its aliases.
    pub fn answers_to(&self, name: &str) -> bool {
        let n = name.to_ascii_lowercase();
        self.name == n || self.aliases.contains(&n.as_str())
    }
}

/// Outputs beyond the image that a render may be asked for; integrators that do not offer one
/// ignore it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct IntegratorOptions {
    /// One image per (s, t) strategy (BDPT).
    pub strategy_images: bool,
    /// Also accumulate a spectral image at these wavelength nodes (`FilmState::spectral`);
    /// `None` costs nothing.
    pub spectral: Option<crate::film::spectral::SpectralBins>,
}

/// A finished render with the integrator's extras.
#[derive(Clone, Debug)]
pub struct IntegratorOutput {
    /// The image and the summary numbers.
    pub result: RenderResult,
    /// BDPT only, when asked for: each strategy's weighted contribution, labelled `(s, t)`;
    /// the label `(u32::MAX, u32::MAX)` holds all longer paths together.
    pub strategy_images: Vec<((u32, u32), XyzImage)>,
    /// Contributions refused by the film's guard (NaN, infinite or negative); details in
    /// `film.rejected`.
    pub non_finite: u64,
    /// Per pixel (row-major), the largest luminance Y of one sample's contribution to that
    /// pixel's sum (before the 1/spp scaling), for firefly checks; empty for `pt`.
    pub max_sample_y: Vec<f64>,
    /// The exact film the image was made from (whole passes only), for slices and checkpoints.
    pub film: crate::film::FilmState,
    /// What the integrator decided while rendering, one line each for the render summary
    /// (pt: the visibility guide of a light, when it is on).
    pub notes: Vec<String>,
}

/// A light transport algorithm, configured from the render settings.
pub trait Integrator: Send + Sync {
    /// Its type information.
    fn info(&self) -> &'static IntegratorInfo;

    /// Render `scene` into the film (camera, budget, seed and threads from `settings`) as
    /// `plan` says (wavelength handling, effects on or off; made for this scene).
    /// `progress` may be called from several threads; `cancel`, when set, stops after the work
    /// in flight and the partial film is returned.
    fn render(
        &self,
        scene: &Scene,
        plan: &RenderPlan,
        settings: &RenderSettings,
        progress: &ProgressFn<'_>,
        cancel: Option<&AtomicBool>,
    ) -> Result<IntegratorOutput, RenderError>;

    /// How it renders a light with `flags`, one line for the render summary.
    fn light_strategy(&self, flags: LightFlags) -> &'static str;
}

/// The constructor of an integrator type: from the render settings and the extra outputs asked
/// for; an error says what is wrong with the settings.
pub type BuildFn = fn(&RenderSettings, IntegratorOptions) -> Result<Box<dyn Integrator>, String>;

/// An integrator type: its information and its constructor.
#[derive(Clone, Copy)]
pub struct Registration {
    /// Name, version, description, parameter table.
    pub info: &'static IntegratorInfo,
    /// Build one from the render settings and the extra outputs asked for.
    pub build: BuildFn,
}

impl std::fmt::Debug for Registration {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Registration")
            .field("info", self.info)
            .finish_non_exhaustive()
    }
}
