//! Illuminance at the points of a sensor grid, in lux, with its standard error.
//!
//! Illuminance is `E_v = K_m ∫ E_λ(λ) V(λ) dλ` with `K_m = 683 lm/W` and `V = ȳ` of the CIE 1931
//! 2° observer (CIE 015), whatever observer the scene's film uses, and spectral irradiance
//! `E_λ = ∫_H L_λ(ω) cos θ dω` over the hemisphere on the grid's normal side.
//!
//! Two estimators, chosen by the integrator the render uses ([`Estimator::for_integrator`]):
//!
//! - **Sensor path tracing** (`pt`, `bdpt`): each sample draws wavelengths, then
//!   (1) next-event estimation: one light point sampled as the path tracer does, weighted
//!   `L·cos θ / pdf`, and (2) one cosine-weighted direction (pdf `cos θ/π`) whose incident
//!   radiance is the path tracer's own estimate [`PathTracer::li`] (its next-event estimation
//!   and Russian roulette further along). The emission the direction finds at its first hit is
//!   weighted against (1) by the power heuristic, as a path tracer weighs a BSDF hit, so the
//!   sensor is a white Lambertian receiver of `f = 1/π` that the path tracer renders exactly.
//!   Delta lights (point, spot, directional) are found by (1) alone.
//! - **Light tracing** (`lt`): the light paths of light tracing (a light chosen by power, an
//!   emitted ray, the random walk in importance mode) are joined to every grid point from each
//!   surface vertex after the first bounce (`β · f · |cos θ_v| · cos θ_x / d²`, one shadow ray
//!   each); light arriving straight from a light source (no bounce) is estimated by (1) at the
//!   point, because a light vertex of a delta light cannot be joined to a point in a way that
//!   covers directional lights. The two parts are independent, so their variances add.
//!
//! Each sample is independent (its own generator stream per point and sample, or per light
//! path), so the standard error is the sample standard deviation over √N. Same seed, same
//! result for any thread count: points are computed independently and the light-tracing sums
//! are added in a fixed order.
//!
//! Both estimators are unbiased for what they can sample: sensor path tracing misses light that
//! reaches the point only through a specular chain from a delta light (a mirror's reflection of
//! a point light), light tracing misses light whose last bounce before the point is specular
//! (a point behind glass); beams-only plugin lights are not measured by either.

use crate::film::Sensor;
use crate::geometry::{spawn_ray, spawn_ray_to};
use crate::integrator::mis::power_heuristic;
use crate::integrator::subpath::light_subpath::{generate_light_subpath, LightStart};
use crate::integrator::subpath::vertex::Vertex;
use crate::integrator::wavelengths::xyz_weights::XyzWeights;
use crate::integrator::{IntegratorKind, PathStats, PathTracer, PixelSampler, SampleRng};
use crate::light::{LightFlags, LightSampleContext};
use crate::material::{sample_cosine_hemisphere, Frame, MaterialFlags, ShadingContext};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3A;
use rayon::prelude::*;
use std::sync::Arc;

use crate::builtin::sensor::grid::IlluminanceGrid;

pub use crate::photometry::efficacy::KM_LM_PER_W;

/// Which estimator measures the grid (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Estimator {
    /// Next-event estimation + cosine-weighted sampling with MIS, continued by the path tracer.
    SensorPathTracing,
    /// Light-path vertices joined to the points, plus next-event estimation for direct light.
    LightTracing,
}

impl Estimator {
    /// The estimator a render with `kind` uses: light tracing for `lt`, sensor path tracing
    /// for `pt` and `bdpt`.
    pub fn for_integrator(kind: IntegratorKind) -> Self {
        if kind == IntegratorKind::Lt {
            Self::LightTracing
        } else {
            Self::SensorPathTracing
        }
    }

    /// One line for the render summary saying what was used.
    pub fn describe(self) -> &'static str {
        match self {
            Self::SensorPathTracing => {
                "sensor path tracing: next-event estimation + cosine-weighted directions \
                 (power-heuristic MIS), continued by the path tracer"
            }
            Self::LightTracing => {
                "light tracing: light-path vertices after the first bounce joined to every point, \
                 direct light by next-event estimation"
            }
        }
    }
}

/// Settings of one measurement.
#[derive(Clone, Debug)]
pub struct MeasureSettings {
    /// The estimator.
    pub estimator: Estimator,
    /// Samples per point (sensor path tracing), or light paths (light tracing; each also gives
    /// every point one next-event sample).
    pub samples: u32,
    /// Seed of all random numbers.
    pub seed: u64,
    /// Worker threads (`None`: one per core).
    pub threads: Option<usize>,
    /// Path length and Russian roulette (and `direct_only` for analytic checks).
    pub tracer: PathTracer,
}

/// The measured grid: lux and standard error per point, row-major like the grid's points.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorReading {
    /// The sensor's name.
    pub name: String,
    /// Point positions (scene units).
    pub points: Vec<glam::DVec3>,
    /// Illuminance per point, lx.
    pub lux: Vec<f64>,
    /// Standard error of each value, lx.
    pub stderr: Vec<f64>,
    /// Points along edge0 and edge1.
    pub resolution: (u32, u32),
    /// The estimator used.
    pub estimator: Estimator,
    /// Samples per point.
    pub samples: u32,
    /// Non-finite samples dropped (counted, not added).
    pub non_finite: u64,
    /// Standard error of the mean over the points, lx. Not `√Σσ²/n` for light tracing: one
    /// light path adds to every point, so the points' errors are correlated; the estimator
    /// measures the spread of each path's mean over the points instead.
    pub mean_stderr: f64,
}

impl SensorReading {
    /// Mean illuminance over the points (the average illuminance of the grid), lx, and its
    /// standard error.
    pub fn mean(&self) -> (f64, f64) {
        let n = self.lux.len().max(1) as f64;
        (self.lux.iter().sum::<f64>() / n, self.mean_stderr)
    }

    /// Smallest and largest illuminance, lx.
    pub fn min_max(&self) -> (f64, f64) {
        self.lux
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            })
    }
}

/// Running sums of one point's samples.
#[derive(Clone, Copy, Debug, Default)]
struct Sums {
    sum: f64,
    sum2: f64,
    non_finite: u64,
}

impl Sums {
    fn add(&mut self, v: f64) {
        if v.is_finite() {
            self.sum += v;
            self.sum2 += v * v;
        } else {
            self.non_finite += 1;
        }
    }

    /// Add another set of sums (of other samples).
    fn merge(&mut self, o: &Sums) {
        self.sum += o.sum;
        self.sum2 += o.sum2;
        self.non_finite += o.non_finite;
    }

    /// (mean, standard error of the mean) over `n` samples.
    fn mean_se(&self, n: f64) -> (f64, f64) {
        let m = self.sum / n;
        let var = if n > 1.0 {
            ((self.sum2 - n * m * m) / (n - 1.0)).max(0.0)
        } else {
            0.0
        };
        (m, (var / n).sqrt())
    }
}

/// A grid point as the estimators need it: position, normal, the frame around the normal and
/// a small error box so rays leaving it clear a surface it lies on.
#[derive(Clone, Copy, Debug)]
struct SensorPoint {
    p: Vec3A,
    p_error: Vec3A,
    n: Vec3A,
    frame: Frame,
}

impl SensorPoint {
    fn new(p: glam::DVec3, n: glam::DVec3) -> Self {
        let p = Vec3A::new(p.x as f32, p.y as f32, p.z as f32);
        let n = Vec3A::new(n.x as f32, n.y as f32, n.z as f32).normalize();
        // A point on a floor is as uncertain as the floor's own f32 intersection points (a few
        // ulps of its coordinates): offset rays by that so the floor does not shadow its own
        // sensor.
        let p_error = (p.abs() + Vec3A::ONE) * (16.0 * f32::EPSILON);
        Self {
            p,
            p_error,
            n,
            frame: Frame::from_normal(n),
        }
    }

    fn ctx(&self) -> LightSampleContext {
        LightSampleContext {
            p: self.p,
            p_error: self.p_error,
            n: self.n,
        }
    }
}

/// Photometric value (lx, or cd/m² for radiance) of one spectral sample: `K_m ∫ E ȳ dλ` by the
/// film's per-lane estimator with the CIE 1931 2° observer.
pub(crate) struct Photometric {
    sensor: Sensor,
    scale: f64,
}

impl Photometric {
    pub(crate) fn new() -> Self {
        let obs = Arc::new(crate::color::CieObserverKind::Cie1931_2.get().clone());
        let scale = KM_LM_PER_W * crate::color::Observer::integral_y(obs.as_ref());
        Self {
            sensor: Sensor::new(obs),
            scale,
        }
    }

    pub(crate) fn of(&self, e: &SampledSpectrum, lambda: &SampledWavelengths) -> f64 {
        if e.is_black() {
            return 0.0;
        }
        self.sensor.to_xyz(e, lambda)[1] * self.scale
    }
}

/// Measure `grid` in `scene`. Errors only for a thread pool that cannot be built.
pub fn measure(
    scene: &Scene,
    grid: &IlluminanceGrid,
    settings: &MeasureSettings,
) -> Result<SensorReading, String> {
    let pool =
        crate::integrator::tiled::thread_pool(settings.threads).map_err(|e| e.to_string())?;
    let normal = grid.normal();
    let points: Vec<glam::DVec3> = grid.points();
    let sp: Vec<SensorPoint> = points
        .iter()
        .map(|p| SensorPoint::new(*p, normal))
        .collect();
    let photo = Photometric::new();
    let n = settings.samples.max(1);
    // Each sensor draws its own random numbers (two grids in one scene are independent).
    let seed = settings.seed ^ crate::film::state_file::fnv1a64(&[grid.name.as_bytes()]);
    let (lux, stderr, non_finite, mean_stderr) = match settings.estimator {
        Estimator::SensorPathTracing => {
            let sums: Vec<Sums> = pool.install(|| {
                sp.par_iter()
                    .enumerate()
                    .map(|(k, x)| {
                        let mut s = Sums::default();
                        let mut stats = PathStats::default();
                        for i in 0..n {
                            let mut rng = point_sampler(seed, k, i);
                            let lambda = draw_wavelengths(rng.next_1d());
                            let direct = next_event(scene, x, &lambda, &mut rng, &mut stats, true);
                            let mut v = photo.of(&direct, &lambda);
                            v += hemisphere(
                                scene,
                                &settings.tracer,
                                x,
                                &lambda,
                                &mut rng,
                                &mut stats,
                                &photo,
                            );
                            s.add(v);
                        }
                        s
                    })
                    .collect()
            });
            let (mut lux, mut se, mut nf) = (Vec::new(), Vec::new(), 0);
            for s in &sums {
                let (m, e) = s.mean_se(n as f64);
                lux.push(m);
                se.push(e);
                nf += s.non_finite;
            }
            // Independent points: the variances of the mean add.
            let p = se.len().max(1) as f64;
            let mean_se = se.iter().map(|e| e * e).sum::<f64>().sqrt() / p;
            (lux, se, nf, mean_se)
        }
        Estimator::LightTracing => {
            light_tracing(scene, &sp, n, seed, &settings.tracer, &photo, &pool)
        }
    };
    Ok(SensorReading {
        name: grid.name.clone(),
        points,
        lux,
        stderr,
        resolution: (grid.nx, grid.ny),
        estimator: settings.estimator,
        samples: n,
        non_finite,
        mean_stderr,
    })
}

/// The generator of sample `i` at point `k`: its own scrambled sequence at index 0, so the
/// samples of a point are independent (the standard error then holds) and the first
/// dimensions are still well distributed.
pub(crate) fn point_sampler(seed: u64, k: usize, i: u32) -> PixelSampler {
    let stream = crate::sampler::mix64(
        (k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ (i as u64) ^ 0x5E45_0A5E,
    );
    PixelSampler::new(seed ^ 0x53E4_5025, stream, 0)
}

/// Four stratified wavelengths importance-sampled for the eye ([`SampledWavelengths::sample_visible`],
/// close to V(λ), the weight of every photometric quantity): for a flat spectrum the spectral
/// noise of a sample is a few per cent, against about 25 % with BDPT's mixture of observer and
/// emission densities.
pub(crate) fn draw_wavelengths(u: f32) -> SampledWavelengths {
    SampledWavelengths::sample_visible(u)
}

/// Next-event estimation at the point: spectral irradiance `L·cos θ/pdf` of one light sample,
/// MIS-weighted against cosine sampling (`mis`) for lights a ray can find.
fn next_event(
    scene: &Scene,
    x: &SensorPoint,
    lambda: &SampledWavelengths,
    rng: &mut PixelSampler,
    stats: &mut PathStats,
    mis: bool,
) -> SampledSpectrum {
    let u_light = rng.next_1d();
    let u2 = rng.next_2d();
    let Some((li, pmf)) = scene.lights.sample(u_light) else {
        return SampledSpectrum::zero();
    };
    let light = &scene.lights.lights()[li];
    if light.flags().contains(LightFlags::BEAMS_ONLY) {
        return SampledSpectrum::zero();
    }
    let Some(ls) = light.sample_li(&x.ctx(), u2, lambda) else {
        return SampledSpectrum::zero();
    };
    let cos = x.n.dot(ls.wi);
    if !(ls.pdf > 0.0 && cos > 0.0) || ls.radiance.is_black() {
        return SampledSpectrum::zero();
    }
    let (shadow, t_max) = spawn_ray_to(
        x.p,
        x.p_error,
        x.n,
        ls.p_light,
        ls.p_light_error,
        ls.n_light,
    );
    stats.shadow_rays += 1;
    if scene.geometry.occluded(&shadow, t_max) {
        return SampledSpectrum::zero();
    }
    let light_pdf = pmf * ls.pdf;
    let w = if mis && light.flags().can_be_hit() {
        power_heuristic(light_pdf, cos / std::f32::consts::PI)
    } else {
        1.0
    };
    ls.radiance * (cos * w / light_pdf)
}

/// The cosine-sampled part of sensor path tracing, already photometric (lx): π × the path
/// tracer's radiance along one cosine-weighted direction, minus the part `(1 − w)` of the
/// emission found at the first hit that next-event estimation covers.
fn hemisphere(
    scene: &Scene,
    tracer: &PathTracer,
    x: &SensorPoint,
    lambda: &SampledWavelengths,
    rng: &mut PixelSampler,
    stats: &mut PathStats,
    photo: &Photometric,
) -> f64 {
    let local = sample_cosine_hemisphere(rng.next_2d());
    if !(local.z > 0.0) {
        return 0.0;
    }
    let pdf = local.z / std::f32::consts::PI;
    let wi = x.frame.to_world(local);
    let ray = spawn_ray(x.p, x.p_error, x.n, wi);
    // The emission at the first hit, to be re-weighted: the path tracer counts it fully.
    let ctx = x.ctx();
    let mut first = SampledSpectrum::zero();
    stats.rays += 1;
    match scene.geometry.intersect(&ray, f32::INFINITY) {
        Some(hit) => {
            let material = scene.objects.material(hit.object);
            if material.flags().contains(MaterialFlags::EMISSIVE) {
                if let Some(li) = scene.lights.light_of_object(hit.object) {
                    let wo_geo = Frame::from_normal(hit.geometric_normal).to_local(-wi);
                    let sctx = ShadingContext::at(
                        hit.point,
                        hit.geometric_normal,
                        hit.shading_normal,
                        hit.uv,
                    );
                    let le = material.emitted(wo_geo, &sctx, lambda);
                    if !le.is_black() {
                        let light = &scene.lights.lights()[li as usize];
                        let light_pdf = scene.lights.pmf(li as usize)
                            * light.pdf_li(&ctx, hit.point, hit.geometric_normal);
                        first = le * (1.0 - power_heuristic(pdf, light_pdf));
                    }
                }
            }
        }
        None => {
            if let Some(ei) = scene.lights.environment() {
                let light = &scene.lights.lights()[ei as usize];
                if let Some((p_env, n_env)) = light.escape_point(&ray) {
                    let le = light.radiance(p_env, n_env, glam::Vec2::ZERO, -wi, lambda);
                    if !le.is_black() {
                        let light_pdf =
                            scene.lights.pmf(ei as usize) * light.pdf_li(&ctx, p_env, n_env);
                        first = le * (1.0 - power_heuristic(pdf, light_pdf));
                    }
                }
            }
        }
    }
    let mut lam = *lambda;
    let l = tracer.li(scene, ray, &mut lam, rng, stats);
    // cos θ/pdf = π for cosine sampling.
    let pi = std::f64::consts::PI;
    pi * (photo.of(&l, &lam) - photo.of(&first, lambda))
}

/// Light tracing for every point (see the module docs): `(lux, stderr, non-finite)`.
fn light_tracing(
    scene: &Scene,
    sp: &[SensorPoint],
    n: u32,
    seed: u64,
    tracer: &PathTracer,
    photo: &Photometric,
    pool: &rayon::ThreadPool,
) -> (Vec<f64>, Vec<f64>, u64, f64) {
    // Direct light: next-event estimation at each point, without MIS (the only strategy here).
    let direct: Vec<Sums> = pool.install(|| {
        sp.par_iter()
            .enumerate()
            .map(|(k, x)| {
                let mut s = Sums::default();
                let mut stats = PathStats::default();
                for i in 0..n {
                    let mut rng = point_sampler(seed, k, i);
                    let lambda = draw_wavelengths(rng.next_1d());
                    let e = next_event(scene, x, &lambda, &mut rng, &mut stats, false);
                    s.add(photo.of(&e, &lambda));
                }
                s
            })
            .collect()
    });
    // Light paths in fixed chunks; each chunk's per-point sums are added in chunk order.
    const CHUNK: u32 = 256;
    let chunks = n.div_ceil(CHUNK);
    let max_depth = if tracer.direct_only {
        1
    } else {
        tracer.max_depth
    };
    let rr = tracer.rr_depth;
    let parts: Vec<(Vec<Sums>, Sums)> = pool.install(|| {
        (0..chunks)
            .into_par_iter()
            .map(|c| {
                let mut acc = vec![Sums::default(); sp.len()];
                // The path's mean over the points (for the grid mean's standard error).
                let mut acc_mean = Sums::default();
                let mut cur = vec![0.0f64; sp.len()];
                let mut path = Vec::with_capacity(16);
                let mut stats = PathStats::default();
                for k in c * CHUNK..((c + 1) * CHUNK).min(n) {
                    let mut rng = SampleRng::for_sample(seed, k as u64, SENSOR_LIGHT_STREAM);
                    let lambda = draw_wavelengths(rng.next_1d());
                    cur.iter_mut().for_each(|v| *v = 0.0);
                    if let LightStart::Path = generate_light_subpath(
                        scene,
                        &lambda,
                        &mut rng,
                        max_depth as usize + 1,
                        rr,
                        &mut path,
                        &mut stats,
                        // Deposits are weighed at the path's own wavelengths, so light paths
                        // for sensors do not shift them (fluorescent surfaces reflect only).
                        crate::integrator::subpath::random_walk::WalkShift::Off,
                    ) {
                        deposit(scene, &path, sp, &lambda, photo, &mut cur, &mut stats);
                    }
                    for (a, v) in acc.iter_mut().zip(&cur) {
                        a.add(*v);
                    }
                    acc_mean.add(cur.iter().sum::<f64>() / sp.len().max(1) as f64);
                }
                (acc, acc_mean)
            })
            .collect()
    });
    let mut lt = vec![Sums::default(); sp.len()];
    let mut lt_mean = Sums::default();
    for (part, part_mean) in &parts {
        for (a, p) in lt.iter_mut().zip(part) {
            a.merge(p);
        }
        lt_mean.merge(part_mean);
    }
    let mut lux = Vec::with_capacity(sp.len());
    let mut se = Vec::with_capacity(sp.len());
    let mut nf = 0;
    for (d, l) in direct.iter().zip(&lt) {
        let (md, sd) = d.mean_se(n as f64);
        let (ml, sl) = l.mean_se(n as f64);
        lux.push(md + ml);
        se.push((sd * sd + sl * sl).sqrt());
        nf += d.non_finite + l.non_finite;
    }
    // The direct parts of the points are independent; the light-traced part is one estimate
    // of the grid mean per path.
    let p = sp.len().max(1) as f64;
    let direct_var: f64 = direct
        .iter()
        .map(|d| d.mean_se(n as f64).1.powi(2))
        .sum::<f64>()
        / (p * p);
    let lt_se = lt_mean.mean_se(n as f64).1;
    (lux, se, nf, (direct_var + lt_se * lt_se).sqrt())
}

/// The generator stream of sensor light paths (apart from the camera's and the image's light
/// paths).
const SENSOR_LIGHT_STREAM: u64 = u64::MAX - 0x5E45;

/// Join every surface vertex after the first bounce of `path` to every point, adding the
/// photometric contributions to `out`.
fn deposit(
    scene: &Scene,
    path: &[Vertex],
    sp: &[SensorPoint],
    lambda: &SampledWavelengths,
    photo: &Photometric,
    out: &mut [f64],
    stats: &mut PathStats,
) {
    let weights = XyzWeights::new(&photo.sensor, lambda);
    for qs in path.iter().skip(1) {
        if !qs.connectible(scene) || !qs.on_surface() {
            continue;
        }
        for (x, o) in sp.iter().zip(out.iter_mut()) {
            let d = x.p - qs.p;
            let d2 = d.length_squared();
            if !(d2 > 0.0) {
                continue;
            }
            let w = d / d2.sqrt();
            let cos_x = -x.n.dot(w);
            if !(cos_x > 0.0) {
                continue;
            }
            let target = Vertex::camera(x.p, x.n, SampledSpectrum::splat(1.0));
            let f = qs.f(
                scene,
                &target,
                lambda,
                crate::material::TransportMode::Importance,
            );
            let c = qs.beta * f * (qs.ns.dot(w).abs() * cos_x / d2);
            if c.is_black() {
                continue;
            }
            let (ray, t_max) = spawn_ray_to(qs.p, qs.p_error, qs.ng, x.p, x.p_error, x.n);
            stats.shadow_rays += 1;
            if scene.geometry.occluded(&ray, t_max) {
                continue;
            }
            *o += weights.xyz(&c, qs.lanes)[1] * photo.scale;
        }
    }
}
