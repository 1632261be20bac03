//! Which integrator renders (`--integrator bdpt|pt|lt`): a lookup in the list of registered
//! integrator types ([`registered`]), the render summary of which light each one handles how,
//! and BDPT's strategy images on disk.

use super::driver::{Integrator, IntegratorOptions, IntegratorOutput, Registration};
use super::render::ProgressFn;
use super::{RenderError, RenderSettings};
use crate::light::LightFlags;
use crate::scene::Scene;

/// Every integrator type this build provides, the default first.
pub fn registered() -> &'static [Registration] {
    const ALL: [Registration; 3] = [
        super::bdpt::REGISTRATION,
        super::path::REGISTRATION,
        super::light_tracer::REGISTRATION,
    ];
    &ALL
}

/// The registered integrator that answers to `name` (its name or an alias, any case).
pub fn find(name: &str) -> Option<&'static Registration> {
    registered().iter().find(|r| r.info.answers_to(name))
}

/// A registered integrator type, by name (`--integrator`); the default is the first
/// registered one (BDPT).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IntegratorKind(&'static str);

// The three built-ins by the names callers have always used for them.
#[allow(non_upper_case_globals)]
impl IntegratorKind {
    /// Bidirectional path tracing with power-heuristic MIS over all (s, t) strategies.
    pub const Bdpt: Self = Self(super::bdpt::INFO.name);
    /// Unidirectional path tracing with next-event estimation.
    pub const Pt: Self = Self(super::path::INFO.name);
    /// Light tracing: light paths connected to the camera (t = 1) only.
    pub const Lt: Self = Self(super::light_tracer::INFO.name);
}

impl IntegratorKind {
    /// Its registration (every `IntegratorKind` names a registered type).
    pub fn registration(self) -> &'static Registration {
        find(self.0).expect("an IntegratorKind names a registered integrator")
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        self.0
    }
}

impl Default for IntegratorKind {
    fn default() -> Self {
        Self(registered()[0].info.name)
    }
}

impl std::str::FromStr for IntegratorKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match find(s) {
            Some(r) => Ok(Self(r.info.name)),
            None => Err(format!(
                "unknown integrator {s:?}: expected {}",
                registered()
                    .iter()
                    .map(|r| r.info.name)
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }
}

impl std::fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.0)
    }
}

/// Build the integrator `kind` from `settings`.
pub fn build(
    kind: IntegratorKind,
    settings: &RenderSettings,
    options: IntegratorOptions,
) -> Result<Box<dyn Integrator>, RenderError> {
    (kind.registration().build)(settings, options).map_err(RenderError::Setup)
}

/// One line per light of the scene saying which strategies of `kind` render it.
pub fn strategy_summary(scene: &Scene, kind: IntegratorKind) -> Vec<String> {
    let Ok(integrator) = build(
        kind,
        &RenderSettings::default(),
        IntegratorOptions::default(),
    ) else {
        return Vec::new();
    };
    let total_w: f64 = scene.lights.lights().iter().map(|l| l.power()).sum();
    scene
        .lights
        .lights()
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let f = l.flags();
            let what = if f.contains(LightFlags::BEAMS_ONLY) {
                "beams-only light"
            } else if f.contains(LightFlags::DELTA_DIRECTION) {
                "directional light"
            } else if f.contains(LightFlags::DELTA_POSITION) {
                "point-like light"
            } else if f.contains(LightFlags::ENVIRONMENT) {
                "environment light"
            } else if f.contains(LightFlags::AREA) {
                "area light"
            } else {
                "light without a surface"
            };
            let item = scene
                .options
                .light_items
                .get(i)
                .map_or(String::new(), |n| format!("{n}, "));
            format!(
                "light {i} ({item}{what}, {}, chosen with p = {:.4}): {}",
                crate::light::luminous::flux_text(
                    l.power(),
                    (!f.contains(LightFlags::BEAMS_ONLY))
                        .then(|| l.spd())
                        .as_deref(),
                    scene.options.relative_emission,
                    total_w,
                ),
                scene.lights.pmf(i),
                integrator.light_strategy(f)
            )
        })
        .chain(fluorescence_strategy(scene, kind))
        .collect()
}

/// What integrator `kind` does at fluorescent surfaces, when the scene renders fluorescence.
fn fluorescence_strategy(scene: &Scene, kind: IntegratorKind) -> Option<String> {
    if !scene.objects.fluorescence() {
        return None;
    }
    Some(
        if kind == IntegratorKind::Bdpt {
            "fluorescence: each lane's wavelength shifts on camera and light subpaths; a lane shifted anywhere is made by s = 0, s = 1 and t = 1 (per-lane MIS over those, with both ends' wavelength densities), unshifted lanes by every strategy"
        } else if kind == IntegratorKind::Lt {
            "fluorescence: light paths shift each lane's wavelength at fluorescent surfaces"
        } else {
            "fluorescence: camera paths shift each lane's wavelength at fluorescent surfaces"
        }
        .to_string(),
    )
}

/// Render `scene` with the integrator `kind`. `strategy_images` asks BDPT for one image per
/// (s, t) strategy (ignored by the other integrators).
pub fn render_with(
    scene: &Scene,
    settings: &RenderSettings,
    kind: IntegratorKind,
    strategy_images: bool,
    progress: &ProgressFn<'_>,
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<IntegratorOutput, RenderError> {
    let plan = crate::integrator::plan::RenderPlan::auto(scene);
    render_planned(
        scene,
        &plan,
        settings,
        kind,
        strategy_images,
        progress,
        cancel,
    )
}

/// Render `scene` with the integrator `kind` and the extra outputs in `options` (strategy
/// images, a spectral image), under the automatic render plan.
pub fn render_with_options(
    scene: &Scene,
    settings: &RenderSettings,
    kind: IntegratorKind,
    options: IntegratorOptions,
    progress: &ProgressFn<'_>,
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<IntegratorOutput, RenderError> {
    let plan = crate::integrator::plan::RenderPlan::auto(scene);
    render_planned_with_options(scene, &plan, settings, kind, options, progress, cancel)
}

/// [`render_with`] under a given render plan (made for `scene` by
/// [`RenderPlan::new`](crate::integrator::plan::RenderPlan::new)): the integrator renders the plan's
/// scene (materials with a switched-off effect replaced) and reads the plan.
pub fn render_planned(
    scene: &Scene,
    plan: &crate::integrator::plan::RenderPlan,
    settings: &RenderSettings,
    kind: IntegratorKind,
    strategy_images: bool,
    progress: &ProgressFn<'_>,
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<IntegratorOutput, RenderError> {
    let options = IntegratorOptions {
        strategy_images,
        ..IntegratorOptions::default()
    };
    render_planned_with_options(scene, plan, settings, kind, options, progress, cancel)
}

/// [`render_with_options`] under a given render plan.
pub fn render_planned_with_options(
    scene: &Scene,
    plan: &crate::integrator::plan::RenderPlan,
    settings: &RenderSettings,
    kind: IntegratorKind,
    options: IntegratorOptions,
    progress: &ProgressFn<'_>,
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<IntegratorOutput, RenderError> {
    let integrator = build(kind, settings, options)?;
    let planned = plan.scene(scene);
    integrator.render(&planned, plan, settings, progress, cancel)
}

/// Write BDPT's strategy images as `DIR/strategy_s{s}_t{t}.exr` (and `strategy_longer.exr`),
/// creating `DIR`; returns the files written.
pub fn write_strategy_images(
    dir: &std::path::Path,
    output: &IntegratorOutput,
    scene: &Scene,
) -> Result<Vec<std::path::PathBuf>, String> {
    if output.strategy_images.is_empty() {
        return Ok(Vec::new());
    }
    std::fs::create_dir_all(dir).map_err(|e| {
        format!(
            "cannot create strategy image directory {}: {e}",
            dir.display()
        )
    })?;
    let mut written = Vec::new();
    for ((s, t), image) in &output.strategy_images {
        if (*s, *t) == (0, 1) {
            continue; // not a strategy (the lens is not in the scene); always black
        }
        let name = if *s == u32::MAX {
            "strategy_longer.exr".to_string()
        } else {
            format!("strategy_s{s}_t{t}.exr")
        };
        let path = dir.join(name);
        crate::film::write_exr(&path, image, &scene.options.rgb_space)
            .map_err(|e| e.to_string())?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every registered integrator is found by its name and each alias, names do not clash,
    /// and each builds from default settings into an integrator reporting the same info.
    #[test]
    fn registered_integrators_are_found_by_name() {
        let mut names = Vec::new();
        for r in registered() {
            for n in std::iter::once(r.info.name).chain(r.info.aliases.iter().copied()) {
                assert!(!names.contains(&n), "name {n} registered twice");
                names.push(n);
                let kind: IntegratorKind = n.to_ascii_uppercase().parse().unwrap();
                assert_eq!(kind.name(), r.info.name);
            }
            assert!(
                !r.info.params.is_empty(),
                "{} has no parameter table",
                r.info.name
            );
            let built = (r.build)(&RenderSettings::default(), IntegratorOptions::default());
            assert_eq!(built.unwrap().info().name, r.info.name);
        }
        assert_eq!(IntegratorKind::default(), IntegratorKind::Bdpt);
        let err = "nope".parse::<IntegratorKind>().unwrap_err();
        assert!(err.contains("bdpt, pt, lt"), "{err}");
    }
}
