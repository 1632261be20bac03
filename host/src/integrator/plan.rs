//! [`RenderPlan`]: what a render does about each effect, decided once from the scene analysis
//! ([`crate::effects::analyze`]) and the command line, and read by the integrators (which never
//! re-derive it). Data flows one way: scene → analysis → plan → integrator.
//!
//! | setting (command line)        | values                 | meaning                                              |
//! |-------------------------------|------------------------|------------------------------------------------------|
//! | `--effects`                   | `auto` (default), `all`| auto: simulate what the analysis finds; all: run every switchable effect's machinery whether or not the scene calls for it |
//! | `--effect NAME=on\|off`       | see below, repeatable  | force one effect on or off (wins over `--effects`)   |
//!
//! | switchable effect (`NAME`)             | on                                                          | off                                                           |
//! |----------------------------------------|-------------------------------------------------------------|---------------------------------------------------------------|
//! | `dispersion`                           | a dispersive event keeps the hero lane only (lane mask)     | dispersive built-in materials use their IOR at [`DISPERSION_OFF_NM`] (550 nm) at every wavelength |
//! | `fluorescence`                         | wavelength shifts at fluorescent events ([`RenderPlan::fluorescence`]) | fluorescent materials reflect only (no re-radiation) |
//! | `thin-film`                            | per-lane Airy reflectance of the film                       | thin-film materials become their bare base (film thickness 0 nm) |
//! | `narrowband-emission` (alias `line-emission`) | pt draws wavelengths half from the observer, half from the lights' spectra (lines with their discrete probability) | every integrator draws wavelengths from the observer alone: lines and narrow bands render black (warned) |
//! | `flat-path-colour`                     | bdpt, lt and pt give a path whose every vertex is spectrally flat the exact colour of its emitter's spectrum ([`FlatColour`]; found when some light has one spectral shape everywhere) | every path's colour is estimated from its four wavelengths |
//! | `manifold` (alias `mnee`)              | bdpt adds the specular-chain connection (`integrator::connect::manifold_connection`) for paths that only `s = 0` can make otherwise (found with specular chains) | those paths come from `s = 0` alone |
//! | `camera-chain`                         | bdpt adds the camera-side specular-chain connection (`integrator::connect::camera_chain`): the lamp seen reflected in or refracted through smooth specular objects from a pinhole (found with specular chains; thin-lens cameras: not run) | those paths come from `s = 0` alone |
//! | `light-subpaths=auto\|Q` (not on/off) | auto (the default): bdpt chooses the fraction `q` of camera samples that trace light subpaths by a short pilot (`integrator::bdpt::light_fraction`), `0` (path trace every camera sample, `integrator::bdpt::path_traced`) among the candidates where path tracing samples every path bdpt does; `Q` forces it: `1` (every camera sample), `0.5`, `1/8`, any value in [0, 1] (0 is an error where path tracing would lose light) | – |
//! | `light-subpath-count=auto\|N` (not on/off) | auto (the default): the same pilot chooses how many light subpaths a camera sample that traces them traces, 1, 2, 4 or 8 where some surface scatters by a delta lobe (caustics), else 1; `N` forces it (1 to 64; with beams-only lights or fluorescence, where no pilot runs, auto means 4 in scenes with delta surfaces) | – |
//! | `visibility-guide` (alias `nee-guide`) | pt's next-event estimation and bdpt's s = 1 strategy draw points of area lights on quads and small meshes, and the directions of the constant, image-map and CIE environments, from a density learned by a short pre-pass where they are partly hidden (`integrator::nee_guide`; found with such lights, then switched on per light where the pre-pass finds at least 30% of their light occluded; forced on or `--effects all`: every such light) | uniform points by area (no pre-pass) |
//!
//! bdpt and lt draw the pair's wavelengths from the observer-plus-emission mixture
//! ([`WavelengthMixture`]) unless `narrowband-emission` is forced off, except where the
//! observer × √emission table applies (no fluorescence, no narrowband emission; see
//! `integrator::wavelengths::pairs`); the plan builds the mixture once ([`RenderPlan::mixture`])
//! and that table on first use ([`RenderPlan::product_table`]). When every light is narrowband (delta lines, or an
//! equivalent width under 10 nm) and fluorescence is off, a wavelength off the lights' spectra
//! carries (almost) no light, so the mixture draws from the lights' spectra alone (all three
//! integrators; unbiased without fluorescence): this removes the half of the draws that were
//! (almost) certain to be wasted, the main noise of line-lamp and laser renders.
//!
//! Not switchable (properties of the scene, not simulation choices): delta lights, delta BSDFs,
//! specular chains, beam-only lights, spectral flatness. The plan records whether some light
//! needs light paths ([`RenderPlan::light_paths_needed`]): beam-only lights, or point-like and
//! directional lights seen through delta BSDFs; pt cannot render those.

use super::wavelengths::flat_colour::FlatColour;
use super::wavelengths::mixture::WavelengthMixture;
use crate::effects::analysis::{Caller, EffectSet};
use crate::effects::effect::Effect;
use crate::light::LightFlags;
use crate::material::{EffectsOff, Material};
use crate::scene::Scene;
use crate::spectrum::wavelength_table::WavelengthTable;
use std::sync::{Arc, OnceLock};

/// Reference wavelength (nm) at which a dispersive material's IOR is taken when dispersion is
/// off: near the peak of the photopic response, so the average colour position changes least.
pub const DISPERSION_OFF_NM: f32 = 550.0;

/// `--effects`: the default for every switchable effect.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum EffectsMode {
    /// Simulate the effects the scene analysis finds, skip the others.
    #[default]
    Auto,
    /// Run every switchable effect's machinery, found or not (for checking `auto`).
    All,
}

/// The effects the command line can switch on or off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Switch {
    /// Wavelength-dependent refraction.
    Dispersion,
    /// Re-emission at other wavelengths.
    Fluorescence,
    /// Thin-film interference.
    ThinFilm,
    /// Wavelengths drawn from the lights' spectra (narrowband and line emission).
    NarrowbandEmission,
    /// The exact colour of spectrally flat paths (an optimisation, not an optical effect:
    /// the image's expectation is the same either way).
    FlatPathColour,
    /// bdpt's specular-chain (manifold) connection (a strategy, not an optical effect: the
    /// image's expectation is the same either way).
    Manifold,
    /// bdpt's camera-side specular-chain connection (a strategy, not an optical effect).
    CameraChain,
    /// pt's visibility-guided light points (a strategy, not an optical effect: the image's
    /// expectation is the same either way).
    VisibilityGuide,
}

impl Switch {
    /// Every switch, in the order summaries print them.
    pub const ALL: [Self; 8] = [
        Self::Dispersion,
        Self::Fluorescence,
        Self::ThinFilm,
        Self::NarrowbandEmission,
        Self::FlatPathColour,
        Self::Manifold,
        Self::CameraChain,
        Self::VisibilityGuide,
    ];

    /// Name on the command line and in summaries.
    pub fn name(self) -> &'static str {
        match self {
            Self::Dispersion => "dispersion",
            Self::Fluorescence => "fluorescence",
            Self::ThinFilm => "thin-film",
            Self::NarrowbandEmission => "narrowband-emission",
            Self::FlatPathColour => "flat-path-colour",
            Self::Manifold => "manifold",
            Self::CameraChain => "camera-chain",
            Self::VisibilityGuide => "visibility-guide",
        }
    }

    /// The analysis findings this switch answers.
    fn effects(self) -> &'static [Effect] {
        match self {
            Self::Dispersion => &[Effect::Dispersion],
            Self::Fluorescence => &[Effect::Fluorescence],
            Self::ThinFilm => &[Effect::ThinFilm],
            Self::NarrowbandEmission => &[Effect::NarrowbandEmission, Effect::LineEmission],
            // Decided from the lights themselves (see `RenderPlan::new`).
            Self::FlatPathColour | Self::VisibilityGuide => &[],
            Self::Manifold | Self::CameraChain => &[Effect::SpecularChains],
        }
    }

    fn parse(name: &str) -> Result<Self, String> {
        let n = name.trim().to_ascii_lowercase().replace('_', "-");
        match n.as_str() {
            "dispersion" => Ok(Self::Dispersion),
            "fluorescence" => Ok(Self::Fluorescence),
            "thin-film" => Ok(Self::ThinFilm),
            "narrowband-emission" | "line-emission" | "narrowband" => Ok(Self::NarrowbandEmission),
            "flat-path-colour" | "flat-path-color" => Ok(Self::FlatPathColour),
            "manifold" | "mnee" | "manifold-next-event" => Ok(Self::Manifold),
            "camera-chain" => Ok(Self::CameraChain),
            "visibility-guide" | "nee-guide" => Ok(Self::VisibilityGuide),
            _ => {
                let fixed = Effect::ALL.iter().find(|e| e.name() == n);
                let names: Vec<&str> = Self::ALL.iter().map(|s| s.name()).collect();
                Err(match fixed {
                    Some(e) => format!(
                        "--effect {name}: `{}` is a property of the scene, not an effect that can \
                         be switched; switchable: {} (line-emission is an alias of \
                         narrowband-emission)",
                        e.name(),
                        names.join(", ")
                    ),
                    None => format!(
                        "--effect {name}: unknown effect; switchable: {} (line-emission is an \
                         alias of narrowband-emission)",
                        names.join(", ")
                    ),
                })
            }
        }
    }
}

/// bdpt's fraction of camera samples that trace light subpaths (`--effect
/// light-subpaths=auto|Q`, see `integrator::bdpt::light_fraction`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum LightSubpaths {
    /// Chosen per scene by a short pilot (the default).
    #[default]
    Auto,
    /// Forced: every camera sample traces them with this probability, in [0, 1] (0: the
    /// camera samples are path traced, `integrator::bdpt::path_traced`).
    Fraction(f32),
}

// The fractions are finite (`LightSubpaths::parse`), so equality is an equivalence.
impl Eq for LightSubpaths {}

impl LightSubpaths {
    /// The value of `--effect light-subpaths=VALUE`: `auto`, or a fraction in [0, 1] as a
    /// decimal or `1/N` (0: bdpt path traces every camera sample, where that loses no light;
    /// the render checks).
    pub fn parse(value: &str) -> Result<Self, String> {
        let v = value.trim().to_ascii_lowercase();
        if v == "auto" {
            return Ok(Self::Auto);
        }
        let q = match v.split_once('/') {
            Some((a, b)) => match (a.trim().parse::<f64>(), b.trim().parse::<f64>()) {
                (Ok(a), Ok(b)) if b != 0.0 => Some(a / b),
                _ => None,
            },
            None => v.parse::<f64>().ok(),
        };
        match q {
            Some(q) if (0.0..=1.0).contains(&q) => Ok(Self::Fraction(q as f32)),
            _ => Err(format!(
                "--effect light-subpaths={value}: expected auto or a fraction in [0, 1] of \
                 the camera samples that trace light subpaths (1, 0.5, 1/8, …; 0: path trace \
                 every camera sample)"
            )),
        }
    }
}

/// bdpt's number of light subpaths per camera sample that traces them (`--effect
/// light-subpath-count=auto|N`, see `integrator::bdpt::light_fraction`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LightSubpathCount {
    /// Chosen per scene by the pilot (the default): 1, 2, 4 or 8 where some surface scatters
    /// by a delta lobe, else 1.
    #[default]
    Auto,
    /// Forced: this many, in [1, [`MAX_LIGHT_SUBPATH_COUNT`]].
    Count(u32),
}

/// The most light subpaths per camera sample `--effect light-subpath-count` accepts.
pub const MAX_LIGHT_SUBPATH_COUNT: u32 = 64;

impl LightSubpathCount {
    /// The value of `--effect light-subpath-count=VALUE`: `auto`, or a whole number in
    /// [1, [`MAX_LIGHT_SUBPATH_COUNT`]].
    pub fn parse(value: &str) -> Result<Self, String> {
        let v = value.trim().to_ascii_lowercase();
        if v == "auto" {
            return Ok(Self::Auto);
        }
        match v.parse::<u32>() {
            Ok(n) if (1..=MAX_LIGHT_SUBPATH_COUNT).contains(&n) => Ok(Self::Count(n)),
            _ => Err(format!(
                "--effect light-subpath-count={value}: expected auto or a whole number from 1 \
                 to {MAX_LIGHT_SUBPATH_COUNT} of light subpaths per camera sample that traces \
                 them (1, 2, 4, 8, …)"
            )),
        }
    }
}

/// What the command line asks for: a mode and single effects forced on or off.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct EffectsRequest {
    /// `--effects`.
    pub mode: EffectsMode,
    /// `--effect NAME=on|off`, in command-line order (a later one wins).
    pub forced: Vec<(Switch, bool)>,
    /// `--effect light-subpaths=auto|Q` (the last one given).
    pub light_subpaths: LightSubpaths,
    /// `--effect light-subpath-count=auto|N` (the last one given).
    pub light_subpath_count: LightSubpathCount,
}

impl EffectsRequest {
    /// `--effects MODE` plus `--effect NAME=on|off` arguments; the error names the bad one.
    pub fn parse(mode: EffectsMode, forced: &[String]) -> Result<Self, String> {
        let mut out = Self {
            mode,
            forced: Vec::new(),
            light_subpaths: LightSubpaths::Auto,
            light_subpath_count: LightSubpathCount::Auto,
        };
        for arg in forced {
            let Some((name, value)) = arg.split_once('=') else {
                return Err(format!(
                    "--effect {arg}: expected NAME=on or NAME=off (for example dispersion=off)"
                ));
            };
            let n = name.trim().to_ascii_lowercase().replace('_', "-");
            if n == "light-subpaths" || n == "light-fraction" {
                out.light_subpaths = LightSubpaths::parse(value)?;
                continue;
            }
            if n == "light-subpath-count" {
                out.light_subpath_count = LightSubpathCount::parse(value)?;
                continue;
            }
            let switch = Switch::parse(name)?;
            let on = match value.trim().to_ascii_lowercase().as_str() {
                "on" | "true" | "yes" | "1" => true,
                "off" | "false" | "no" | "0" => false,
                v => return Err(format!("--effect {arg}: value `{v}` is neither on nor off")),
            };
            out.forced.push((switch, on));
        }
        Ok(out)
    }

    /// The forced value of `switch`, if any (the last one given).
    fn forced(&self, switch: Switch) -> Option<bool> {
        self.forced
            .iter()
            .rev()
            .find(|(s, _)| *s == switch)
            .map(|(_, on)| *on)
    }

    /// A stable text of the request (for the settings fingerprint of checkpoints).
    pub fn key(&self) -> String {
        let forced: Vec<String> = self
            .forced
            .iter()
            .map(|(s, on)| format!("{}={}", s.name(), if *on { "on" } else { "off" }))
            .collect();
        let count = match self.light_subpath_count {
            // The key of every request before the setting existed.
            LightSubpathCount::Auto => String::new(),
            LightSubpathCount::Count(n) => format!("light-subpath-count={n}"),
        };
        match self.light_subpaths {
            LightSubpaths::Auto => format!("{:?}[{}]{count}", self.mode, forced.join(",")),
            LightSubpaths::Fraction(q) => format!(
                "{:?}[{}]light-subpaths={}{count}",
                self.mode,
                forced.join(","),
                q.to_bits()
            ),
        }
    }
}

/// Why a switch is on or off.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reason {
    /// The analysis found the effect (auto).
    Found,
    /// The analysis did not find it (auto).
    Absent,
    /// `--effects all`.
    All,
    /// `--effect NAME=on|off`.
    Forced,
}

/// One switch's decision.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decision {
    /// Simulated or not.
    pub on: bool,
    /// Why.
    pub reason: Reason,
}

impl Decision {
    fn text(&self) -> &'static str {
        match (self.on, self.reason) {
            (true, Reason::Found) => "on (found)",
            (false, Reason::Absent) => "off (absent)",
            (true, Reason::All) => "on (--effects all)",
            (true, Reason::Forced) => "on (forced)",
            (false, Reason::Forced) => "OFF (forced)",
            (true, _) => "on",
            (false, _) => "off",
        }
    }
}

/// The render plan (see the module docs).
#[derive(Clone, Debug)]
pub struct RenderPlan {
    effects: EffectSet,
    request: EffectsRequest,
    decisions: [Decision; 8],
    light_paths: Vec<String>,
    mixture: Arc<WavelengthMixture>,
    /// The observer × √emission table of `mixture`'s emission, built on first use and then
    /// shared by everything that reads this plan (the render and its summary line).
    product: Arc<OnceLock<Option<WavelengthTable>>>,
    notes: Vec<String>,
    replacements: Vec<(usize, Arc<dyn Material>)>,
}

impl RenderPlan {
    /// The plan for `scene` under `request`.
    pub fn new(scene: &Scene, request: &EffectsRequest) -> Self {
        let effects = crate::effects::analyze(scene);
        let decisions = Switch::ALL.map(|s| {
            if let Some(on) = request.forced(s) {
                return Decision {
                    on,
                    reason: Reason::Forced,
                };
            }
            let found = match s {
                Switch::FlatPathColour => scene.lights.lights().iter().any(|l| {
                    l.uniform_spectral_shape() && !l.flags().contains(LightFlags::BEAMS_ONLY)
                }),
                Switch::VisibilityGuide => scene
                    .lights
                    .lights()
                    .iter()
                    .any(|l| super::nee_guide::NeeGuide::can_guide(l.as_ref())),
                _ => s.effects().iter().any(|e| effects.contains(*e)),
            };
            match (request.mode, found) {
                (EffectsMode::All, _) => Decision {
                    on: true,
                    reason: Reason::All,
                },
                (EffectsMode::Auto, true) => Decision {
                    on: true,
                    reason: Reason::Found,
                },
                (EffectsMode::Auto, false) => Decision {
                    on: false,
                    reason: Reason::Absent,
                },
            }
        });
        let mut plan = Self {
            effects,
            request: request.clone(),
            decisions,
            light_paths: Vec::new(),
            mixture: Arc::new(WavelengthMixture::visible_only()),
            product: Arc::new(OnceLock::new()),
            notes: Vec::new(),
            replacements: Vec::new(),
        };
        let emission_forced_off = plan.decision(Switch::NarrowbandEmission)
            == Decision {
                on: false,
                reason: Reason::Forced,
            };
        plan.mixture = Arc::new(if emission_forced_off {
            // The observer alone (bdpt and lt included), so lines are lost.
            WavelengthMixture::visible_only()
        } else {
            let m = WavelengthMixture::new(scene);
            // All emission narrowband (lines or < 10 nm), and nothing shifts wavelengths: a draw
            // off the lights' spectra carries (almost) no light, so every draw comes from them.
            if m.all_narrowband() && !plan.fluorescence() {
                m.emission_only()
            } else {
                m
            }
        });
        if emission_forced_off {
            for c in plan.callers(&[Effect::NarrowbandEmission, Effect::LineEmission]) {
                plan.notes.push(format!(
                    "narrowband-emission off: {c} renders black or nearly so (wavelengths come \
                     from the observer alone and miss its lines or narrow band)"
                ));
            }
        }
        if !plan.fluorescence() {
            for c in plan.callers(&[Effect::Fluorescence]) {
                plan.notes.push(format!(
                    "fluorescence off: {c} reflects only (no re-radiation at other wavelengths)"
                ));
            }
        }
        plan.replace_materials(scene);
        plan.light_paths = light_path_reasons(&plan.effects);
        plan
    }

    /// The automatic plan (`--effects auto`, nothing forced).
    pub fn auto(scene: &Scene) -> Self {
        Self::new(scene, &EffectsRequest::default())
    }

    /// Built-in materials whose dispersion or thin film is switched off get a replacement.
    fn replace_materials(&mut self, scene: &Scene) {
        let off = EffectsOff {
            dispersion: !self.dispersion(),
            thin_film: !self.thin_film(),
            reference_nm: DISPERSION_OFF_NM,
        };
        if !off.dispersion && !off.thin_film {
            return;
        }
        for (i, obj) in scene.objects.objects().iter().enumerate() {
            let m = obj.material.as_ref();
            let flags = m.flags();
            let relevant = (off.dispersion
                && flags.contains(crate::material::MaterialFlags::DISPERSIVE))
                || (off.thin_film && flags.contains(crate::material::MaterialFlags::THIN_FILM));
            if !relevant {
                continue;
            }
            match m.without_effects(&off) {
                Some((replacement, what)) => {
                    self.notes.push(format!("object \"{}\": {what}", obj.name));
                    self.replacements.push((i, replacement));
                }
                None => self.notes.push(format!(
                    "object \"{}\": its material cannot switch these effects off (a plugin \
                     material?); it renders with them",
                    obj.name
                )),
            }
        }
    }

    /// Callers of any of `effects`, each once.
    fn callers(&self, effects: &[Effect]) -> Vec<Caller> {
        let mut out: Vec<Caller> = Vec::new();
        for e in effects {
            for c in self.effects.callers(*e) {
                if !out.contains(c) {
                    out.push(c.clone());
                }
            }
        }
        out
    }

    fn decision(&self, s: Switch) -> Decision {
        self.decisions[Switch::ALL.iter().position(|x| *x == s).unwrap_or(0)]
    }

    /// The scene analysis the plan was made from.
    pub fn effects(&self) -> &EffectSet {
        &self.effects
    }

    /// What the command line asked for.
    pub fn request(&self) -> &EffectsRequest {
        &self.request
    }

    /// Dispersive events keep the hero lane only (when off, built-in dispersive materials have
    /// been replaced by constant-IOR ones in [`scene`](Self::scene)).
    pub fn dispersion(&self) -> bool {
        self.decision(Switch::Dispersion).on
    }

    /// Fluorescent events may shift the wavelength; when false the integrators do no
    /// fluorescence bookkeeping and fluorescent materials reflect only.
    pub fn fluorescence(&self) -> bool {
        self.decision(Switch::Fluorescence).on
    }

    /// Thin films are simulated (when off, built-in thin-film materials have been replaced by
    /// their bare base in [`scene`](Self::scene)).
    pub fn thin_film(&self) -> bool {
        self.decision(Switch::ThinFilm).on
    }

    /// pt draws wavelengths from the observer-plus-emission [`mixture`](Self::mixture)
    /// instead of the observer alone (narrowband or line emission present, or forced).
    pub fn emission_wavelengths(&self) -> bool {
        self.decision(Switch::NarrowbandEmission).on
    }

    /// bdpt and lt give spectrally flat paths the exact colour of their emitter
    /// ([`FlatColour`]); when off every path's colour comes from its wavelengths.
    pub fn flat_path_colour(&self) -> bool {
        self.decision(Switch::FlatPathColour).on
    }

    /// bdpt adds the specular-chain connection (`integrator::connect::manifold_connection`).
    pub fn manifold(&self) -> bool {
        self.decision(Switch::Manifold).on
    }

    /// bdpt adds the camera-side specular-chain connection (`integrator::connect::camera_chain`;
    /// pinhole cameras only).
    pub fn camera_chain(&self) -> bool {
        self.decision(Switch::CameraChain).on
    }

    /// bdpt's fraction of camera samples that trace light subpaths (`--effect
    /// light-subpaths`; `integrator::bdpt::light_fraction`).
    pub fn light_subpaths(&self) -> LightSubpaths {
        self.request.light_subpaths
    }

    /// bdpt's light subpaths per camera sample that traces them (`--effect
    /// light-subpath-count`; `integrator::bdpt::light_fraction`).
    pub fn light_subpath_count(&self) -> LightSubpathCount {
        self.request.light_subpath_count
    }

    /// pt's visibility guide (`integrator::nee_guide`): `None` when its pre-pass decides per
    /// light (found, auto), `Some(true)` to guide every light it can (forced on or
    /// `--effects all`), `Some(false)` for none (forced off, or no light it can guide).
    pub fn visibility_guide(&self) -> Option<bool> {
        let d = self.decision(Switch::VisibilityGuide);
        match (d.on, d.reason) {
            (true, Reason::Found) => None,
            (on, _) => Some(on),
        }
    }

    /// The flat-path colour tables for `scene` under `observer`, for lanes drawn with the
    /// wavelength density `density` (1/nm), when the switch is on and some light qualifies (see
    /// [`FlatColour::new`]).
    pub fn flat_colour(
        &self,
        scene: &Scene,
        observer: &dyn crate::color::observer::Observer,
        density: &dyn Fn(f64) -> f64,
    ) -> Option<FlatColour> {
        if self.flat_path_colour() {
            FlatColour::new(scene, observer, density)
        } else {
            None
        }
    }

    /// The observer × √emission wavelength table of the [`mixture`](Self::mixture)'s emission
    /// ([`product_table`](crate::integrator::wavelengths::mixture::product_table)); `None` without
    /// evaluable lights or when they emit nothing in the visible range. Built once per plan, on
    /// first use (about 7 M instructions), so the render and its summary share it.
    pub fn product_table(&self) -> Option<&WavelengthTable> {
        self.product
            .get_or_init(|| {
                Some(self.mixture.as_ref())
                    .filter(|m| m.has_emission())
                    .and_then(|m| super::wavelengths::mixture::product_table(m).ok())
            })
            .as_ref()
    }

    /// The wavelength mixture of camera/light path pairs (bdpt, lt; pt when
    /// [`emission_wavelengths`](Self::emission_wavelengths)): observer plus the lights'
    /// spectra, or the observer alone when narrowband emission is forced off. Built once.
    pub fn mixture(&self) -> &WavelengthMixture {
        &self.mixture
    }

    /// Why light paths are needed (empty: camera paths alone render every light).
    pub fn light_paths_needed(&self) -> &[String] {
        &self.light_paths
    }

    /// What is switched off and what it means, one sentence each (stated at run time).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The scene the integrators render: `scene` itself, or a copy whose materials with a
    /// switched-off effect are replaced (materials are shared, so the copy is cheap).
    pub fn scene<'a>(&self, scene: &'a Scene) -> std::borrow::Cow<'a, Scene> {
        // Fluorescence off: the objects keep their materials, which then reflect only.
        let fluorescence_off = scene.objects.fluorescence() && !self.fluorescence();
        if self.replacements.is_empty() && !fluorescence_off {
            return std::borrow::Cow::Borrowed(scene);
        }
        let mut s = scene.clone();
        if !self.replacements.is_empty() {
            let mut objects: Vec<crate::scene::SceneObject> = scene.objects.objects().to_vec();
            for (i, m) in &self.replacements {
                if let Some(o) = objects.get_mut(*i) {
                    o.material = m.clone();
                }
            }
            s.objects = crate::scene::SceneObjectManager::new(objects);
        }
        s.objects.set_fluorescence(self.fluorescence());
        std::borrow::Cow::Owned(s)
    }

    /// One line for the render summary.
    pub fn summary_line(&self) -> String {
        let parts: Vec<String> = Switch::ALL
            .iter()
            .map(|s| format!("{} {}", s.name(), self.decision(*s).text()))
            .collect();
        let lp = if self.light_paths.is_empty() {
            "light paths not needed".to_string()
        } else {
            format!("light paths needed ({})", self.light_paths.join("; "))
        };
        let m = &self.mixture;
        let wl = if !m.has_emission() {
            "wavelengths from the observer"
        } else if m.emission_weight() >= 1.0 {
            "wavelengths from the lights' spectra only (all emission is narrowband)"
        } else if self.emission_wavelengths() {
            "wavelengths half from the observer, half from the lights' spectra (pt; bdpt, lt where some light is narrowband or has lines)"
        } else if self.fluorescence() {
            "wavelengths: pt by its wavelength sampling (visible importance with fluorescence), bdpt/lt half observer, half lights' spectra where objects fluoresce"
        } else {
            "wavelengths by the wavelength sampling (default observer × √emission; pt, bdpt, lt)"
        };
        let ls = match self.request.light_subpaths {
            LightSubpaths::Auto => String::new(),
            LightSubpaths::Fraction(q) if q <= 0.0 => {
                "; bdpt light subpaths in none of the camera samples: path traced (forced)"
                    .to_string()
            }
            LightSubpaths::Fraction(q) => {
                format!("; bdpt light subpaths in {q} of camera samples (forced)")
            }
        };
        let ls = match self.request.light_subpath_count {
            LightSubpathCount::Auto => ls,
            LightSubpathCount::Count(n) => {
                format!("{ls}; bdpt light subpaths per camera sample: {n} (forced)")
            }
        };
        format!(
            "plan (--effects {}): {}; {wl}; {lp}{ls}",
            match self.request.mode {
                EffectsMode::Auto => "auto",
                EffectsMode::All => "all",
            },
            parts.join(", ")
        )
    }

    /// The plan as `spectrace explain` prints it: each switch with what the render does, then
    /// the run-time notes.
    pub fn report(&self) -> String {
        let mut out = String::from("render plan:\n");
        out.push_str(&format!("  {}\n", self.summary_line()));
        for s in Switch::ALL {
            let d = self.decision(s);
            let what = match (s, d.on) {
                (_, false) if d.reason == Reason::Absent => "none in the scene: no work for it",
                (Switch::Dispersion, true) => {
                    "a dispersive event keeps only the hero wavelength (per-lane mask)"
                }
                (Switch::Dispersion, false) => {
                    "no per-wavelength IOR: dispersive built-in materials use their IOR at 550 nm"
                }
                (Switch::Fluorescence, true) => "fluorescent events may shift the wavelength",
                (Switch::Fluorescence, false) => "no fluorescence bookkeeping",
                (Switch::ThinFilm, true) => "thin films weight each lane by its Airy R/T",
                (Switch::ThinFilm, false) => "no film: thin-film materials show their bare base",
                (Switch::NarrowbandEmission, true) => {
                    "pt draws wavelengths half from the observer, half from the lights' spectra"
                }
                (Switch::NarrowbandEmission, false) => {
                    "pt draws wavelengths from the observer alone (bdpt, lt: observer plus \
                     lights' spectra unless forced off)"
                }
                (Switch::FlatPathColour, true) => {
                    "bdpt and lt: a path whose every vertex is spectrally flat (grey, constant \
                     IOR) gets its emitter's exact colour, no colour noise from the wavelengths \
                     (the spectral film keeps the per-wavelength estimate; pt: not yet)"
                }
                (Switch::FlatPathColour, false) => {
                    "every path's colour is estimated from its wavelengths"
                }
                (Switch::Manifold, true) => {
                    "bdpt: paths camera → specular → diffuse → refractions (or one reflection) \
                     → area light also by solving the chain to a sampled light point (MIS with \
                     s = 0)"
                }
                (Switch::Manifold, false) => "those paths come from s = 0 alone",
                (Switch::CameraChain, true) => {
                    "bdpt, pinhole cameras only: paths camera → specular → area light (the lamp \
                     seen in or through glass) also by solving seeded chains from the pinhole \
                     to a sampled light point (MIS with s = 0); thin-lens cameras: s = 0 alone"
                }
                (Switch::CameraChain, false) => "those paths come from s = 0 alone",
                (Switch::VisibilityGuide, true) => {
                    "pt's next-event estimation and bdpt's s = 1 strategy: points of area lights \
                     on quads and small meshes, and the environment's directions, drawn from a \
                     density learned by a short pre-pass (where the light is visible from each \
                     region), for every light whose pre-pass light is at least 30% occluded \
                     (forced on: every such light)"
                }
                (Switch::VisibilityGuide, false) => {
                    "light points uniform by area, environment directions by its own sampling"
                }
            };
            out.push_str(&format!("  {}: {} — {what}\n", s.name(), d.text()));
        }
        out.push_str(&format!(
            "  light-subpaths: {} — bdpt: {}\n",
            match self.request.light_subpaths {
                LightSubpaths::Auto => "auto".to_string(),
                LightSubpaths::Fraction(q) => format!("{q} (forced)"),
            },
            match self.request.light_subpaths {
                LightSubpaths::Auto => {
                    "a short pilot chooses the fraction q of camera samples that trace light \
                     subpaths (1, 1/2, …, 1/16, and 0: every camera sample path traced, where \
                     path tracing samples every path bdpt does) and, unless \
                     light-subpath-count is given, how many each traces (1, 2, 4 or 8 where \
                     some surface scatters by a delta lobe, else 1) by estimated variance × \
                     cost; the light-subpath strategies are weighted by their expected counts \
                     (q = 1 with beams-only lights or fluorescence)"
                }
                LightSubpaths::Fraction(q) if q <= 0.0 => {
                    "no light subpaths: the camera samples are path traced (pt's estimator and \
                     visibility guide); an error with beams-only lights, fluorescence, \
                     --strategy-images, or a light that rays cannot hit with a specular surface"
                }
                LightSubpaths::Fraction(_) => {
                    "this fraction of camera samples trace light subpaths, the strategies that \
                     use them weighted by their expected counts (q = 1 with beams-only lights \
                     or fluorescence)"
                }
            }
        ));
        out.push_str(&format!(
            "  light-subpath-count: {} — bdpt: light subpaths per camera sample that traces \
             them, the first joined to every camera vertex, the others to the camera only \
             (t = 1)\n",
            match self.request.light_subpath_count {
                LightSubpathCount::Auto => "auto (the pilot's choice)".to_string(),
                LightSubpathCount::Count(n) => format!("{n} (forced)"),
            }
        ));
        for n in &self.notes {
            out.push_str(&format!("  note: {n}\n"));
        }
        out
    }
}

/// Why light paths are needed: beam-only lights, or delta lights behind delta BSDFs.
fn light_path_reasons(effects: &EffectSet) -> Vec<String> {
    let mut out = Vec::new();
    for c in effects.callers(Effect::BeamOnlyLights) {
        out.push(format!("{c} is beam-only"));
    }
    if effects.contains(Effect::SpecularChains) {
        for c in effects.callers(Effect::DeltaLights) {
            out.push(format!("{c} is seen through delta BSDFs"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    // Names, aliases, values and the errors naming the bad part.
    #[test]
    fn request_parsing() {
        let r = EffectsRequest::parse(
            EffectsMode::Auto,
            &[
                "dispersion=off".into(),
                "line_emission=ON".into(),
                "dispersion=on".into(),
            ],
        )
        .unwrap();
        assert_eq!(r.forced(Switch::Dispersion), Some(true));
        assert_eq!(r.forced(Switch::NarrowbandEmission), Some(true));
        assert_eq!(r.forced(Switch::ThinFilm), None);
        let e = EffectsRequest::parse(EffectsMode::Auto, &["delta-lights=off".into()]).unwrap_err();
        assert!(e.contains("property of the scene"), "{e}");
        let e = EffectsRequest::parse(EffectsMode::Auto, &["sparkle=on".into()]).unwrap_err();
        assert!(e.contains("unknown effect") && e.contains("sparkle"), "{e}");
        let e = EffectsRequest::parse(EffectsMode::Auto, &["dispersion=maybe".into()]).unwrap_err();
        assert!(e.contains("maybe"), "{e}");
        // The count of light subpaths: auto or 1..=64, the error naming the value; it enters
        // the settings' key only when forced (older keys stay as they were).
        let r = EffectsRequest::parse(
            EffectsMode::Auto,
            &[
                "light-subpath-count=2".into(),
                "light_subpath_count=8".into(),
            ],
        )
        .unwrap();
        assert_eq!(r.light_subpath_count, LightSubpathCount::Count(8));
        assert!(r.key().ends_with("light-subpath-count=8"), "{}", r.key());
        assert_eq!(
            EffectsRequest::parse(EffectsMode::Auto, &[]).unwrap().key(),
            "Auto[]"
        );
        for bad in ["0", "65", "2.5", "four", "-1"] {
            let e =
                EffectsRequest::parse(EffectsMode::Auto, &[format!("light-subpath-count={bad}")])
                    .unwrap_err();
            assert!(e.contains(&format!("light-subpath-count={bad}")), "{e}");
        }
        let e = EffectsRequest::parse(EffectsMode::Auto, &["dispersion".into()]).unwrap_err();
        assert!(e.contains("NAME=on"), "{e}");
    }

    // Auto follows the analysis, all turns everything on, forcing wins; the Cornell box has
    // none of the switchable effects.
    #[test]
    fn decisions_follow_analysis_mode_and_forcing() {
        let scene = crate::scene::default_scene().unwrap();
        let auto = RenderPlan::auto(&scene);
        assert!(!auto.dispersion() && !auto.fluorescence() && !auto.thin_film());
        assert!(!auto.emission_wavelengths());
        assert!(auto.notes().is_empty());
        assert!(auto.mixture().has_emission());
        // Its light is an area light: one spectral shape everywhere.
        assert!(auto.flat_path_colour());
        let all = RenderPlan::new(
            &scene,
            &EffectsRequest {
                mode: EffectsMode::All,
                forced: vec![(Switch::ThinFilm, false)],
                ..Default::default()
            },
        );
        assert!(all.dispersion() && all.fluorescence() && all.emission_wavelengths());
        assert!(!all.thin_film());
        assert!(all.summary_line().contains("thin-film OFF (forced)"));
        let off = RenderPlan::new(
            &scene,
            &EffectsRequest {
                mode: EffectsMode::Auto,
                forced: vec![(Switch::NarrowbandEmission, false)],
                ..Default::default()
            },
        );
        assert!(!off.mixture().has_emission());
    }
}
