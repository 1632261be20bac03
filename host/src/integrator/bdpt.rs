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
//! Light subpaths: a camera sample that traces them traces `L`: the first is joined to every
//! camera-subpath prefix; all of them are joined to the camera (t = 1), which the power
//! heuristic then counts as that many samples (see [`LIGHT_PATHS`]). `L` is chosen per scene
//! by the pilot of [`light_fraction`] among 1, 2, 4 and 8 in a scene with delta surfaces
//! (caustics, [`light_paths_for`]), otherwise 1 (`--effect light-subpath-count=auto|N`).
//!
//! Light-subpath fraction: a camera sample traces its light subpaths only with probability `q`
//! (`--effect light-subpaths=auto|Q`; `auto` chooses `q` per scene by the same pilot); the
//! strategies that use them are divided by their expected count and weighted by it
//! ([`mis::SampleCounts`], [`light_fraction`]). `q = 1` traces them in every sample. `q = 0`
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
use crate::camera::{Camera, CameraRay};
use crate::film::rejected::{check_sample, RejectKind};
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
use light_fraction::{
    AltWeights, Candidates, Choice, LightSubpathCount, LightSubpaths, Part, PartCost, PilotSample,
    MAX_CANDIDATES,
};
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
    /// Light subpaths per camera sample in scenes with delta surfaces ([`light_paths_for`])
    /// where nothing chooses it: the pilot's base count, and the count where no pilot runs
    /// (`--effect light-subpath-count=N` wins over it). The first is joined to every
    /// camera-subpath prefix, every one to the camera (t = 1, see [`LIGHT_PATHS`]).
    pub light_paths: u32,
}

/// Light subpaths per camera sample that traces them, in a scene with delta surfaces, where
/// nothing chooses it: the pilot's base candidate (kept unless another count is estimated
/// [`light_fraction::MIN_GAIN_COUNT`] better), and the count with beams-only lights or
/// fluorescence (no pilot) unless `--effect light-subpath-count=N` gives one.
///
/// Why more than one: a camera sample of BDPT (camera subpath, its connections, the
/// specular-chain strategies) costs several light paths of `lt` (callgrind: 4.0× on
/// `scenes/bench/glass_sphere_mesh.ron`, 2.8× on the Cornell box), while a caustic seen on a
/// diffuse surface is made by the light-tracing strategy alone: with one light subpath per
/// camera sample, BDPT's efficiency in that caustic's core was 0.22× that of `lt`. Each
/// further light subpath is joined to the camera only (t = 1), the cheap part of a light
/// path's use, and the power heuristic counts the t = 1 strategy `L` times (Veach 1997, §9.2:
/// the heuristic over `nᵢ·pᵢ`; [`mis::heuristic_scale`]) while each t = 1 contribution is
/// divided by `L`: the estimate stays unbiased and the images deterministic (the subpaths
/// draw from the camera sample's own sequence).
///
/// The pilot's candidates are `L` ∈ [`light_fraction::COUNTS`] (1, 2, 4, 8) × the fractions
/// `q`. Measured (efficiency 1/(variance·instructions) relative to `q = 1, L = 4`: per-pixel
/// variance of Y over the pixels that see no emitter, 16 seeds × 4 spp at 80 × 60; instructions
/// per camera sample from callgrind, 3 spp minus 1 spp at 64 × 48, `--threads 1`, seed 3;
/// predicted: the pilot at 160 × 120, seed 3; auto's choice the same at 80 × 60, seeds 1–4):
///
/// | scene                        | auto's (q, L) | candidate | predicted | measured | without fireflies |
/// |------------------------------|---------------|-----------|-----------|----------|------------------|
/// | `prism.ron`                  | (1, 8)        | (1, 8)    | 1.24      | 1.29     | 1.55             |
/// | `bench/glass_sphere_mesh.ron`| (1, 4)        | (1, 8)    | 0.91 (80 × 60: 1.00–1.06) | 0.98 | 1.01 |
/// |                              |               | (1, 1)    | 0.65      | 0.52     | 0.49             |
/// | `caustic.ron`                | (½, 4)        | (½, 4)    | 1.19      | 1.44     | 1.43             |
/// |                              |               | (1, 8)    | 0.66      | 0.63     | 0.63             |
/// | `bench/spectral_caustic.ron` | (½ or ¼, 4)   | (½, 4)    | 1.19      | 1.43     | 1.24             |
/// |                              |               | (1, 1)    | 1.11      | 1.62     | 1.08             |
///
/// ("Without fireflies": the pixels where one of the 16 seeds carries 90% of the squared
/// deviations left out; on the spectral caustic one such pixel, the same in every candidate's
/// renders, holds 90% of the variance over all pixels, so there the ratios over all pixels
/// are mostly the instructions'.)
///
/// Instructions per camera sample: prism 23.8 k / 38.7 k (L = 4 / 8); glass sphere 22.7 k,
/// 27.1 k, 35.7 k, 52.0 k (L = 1, 2, 4, 8); spectral caustic 23.4 k, 29.1 k, 40.2 k, 61.1 k,
/// at (½, 4) 27.7 k; `caustic.ron` 32.4 k, 52.5 k (L = 4, 8), at (½, 4) 21.3 k. Only the
/// prism (light tracing alone makes its image) changes `L`; elsewhere another count is
/// estimated within 1.15× of the best fraction at `L = 4`, and the fraction takes most of
/// what the count would (the pilot's efficiencies depend mostly on `q·L`, the expected number
/// of light subpaths per camera sample). On the spectral caustic `L = 1` at `q = 1` is
/// measured 1.13× auto's `(½, 4)` over all pixels (0.87× without the firefly) but estimated
/// below it (0.93×).
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
            // The pilot's parts of the weight (its weight under each candidate (q, L) follows,
            // `light_fraction`) and the path tracer's densities of this path (q = 0).
            alt.terms = mis::pilot_terms(
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

/// The chain connections a render runs: the specular-chain connection (on or off), the
/// camera-side chain connection, and the reflecting shapes that seed the former.
type Chains<'a> = (bool, Option<&'a CameraChain>, Option<&'a SpecularShapes>);

/// What the steps of one camera sample ([`Bdpt::sample`]) share: the scene and camera, the
/// sample's pixel, wavelengths and observer weights, and the films it writes.
struct SampleFrame<'a> {
    scene: &'a Scene,
    camera: &'a dyn Camera,
    sensor: &'a Sensor,
    mixture: &'a WavelengthMixture,
    lambda: SampledWavelengths,
    /// The observer's weights at `lambda`.
    weights: XyzWeights,
    /// The pixel, and its centre in raster units.
    pixel: (u32, u32),
    center: Vec2,
    splats: &'a SplatFilm,
    spectral: Option<&'a SpectralFilm>,
    pixel_max: &'a PixelMaxY,
    strategies: Option<&'a StrategyFilms>,
    flat: Option<&'a FlatColour>,
    guide: Option<&'a NeeGuide>,
    /// Longest full path (bounces).
    max_depth: usize,
}

impl SampleFrame<'_> {
    /// Counts a contribution the film must not take (`kind`) under this sample's pixel and
    /// `strategy`, never in the image.
    fn reject(&self, strategy: String, kind: RejectKind) {
        let (x, y) = self.pixel;
        self.splats.reject(Rejection {
            x,
            y,
            strategy,
            kind,
        });
    }

    /// A contribution landing at raster position `raster` (t = 1, the camera-side chain,
    /// beams): the splat film, the strategy image of `st` (`None`: beams) and the spectral
    /// film, with the lane energies `energies` gives.
    fn splat(
        &self,
        raster: Vec2,
        xyz: [f64; 3],
        st: Option<(usize, usize)>,
        energies: impl FnOnce() -> LaneEnergies,
    ) {
        Bdpt::record_splat(
            self.splats,
            self.strategies,
            self.pixel_max,
            raster,
            xyz,
            st,
        );
        if let Some(sf) = self.spectral {
            sf.splat(raster.x, raster.y, &xyz, &energies());
        }
    }
}

/// A camera sample's contributions to its own pixel (the t ≥ 2 strategies and the
/// specular-chain connection), which the pixel film takes as one sample.
#[derive(Default)]
struct OwnPixel {
    xyz: [f64; 3],
    lanes: LaneEnergies,
    /// Per strategy (s, t), for the strategy images.
    per_strategy: Vec<(usize, usize, [f64; 3])>,
}

impl OwnPixel {
    /// Adds `xyz` of strategy `st`, with the lane energies `energies` gives where the frame
    /// has a spectral film.
    fn add(
        &mut self,
        frame: &SampleFrame<'_>,
        xyz: [f64; 3],
        (s, t): (usize, usize),
        energies: impl FnOnce() -> LaneEnergies,
    ) {
        for (sum, v) in self.xyz.iter_mut().zip(xyz) {
            *sum += v;
        }
        if frame.spectral.is_some() {
            self.lanes.accumulate(&energies());
        }
        if frame.strategies.is_some() {
            self.per_strategy.push((s, t, xyz));
        }
    }

    /// Hands the sum to the frame's spectral film and strategy images; returns it (for the
    /// pixel film).
    fn finish(self, frame: &SampleFrame<'_>) -> [f64; 3] {
        let c = frame.center;
        frame.pixel_max.record(c.x, c.y, self.xyz[1]);
        if let Some(sf) = frame.spectral {
            // The spectral film judges the sum as the pixel film's guard does.
            sf.add(frame.pixel.0, frame.pixel.1, &self.xyz, &[self.lanes]);
        }
        if let Some(sf) = frame.strategies {
            for (s, t, xyz) in self.per_strategy {
                sf.film(s, t).splat(c.x, c.y, xyz);
            }
        }
        self.xyz
    }
}

/// The light-fraction pilot's work counts of one camera sample: the light parts', and the
/// camera part's connections (its rays and shadow rays are the rest of the sample's, counted
/// from `before`).
struct SampleWork {
    before: PathStats,
    /// The first light subpath and its joins.
    light: PartCost,
    /// The further light subpaths (light tracing only).
    further: PartCost,
    camera_connections: u64,
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
/// of each pilot pixel at `q = 1` with the largest `L` of `candidates`, under the pilot's own
/// seed, fixed chunks reduced in order.
#[allow(clippy::too_many_arguments)]
fn pilot_sums(
    bdpt: &Bdpt,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    cam: &crate::camera::manager::NamedCamera,
    setup: &Setup<'_>,
    candidates: Candidates,
) -> Result<light_fraction::PilotSums, RenderError> {
    let bdpt = &Bdpt {
        light_paths: candidates.pilot_paths(),
        ..*bdpt
    };
    let (width, height) = cam.camera.resolution();
    let pool = super::tiled::thread_pool(settings.threads)?;
    let seed = light_fraction::pilot_seed(settings.seed);
    let splats = SplatFilm::new(width, height);
    let pilot_max = PixelMaxY::new(width, height);
    Ok(light_fraction::run_pilot(&pool, width, height, |pixels| {
        let mut worker = Worker::new(
            light_fraction::counts(bdpt.light_paths, 1.0),
            Some(PilotSample::new(width, height, candidates)),
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

/// The candidates (q, L) of the pilot for `scene` under `plan`'s requests (`light_fraction`),
/// and whether `q = 0` may be offered (the fraction not forced); `None` where nothing is left
/// to choose: both forced, or the fraction forced in a scene with one count.
fn pilot_candidates(bdpt: &Bdpt, scene: &Scene, plan: &RenderPlan) -> Option<(Candidates, bool)> {
    let default_paths = light_paths_for(scene, bdpt.light_paths);
    let forced = match plan.light_subpath_count() {
        LightSubpathCount::Count(n) => Some(n),
        LightSubpathCount::Auto => None,
    };
    let counts: Vec<u32> = match forced {
        Some(n) => vec![n],
        None if default_paths > 1 => light_fraction::COUNTS.to_vec(),
        None => vec![1],
    };
    let (fractions, offer_pt) = match plan.light_subpaths() {
        LightSubpaths::Auto => (light_fraction::CANDIDATES.to_vec(), true),
        LightSubpaths::Fraction(q) => (vec![q.min(1.0)], false),
    };
    if !offer_pt && counts.len() == 1 {
        return None;
    }
    let base = forced.unwrap_or(default_paths);
    Some((Candidates::new(&fractions, &counts, base), offer_pt))
}

/// The fraction `q` of camera samples that trace light subpaths (`light_fraction`; 0: the
/// camera samples are path traced, `path_traced`), the number `L` each traces, and the
/// run-time note: forced, kept at `q = 1` (`fraction_stays_one`), or the pilot's choice. A
/// forced 0 where the path tracer cannot stand for BDPT is an error naming why.
#[allow(clippy::too_many_arguments)]
fn choose_fraction(
    bdpt: &Bdpt,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    cam: &crate::camera::manager::NamedCamera,
    setup: &Setup<'_>,
    start: std::time::Instant,
) -> Result<(f32, u32, Option<String>), RenderError> {
    let stays_one = fraction_stays_one(scene);
    let paths = match plan.light_subpath_count() {
        LightSubpathCount::Count(n) => n,
        LightSubpathCount::Auto => light_paths_for(scene, bdpt.light_paths),
    };
    if let LightSubpaths::Fraction(q) = plan.light_subpaths() {
        if q <= 0.0 {
            if let Some(why) =
                stays_one.or_else(|| path_traced::refusal(&bdpt.path_traced(), scene, plan))
            {
                return Err(RenderError::Setup(format!(
                    "--effect light-subpaths=0: bdpt cannot path trace every camera sample in \
                     this scene ({why}); use auto or a fraction in (0, 1]"
                )));
            }
            let note = "bdpt light subpaths: q = 0 (forced), the camera samples are path traced";
            return Ok((0.0, paths, Some(note.to_string())));
        }
    }
    if let Some(why) = stays_one {
        let forced_one = matches!(plan.light_subpaths(), LightSubpaths::Fraction(q) if q >= 1.0);
        let note = (!forced_one).then(|| {
            format!(
                "bdpt light subpaths: q = 1, L = {paths} (every camera sample traces them: {why})"
            )
        });
        return Ok((1.0, paths, note));
    }
    match pilot_candidates(bdpt, scene, plan) {
        None => {
            let q = match plan.light_subpaths() {
                LightSubpaths::Fraction(q) => q.min(1.0),
                LightSubpaths::Auto => 1.0,
            };
            Ok((q, paths, None))
        }
        Some((candidates, offer_pt)) => {
            let choice = pilot_choice(
                bdpt, scene, plan, settings, cam, setup, candidates, offer_pt,
            )?;
            let note = choice.note(start.elapsed().as_secs_f64());
            Ok((choice.q, choice.light_paths, Some(note)))
        }
    }
}

/// The pilots' decision among `candidates` (BDPT's and, where `offer_pt` and it may stand for
/// BDPT, the path tracer's).
#[allow(clippy::too_many_arguments)]
fn pilot_choice(
    bdpt: &Bdpt,
    scene: &Scene,
    plan: &RenderPlan,
    settings: &RenderSettings,
    cam: &crate::camera::manager::NamedCamera,
    setup: &Setup<'_>,
    candidates: Candidates,
    offer_pt: bool,
) -> Result<Choice, RenderError> {
    let sums = pilot_sums(bdpt, scene, plan, settings, cam, setup, candidates)?;
    let refused = if offer_pt {
        path_traced::refusal(&bdpt.path_traced(), scene, plan)
    } else {
        Some("the fraction is forced (--effect light-subpaths)")
    };
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
    let (q, light_paths, note) =
        choose_fraction(bdpt, scene, plan, settings, cam, &setup, pilot_start)?;
    let bdpt = &Bdpt {
        light_paths,
        ..*bdpt
    };
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
    /// and `light-subpath-count=auto` render with, `q = 0` among the candidates where
    /// [`path_traced::refusal`] allows it), run as the render would run it; `None`
    /// where no pilot runs: the fraction stays 1 (beams-only lights, fluorescence) or nothing
    /// is left to choose (both forced, or the fraction forced in a scene with one count).
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
        let Some((candidates, offer_pt)) = pilot_candidates(self, scene, plan) else {
            return Ok(None);
        };
        let setup = Setup::new(scene, plan, settings, cam.camera.as_ref());
        pilot_choice(
            self, scene, plan, settings, cam, &setup, candidates, offer_pt,
        )
        .map(Some)
    }

    /// One camera sample of pixel `(x, y)`: returns the XYZ of all t ≥ 2 strategies for the
    /// pixel film and splats the t = 1 strategies (and beams) into `splats`.
    ///
    /// The steps, in the order they draw numbers: the subpaths ([`Self::trace_subpaths`]),
    /// every (s, t) join of the two ([`Self::connect_subpaths`]), the specular-chain
    /// connection ([`Self::specular_chain`]), the camera-side chain connection
    /// ([`Self::camera_chain`]) and the further light subpaths, joined to the camera only
    /// ([`Self::further_light_subpaths`]).
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
        chains: Chains<'_>,
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
        let center = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        let Some(cray) = camera.generate_ray(&cs) else {
            return [0.0; 3];
        };
        let frame = SampleFrame {
            scene,
            camera,
            sensor,
            mixture,
            lambda,
            weights,
            pixel: (x, y),
            center,
            splats,
            spectral,
            pixel_max,
            strategies,
            flat,
            guide,
            max_depth: self.max_depth as usize,
        };
        let mut camera_path = std::mem::take(&mut worker.camera_path);
        let mut light_path = std::mem::take(&mut worker.light_path);
        let (trace_light, mode, mut work) =
            self.trace_subpaths(&frame, cray, ld, worker, &mut camera_path, &mut light_path);
        let mut own = OwnPixel::default();
        let paths = (camera_path.as_slice(), light_path.as_slice());
        self.connect_subpaths(
            &frame,
            paths,
            mode.as_ref(),
            chains,
            ld,
            worker,
            &mut own,
            &mut work,
        );
        let (manifold, camera_chain, reflection_shapes) = chains;
        if manifold {
            self.specular_chain(
                &frame,
                &camera_path,
                reflection_shapes,
                ld,
                worker,
                &mut own,
            );
        }
        if let Some(cc) = camera_chain {
            self.camera_chain(&frame, cc, ld, worker);
        }
        if trace_light {
            self.further_light_subpaths(
                &frame,
                &camera_path,
                &mut light_path,
                ld,
                worker,
                &mut work,
            );
        }
        if let Some(p) = worker.pilot.as_mut() {
            let camera_cost = PartCost {
                rays: worker.stats.rays - work.before.rays - work.light.rays - work.further.rays,
                shadow_rays: worker.stats.shadow_rays
                    - work.before.shadow_rays
                    - work.light.shadow_rays
                    - work.further.shadow_rays,
                connections: work.camera_connections,
            };
            p.finish_sample(center, camera_cost, work.light, work.further);
        }
        worker.camera_path = camera_path;
        worker.light_path = light_path;
        own.finish(&frame)
    }

    /// The sample's camera subpath and its first light subpath, which it traces with
    /// probability `q` (drawn from a stratified dimension of its own: a pixel's samples trace
    /// about `q` of them; with `q = 1` no number is drawn), with a beams-only light's beams and
    /// the subpaths' flatness. Returns whether this sample traces light subpaths, the light
    /// subpath's fluorescence mode, and the pilot's work counts so far.
    fn trace_subpaths(
        &self,
        frame: &SampleFrame<'_>,
        cray: CameraRay,
        ld: &mut PixelSampler,
        worker: &mut Worker,
        camera_path: &mut Vec<Vertex>,
        light_path: &mut Vec<Vertex>,
    ) -> (bool, Option<LightMode>, SampleWork) {
        let counts = worker.counts;
        let trace_light = counts.fraction >= 1.0 || {
            block(ld, dimensions::LIGHT_FRACTION);
            ld.next_1d() < counts.fraction
        };
        let u_start = trace_light.then(|| Self::light_start(frame.scene, ld, 0));
        let before = worker.stats;
        block(ld, dimensions::CAMERA_WALK);
        generate_camera_subpath(
            frame.scene,
            frame.camera,
            cray.ray,
            cray.weight,
            &frame.lambda,
            ld,
            frame.max_depth + 2,
            self.rr_depth,
            camera_path,
            &mut worker.stats,
        );
        let after_camera = worker.stats;
        let (start, mode) = match u_start {
            Some(u_start) => self.light_subpath(
                frame.scene,
                frame.mixture,
                &frame.lambda,
                u_start,
                0,
                ld,
                light_path,
                &mut worker.stats,
            ),
            None => {
                light_path.clear();
                (LightStart::None, None)
            }
        };
        // The pilot's cost counts of the light part (the rest is the camera part).
        let work = SampleWork {
            before,
            light: PartCost {
                rays: worker.stats.rays - after_camera.rays,
                ..PartCost::default()
            },
            further: PartCost::default(),
            camera_connections: 0,
        };
        if let LightStart::Beams { index, pmf } = start {
            self.trace_beams(frame, (index, pmf), 0, ld, &mut worker.stats);
        }
        if let Some(fc) = frame.flat {
            fc.prefix(camera_path, &mut worker.camera_flat);
            fc.prefix(light_path, &mut worker.light_flat);
        }
        (trace_light, mode, work)
    }

    /// A beams-only light's subpath `j` of this camera sample: light tracing alone, each
    /// splat weighted 1/light_paths.
    fn trace_beams(
        &self,
        frame: &SampleFrame<'_>,
        (index, pmf): (usize, f32),
        j: u32,
        ld: &mut PixelSampler,
        stats: &mut PathStats,
    ) {
        let inv = 1.0 / self.light_paths as f64;
        let mut splat = |raster: Vec2, xyz: [f64; 3], e: &dyn Fn() -> LaneEnergies| {
            frame.splat(raster, xyz.map(|v| v * inv), None, || {
                let mut e = e();
                e.e = e.e.map(|v| v * inv);
                e
            });
        };
        block(ld, dimensions::beams(j));
        trace_beam(
            frame.scene,
            frame.camera,
            frame.sensor,
            index,
            pmf,
            self.max_depth,
            self.rr_depth,
            ld,
            stats,
            &mut splat,
        );
    }

    /// Every (s, t) strategy joining the camera subpath to the first light subpath: t ≥ 2 to
    /// the pixel, t = 1 splatted where it lands. An s = 0 path that a chain connection also
    /// makes gives up the chain's share.
    #[allow(clippy::too_many_arguments)]
    fn connect_subpaths(
        &self,
        frame: &SampleFrame<'_>,
        (camera_path, light_path): (&[Vertex], &[Vertex]),
        mode: Option<&LightMode>,
        (manifold, camera_chain, reflection_shapes): Chains<'_>,
        ld: &mut PixelSampler,
        worker: &mut Worker,
        own: &mut OwnPixel,
        work: &mut SampleWork,
    ) {
        let (scene, camera, lambda) = (frame.scene, frame.camera, &frame.lambda);
        let (max_depth, counts) = (frame.max_depth, worker.counts);
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
                    frame.mixture,
                    light_path,
                    camera_path,
                    s,
                    t,
                    lambda,
                    mode,
                    counts,
                    frame.guide,
                    ld,
                    &mut worker.stats,
                    worker.pilot.is_some().then_some(&mut alt),
                );
                if worker.pilot.is_none() {
                    // (The cost counts below are the pilot's.)
                } else if SampleCounts::uses_light_subpath(s, t) {
                    work.light.shadow_rays += worker.stats.shadow_rays - shadow_before;
                    work.light.connections += connected.is_some() as u64;
                } else {
                    work.camera_connections += connected.is_some() as u64;
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
                    if let Some(w) =
                        s0_weight(scene, camera, camera_path, t, lambda, max_depth, &mut seeds)
                    {
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
                            camera_path,
                            t,
                            lambda,
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
                let weights = match (t, light_path.get(s.wrapping_sub(1)), mode) {
                    (1, Some(q), Some(m)) => {
                        shifted_weights = XyzWeights::new(frame.sensor, &t1_wavelengths(m, q));
                        &shifted_weights
                    }
                    _ => &frame.weights,
                };
                let xyz = connection_xyz(
                    frame.flat,
                    (&worker.camera_flat, &worker.light_flat),
                    s,
                    t,
                    &c,
                    weights,
                    lambda,
                );
                if let Some(kind) = check_sample(&xyz) {
                    frame.reject(format!("bdpt s={s} t={t}"), kind);
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
                        // Each candidate's weight over the current one (and count, t = 1).
                        let ratios = p.candidates().ratios(&alt.terms, (s, t), w_mis);
                        let at = c.raster.unwrap_or(frame.center);
                        let part = match (s, t) {
                            (_, 1) => Part::LightTracing(0),
                            (2.., _) => Part::Join,
                            _ => Part::Camera,
                        };
                        p.book(at, part, xyz[1], &ratios);
                        let n = counts.count(s, t);
                        let own = c.raster.is_none().then_some(s + t - 2);
                        p.book_pt(xyz[1], c.weight[0], n, &alt.terms.pt_ratios, own);
                    }
                }
                let energies = || weights.energies(&(c.l * c.weight), c.lanes);
                match c.raster {
                    Some(r) => frame.splat(r, xyz, Some((s, t)), energies),
                    None => own.add(frame, xyz, (s, t), energies),
                }
            }
        }
    }

    /// The specular-chain connection from the first non-specular camera vertex (a light seen
    /// through delta surfaces), to the pixel.
    fn specular_chain(
        &self,
        frame: &SampleFrame<'_>,
        camera_path: &[Vertex],
        reflection_shapes: Option<&SpecularShapes>,
        ld: &mut PixelSampler,
        worker: &mut Worker,
        own: &mut OwnPixel,
    ) {
        let Some(j) = anchor(frame.scene, camera_path) else {
            return;
        };
        block(ld, dimensions::MANIFOLD);
        let u = (light_choice_number(frame.scene, ld), ld.next_2d());
        let mut seeds = Seeds {
            shapes: reflection_shapes,
            set: &mut worker.manifold_set,
        };
        connect_manifold(
            frame.scene,
            frame.camera,
            camera_path,
            j,
            &frame.lambda,
            u,
            frame.max_depth,
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
                    frame.flat.filter(|_| m.flat_chain),
                    (&worker.camera_flat, &worker.light_flat),
                    1,
                    j + 1,
                    &c,
                    &frame.weights,
                    &frame.lambda,
                );
                if let Some(kind) = check_sample(&xyz) {
                    frame.reject("bdpt specular chain".into(), kind);
                } else {
                    if let Some(p) = worker.pilot.as_mut() {
                        p.book(frame.center, Part::Camera, xyz[1], &[1.0; MAX_CANDIDATES]);
                    }
                    // Filed with s = 0 of the same path: the two share its class.
                    own.add(frame, xyz, (0, m.t_equivalent), || {
                        frame.weights.energies(&(c.l * c.weight), c.lanes)
                    });
                }
            },
        );
    }

    /// The camera-side chain connection (a light's image through delta surfaces, from the
    /// camera's side), splatted like t = 1.
    fn camera_chain(
        &self,
        frame: &SampleFrame<'_>,
        cc: &CameraChain,
        ld: &mut PixelSampler,
        worker: &mut Worker,
    ) {
        block(ld, dimensions::CAMERA_CHAIN);
        let u_run = ld.next_1d();
        let u = if u_run < super::connect::camera_chain::CAMERA_CHAIN_RATE {
            (u_run, ld.next_1d(), ld.next_2d())
        } else {
            (u_run, 0.0, Vec2::ZERO)
        };
        cc.connect(
            frame.scene,
            frame.camera,
            &frame.lambda,
            u,
            frame.max_depth,
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
                    frame.flat.filter(|_| m.sample.flat_chain),
                    (&worker.camera_flat, &worker.light_flat),
                    0,
                    1,
                    &c,
                    &frame.weights,
                    &frame.lambda,
                );
                if let Some(kind) = check_sample(&xyz) {
                    frame.reject("bdpt camera chain".into(), kind);
                    return;
                }
                if let Some(p) = worker.pilot.as_mut() {
                    p.book(m.raster, Part::Camera, xyz[1], &[1.0; MAX_CANDIDATES]);
                }
                frame.splat(m.raster, xyz, Some((0, m.sample.t_equivalent)), || {
                    frame.weights.energies(&(c.l * c.weight), c.lanes)
                });
            },
        );
    }

    /// The further light subpaths of this camera sample (`light_paths − 1` of them), each
    /// joined to the camera only: light tracing (t = 1).
    fn further_light_subpaths(
        &self,
        frame: &SampleFrame<'_>,
        camera_path: &[Vertex],
        light_path: &mut Vec<Vertex>,
        ld: &mut PixelSampler,
        worker: &mut Worker,
        work: &mut SampleWork,
    ) {
        let (scene, counts) = (frame.scene, worker.counts);
        for j in 1..self.light_paths {
            let u_start = Self::light_start(frame.scene, ld, j);
            let rays_before = worker.stats.rays;
            let (start, mode) = self.light_subpath(
                scene,
                frame.mixture,
                &frame.lambda,
                u_start,
                j,
                ld,
                light_path,
                &mut worker.stats,
            );
            if let LightStart::Beams { index, pmf } = start {
                self.trace_beams(frame, (index, pmf), j, ld, &mut worker.stats);
            }
            work.further.rays += worker.stats.rays - rays_before;
            if let Some(fc) = frame.flat {
                fc.prefix(light_path, &mut worker.light_flat);
            }
            for s in 1..=light_path.len().min(frame.max_depth + 1) {
                block(ld, dimensions::t1(j, s));
                let shadow_before = worker.stats.shadow_rays;
                let mut alt = AltWeights::default();
                let connected = connect(
                    scene,
                    frame.camera,
                    frame.mixture,
                    light_path,
                    camera_path,
                    s,
                    1,
                    &frame.lambda,
                    mode.as_ref(),
                    counts,
                    frame.guide,
                    ld,
                    &mut worker.stats,
                    worker.pilot.is_some().then_some(&mut alt),
                );
                work.further.shadow_rays += worker.stats.shadow_rays - shadow_before;
                work.further.connections += connected.is_some() as u64;
                let Some(c) = connected else {
                    continue;
                };
                let Some(r) = c.raster else { continue };
                let shifted_weights;
                let w = match (&mode, light_path.get(s - 1)) {
                    (Some(m), Some(q)) => {
                        shifted_weights = XyzWeights::new(frame.sensor, &t1_wavelengths(m, q));
                        &shifted_weights
                    }
                    _ => &frame.weights,
                };
                let xyz = connection_xyz(
                    frame.flat,
                    (&worker.camera_flat, &worker.light_flat),
                    s,
                    1,
                    &c,
                    w,
                    &frame.lambda,
                );
                if let Some(kind) = check_sample(&xyz) {
                    frame.reject(format!("bdpt s={s} t=1"), kind);
                    continue;
                }
                if let Some(p) = worker.pilot.as_mut() {
                    let cw = c.weight[0];
                    // Left out where the camera sees an emitter, as above.
                    if light_path[s - 1].light_index(scene).is_none() {
                        let ratios = p.candidates().ratios(&alt.terms, (s, 1), cw);
                        p.book(r, Part::LightTracing(j), xyz[1], &ratios);
                        let n = counts.count(s, 1);
                        p.book_pt(xyz[1], cw, n, &alt.terms.pt_ratios, None);
                    }
                }
                frame.splat(r, xyz, Some((s, 1)), || {
                    w.energies(&(c.l * c.weight), c.lanes)
                });
            }
            if let Some(p) = worker.pilot.as_mut() {
                p.end_subpath();
            }
        }
    }

    /// The start of light subpath `j` (light choice, `sample_le`'s two 2D numbers), the light
    /// choice's number skipped in a scene of one light ([`light_choice_number`]: the same
    /// numbers, one Sobol' request fewer).
    #[inline]
    fn light_start(scene: &Scene, ld: &mut PixelSampler, j: u32) -> (f32, Vec2, Vec2) {
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

    /// The light-subpath pilot's weights under each candidate (q, L), from one evaluation's
    /// parts (`mis::PilotTerms::weight`), against `mis_weight_guided` evaluated under those
    /// counts. Quantity: the s = 0 weights of every camera-subpath vertex on the lamp of the
    /// Cornell box (20 000 camera rays), whose alternatives are all three kinds the terms
    /// separate (s = 1, the joins s ≥ 2, light tracing t = 1). Tolerance: 1e-4 relative plus
    /// 1e-6 (single-precision rounding of the same sums in another order).
    #[test]
    fn pilot_weights_match_the_weights_under_each_candidate() {
        let file = Path::new("cornell_box.ron");
        let desc = parse_scene_str(include_str!("../../../scenes/cornell_box.ron"), file).unwrap();
        let scene = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap();
        let cam = scene.cameras.get(None).unwrap();
        let camera = cam.camera.as_ref();
        let candidates = Candidates::new(&light_fraction::CANDIDATES, &light_fraction::COUNTS, 4);
        let pilot = light_fraction::counts(candidates.pilot_paths(), 1.0);
        let window = (Vec2::ZERO, Vec2::new(256.0, 256.0));
        let (mut checked, mut shared) = (0u64, 0u64);
        for_each_camera_subpath(&scene, 11, 20_000, window, (18, 1), |path, lambda| {
            for t in 2..=path.len() {
                if path[t - 1].light_index(&scene).is_none() {
                    continue;
                }
                let terms =
                    mis::pilot_terms(&scene, camera, &[], path, None, (0, t), lambda, pilot, None);
                for &(q, l) in candidates.list() {
                    let counts = light_fraction::counts(l, q);
                    let w = mis_weight_guided(
                        &scene,
                        camera,
                        &[],
                        path,
                        None,
                        (0, t),
                        lambda,
                        counts,
                        None,
                    );
                    let w_terms = terms.weight(0, t, counts);
                    assert!(
                        (w - w_terms).abs() <= 1e-4 * w.abs() + 1e-6,
                        "t = {t}, q = {q}, L = {l}: {w} against {w_terms}"
                    );
                    checked += 1;
                    shared += (w < 0.99 && w > 0.01) as u64;
                }
            }
        });
        assert!(
            checked > 500 && shared > 50,
            "{checked} weights, {shared} shared"
        );
    }
}
