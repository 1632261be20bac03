//! Error versus time of renderer configurations: each configuration renders the scene at
//! 1, 2, 4, … samples per pixel (fresh renders, doubling) until its time budget is used, and
//! every render is compared with a reference. A converged unbiased estimator's RMSE falls as
//! time^−½, so the fitted log–log slope should approach −0.5; a biased configuration flattens
//! out at its bias. Configurations that change the scene's spectral representation get their own
//! scene, built from a [`SceneProvider`] (not timed).

use super::{
    compare_images_excluding, specular_view_mask, AnalysisError, CompareOptions, RgbImage,
};
use crate::integrator::{render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget};
use crate::scene::{Scene, SceneSource};
use crate::scene_file::{ReflectanceSource, RepresentationOptions};
use crate::spectrum::Interpolation;
use std::time::{Duration, Instant};

/// Builds the benchmark's scene for a configuration's representation switches.
pub trait SceneProvider {
    /// The scene built with `representation`.
    fn scene_with(&self, representation: &RepresentationOptions) -> Result<Scene, String>;
}

/// An already built scene serves only the default representation (it cannot be rebuilt).
impl SceneProvider for Scene {
    fn scene_with(&self, representation: &RepresentationOptions) -> Result<Scene, String> {
        if representation.is_default() {
            Ok(self.clone())
        } else {
            Err(format!(
                "a prebuilt scene cannot be rebuilt with {}; pass a SceneSource",
                representation.label()
            ))
        }
    }
}

impl SceneProvider for SceneSource {
    fn scene_with(&self, representation: &RepresentationOptions) -> Result<Scene, String> {
        self.build(representation).map_err(|e| e.to_string())
    }
}

/// One renderer configuration of the benchmark.
#[derive(Clone, Debug, PartialEq)]
pub struct AccuracyConfig {
    /// Short name used on the command line, in the CSV and in the plot.
    pub name: String,
    /// What it trades, in one sentence.
    pub trade_off: String,
    /// Light transport algorithm.
    pub integrator: IntegratorKind,
    /// Path settings (depth, Russian roulette).
    pub tracer: PathTracer,
    /// How the scene's spectra and observer are represented (default: as written, 1 nm CIE).
    pub representation: RepresentationOptions,
}

/// The configurations the renderer really supports, for a scene whose default maximum depth is
/// `max_depth`: the three integrators, path tracing's path and wavelength settings, and the
/// spectral representations.
pub fn available_configs(max_depth: u32) -> Vec<AccuracyConfig> {
    let base = PathTracer {
        max_depth,
        ..PathTracer::default()
    };
    let mut out = integrator_configs(base);
    out.extend(path_configs(base));
    out.extend(representation_configs(base));
    out
}

/// A configuration of `integrator` with `tracer` and the scene's spectra as written.
fn config(
    name: &str,
    trade_off: &str,
    integrator: IntegratorKind,
    tracer: PathTracer,
) -> AccuracyConfig {
    AccuracyConfig {
        name: name.into(),
        trade_off: trade_off.into(),
        integrator,
        tracer,
        representation: RepresentationOptions::default(),
    }
}

/// The three integrators with their default settings.
fn integrator_configs(base: PathTracer) -> Vec<AccuracyConfig> {
    let cfg = config;
    vec![
        cfg(
            "pt",
            "Path tracing with next-event estimation and MIS, Russian roulette from bounce 3, \
             wavelengths importance-sampled for the observer: the cheap, robust baseline.",
            IntegratorKind::Pt,
            base,
        ),
        cfg(
            "bdpt",
            "Bidirectional path tracing over all (s, t) strategies with MIS and wavelengths from \
             the observer/emission mixture: several times the work per sample for lower \
             variance where light arrives indirectly or through specular paths.",
            IntegratorKind::Bdpt,
            base,
        ),
        cfg(
            "lt",
            "Light tracing (light paths splatted to the camera only): cheap per path and good \
             for caustics, but noisy on what the camera sees through specular surfaces and \
             spread thin over the image.",
            IntegratorKind::Lt,
            base,
        ),
    ]
}

/// Path tracing with one path or wavelength setting changed from `base`.
fn path_configs(base: PathTracer) -> Vec<AccuracyConfig> {
    let cfg = config;
    let max_depth = base.max_depth;
    vec![
        cfg(
            "pt-rr1",
            "Path tracing with Russian roulette from the first bounce: shorter paths and more \
             samples per second for more variance per sample.",
            IntegratorKind::Pt,
            PathTracer {
                rr_depth: 1,
                ..base
            },
        ),
        cfg(
            "pt-norr",
            "Path tracing without Russian roulette (every path runs to the maximum depth): the \
             least variance per sample, bought with much longer paths.",
            IntegratorKind::Pt,
            PathTracer {
                rr_depth: u32::MAX,
                ..base
            },
        ),
        cfg(
            "pt-uniform-lambda",
            "Path tracing with wavelengths drawn uniformly over 360–830 nm instead of for the \
             observer's response: the same cost per sample, more colour noise, since many \
             wavelengths land where the eye barely sees.",
            IntegratorKind::Pt,
            PathTracer {
                wavelengths: crate::integrator::WavelengthSampling::Uniform,
                ..base
            },
        ),
        cfg(
            "pt-light-lambda",
            "Path tracing with wavelengths drawn from the lights' emission spectra: no wavelength \
             is spent where nothing is emitted, but where a light is strong and the eye is \
             insensitive (deep red, violet) samples are wasted on dim colour.",
            IntegratorKind::Pt,
            PathTracer {
                wavelengths: crate::integrator::WavelengthSampling::LightSpd,
                ..base
            },
        ),
        cfg(
            "pt-lambda1",
            "Path tracing with one wavelength per path instead of four: the classic spectral \
             estimator, much more colour noise per sample for almost no time saved (the four \
             lanes are computed as one vector).",
            IntegratorKind::Pt,
            PathTracer {
                wavelengths_per_path: 1,
                ..base
            },
        ),
        cfg(
            "pt-lambda8",
            "Path tracing with eight wavelengths per path (two groups of four sharing the \
             geometric path): less colour noise per sample, paid with twice the material and \
             light evaluations.",
            IntegratorKind::Pt,
            PathTracer {
                wavelengths_per_path: 8,
                ..base
            },
        ),
        cfg(
            "pt-lambda16",
            "Path tracing with sixteen wavelengths per path: colour noise nearly gone per \
             sample, at four times the spectral work; worth it only where colour noise, not \
             geometric noise, dominates.",
            IntegratorKind::Pt,
            PathTracer {
                wavelengths_per_path: 16,
                ..base
            },
        ),
        cfg(
            "pt-depth4",
            "Path tracing cut at 4 bounces: faster, but biased (the energy of longer paths is \
             missing), so its error stops falling at the bias.",
            IntegratorKind::Pt,
            PathTracer {
                max_depth: 4.min(max_depth),
                ..base
            },
        ),
    ]
}

/// Path tracing with the scene's spectra or observer represented otherwise.
fn representation_configs(base: PathTracer) -> Vec<AccuracyConfig> {
    let repr = |name: &str, trade_off: &str, representation| AccuracyConfig {
        representation,
        ..config(name, trade_off, IntegratorKind::Pt, base)
    };
    let as_written = RepresentationOptions::default();
    vec![
        repr(
            "pt-spd-step",
            "Path tracing with every tabulated spectrum (reflectances, emission, CSV and bundled \
             tables) read as steps, seed §5's piecewise-constant representation, instead of \
             linearly: the same cost, but coarse tables change shape and power, so the error \
             flattens at that representation bias.",
            RepresentationOptions {
                spd_interpolation: Interpolation::Step,
                ..as_written
            },
        ),
        repr(
            "pt-rgb-uplift",
            "Path tracing with each measured reflectance replaced by the smooth spectrum uplifted \
             from its linear sRGB colour under D65, as an RGB-authored scene stores it: the same \
             cost and colours under D65, but other spectra under the scene's light and after \
             inter-reflection, so the error flattens at that bias.",
            RepresentationOptions {
                reflectance: ReflectanceSource::RgbUplift,
                ..as_written
            },
        ),
        repr(
            "pt-observer-5nm",
            "Path tracing with the colour-matching functions known every 5 nm and interpolated \
             linearly, as renderers storing 5 nm CIE tables do: a smaller table for a small \
             colour bias at which the error flattens.",
            RepresentationOptions {
                observer_step_nm: 5,
                ..as_written
            },
        ),
        repr(
            "pt-observer-10nm",
            "Path tracing with the colour-matching functions known every 10 nm and interpolated \
             linearly: the coarsest common table, whose colour bias is where the error flattens.",
            RepresentationOptions {
                observer_step_nm: 10,
                ..as_written
            },
        ),
    ]
}

/// Configurations the issue asks for that the renderer has no switch for yet: (name, why).
pub fn unavailable_configs() -> Vec<(&'static str, &'static str)> {
    vec![(
        "wavelengths per path and wavelength sampling for bdpt/lt",
        "bdpt and lt always carry four wavelengths drawn from the observer/emission mixture; \
         the wavelength switches are path-tracer settings",
    )]
}

/// Select configurations by name (`None`: all); unknown names are an error listing the known.
pub fn select_configs(
    all: Vec<AccuracyConfig>,
    names: Option<&[String]>,
) -> Result<Vec<AccuracyConfig>, String> {
    let Some(names) = names else {
        return Ok(all);
    };
    let known: Vec<String> = all.iter().map(|c| c.name.clone()).collect();
    names
        .iter()
        .map(|n| {
            all.iter().find(|c| &c.name == n).cloned().ok_or_else(|| {
                let extra = unavailable_configs()
                    .iter()
                    .map(|(n, _)| *n)
                    .collect::<Vec<_>>()
                    .join("; ");
                format!(
                    "unknown configuration {n:?}; available: {} (not yet available: {extra})",
                    known.join(", ")
                )
            })
        })
        .collect()
}

/// One measurement.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AccuracyPoint {
    /// Configuration name.
    pub config: String,
    /// Samples per pixel.
    pub spp: u32,
    /// Wall-clock seconds of the render (scene already loaded).
    pub seconds: f64,
    /// Camera samples per second.
    pub samples_per_second: f64,
    /// RMSE against the reference, light excluded (linear sRGB).
    pub rmse: f64,
    /// Relative MSE, light excluded.
    pub rel_mse: f64,
    /// Mean CIEDE2000, light excluded.
    pub delta_e_mean: f64,
    /// 99th-percentile CIEDE2000, light excluded.
    pub delta_e_p99: f64,
}

/// Header of the CSV written by [`to_csv`].
pub const CSV_HEADER: &str =
    "config,spp,seconds,samples_per_second,rmse,rel_mse,delta_e_mean,delta_e_p99";

/// The points as CSV (header first).
pub fn to_csv(points: &[AccuracyPoint]) -> String {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for p in points {
        s.push_str(&format!(
            "{},{},{:.6},{:.1},{:.6e},{:.6e},{:.6},{:.6}\n",
            p.config,
            p.spp,
            p.seconds,
            p.samples_per_second,
            p.rmse,
            p.rel_mse,
            p.delta_e_mean,
            p.delta_e_p99
        ));
    }
    s
}

/// Least-squares slope and intercept of log10(y) against log10(x) over points with x, y > 0;
/// `None` with fewer than two distinct x.
pub fn loglog_fit(points: &[(f64, f64)]) -> Option<(f64, f64)> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0 && x.is_finite() && y.is_finite())
        .map(|(x, y)| (x.log10(), y.log10()))
        .collect();
    let n = pts.len() as f64;
    if pts.len() < 2 {
        return None;
    }
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let slope = sxy / sxx;
    Some((slope, my - slope * mx))
}

/// The points used for the slope: those at 4 spp and more (the first renders are dominated by
/// fixed costs and by the few-sample regime).
pub fn converged(points: &[AccuracyPoint], config: &str) -> Vec<AccuracyPoint> {
    points
        .iter()
        .filter(|p| p.config == config && p.spp >= 4)
        .cloned()
        .collect()
}

/// Settings of a benchmark run.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchSettings {
    /// Time budget per configuration.
    pub budget: Duration,
    /// Largest sample count tried.
    pub max_spp: u32,
    /// Seed of every render.
    pub seed: u64,
    /// Worker threads (`None`: one per core).
    pub threads: Option<usize>,
    /// Leave out the pixels that show specular surfaces ([`specular_view_mask`]) besides the
    /// light.
    pub exclude_specular: bool,
}

/// Run every configuration (see the module docs); `on_point` sees each measurement as it is
/// made. `scenes` builds one scene per distinct representation (a prebuilt [`Scene`] serves
/// configurations with the default representation; a [`SceneSource`] serves all).
pub fn run_accuracy_bench(
    scenes: &dyn SceneProvider,
    reference: &RgbImage,
    configs: &[AccuracyConfig],
    settings: &BenchSettings,
    on_point: &dyn Fn(&AccuracyPoint),
) -> Result<Vec<AccuracyPoint>, AnalysisError> {
    let mut points = Vec::new();
    let mut built: Vec<(RepresentationOptions, Scene, Option<Vec<bool>>)> = Vec::new();
    for cfg in configs {
        let idx = match built.iter().position(|(r, _, _)| *r == cfg.representation) {
            Some(i) => i,
            None => {
                let scene = scenes
                    .scene_with(&cfg.representation)
                    .map_err(|e| AnalysisError::Render(format!("{}: {e}", cfg.name)))?;
                let mask = settings
                    .exclude_specular
                    .then(|| specular_view_mask(&scene));
                built.push((cfg.representation, scene, mask));
                built.len() - 1
            }
        };
        let (scene, mask) = (&built[idx].1, built[idx].2.as_deref());
        let mut used = 0.0f64;
        let mut last = 0.0f64;
        let mut spp = 1u32;
        while spp <= settings.max_spp {
            // The next render takes about twice the last: skip it if it cannot fit.
            if used > 0.0 && used + 2.0 * last > settings.budget.as_secs_f64() {
                break;
            }
            let rs = RenderSettings {
                sampler: Default::default(),
                budget: SampleBudget::Spp(spp),
                seed: settings.seed,
                threads: settings.threads,
                camera: None,
                tile_size: 16,
                tracer: cfg.tracer,
            };
            let t = Instant::now();
            let out = render_with(scene, &rs, cfg.integrator, false, &|_, _| {}, None)
                .map_err(|e| AnalysisError::Render(format!("{}: {e}", cfg.name)))?;
            let secs = t.elapsed().as_secs_f64();
            let img = RgbImage::from_xyz(&out.result.image, &crate::color::SRGB);
            if (img.width, img.height) != (reference.width, reference.height) {
                return Err(AnalysisError::Render(format!(
                    "the scene renders {}×{} but the reference is {}×{}",
                    img.width, img.height, reference.width, reference.height
                )));
            }
            let (c, _) = compare_images_excluding(
                &img,
                reference,
                CompareOptions {
                    exclude_light: true,
                },
                mask,
            );
            let p = AccuracyPoint {
                config: cfg.name.clone(),
                spp,
                seconds: secs,
                samples_per_second: out.result.samples as f64 / secs.max(1e-9),
                rmse: c.rmse,
                rel_mse: c.rel_mse,
                delta_e_mean: c.delta_e_mean,
                delta_e_p99: c.delta_e_p99,
            };
            on_point(&p);
            points.push(p);
            used += secs;
            last = secs;
            spp = match spp.checked_mul(2) {
                Some(s) => s,
                None => break,
            };
        }
    }
    Ok(points)
}

/// First measured time at which `config` reaches `metric ≤ target`, if it does.
pub fn time_to_reach(
    points: &[AccuracyPoint],
    config: &str,
    metric: fn(&AccuracyPoint) -> f64,
    target: f64,
) -> Option<(f64, u32)> {
    points
        .iter()
        .filter(|p| p.config == config && metric(p) <= target)
        .map(|p| (p.seconds, p.spp))
        .min_by(|a, b| a.0.total_cmp(&b.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fit recovers an exact power law y = 3·x^−0.5 (slope −0.5, intercept log10 3) to
    /// 1e-12 (only rounding), and refuses a single point.
    #[test]
    fn fit_recovers_power_law() {
        let pts: Vec<(f64, f64)> = [0.5, 1.0, 2.0, 8.0]
            .iter()
            .map(|&x| (x, 3.0 / f64::sqrt(x)))
            .collect();
        let (m, b) = loglog_fit(&pts).unwrap();
        assert!((m + 0.5).abs() < 1e-12 && (b - 3f64.log10()).abs() < 1e-12);
        assert!(loglog_fit(&pts[..1]).is_none());
    }

    /// Names select configurations; an unknown name lists what exists.
    #[test]
    fn selection() {
        let all = available_configs(64);
        let s = select_configs(all.clone(), Some(&["bdpt".into(), "pt".into()])).unwrap();
        assert_eq!(s[0].name, "bdpt");
        let e = select_configs(all, Some(&["spp16".into()])).unwrap_err();
        assert!(e.contains("pt-rr1"), "{e}");
    }
}
