//! Bidirectional path tracing (Veach 1997, ch. 10; structure after pbrt-v4's named steps): for
//! each camera sample a camera subpath and a light subpath are traced
//! ([`generate_camera_subpath`], [`generate_light_subpath`], both by [`random_walk`]), and every
//! prefix pair is joined by [`connect`] into a full path of `s` light and `t` camera vertices.
//! Each such (s, t) strategy is weighted by the power heuristic ([`mis_weight`](mis::mis_weight)), computed from
//! per-vertex forward/reverse area densities, the light-tracing strategy's (t = 1) scaled by
//! [`LIGHT_TRACING_MIS_SCALE`]; the vertices touched by a connection get their reverse
//! densities as overrides instead of being patched in place.
//!
//! Special cases: s = 0 (the camera path hits an area light), s = 1 (a light point sampled
//! afresh, as in next-event estimation), t = 1 (a lens point sampled afresh; the contribution
//! lands on another pixel and is splatted), delta lights (never hit, so s = 0 is not a strategy
//! for them), delta BSDFs (no connection through them; their directions carry the stand-in
//! densities of [`super::subpath::vertex::delta_densities`], which keep the geometry terms), directional
//! lights (positional density on a disk, see [`Vertex::pdf_light`]), finite apertures (the lens
//! density is the camera's own), shading normals (adjoint correction on light subpaths).
//! Wavelengths: one set per pair ([`PairWavelengths`]: observer × √emission, or the plan's
//! [`WavelengthMixture`] in fluorescent and narrowband scenes). Fluorescence: both subpaths shift
//! each lane's wavelength on its own at fluorescent surfaces; with probability α the light
//! subpath starts at the pair's wavelengths (its connections join the lanes that never shift),
//! otherwise at its own draw from its light's spectrum, and then a connection evaluates the
//! re-radiation between the two subpaths' wavelengths at a fluorescent endpoint
//! (`integrator/fluorescence/join.rs`); the MIS weights are then per lane over both modes
//! ([`mis_weight_lanes`], `integrator/bdpt/fluorescent_mis.rs`).
//!
//! | parameter   | unit     | default | meaning                                              |
//! |-------------|----------|---------|------------------------------------------------------|
//! | `max_depth` | bounces  | 64      | longest full path (`s + t − 2`), `--max-depth`       |
//! | `rr_depth`  | vertices | 3       | subpath length from which Russian roulette may stop  |
//!
//! Roulette from 3 vertices (path tracing waits 5 bounces): against 2, 4 and 5, BDPT's
//! efficiency 1/(MSE·cost) relative to 3 (whole image; MSE at 32 spp, 160×120, 4 seeds,
//! against the Mitsuba references minus their own noise; cost from callgrind instruction
//! counts) is 0.98, 0.93, 0.84 on the Cornell box, 1.10, 0.86, 0.72 on
//! `bench/window_room.ron` and 0.95, 1.00, 0.95 on `bench/glossy_metals.ron`: later roulette
//! lowers the MSE (by 12%, 7%, 20% at 5) less than it adds cost (35%, 48%, 32%).
//!
//! Numbers: every request of a camera sample comes from the pixel's sampler, each walk and
//! connection in its own fixed block of dimensions ([`dimensions`]), so a pixel's samples are
//! stratified in the first bounces and next-event estimates too.
//!
//! Light subpaths: in a scene with delta surfaces (caustics), each camera sample traces
//! [`LIGHT_PATHS`] of them ([`light_paths_for`]), otherwise one. The first is joined to every
//! camera-subpath prefix; all of them are joined to the camera (t = 1), which the power
//! heuristic then counts as that many samples (see [`LIGHT_PATHS`]).
//!
//! Light-subpath fraction: a camera sample traces its light subpaths only with probability `q`
//! (`--effect light-subpaths=auto|Q`; `auto` chooses `q` per scene by a short pilot); the
//! strategies that use them are divided by their expected count and weighted by it
//! ([`mis::SampleCounts`], [`light_fraction`]). `q = 1` renders exactly as before. `q = 0`
//! (chosen by the pilot, or forced, where path tracing samples every path BDPT does) traces no
//! light subpaths and hands the render to the path tracer ([`path_traced`]), whose estimator is
//! BDPT's s = 0 and s = 1 at less cost per camera sample.
//!
//! Visibility guide: where the plan turns on the path tracer's guide (`super::nee_guide`: the
//! same pre-pass, built once per render in `Setup` under the render's seed, the same per-light
//! decision and run-time note, its time in the render's), the s = 1 strategy draws its light
//! point's numbers from the guide's density for the camera vertex's key ([`connect_s1`]), so
//! that strategy's density of the light vertex x₀ is `pdf_li · g(u(x₀), key(x₁))`. The MIS
//! weights ([`mis::mis_weight_guided`], [`mis_weight_lanes`]) multiply by `g` exactly that
//! density wherever it enters the power heuristic: the s = 1 term of every other strategy's
//! sum, and the s = 1 strategy's own density; the light subpath's start density (s ≥ 2, t = 1)
//! and s = 0 keep theirs. For paths made by other strategies `g` is evaluated at x₀'s numbers
//! from x₁ ([`Light::sample_coords`](crate::light::Light::sample_coords); none: 1, as in the
//! path tracer). The specular-chain and camera-chain connections weigh themselves against
//! s = 0 only and never read the s = 1 density. Measured on `bench/window_room.ron`
//! (docs/performance.md, "BDPT and its own strategies"; 6 seeds × 16 spp, callgrind instructions
//! per camera sample), at the auto fraction (q = 1/16 either way): per-sample variance 2.29×
//! lower for 21% more instructions (more light points pass their shadow rays, so more
//! connections are weighed), 1.90× the efficiency (2.00× at q = 1); `pt` stays 1.69× ahead
//! (3.2× without the guide in BDPT).

pub mod dimensions;
pub mod fluorescent_mis;
pub mod light_fraction;
pub mod mis;
pub mod path_traced;

use super::connect::camera_chain::{CameraChain, ChainScratch};
use super::connect::manifold_connection::{anchor, connect_manifold, s0_weight, Seeds};
use super::connect::specular_seeds::{SolutionSet, SpecularShapes};
use super::driver::{Integrator, IntegratorInfo, IntegratorOutput, Registration};
use super::fluorescence::join::{connect_own, t1_wavelengths, LightMode, SHARED_MODE_PROBABILITY};
use super::nee_guide::NeeGuide;
use super::pixel_max::PixelMaxY;
use super::render::ProgressFn;
use super::subpath::beam::trace_beam;
use super::subpath::camera_connection::connect_to_camera;
use super::subpath::light_subpath::{
    generate_light_subpath_own, generate_light_subpath_with, LightStart,
};
use super::subpath::random_walk::{generate_camera_subpath, WalkShift};
use super::subpath::vertex::{geometry_term, unoccluded, Vertex};
use super::tiled::render_tiles;
use super::wavelengths::flat_colour::FlatColour;
use super::wavelengths::mixture::WavelengthMixture;
use super::wavelengths::pairs::PairWavelengths;
use super::wavelengths::xyz_weights::XyzWeights;
use super::{PathStats, PixelSampler, RenderError, RenderResult, RenderSettings, UniformSource};
use crate::camera::Camera;
use crate::film::rejected::check_sample;
use crate::film::spectral::SpectralBins;
use crate::film::spectral_film::{LaneEnergies, SpectralFilm};
use crate::film::{Rejection, Sensor, SplatFilm};
use crate::integrator::plan::RenderPlan;
use crate::light::{LightFlags, LightSampleContext};
use crate::material::{MaterialFlags, TransportMode};
use crate::scene::Scene;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};
use fluorescent_mis::mis_weight_lanes;
use glam::Vec2;
use light_fraction::{AltWeights, Choice, LightSubpaths, PartCost, PilotSample, CANDIDATES};
use mis::{mis_weight_guided, s1_guide_key, SampleCounts};
use spectrace_plugin_api::ParamDoc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Type information of BDPT.
pub const INFO: IntegratorInfo = IntegratorInfo {
    name: "bdpt",
    aliases: &[],
    version: 1,
    description: "bidirectional path tracing, power-heuristic MIS over all (s, t) strategies",
    params: &[
        ParamDoc::optional(
            "max_depth",
            "bounces",
            "64",
            "longest full path (s + t - 2); --max-depth or the scene's max_depth",
        ),
        ParamDoc::optional(
            "rr_depth",
            "vertices",
            "3",
            "subpath length from which Russian roulette may end a subpath",
        ),
    ],
};

/// BDPT's registration.
pub const REGISTRATION: Registration = Registration {
    info: &INFO,
    build: |settings, options| {
        Ok(Box::new(Bdpt {
            max_depth: settings.tracer.max_depth,
            rr_depth: settings.tracer.rr_depth,
            strategy_images: options.strategy_images,
            spectral: options.spectral,
            light_paths: LIGHT_PATHS,
        }))
    },
};

/// Longest path (bounces) that gets its own strategy image; longer ones are summed into one.
pub const STRATEGY_IMAGE_MAX_DEPTH: u32 = 5;

/// BDPT settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bdpt {
    /// Maximum number of bounces of a full path (`s + t − 2`).
    pub max_depth: u32,
    /// Subpath vertex count from which Russian roulette may end a subpath.
    pub rr_depth: u32,
    /// Also produce one image per (s, t) strategy.
    pub strategy_images: bool,
    /// Also accumulate a spectral image at these nodes.
    pub spectral: Option<SpectralBins>,
    /// Light subpaths per camera sample in scenes with delta surfaces ([`light_paths_for`]):
    /// the first is joined to every camera-subpath prefix, every one to the camera (t = 1, see
    /// [`LIGHT_PATHS`]).
    pub light_paths: u32,
}

/// Light subpaths traced per camera sample (see [`Bdpt::light_paths`]).
///
/// Why more than one: a camera sample of BDPT (camera subpath, its connections, the
/// specular-chain strategies) costs several light paths of `lt` (callgrind: 4.0× on
/// `scenes/bench/glass_sphere_mesh.ron`, 2.8× on the Cornell box), while a caustic seen on a
/// diffuse surface is made by the light-tracing strategy alone: with one light subpath per
/// camera sample, BDPT's efficiency in that caustic's core was 0.22× that of `lt`. Each
/// further light subpath is joined to the camera only (t = 1), the cheap part of a light
/// path's use, and the power heuristic counts the t = 1 strategy `light_paths` times (Veach
/// 1997, §9.2: the heuristic over `nᵢ·pᵢ`; [`mis::heuristic_scale`]) while each t = 1
/// contribution is divided by `light_paths`: the estimate stays unbiased and the images
/// deterministic (the subpaths draw from the camera sample's own sequence).
///
/// Why 4 (docs/performance.md, "BDPT and its own strategies": instruction counts and
/// variances per region): it raises BDPT's efficiency in the caustic cores of the glass
/// sphere and the spectral caustic 2.4× and 2.6×, and costs the lamp images seen in the
/// glass 1.6–1.7×, where BDPT stays 3.5× or more ahead of path tracing.
///
/// Counts 1, 2, 4 and 8 compared (efficiency 1/(MSE·cost) relative to 4: MSE at 32 spp,
/// 160×120, against the Mitsuba references, 8–12 seeds, the references' own noise from their
/// two halves subtracted; cost from callgrind instruction counts of the render at 40×30, 8 spp;
/// "core" is the largest component of pixels brighter than 4× the median, the floor caustic):
///
/// | scene                            | region | 1    | 2    | 4 | 8    |
/// |----------------------------------|--------|------|------|---|------|
/// | `bench/glass_sphere_mesh.ron`    | core   | 0.47 | 0.72 | 1 | 1.27 |
/// |                                  | rest   | 1.09 | 1.16 | 1 | 0.71 |
/// |                                  | all    | 0.78 | 0.97 | 1 | 0.83 |
/// | `bench/spectral_caustic.ron`     | core   | 1.51 | 1.34 | 1 | 0.66 |
/// |                                  | rest   | 1.63 | 1.37 | 1 | 0.64 |
///
/// Cost per camera sample relative to one light subpath: 1.20, 1.59, 2.38 (glass sphere) and
/// 1.25, 1.74, 2.73 (spectral caustic) for 2, 4, 8. On the glass sphere 4 is the best of the
/// four over the whole image and its caustic wants more; on the spectral caustic the extra
/// subpaths lower the core's variance by only 13% (luminance and colour alike: most of it does
/// not come from the t = 1 strategy) and one subpath is best everywhere. No count is best on
/// both: 4 stays.
pub const LIGHT_PATHS: u32 = 4;

/// Light subpaths per camera sample that `bdpt` traces in `scene`: `light_paths` when some
/// non-emissive surface scatters by a delta lobe (smooth glass, mirrors, coatings), else 1.
///
/// Why: the paths only light tracing makes well are those whose first camera-side vertex is
/// diffuse and whose light side reaches it through delta vertices (`L S+ D E`, caustics seen
/// directly); without delta surfaces every light-subpath vertex can be joined to the camera
/// subpath, the t ≥ 2 strategies make the same paths as t = 1 at comparable densities, and
/// extra light subpaths cost more than they give (measured: docs/performance.md, "BDPT and
/// its own strategies": the Cornell box with 4 light subpaths, 2.2× the instructions per
/// sample for 1.4–1.7× less variance). A scene without such surfaces renders exactly as with
/// one light subpath.
pub fn light_paths_for(scene: &Scene, light_paths: u32) -> u32 {
    let caustics = (0..scene.geometry.object_count() as u32).any(|o| {
        let f = scene.objects.material(o).flags();
        f.is_specular() && !f.contains(MaterialFlags::EMISSIVE)
    });
    if caustics {
        light_paths.max(1)
    } else {
        1
    }
}

/// One strategy's unweighted contribution and where it goes.
#[derive(Clone, Copy, Debug)]
pub struct Connection {
    /// Contribution (radiance units per lane, before the wavelength pdfs).
    pub l: SampledSpectrum,
    /// Power-heuristic weight, per lane (the same in every lane unless fluorescence moved some
    /// lanes' wavelengths, see [`mis_weight_lanes`]).
    pub weight: SampledSpectrum,
    /// For t = 1: the raster position to splat at.
    pub raster: Option<Vec2>,
    /// Lanes valid on both subpaths (only the hero after a dispersive event on either).
    pub lanes: LaneMask,
    /// The light whose emission this path carries (for the exact colour of flat paths).
    pub emitter: Option<u32>,
}

/// Join the first `s` light vertices and the first `t` camera vertices (Veach's (s, t)
/// strategy). `None` when the strategy gives nothing for this pair. `mode` is how the light
/// subpath started in a scene that renders fluorescence (`None` elsewhere).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn connect<S: UniformSource>(
    scene: &Scene,
    camera: &dyn Camera,
    mixture: &WavelengthMixture,
    light_path: &[Vertex],
    camera_path: &[Vertex],
    s: usize,
    t: usize,
    lambda: &SampledWavelengths,
    mode: Option<&LightMode>,
    counts: SampleCounts,
    guide: Option<&NeeGuide>,
    rng: &mut S,
    stats: &mut PathStats,
    alt: Option<&mut AltWeights>,
) -> Option<Connection> {
    // Two instances, so that scenes without fluorescence run no test of the mode (measured:
    // one instance for both cost the Cornell box +0.4% of bdpt's instructions).
    if mode.is_some() {
        connect_in::<true, S>(
            scene,
            camera,
            mixture,
            (light_path, camera_path),
            (s, t),
            lambda,
            mode,
            counts,
            guide,
            rng,
            stats,
            alt,
        )
    } else {
        connect_in::<false, S>(
            scene,
            camera,
            mixture,
            (light_path, camera_path),
            (s, t),
            lambda,
            None,
            counts,
            guide,
            rng,
            stats,
            alt,
        )
    }
}

/// [`connect`], with `FLUORESCENT` saying whether `mode` can be `Some`.
#[allow(clippy::too_many_arguments)]
fn connect_in<const FLUORESCENT: bool, S: UniformSource>(
    scene: &Scene,
    camera: &dyn Camera,
    mixture: &WavelengthMixture,
    (light_path, camera_path): (&[Vertex], &[Vertex]),
    (s, t): (usize, usize),
    lambda: &SampledWavelengths,
    mode: Option<&LightMode>,
    counts: SampleCounts,
    guide: Option<&NeeGuide>,
    rng: &mut S,
    stats: &mut PathStats,
    alt: Option<&mut AltWeights>,
) -> Option<Connection> {
    let mode = if FLUORESCENT { mode } else { None };
    let own = mode.is_some_and(|m| m.own);
    // Without a mode no lane has moved: either the scene renders no fluorescence (no walk
    // shifts a lane) or this camera sample traced no light subpath (s ≤ 1, which
    // `moved_lanes` never masks). Not asked there (-0.5% of bdpt's instructions per camera
    // sample on the Cornell box).
    let moved = if FLUORESCENT {
        moved_lanes(light_path, camera_path, s, t, own)?
    } else {
        debug_assert_eq!(
            moved_lanes(light_path, camera_path, s, t, own),
            Some(LaneMask::NONE)
        );
        LaneMask::NONE
    };
    let (mut l, sampled, raster) = if s == 0 {
        (connect_s0(scene, camera_path, t, lambda)?, None, None)
    } else if t == 1 {
        let start = mode.map_or(lambda, |m| &m.lambda);
        // A pinhole's lens point needs no numbers (a Sobol' request costs ~80 instructions).
        let u = if camera.pinhole() {
            Vec2::ZERO
        } else {
            rng.next_2d()
        };
        let (c, r, cam_v) = connect_to_camera(scene, camera, light_path, s, start, u, stats)?;
        (c, Some(cam_v), Some(r))
    } else if s == 1 {
        let (c, lv) = connect_s1(scene, camera_path, t, lambda, guide, rng, stats)?;
        (c, Some(lv), None)
    } else if let (true, Some(m)) = (own, mode) {
        // Light wavelengths drawn on their own: a fluorescent endpoint evaluates the
        // re-radiation between the two subpaths' wavelengths.
        let c = connect_own(scene, light_path, camera_path, s, t, lambda, m, stats)?;
        (c, None, None)
    } else {
        (
            connect_surfaces(scene, light_path, camera_path, s, t, lambda, stats)?,
            None,
            None,
        )
    };
    if moved != LaneMask::NONE {
        for k in 0..LANES {
            if moved.contains(k) {
                l[k] = 0.0;
            }
        }
    }
    if l.is_black() {
        return None;
    }
    let weight = if let Some(m) = mode {
        if s >= 2 && t >= 2 && !own {
            // The shared mode was chosen with probability α.
            l *= 1.0 / m.alpha;
        }
        mis_weight_lanes(
            scene,
            camera,
            mixture,
            (light_path, camera_path),
            sampled.as_ref(),
            (s, t),
            lambda,
            m,
            (0..LANES)
                .filter(|&k| l[k] != 0.0)
                .fold(LaneMask::NONE, |acc, k| acc.with(k)),
            counts,
            guide,
        )
    } else {
        let weight = |counts| {
            mis_weight_guided(
                scene,
                camera,
                light_path,
                camera_path,
                sampled.as_ref(),
                (s, t),
                lambda,
                counts,
                guide,
            )
        };
        if let Some(alt) = alt {
            // The pilot's weights under each candidate fraction (`light_fraction`).
            for (a, &q) in alt.weights.iter_mut().zip(CANDIDATES.iter()) {
                *a = weight(SampleCounts {
                    fraction: q,
                    ..counts
                });
            }
            // And the path tracer's densities of this path (the candidate q = 0).
            alt.pt_ratios = mis::path_tracing_ratios(
                scene,
                camera,
                light_path,
                camera_path,
                sampled.as_ref(),
                (s, t),
                lambda,
                counts,
                guide,
            );
        }
        SampledSpectrum::splat(weight(counts))
    };
    let n = counts.count(s, t);
    if n != 1.0 {
        // One of `n` expected samples of this strategy per camera sample: `light_paths` for
        // light tracing, times the fraction of camera samples that trace light subpaths.
        l *= 1.0 / n;
    }
    let mut lanes = camera_path[t - 1].lanes;
    if s > 0 && s <= light_path.len() {
        lanes = lanes.intersect(light_path[s - 1].lanes);
    }
    let emitter = match (s, t, &sampled) {
        (0, _, _) => camera_path[t - 1].light_index(scene),
        (1, 2.., Some(v)) => v.light_index(scene),
        _ => light_path.first().and_then(|v| v.light_index(scene)),
    };
    Some(Connection {
        l,
        weight,
        raster,
        lanes,
        emitter,
    })
}

/// The lanes a fluorescent shift moved on either subpath, which strategy (s ≥ 2, t ≥ 2) cannot
/// join when both subpaths start at the pair's wavelength (a shift only lengthens it): those
/// lanes get nothing from this strategy (see `mis_weight_lanes`). `None` when that leaves no
/// live lane.
#[inline]
fn moved_lanes(
    light_path: &[Vertex],
    camera_path: &[Vertex],
    s: usize,
    t: usize,
    own: bool,
) -> Option<LaneMask> {
    let moved = if s >= 2 && t >= 2 && !own {
        camera_path[t - 1].moved.union(light_path[s - 1].moved)
    } else {
        LaneMask::NONE
    };
    if moved != LaneMask::NONE {
        let live = camera_path[t - 1].lanes.intersect(light_path[s - 1].lanes);
        if live.intersect(moved) == live {
            return None;
        }
    }
    Some(moved)
}

/// s = 0: the camera path found an emitter by itself.
#[inline(always)]
fn connect_s0(
    scene: &Scene,
    camera_path: &[Vertex],
    t: usize,
    lambda: &SampledWavelengths,
) -> Option<SampledSpectrum> {
    let pt = &camera_path[t - 1];
    let li = pt.light_index(scene)?;
    let lam = pt.wavelengths(lambda);
    let mut le = pt.le(scene, &camera_path[t - 2], &lam);
    scene
        .lights
        .keep_line_power_only(li as usize, &lam, &mut le);
    Some(le * pt.beta)
}

/// s = 1, t ≥ 2 (next-event estimation): a fresh light point as seen from the camera vertex;
/// the contribution and the light vertex. Where `guide` guides the chosen light, the light's
/// numbers are drawn from its density for the camera vertex's key (`mis::s1_guide_key`) and
/// the point's density is `pdf_li` times its factor, which the MIS weights evaluate at the
/// point (`mis::s1_guide_factor`).
#[inline(always)]
fn connect_s1<S: UniformSource>(
    scene: &Scene,
    camera_path: &[Vertex],
    t: usize,
    lambda: &SampledWavelengths,
    guide: Option<&NeeGuide>,
    rng: &mut S,
    stats: &mut PathStats,
) -> Option<(SampledSpectrum, Vertex)> {
    let pt = &camera_path[t - 1];
    if !pt.connectible(scene) {
        return None;
    }
    let (li, pmf) = scene.lights.sample(light_choice_number(scene, rng))?;
    let u = rng.next_2d();
    let (u, guided) = match guide {
        Some(g) if g.guides(li) => g.sample(li, s1_guide_key(g, pt, &camera_path[t - 2]), u),
        _ => (u, 1.0),
    };
    let light = &scene.lights.lights()[li];
    let ctx = LightSampleContext {
        p: pt.p,
        p_error: pt.p_error,
        n: pt.ng,
    };
    let lambda = &pt.wavelengths(lambda);
    let mut ls = light.sample_li(&ctx, u, lambda)?;
    scene
        .lights
        .keep_line_power_only(li, lambda, &mut ls.radiance);
    if !(ls.pdf > 0.0) || ls.radiance.is_black() {
        return None;
    }
    let mut lv = Vertex::light(
        li as u32,
        ls.p_light,
        ls.p_light_error,
        ls.n_light,
        ls.radiance / (pmf * ls.pdf * guided),
    );
    let mut c = pt.beta * pt.f(scene, &lv, lambda, TransportMode::Radiance) * lv.beta;
    if pt.on_surface() {
        c *= ls.wi.dot(pt.ns).abs();
    }
    if c.is_black() {
        return None;
    }
    stats.shadow_rays += 1;
    if !unoccluded(scene, pt, &lv) {
        return None;
    }
    // Only the MIS weight reads it: not asked for connections that give nothing.
    lv.pdf_fwd = lv.pdf_light_origin(scene, pt);
    Some((c, lv))
}

/// The number that chooses a light (`LightSourceManager::sample`). With one light the choice
/// ignores it: its dimension is consumed without computing it (`skip_1d`, every later number
/// stays the same, so the same image), as the path tracer's next-event estimation does.
#[inline]
fn light_choice_number<S: UniformSource>(scene: &Scene, rng: &mut S) -> f32 {
    if scene.lights.lights().len() > 1 {
        rng.next_1d()
    } else {
        rng.skip_1d();
        0.0
    }
}

/// s ≥ 2, t ≥ 2, the general case: join two surface vertices.
#[inline(always)]
fn connect_surfaces(
    scene: &Scene,
    light_path: &[Vertex],
    camera_path: &[Vertex],
    s: usize,
    t: usize,
    lambda: &SampledWavelengths,
    stats: &mut PathStats,
) -> Option<SampledSpectrum> {
    let qs = &light_path[s - 1];
    let pt = &camera_path[t - 1];
    if !qs.connectible(scene) || !pt.connectible(scene) {
        return None;
    }
    let c = qs.beta
        * qs.f(scene, pt, lambda, TransportMode::Importance)
        * pt.f(scene, qs, lambda, TransportMode::Radiance)
        * pt.beta;
    if c.is_black() {
        return None;
    }
    let g = geometry_term(qs, pt);
    if !(g > 0.0) {
        return None;
    }
    stats.shadow_rays += 1;
    if !unoccluded(scene, qs, pt) {
        return None;
    }
    Some(c * g)
}

/// Per-thread scratch and counters of the BDPT driver.
struct Worker {
    camera_path: Vec<Vertex>,
    light_path: Vec<Vertex>,
    stats: PathStats,
    /// Flatness of each subpath prefix (see [`FlatColour::prefix`]).
    camera_flat: Vec<bool>,
    light_flat: Vec<bool>,
    /// Solutions of the camera-side chain connection.
    chain_scratch: ChainScratch,
    /// Solutions of the specular-chain connection.
    manifold_set: SolutionSet,
    /// Light subpaths per camera sample and the fraction of camera samples tracing them.
    counts: SampleCounts,
    /// The light-fraction pilot's recorder (pilot renders only).
    pilot: Option<PilotSample>,
}

impl Worker {
    fn new(counts: SampleCounts, pilot: Option<PilotSample>) -> Self {
        Self {
            camera_path: Vec::with_capacity(16),
            light_path: Vec::with_capacity(16),
            stats: PathStats::default(),
            camera_flat: Vec::with_capacity(16),
            light_flat: Vec::with_capacity(16),
            chain_scratch: ChainScratch::default(),
            manifold_set: SolutionSet::default(),
            counts,
            pilot,
        }
    }
}

/// Film XYZ of connection `c` of strategy (s, t): the exact colour of its emitter when the
/// whole path is spectrally flat ([`FlatColour`]), else the ordinary per-lane estimate.
#[allow(clippy::too_many_arguments)]
fn connection_xyz(
    flat: Option<&FlatColour>,
    (camera_flat, light_flat): (&[bool], &[bool]),
    s: usize,
    t: usize,
    c: &Connection,
    weights: &XyzWeights,
    lambda: &SampledWavelengths,
) -> [f64; 3] {
    let l = c.l * c.weight;
    if let (Some(fc), Some(e)) = (flat, c.emitter) {
        // s = 1 with t ≥ 2 uses a fresh light vertex (flat by itself); t = 1 a fresh lens point;
        // for s = 0 the last camera vertex only emits (its scattering is not on the path).
        let cam_ok = match (s, t) {
            (_, 1) => true,
            (0, _) => camera_flat.get(t - 2).copied().unwrap_or(false),
            _ => camera_flat.get(t - 1).copied().unwrap_or(false),
        };
        let light_ok =
            s == 0 || (s == 1 && t >= 2) || light_flat.get(s - 1).copied().unwrap_or(false);
        if cam_ok && light_ok && c.lanes.is_all() {
            if let Some(xyz) = fc.xyz(e, &l, lambda) {
                return xyz;
            }
        }
    }
    weights.xyz(&l, c.lanes)
}

/// Strategy images: one splat film per (s, t) up to [`STRATEGY_IMAGE_MAX_DEPTH`] bounces, and
/// one for everything longer (the last entry).
struct StrategyFilms {
    films: Vec<((u32, u32), SplatFilm)>,
    max_st: usize,
}

impl StrategyFilms {
    fn new(width: u32, height: u32) -> Self {
        let max_st = STRATEGY_IMAGE_MAX_DEPTH as usize + 2;
        let mut films = Vec::new();
        for total in 1..=max_st {
            for s in 0..=total {
                let t = total - s;
                if t >= 1 {
                    films.push(((s as u32, t as u32), SplatFilm::new(width, height)));
                }
            }
        }
        films.push(((u32::MAX, u32::MAX), SplatFilm::new(width, height)));
        Self { films, max_st }
    }

    fn film(&self, s: usize, t: usize) -> &SplatFilm {
        if s + t > self.max_st {
            return &self.films[self.films.len() - 1].1;
        }
        // Films are ordered by total = s + t, then s.
        let before: usize = (1..s + t).sum::<usize>();
        &self.films[before + s].1
    }
}

/// Why `scene` keeps every camera sample tracing light subpaths (`q = 1`), if it does.
fn fraction_stays_one(scene: &Scene) -> Option<&'static str> {
    if scene
        .lights
        .lights()
        .iter()
        .any(|l| l.flags().contains(LightFlags::BEAMS_ONLY))
    {
        Some("the scene has beams-only lights, whose subpaths are light tracing alone")
    } else if scene.objects.fluorescence() {
        Some("fractions below 1 are not covered for fluorescence")
    } else {
        None
    }
}

/// What every camera sample of a render reads besides the scene (built once per render).
struct Setup<'p> {
    sensor: Sensor,
    pair: PairWavelengths<'p>,
    flat: Option<FlatColour>,
    manifold: bool,
    camera_chain: Option<CameraChain>,
    shapes: SpecularShapes,
    /// The visibility guide of the s = 1 strategy's light points (`nee_guide`), when the plan
    /// and its pre-pass turn it on for some light.
    guide: Option<NeeGuide>,
}

impl<'p> Setup<'p> {
    fn new(
        scene: &Scene,
        plan: &'p RenderPlan,
        settings: &RenderSettings,
        camera: &dyn Camera,
    ) -> Self {
        let sensor = Sensor::new(scene.observer.clone());
        let pair = PairWavelengths::new(plan, scene, settings.tracer.wavelengths);
        // Not in a fluorescent scene: its per-lane MIS weights vary with the wavelength (the end
        // densities of the two modes differ), which the flat path's exact colour cannot carry.
        let flat = plan
            .flat_colour(scene, sensor.observer().as_ref(), &|l| pair.pdf(l))
            .filter(|_| !scene.objects.fluorescence());
        // Not with fluorescence: the strategy does not follow wavelength shifts.
        let manifold = plan.manifold() && !scene.objects.fluorescence();
        // The camera-side chains: pinhole cameras only (`CameraChain::new`), no fluorescence.
        let camera_chain = (plan.camera_chain() && !scene.objects.fluorescence())
            .then(|| CameraChain::new(scene, camera))
            .flatten();
        // The specular objects whose reflections seed the specular-chain connection too.
        let shapes = SpecularShapes::new(scene);
        // The path tracer's visibility guide, the same pre-pass and per-light decision (its
        // own seed from the render's: the same guide whatever the thread count).
        let guide = NeeGuide::build(
            scene,
            camera,
            settings.seed,
            plan.visibility_guide(),
            settings.threads,
        );
        Self {
            sensor,
            pair,
            flat,
            manifold,
            camera_chain,
            shapes,
            guide,
        }
    }

    /// The specular objects whose reflections seed the specular-chain connection too.
    fn reflection_shapes(&self) -> Option<&SpecularShapes> {
        (self.manifold && !self.shapes.is_empty()).then_some(&self.shapes)
    }
}

/// The light-fraction pilot (`light_fraction`): [`light_fraction::PILOT_SPP`] camera samples
/// of each pilot pixel at `q = 1` under the pilot's own seed, fixed chunks reduced in order.
fn pilot_sums(
    bdpt: &Bdpt,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    cam: &crate::camera::manager::NamedCamera,
    setup: &Setup<'_>,
) -> Result<light_fraction::PilotSums, RenderError> {
    let (width, height) = cam.camera.resolution();
    let pool = super::tiled::thread_pool(settings.threads)?;
    let seed = light_fraction::pilot_seed(settings.seed);
    let splats = SplatFilm::new(width, height);
    let pilot_max = PixelMaxY::new(width, height);
    Ok(light_fraction::run_pilot(&pool, width, height, |pixels| {
        let mut worker = Worker::new(
            light_fraction::counts(bdpt.light_paths, 1.0),
            Some(PilotSample::new(width, height)),
        );
        for &(x, y) in pixels {
            let pixel = y as u64 * width as u64 + x as u64;
            for si in 0..light_fraction::PILOT_SPP {
                let mut ld = PixelSampler::with_kind(settings.sampler, seed, pixel, si);
                bdpt.sample(
                    scene,
                    cam,
                    &setup.sensor,
                    (plan.mixture(), &setup.pair),
                    (x, y),
                    &mut ld,
                    (&splats, None),
                    &pilot_max,
                    None,
                    setup.flat.as_ref(),
                    (
                        setup.manifold,
                        setup.camera_chain.as_ref(),
                        setup.reflection_shapes(),
                    ),
                    setup.guide.as_ref(),
                    &mut worker,
                );
            }
            if let Some(p) = worker.pilot.as_mut() {
                p.finish_pixel();
            }
        }
        worker.pilot.map(|p| p.sums().clone()).unwrap_or_default()
    }))
}

/// The visibility guide's run-time notes as BDPT words them (it guides the s = 1 strategy).
fn guide_notes(scene: &Scene, guide: Option<&NeeGuide>) -> Vec<String> {
    guide.map_or_else(Vec::new, |g| {
        g.notes(|i| {
            let name = scene
                .options
                .light_items
                .get(i)
                .map_or_else(|| format!("light {i}"), |n| format!("light {i} ({n})"));
            format!("{name} (bdpt's s = 1 strategy)")
        })
    })
}

/// The fraction `q` of camera samples that trace light subpaths (`light_fraction`; 0: the
/// camera samples are path traced, `path_traced`) and its run-time note: forced, kept at 1
/// (`fraction_stays_one`), or the pilot's choice. A forced 0 where the path tracer cannot
/// stand for BDPT is an error naming why.
#[allow(clippy::too_many_arguments)]
fn choose_fraction(
    bdpt: &Bdpt,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    cam: &crate::camera::manager::NamedCamera,
    setup: &Setup<'_>,
    start: std::time::Instant,
) -> Result<(f32, Option<String>), RenderError> {
    let stays_one = fraction_stays_one(scene);
    Ok(match (plan.light_subpaths(), stays_one) {
        (LightSubpaths::Fraction(q), _) if q >= 1.0 => (1.0, None),
        (LightSubpaths::Fraction(q), _) if q <= 0.0 => {
            if let Some(why) =
                stays_one.or_else(|| path_traced::refusal(&bdpt.path_traced(), scene, plan))
            {
                return Err(RenderError::Setup(format!(
                    "--effect light-subpaths=0: bdpt cannot path trace every camera sample in \
                     this scene ({why}); use auto or a fraction in (0, 1]"
                )));
            }
            let note = "bdpt light subpaths: q = 0 (forced), the camera samples are path traced";
            (0.0, Some(note.to_string()))
        }
        (_, Some(why)) => (
            1.0,
            Some(format!(
                "bdpt light subpaths: q = 1 (every camera sample traces them: {why})"
            )),
        ),
        (LightSubpaths::Fraction(q), None) => (q, None),
        (LightSubpaths::Auto, None) => {
            let choice = pilot_choice(bdpt, scene, plan, settings, cam, setup)?;
            (choice.q, Some(choice.note(start.elapsed().as_secs_f64())))
        }
    })
}

/// The pilots' decision (BDPT's and, where it may stand for BDPT, the path tracer's).
fn pilot_choice(
    bdpt: &Bdpt,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    cam: &crate::camera::manager::NamedCamera,
    setup: &Setup<'_>,
) -> Result<Choice, RenderError> {
    let sums = pilot_sums(bdpt, scene, plan, settings, cam, setup)?;
    let refused = path_traced::refusal(&bdpt.path_traced(), scene, plan);
    let pt = match refused {
        None => Some(path_traced::pilot(
            &bdpt.path_traced(),
            scene,
            plan,
            settings,
            cam,
            setup.guide.as_ref(),
            &sums,
        )?),
        Some(_) => None,
    };
    let mut choice = Choice::from_sums(&sums, pt.map(|(e, _)| e));
    choice.path_traced_refused = refused;
    choice.path_traced_work = pt.map(|(_, w)| w);
    Ok(choice)
}

/// Render `scene` by BDPT with the tiles, passes and seeding of the path tracer's driver;
/// t = 1 contributions (and beams-only lights) are splatted and scaled by 1/spp.
fn render_bdpt(
    bdpt: &Bdpt,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    progress: &ProgressFn<'_>,
    cancel: Option<&AtomicBool>,
) -> Result<IntegratorOutput, RenderError> {
    let cam = scene
        .cameras
        .get(settings.camera.as_deref())
        .map_err(RenderError::Setup)?;
    let camera = cam.camera.as_ref();
    let (width, height) = camera.resolution();
    let bdpt = &Bdpt {
        light_paths: light_paths_for(scene, bdpt.light_paths),
        ..*bdpt
    };
    let setup = Setup::new(scene, plan, settings, camera);
    let (sensor, mixture, pair, flat) = (&setup.sensor, plan.mixture(), &setup.pair, &setup.flat);
    let (manifold, camera_chain) = (setup.manifold, &setup.camera_chain);
    let reflection_shapes = setup.reflection_shapes();
    let strategies = bdpt
        .strategy_images
        .then(|| StrategyFilms::new(width, height));
    let guide = setup.guide.as_ref();
    // The fraction of camera samples that trace light subpaths (`light_fraction`).
    let pilot_start = std::time::Instant::now();
    let (q, note) = choose_fraction(bdpt, scene, plan, settings, cam, &setup, pilot_start)?;
    // The pilot and the guide's pre-pass are part of the render: a time budget counts them.
    let prepass_time = std::time::Duration::from_secs_f64(guide.map_or(0.0, NeeGuide::seconds));
    let pilot_time = pilot_start.elapsed() + prepass_time;
    if q == 0.0 {
        let run = (progress, cancel);
        let notes = note.into_iter().collect();
        let stand_in = bdpt.path_traced();
        return path_traced::render(
            &stand_in, scene, plan, settings, run, guide, pilot_time, notes,
        );
    }
    let mut notes = guide_notes(scene, guide);
    notes.extend(note);
    let counts = light_fraction::counts(bdpt.light_paths, q);
    let settings = &RenderSettings {
        budget: match &settings.budget {
            super::SampleBudget::Time(d) => super::SampleBudget::Time(d.saturating_sub(pilot_time)),
            other => *other,
        },
        ..settings.clone()
    };
    let rays = AtomicU64::new(0);
    let pixel_max = PixelMaxY::new(width, height);
    let outcome = render_tiles(
        (width, height),
        settings,
        progress,
        cancel,
        true,
        bdpt.spectral,
        |buf, samples, splats, spectral| {
            let mut worker = Worker::new(counts, None);
            // One sampler per tile, restarted for every sample: with several samples of a
            // pixel in this pass it keeps the pixel's scramble seeds across them (the same
            // numbers as a new sampler each time, as in the path tracer; callgrind, passes of
            // 4 to 16 spp: 1.1-1.2% fewer of bdpt's instructions per camera sample on the
            // Cornell box and the two caustics). A pass of one sample per pixel (a render's
            // first ones) would only fill the memo, +0.7%: it hashes as before.
            let (first_pixel, pass_spp) = (
                buf.y0 as u64 * width as u64 + buf.x0 as u64,
                samples.end.saturating_sub(samples.start),
            );
            let mut ld = if pass_spp > 1 {
                PixelSampler::memoised(settings.sampler, settings.seed, first_pixel, 0)
            } else {
                PixelSampler::with_kind(settings.sampler, settings.seed, first_pixel, 0)
            };
            for y in buf.y0..buf.y0 + buf.h {
                for x in buf.x0..buf.x0 + buf.w {
                    let pixel = y as u64 * width as u64 + x as u64;
                    for si in samples.clone() {
                        ld.restart(pixel, si);
                        let xyz = bdpt.sample(
                            scene,
                            cam,
                            sensor,
                            (mixture, pair),
                            (x, y),
                            &mut ld,
                            (splats, spectral),
                            &pixel_max,
                            strategies.as_ref(),
                            flat.as_ref(),
                            (manifold, camera_chain.as_ref(), reflection_shapes),
                            guide,
                            &mut worker,
                        );
                        buf.add(x, y, xyz, "bdpt camera film (t ≥ 2)");
                    }
                }
            }
            rays.fetch_add(
                worker.stats.rays + worker.stats.shadow_rays,
                Ordering::Relaxed,
            );
        },
    )?;
    let (film, spp_done, dropped_pass) = (outcome.film, outcome.spp, outcome.dropped_pass);
    // The guide's pre-pass and the light-fraction pilot are in the render's time (the path
    // tracer counts its pre-pass the same way), so a timed comparison pays for them.
    let elapsed = outcome.elapsed + pilot_time;
    let scale = 1.0 / spp_done.max(1) as f64;
    // Pixel means plus splat sums / spp, from the exact film.
    let image = film.image();
    let strategy_images = strategies
        .map(|sf| {
            sf.films
                .iter()
                .map(|(st, f)| (*st, f.image(scale)))
                .collect()
        })
        .unwrap_or_default();
    Ok(IntegratorOutput {
        result: RenderResult {
            image,
            spp: spp_done,
            samples: film.camera.sample_count(),
            rays: rays.load(Ordering::Relaxed),
            elapsed,
            dropped_pass,
        },
        strategy_images,
        non_finite: film.rejected.total(),
        // Non-negative f64 bit patterns order like the values.
        max_sample_y: pixel_max.values(),
        notes,
        film,
    })
}

impl Integrator for Bdpt {
    fn info(&self) -> &'static IntegratorInfo {
        &INFO
    }

    fn render(
        &self,
        scene: &Scene,
        plan: &RenderPlan,
        settings: &RenderSettings,
        progress: &ProgressFn<'_>,
        cancel: Option<&AtomicBool>,
    ) -> Result<IntegratorOutput, RenderError> {
        render_bdpt(self, scene, plan, settings, progress, cancel)
    }

    fn light_strategy(&self, flags: LightFlags) -> &'static str {
        if flags.contains(LightFlags::BEAMS_ONLY) {
            "light tracing of its beams (t = 1 splats, unweighted)"
        } else if !flags.can_be_hit() {
            "bdpt: all strategies with s ≥ 1 (never hit by camera paths), power-heuristic MIS"
        } else {
            "bdpt: all (s, t) strategies incl. s = 0 and t = 1, power-heuristic MIS"
        }
    }
}

impl Bdpt {
    /// What the path tracer standing for BDPT at `q = 0` reads of these settings.
    fn path_traced(&self) -> path_traced::BdptSettings {
        path_traced::BdptSettings {
            max_depth: self.max_depth,
            strategy_images: self.strategy_images,
            spectral: self.spectral,
        }
    }

    /// The light-fraction pilot's decision for `scene` (what `--effect light-subpaths=auto`
    /// renders with, `q = 0` among the candidates where [`path_traced::refusal`] allows it),
    /// run as the render would run it; `None` where the fraction stays 1 without a pilot
    /// (beams-only lights, fluorescence).
    pub fn light_fraction_pilot(
        &self,
        scene: &Scene,
        plan: &RenderPlan,
        settings: &RenderSettings,
    ) -> Result<Option<Choice>, RenderError> {
        if fraction_stays_one(scene).is_some() {
            return Ok(None);
        }
        let cam = scene
            .cameras
            .get(settings.camera.as_deref())
            .map_err(RenderError::Setup)?;
        let bdpt = &Bdpt {
            light_paths: light_paths_for(scene, self.light_paths),
            ..*self
        };
        let setup = Setup::new(scene, plan, settings, cam.camera.as_ref());
        pilot_choice(bdpt, scene, plan, settings, cam, &setup).map(Some)
    }

    /// One camera sample of pixel `(x, y)`: returns the XYZ of all t ≥ 2 strategies for the
    /// pixel film and splats the t = 1 strategies (and beams) into `splats`.
    #[allow(clippy::too_many_arguments)]
    fn sample(
        &self,
        scene: &Scene,
        cam: &crate::camera::manager::NamedCamera,
        sensor: &Sensor,
        (mixture, pair): (&WavelengthMixture, &PairWavelengths<'_>),
        (x, y): (u32, u32),
        ld: &mut PixelSampler,
        (splats, spectral): (&SplatFilm, Option<&SpectralFilm>),
        pixel_max: &PixelMaxY,
        strategies: Option<&StrategyFilms>,
        flat: Option<&FlatColour>,
        (manifold, camera_chain, reflection_shapes): (
            bool,
            Option<&CameraChain>,
            Option<&SpecularShapes>,
        ),
        guide: Option<&NeeGuide>,
        worker: &mut Worker,
    ) -> [f64; 3] {
        let camera = cam.camera.as_ref();
        // Every number comes from the pixel's sampler, each walk and connection in its own
        // block of dimensions (`dimensions.rs`), so a pixel's samples are stratified in each.
        let lambda = pair.sample(ld);
        let weights = XyzWeights::new(sensor, &lambda);
        // The film and lens numbers as the path tracer draws them: a pinhole's lens numbers,
        // which it never reads, are skipped (the same later numbers, so the same image).
        let cs = super::path::camera_sample(cam, camera.pinhole(), ld, (x, y));
        let Some(cray) = camera.generate_ray(&cs) else {
            return [0.0; 3];
        };
        let max_depth = self.max_depth as usize;
        let mut camera_path = std::mem::take(&mut worker.camera_path);
        let mut light_path = std::mem::take(&mut worker.light_path);
        let counts = worker.counts;
        // Whether this camera sample traces its light subpaths (probability `q`, from a
        // stratified dimension of its own: a pixel's samples trace ~q of them). With q = 1
        // no number is drawn, so the image is the one every sample tracing them gives.
        let trace_light = counts.fraction >= 1.0 || {
            block(ld, dimensions::LIGHT_FRACTION);
            ld.next_1d() < counts.fraction
        };
        let u_start = trace_light.then(|| Self::light_start_in(scene, ld, 0));
        let before = worker.stats;
        block(ld, dimensions::CAMERA_WALK);
        generate_camera_subpath(
            scene,
            camera,
            cray.ray,
            cray.weight,
            &lambda,
            ld,
            max_depth + 2,
            self.rr_depth,
            &mut camera_path,
            &mut worker.stats,
        );
        let after_camera = worker.stats;
        let (start, mode) = match u_start {
            Some(u_start) => self.light_subpath(
                scene,
                mixture,
                &lambda,
                u_start,
                0,
                ld,
                &mut light_path,
                &mut worker.stats,
            ),
            None => {
                light_path.clear();
                (LightStart::None, None)
            }
        };
        // The pilot's cost counts of the light part (the rest is the camera part).
        let mut light_cost = PartCost {
            rays: worker.stats.rays - after_camera.rays,
            ..PartCost::default()
        };
        let mut camera_connections = 0u64;
        // A beams-only light's subpath, one of `light_paths` of this camera sample: light
        // tracing alone, each splat weighted 1/light_paths.
        let trace_beams = |index: usize, pmf: f32, j: u32, ld: &mut PixelSampler, stats: &mut _| {
            let inv = 1.0 / self.light_paths as f64;
            let mut splat = |raster: Vec2, xyz: [f64; 3], e: &dyn Fn() -> LaneEnergies| {
                let xyz = xyz.map(|v| v * inv);
                Self::record_splat(splats, strategies, pixel_max, raster, xyz, None);
                if let Some(sf) = spectral {
                    let mut e = e();
                    e.e = e.e.map(|v| v * inv);
                    sf.splat(raster.x, raster.y, &xyz, &e);
                }
            };
            block(ld, dimensions::beams(j));
            trace_beam(
                scene,
                camera,
                sensor,
                index,
                pmf,
                self.max_depth,
                self.rr_depth,
                ld,
                stats,
                &mut splat,
            );
        };
        if let LightStart::Beams { index, pmf } = start {
            trace_beams(index, pmf, 0, ld, &mut worker.stats);
        }
        if let Some(fc) = flat {
            fc.prefix(&camera_path, &mut worker.camera_flat);
            fc.prefix(&light_path, &mut worker.light_flat);
        }
        let pixel_center = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        let mut total = [0.0f64; 3];
        let mut total_lanes = LaneEnergies::default();
        let mut per_strategy: Vec<(usize, usize, [f64; 3])> = Vec::new();
        for t in 1..=camera_path.len() {
            // s = 1 with t ≥ 2 samples its own light point, so it runs even when this pair's
            // light subpath is empty (a beams-only light was chosen, or sampling failed):
            // skipping it there would darken next-event estimation by that probability.
            for s in 0..=light_path.len().max(1) {
                let depth = s as i64 + t as i64 - 2;
                if depth < 0
                    || depth > max_depth as i64
                    || (s == 0 && t < 2)
                    || (s > light_path.len() && t < 2)
                {
                    continue;
                }
                // The strategies that draw numbers (a fresh lens or light point) read their own.
                if t == 1 {
                    block(ld, dimensions::t1(0, s));
                } else if s == 1 {
                    block(ld, dimensions::s1(t));
                }
                let shadow_before = worker.stats.shadow_rays;
                let mut alt = AltWeights::default();
                let connected = connect(
                    scene,
                    camera,
                    mixture,
                    &light_path,
                    &camera_path,
                    s,
                    t,
                    &lambda,
                    mode.as_ref(),
                    counts,
                    guide,
                    ld,
                    &mut worker.stats,
                    worker.pilot.is_some().then_some(&mut alt),
                );
                if worker.pilot.is_none() {
                    // (The cost counts below are the pilot's.)
                } else if SampleCounts::uses_light_subpath(s, t) {
                    light_cost.shadow_rays += worker.stats.shadow_rays - shadow_before;
                    light_cost.connections += connected.is_some() as u64;
                } else {
                    camera_connections += connected.is_some() as u64;
                }
                let Some(mut c) = connected else {
                    continue;
                };
                // The weight before the chain shares below (which no fraction changes), for
                // the pilot's ratios.
                let w_mis = c.weight[0];
                if manifold && s == 0 {
                    // A path the specular-chain connection can make too: its share.
                    let mut seeds = Seeds {
                        shapes: reflection_shapes,
                        set: &mut worker.manifold_set,
                    };
                    if let Some(w) = s0_weight(
                        scene,
                        camera,
                        &camera_path,
                        t,
                        &lambda,
                        max_depth,
                        &mut seeds,
                    ) {
                        c.weight *= w;
                    }
                }
                if s == 0 {
                    // A path the camera-side chain connection can make too: its share,
                    // whatever `manifold` says (the chain has its own switch, and whenever it
                    // runs, the s = 0 paths it also makes must give up its share).
                    if let Some(cc) = camera_chain {
                        if let Some(w) = cc.s0_weight(
                            scene,
                            camera,
                            &camera_path,
                            t,
                            &lambda,
                            max_depth,
                            &mut worker.chain_scratch,
                        ) {
                            c.weight *= w;
                        }
                    }
                }
                // A t = 1 splat in a fluorescent scene: the observer weighs the wavelengths
                // that reach the camera, each divided by its lane's start density over both
                // modes (`t1_wavelengths`).
                let shifted_weights;
                let weights = match (t, light_path.get(s.wrapping_sub(1)), &mode) {
                    (1, Some(q), Some(m)) => {
                        shifted_weights = XyzWeights::new(sensor, &t1_wavelengths(m, q));
                        &shifted_weights
                    }
                    _ => &weights,
                };
                let xyz = connection_xyz(
                    flat,
                    (&worker.camera_flat, &worker.light_flat),
                    s,
                    t,
                    &c,
                    weights,
                    &lambda,
                );
                if let Some(kind) = check_sample(&xyz) {
                    // Counted under this sample's pixel and strategy, never in the image.
                    splats.reject(Rejection {
                        x,
                        y,
                        strategy: format!("bdpt s={s} t={t}"),
                        kind,
                    });
                    continue;
                }
                if let Some(p) = worker.pilot.as_mut() {
                    // Left out where the camera sees an emitter (as the bench leaves those
                    // pixels out): s = 0 makes them without noise, while the power heuristic
                    // gives light tracing a share there whose variance would decide q.
                    let seen = match c.raster {
                        Some(_) => light_path.get(s - 1),
                        None => camera_path.get(1),
                    };
                    if seen.is_none_or(|v| v.light_index(scene).is_none()) {
                        // Candidate weights over the current one.
                        let ratios =
                            alt.weights
                                .map(|a| if w_mis > 0.0 { (a / w_mis) as f64 } else { 0.0 });
                        let at = c.raster.unwrap_or(pixel_center);
                        p.book(at, SampleCounts::uses_light_subpath(s, t), xyz[1], &ratios);
                        let n = counts.count(s, t);
                        let own = c.raster.is_none().then_some(s + t - 2);
                        p.book_pt(xyz[1], c.weight[0], n, &alt.pt_ratios, own);
                    }
                }
                match c.raster {
                    Some(r) => {
                        Self::record_splat(splats, strategies, pixel_max, r, xyz, Some((s, t)));
                        if let Some(sf) = spectral {
                            sf.splat(
                                r.x,
                                r.y,
                                &xyz,
                                &weights.energies(&(c.l * c.weight), c.lanes),
                            );
                        }
                    }
                    None => {
                        for k in 0..3 {
                            total[k] += xyz[k];
                        }
                        if spectral.is_some() {
                            total_lanes.accumulate(&weights.energies(&(c.l * c.weight), c.lanes));
                        }
                        if strategies.is_some() {
                            per_strategy.push((s, t, xyz));
                        }
                    }
                }
            }
        }
        if let Some(j) = manifold.then(|| anchor(scene, &camera_path)).flatten() {
            // The specular-chain connection from the first non-specular camera vertex.
            block(ld, dimensions::MANIFOLD);
            let u = (light_choice_number(scene, ld), ld.next_2d());
            let mut seeds = Seeds {
                shapes: reflection_shapes,
                set: &mut worker.manifold_set,
            };
            connect_manifold(
                scene,
                camera,
                &camera_path,
                j,
                &lambda,
                u,
                max_depth,
                &mut seeds,
                &mut worker.stats,
                &mut |m| {
                    let c = Connection {
                        l: m.l,
                        weight: SampledSpectrum::splat(m.weight),
                        raster: None,
                        lanes: m.lanes,
                        emitter: Some(m.emitter),
                    };
                    // Flat-path colour as for s = 1 at the same vertex, if the chain is flat too.
                    let xyz = connection_xyz(
                        flat.filter(|_| m.flat_chain),
                        (&worker.camera_flat, &worker.light_flat),
                        1,
                        j + 1,
                        &c,
                        &weights,
                        &lambda,
                    );
                    if let Some(kind) = check_sample(&xyz) {
                        splats.reject(Rejection {
                            x,
                            y,
                            strategy: "bdpt specular chain".into(),
                            kind,
                        });
                    } else {
                        if let Some(p) = worker.pilot.as_mut() {
                            p.book(pixel_center, false, xyz[1], &[1.0; CANDIDATES.len()]);
                        }
                        for k in 0..3 {
                            total[k] += xyz[k];
                        }
                        if spectral.is_some() {
                            total_lanes.accumulate(&weights.energies(&(c.l * c.weight), c.lanes));
                        }
                        if strategies.is_some() {
                            // Filed with s = 0 of the same path: the two share its class.
                            per_strategy.push((0, m.t_equivalent, xyz));
                        }
                    }
                },
            );
        }
        if let Some(cc) = camera_chain {
            // The camera-side chain connection, splatted like t = 1.
            block(ld, dimensions::CAMERA_CHAIN);
            let u_run = ld.next_1d();
            let u = if u_run < super::connect::camera_chain::CAMERA_CHAIN_RATE {
                (u_run, ld.next_1d(), ld.next_2d())
            } else {
                (u_run, 0.0, Vec2::ZERO)
            };
            cc.connect(
                scene,
                camera,
                &lambda,
                u,
                max_depth,
                &mut worker.chain_scratch,
                &mut worker.stats,
                |m| {
                    let c = Connection {
                        l: m.sample.l,
                        weight: SampledSpectrum::splat(m.sample.weight),
                        raster: Some(m.raster),
                        lanes: m.sample.lanes,
                        emitter: Some(m.sample.emitter),
                    };
                    let xyz = connection_xyz(
                        flat.filter(|_| m.sample.flat_chain),
                        (&worker.camera_flat, &worker.light_flat),
                        0,
                        1,
                        &c,
                        &weights,
                        &lambda,
                    );
                    if let Some(kind) = check_sample(&xyz) {
                        splats.reject(Rejection {
                            x,
                            y,
                            strategy: "bdpt camera chain".into(),
                            kind,
                        });
                        return;
                    }
                    if let Some(p) = worker.pilot.as_mut() {
                        p.book(m.raster, false, xyz[1], &[1.0; CANDIDATES.len()]);
                    }
                    Self::record_splat(
                        splats,
                        strategies,
                        pixel_max,
                        m.raster,
                        xyz,
                        Some((0, m.sample.t_equivalent)),
                    );
                    if let Some(sf) = spectral {
                        sf.splat(
                            m.raster.x,
                            m.raster.y,
                            &xyz,
                            &weights.energies(&(c.l * c.weight), c.lanes),
                        );
                    }
                },
            );
        }
        for j in 1..self.light_paths * trace_light as u32 {
            // The further light subpaths of this camera sample: light tracing only (t = 1).
            let u_start = Self::light_start(ld, j);
            let rays_before = worker.stats.rays;
            let (start, mode) = self.light_subpath(
                scene,
                mixture,
                &lambda,
                u_start,
                j,
                ld,
                &mut light_path,
                &mut worker.stats,
            );
            if let LightStart::Beams { index, pmf } = start {
                trace_beams(index, pmf, j, ld, &mut worker.stats);
            }
            light_cost.rays += worker.stats.rays - rays_before;
            if let Some(fc) = flat {
                fc.prefix(&light_path, &mut worker.light_flat);
            }
            for s in 1..=light_path.len().min(max_depth + 1) {
                block(ld, dimensions::t1(j, s));
                let shadow_before = worker.stats.shadow_rays;
                let mut alt = AltWeights::default();
                let connected = connect(
                    scene,
                    camera,
                    mixture,
                    &light_path,
                    &camera_path,
                    s,
                    1,
                    &lambda,
                    mode.as_ref(),
                    counts,
                    guide,
                    ld,
                    &mut worker.stats,
                    worker.pilot.is_some().then_some(&mut alt),
                );
                light_cost.shadow_rays += worker.stats.shadow_rays - shadow_before;
                light_cost.connections += connected.is_some() as u64;
                let Some(c) = connected else {
                    continue;
                };
                let Some(r) = c.raster else { continue };
                let shifted_weights;
                let w = match (&mode, light_path.get(s - 1)) {
                    (Some(m), Some(q)) => {
                        shifted_weights = XyzWeights::new(sensor, &t1_wavelengths(m, q));
                        &shifted_weights
                    }
                    _ => &weights,
                };
                let xyz = connection_xyz(
                    flat,
                    (&worker.camera_flat, &worker.light_flat),
                    s,
                    1,
                    &c,
                    w,
                    &lambda,
                );
                if let Some(kind) = check_sample(&xyz) {
                    splats.reject(Rejection {
                        x,
                        y,
                        strategy: format!("bdpt s={s} t=1"),
                        kind,
                    });
                    continue;
                }
                if let Some(p) = worker.pilot.as_mut() {
                    let cw = c.weight[0];
                    let ratios = alt
                        .weights
                        .map(|a| if cw > 0.0 { (a / cw) as f64 } else { 0.0 });
                    // Left out where the camera sees an emitter, as above.
                    if light_path[s - 1].light_index(scene).is_none() {
                        p.book(r, true, xyz[1], &ratios);
                        p.book_pt(xyz[1], cw, counts.count(s, 1), &alt.pt_ratios, None);
                    }
                }
                Self::record_splat(splats, strategies, pixel_max, r, xyz, Some((s, 1)));
                if let Some(sf) = spectral {
                    sf.splat(r.x, r.y, &xyz, &w.energies(&(c.l * c.weight), c.lanes));
                }
            }
        }
        if let Some(p) = worker.pilot.as_mut() {
            let camera_cost = PartCost {
                rays: worker.stats.rays - before.rays - light_cost.rays,
                shadow_rays: worker.stats.shadow_rays - before.shadow_rays - light_cost.shadow_rays,
                connections: camera_connections,
            };
            p.finish_sample(pixel_center, camera_cost, light_cost);
        }
        worker.camera_path = camera_path;
        worker.light_path = light_path;
        pixel_max.record(pixel_center.x, pixel_center.y, total[1]);
        if let Some(sf) = spectral {
            // The t ≥ 2 strategies go to this pixel's film as one sample (the film's guard
            // judges their sum, so the spectral film does too).
            sf.add(x, y, &total, &[total_lanes]);
        }
        if let Some(sf) = strategies {
            for (s, t, xyz) in per_strategy {
                sf.film(s, t).splat(pixel_center.x, pixel_center.y, xyz);
            }
        }
        total
    }

    /// The start of light subpath `j` (light choice, `sample_le`'s two 2D numbers).
    #[inline]
    fn light_start(ld: &mut PixelSampler, j: u32) -> (f32, Vec2, Vec2) {
        block(ld, dimensions::light_start(j));
        (ld.next_1d(), ld.next_2d(), ld.next_2d())
    }

    /// [`light_start`](Self::light_start) with the light choice's number skipped in a scene
    /// of one light ([`light_choice_number`]): the same numbers, one Sobol' request fewer.
    #[inline]
    fn light_start_in(scene: &Scene, ld: &mut PixelSampler, j: u32) -> (f32, Vec2, Vec2) {
        block(ld, dimensions::light_start(j));
        (light_choice_number(scene, ld), ld.next_2d(), ld.next_2d())
    }

    /// Light subpath `j` of a pair, and in a fluorescent scene its mode (see
    /// `integrator/fluorescence/join.rs`): with probability α it starts at the pair's
    /// wavelengths, otherwise at its own draw from its light's spectrum. Scenes without
    /// fluorescence draw nothing more than before.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn light_subpath(
        &self,
        scene: &Scene,
        mixture: &WavelengthMixture,
        lambda: &SampledWavelengths,
        u_start: (f32, Vec2, Vec2),
        j: u32,
        rng: &mut PixelSampler,
        light_path: &mut Vec<Vertex>,
        stats: &mut PathStats,
    ) -> (LightStart, Option<LightMode>) {
        let max = self.max_depth as usize + 1;
        block(rng, dimensions::light_walk(j));
        if !scene.objects.fluorescence() {
            let start = generate_light_subpath_with(
                scene,
                lambda,
                u_start,
                rng,
                max,
                self.rr_depth,
                light_path,
                stats,
                WalkShift::LightLanesRecorded,
            );
            return (start, None);
        }
        let alpha = SHARED_MODE_PROBABILITY;
        let own = rng.next_1d() >= alpha;
        let mut start_lambda = *lambda;
        // Both mode numbers are consumed in either mode, so the walk's requests keep theirs.
        let u_own = rng.next_1d() as f64;
        let start = if own {
            let u = u_own;
            generate_light_subpath_own(
                scene,
                mixture,
                u,
                u_start,
                rng,
                max,
                self.rr_depth,
                light_path,
                stats,
                &mut start_lambda,
            )
        } else {
            generate_light_subpath_with(
                scene,
                lambda,
                u_start,
                rng,
                max,
                self.rr_depth,
                light_path,
                stats,
                WalkShift::LightLanesRecorded,
            )
        };
        let mode = LightMode::new(own, start_lambda, alpha, scene, mixture, light_path);
        (start, Some(mode))
    }

    fn record_splat(
        splats: &SplatFilm,
        strategies: Option<&StrategyFilms>,
        pixel_max: &PixelMaxY,
        raster: Vec2,
        xyz: [f64; 3],
        st: Option<(usize, usize)>,
    ) {
        pixel_max.record(raster.x, raster.y, xyz[1]);
        splats.splat_as(raster.x, raster.y, xyz, "bdpt t = 1 splat");
        if let Some(sf) = strategies {
            // Beams are light tracing with s = number of light vertices, t = 1; they are filed
            // under the longer-path image unless their (s, t) is known.
            let (s, t) = st.unwrap_or((usize::MAX / 4, 1));
            sf.film(s, t).splat(raster.x, raster.y, xyz);
        }
    }
}

/// Continue `ld` at `block` (see [`dimensions`]).
#[inline]
fn block(ld: &mut PixelSampler, (start, len): dimensions::Block) {
    ld.set_block(start, len);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::subpath::vertex::VertexKind;
    use crate::integrator::test_support::for_each_camera_subpath;
    use crate::scene::{build_scene, parse_scene_str, BuiltinFactory};
    use std::path::Path;

    /// Russian roulette on camera subpaths must not count refraction's 1/η² radiance scaling as
    /// a loss. Quantity: the throughput `β` of every camera-subpath vertex that lies outside the
    /// glass (floor, wall, lamp) on the caustic scene, for 40 000 camera rays aimed at and
    /// around the glass sphere, roulette from the first bounce. Bound: `1/(1 − 0.05)`, because
    /// every factor `f·|cos|/pdf` here is at most 1 once the η² of entering and leaving the
    /// sphere has cancelled, and a roulette step divides by at most `1 − q` with `q ≥ 0.05`.
    /// A roulette that saw the 1/η² = 0.44 of entering the glass as a loss returns the survivors
    /// with β = η² = 2.25 after they leave it (this gave the isolated s = 0 outliers through
    /// the sphere, e.g. pixel (80, 26) at 128 spp: one sample of 2.25× the lamp's radiance).
    #[test]
    fn roulette_ignores_the_radiance_scaling_of_refraction() {
        let file = Path::new("caustic.ron");
        // The scene file as shipped (source: scenes/caustic.ron).
        let desc = parse_scene_str(include_str!("../../../scenes/caustic.ron"), file).unwrap();
        let scene = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap();
        let glass = 2u32; // object index of "glass_ball" in the scene file
        let (mut outside, mut through_glass, mut worst) = (0u64, 0u64, 0.0f32);
        // The sphere covers roughly pixels x 55..105, y 20..80 of the 160×120 image.
        let window = (Vec2::new(50.0, 15.0), Vec2::new(60.0, 70.0));
        for_each_camera_subpath(&scene, 7, 40_000, window, (18, 1), |path, _| {
            let mut seen_glass = false;
            for v in &path[1..] {
                if v.kind == (VertexKind::Surface { object: glass }) {
                    seen_glass = true;
                    continue;
                }
                outside += 1;
                through_glass += seen_glass as u64;
                worst = worst.max(v.beta.max_value());
            }
        });
        assert!(through_glass > 1000, "too few paths through the glass");
        assert!(
            worst <= 1.0 / 0.95 + 1e-4,
            "camera-subpath throughput {worst} outside the glass ({outside} vertices)"
        );
    }
}
