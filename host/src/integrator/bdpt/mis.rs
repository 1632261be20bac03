//! The multiple-importance weights of bidirectional path tracing: the power heuristic over the
//! strategies (s, t) that can make a path (Veach 1997, §10.2), the reverse densities a
//! connection gives its joined vertices ([`Overrides`]), and the scale of the light-tracing
//! strategy ([`LIGHT_TRACING_MIS_SCALE`]). [`super::fluorescent_mis`] builds the per-lane
//! weights of fluorescent connections from the same parts.

use crate::camera::Camera;
use crate::integrator::nee_guide::{NeeGuide, NO_KEY};
use crate::integrator::subpath::vertex::{remap0, Vertex};
use crate::light::LightSampleContext;
use crate::material::TransportMode;
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;

/// The joined vertices of strategy (s, t) and the reverse densities the connection gives
/// them (area measure, 1/m²), for [`mis_weight_lanes`](super::fluorescent_mis::mis_weight_lanes): the same computation as the start of
/// [`mis_weight`], which keeps its own inline copy (a call returning two vertex copies cost
/// the scalar weight 15% more instructions).
pub struct Overrides {
    /// The camera-side endpoint (the sampled lens vertex for t = 1), as a copy.
    pub pt: Vertex,
    /// The light-side endpoint (the sampled light vertex for s = 1, t ≥ 2), if s ≥ 1.
    pub qs: Option<Vertex>,
    /// Density of `pt` sampled from the light side.
    pub pt_rev: f32,
    /// Density of the vertex before `pt` sampled from the light side, if t ≥ 2.
    pub pt_minus_rev: Option<f32>,
    /// Density of `qs` sampled from the camera side.
    pub qs_rev: Option<f32>,
    /// Density of the vertex before `qs` sampled from the camera side, if s ≥ 2.
    pub qs_minus_rev: Option<f32>,
}

/// [`Overrides`] of strategy (s, t); `sampled` as for [`mis_weight`].
#[allow(clippy::too_many_arguments)]
pub fn mis_weight_overrides(
    scene: &Scene,
    camera: &dyn Camera,
    light_path: &[Vertex],
    camera_path: &[Vertex],
    sampled: Option<&Vertex>,
    s: usize,
    t: usize,
    lambda: &SampledWavelengths,
) -> Overrides {
    // The (up to) four vertices whose reverse densities the connection changes, as copies.
    let pt = match (t, sampled) {
        (1, Some(v)) => *v,
        _ => camera_path[t - 1],
    };
    let qs = if s == 0 {
        None
    } else if s == 1 && t > 1 {
        sampled.copied()
    } else {
        Some(light_path[s - 1])
    };
    let pt_minus = if t >= 2 {
        Some(&camera_path[t - 2])
    } else {
        None
    };
    let qs_minus = if s >= 2 {
        Some(&light_path[s - 2])
    } else {
        None
    };
    use TransportMode::{Importance, Radiance};
    let pt_rev = match &qs {
        Some(q) => q.pdf(scene, camera, qs_minus, &pt, lambda, Importance),
        None => pt_minus.map_or(0.0, |m| pt.pdf_light_origin(scene, m)),
    };
    let pt_minus_rev = pt_minus.map(|m| match &qs {
        Some(q) => pt.pdf(scene, camera, Some(q), m, lambda, Importance),
        None => pt.pdf_light(scene, m),
    });
    let qs_rev = qs
        .as_ref()
        .map(|q| pt.pdf(scene, camera, pt_minus, q, lambda, Radiance));
    let qs_minus_rev = match (&qs, qs_minus) {
        (Some(q), Some(m)) => Some(q.pdf(scene, camera, Some(&pt), m, lambda, Radiance)),
        _ => None,
    };
    Overrides {
        pt,
        qs,
        pt_rev,
        pt_minus_rev,
        qs_rev,
        qs_minus_rev,
    }
}

/// Power-heuristic weight of strategy (s, t) for the path it produced, relative to all other
/// strategies that could have produced the same path (Veach 1997, §10.2), with t = 1's density
/// scaled by [`LIGHT_TRACING_MIS_SCALE`]. `sampled` is the
/// freshly sampled lens vertex (t = 1) or light vertex (s = 1, t ≥ 2).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn mis_weight(
    scene: &Scene,
    camera: &dyn Camera,
    light_path: &[Vertex],
    camera_path: &[Vertex],
    sampled: Option<&Vertex>,
    s: usize,
    t: usize,
    lambda: &SampledWavelengths,
    counts: impl Into<SampleCounts>,
) -> f32 {
    mis_weight_guided(
        scene,
        camera,
        light_path,
        camera_path,
        sampled,
        (s, t),
        lambda,
        counts.into(),
        None,
    )
}

/// [`mis_weight`] where the s = 1 strategy (t ≥ 2) draws its light point with the visibility
/// guide `guide` ([`s1_guide_factor`]): that strategy's density of x₀ carries the guide's
/// factor wherever it enters the sum (its own density when s = 1, its term otherwise).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn mis_weight_guided(
    scene: &Scene,
    camera: &dyn Camera,
    light_path: &[Vertex],
    camera_path: &[Vertex],
    sampled: Option<&Vertex>,
    (s, t): (usize, usize),
    lambda: &SampledWavelengths,
    counts: SampleCounts,
    guide: Option<&NeeGuide>,
) -> f32 {
    // Two instances: with every camera sample tracing light subpaths (q = 1) the joins' scale
    // is 1 and drops out, as before the fraction existed (one instance for both cost bdpt
    // +0.6% of its instructions on the Cornell box at q = 1).
    let args = (
        scene,
        camera,
        light_path,
        camera_path,
        sampled,
        s,
        t,
        lambda,
        counts,
        guide,
    );
    // And two more with the guide: unguided renders keep the weights' code as it was (one
    // instance for both cost the Cornell box +1.0% of bdpt's instructions, the guide off).
    match (counts.fraction >= 1.0, guide.is_some()) {
        (true, false) => mis_weight_in::<false, false>(args, None),
        (false, false) => mis_weight_in::<true, false>(args, None),
        (true, true) => mis_weight_in::<false, true>(args, None),
        (false, true) => mis_weight_in::<true, true>(args, None),
    }
}

/// What the light-fraction pilot (`light_fraction`) reads of one connection's weight: the
/// power heuristic's sum split by the scale each alternative strategy carries, so that the
/// weight under any sample counts is [`PilotTerms::weight`] without evaluating the densities
/// again, and the squared densities `(p₀/p, p₁/p)²` with which the path tracer's two
/// strategies (s = 0, s = 1) make the path of strategy (s, t), relative to that strategy's own
/// density `p` (the chain [`mis_weight_guided`] sums, with the same next-event correction and
/// guide factor; 0 where the strategy cannot make the path: a delta vertex or an unhittable
/// light), for the path-tracing candidate (`light_fraction::PtPilotSums`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PilotTerms {
    /// `(p₀/p)²`, `(p₁/p)²`.
    pub pt_ratios: [f32; 2],
    /// Σ of the alternatives counted once per camera sample (s ≤ 1, t ≥ 2), unscaled.
    pub unit: f32,
    /// Σ of the joins' terms (s ≥ 2, t ≥ 2), before their scale `q²`.
    pub join: f32,
    /// The light-tracing term (t = 1), before its scale ([`heuristic_scale`]`(1, 1, ·)`).
    pub t1: f32,
    /// What the sum is divided by besides the strategy's own scale: the next-event factor
    /// when the strategy is s = 1, t ≥ 2 (see [`mis_weight_guided`]), else 1.
    pub own: f32,
}

impl PilotTerms {
    /// The weight of strategy (s, t) for this path under `counts`: what [`mis_weight_guided`]
    /// computes (up to rounding) from the same terms.
    #[inline]
    pub fn weight(&self, s: usize, t: usize, counts: SampleCounts) -> f32 {
        let sum = (self.unit
            + self.join * counts.fraction * counts.fraction
            + self.t1 * heuristic_scale(1, 1, counts))
            / (heuristic_scale(s, t, counts) * self.own);
        let w = 1.0 / (1.0 + sum);
        if w.is_finite() {
            w
        } else {
            0.0
        }
    }
}

/// The [`PilotTerms`] of strategy (s, t)'s path (the light-fraction pilot's, see there).
#[allow(clippy::too_many_arguments)]
pub fn pilot_terms(
    scene: &Scene,
    camera: &dyn Camera,
    light_path: &[Vertex],
    camera_path: &[Vertex],
    sampled: Option<&Vertex>,
    (s, t): (usize, usize),
    lambda: &SampledWavelengths,
    counts: SampleCounts,
    guide: Option<&NeeGuide>,
) -> PilotTerms {
    let mut out = PilotTerms {
        own: 1.0,
        ..PilotTerms::default()
    };
    let args = (
        scene,
        camera,
        light_path,
        camera_path,
        sampled,
        s,
        t,
        lambda,
        counts,
        guide,
    );
    mis_weight_in::<true, true>(args, Some(&mut out));
    out
}

/// The arguments of [`mis_weight_guided`], passed on as one.
type WeightArgs<'a> = (
    &'a Scene,
    &'a dyn Camera,
    &'a [Vertex],
    &'a [Vertex],
    Option<&'a Vertex>,
    usize,
    usize,
    &'a SampledWavelengths,
    SampleCounts,
    Option<&'a NeeGuide>,
);

/// [`mis_weight_guided`], with `FRACTION` saying whether `counts.fraction` can be below 1 and
/// `GUIDED` whether `guide` can be `Some`.
#[inline(always)]
fn mis_weight_in<const FRACTION: bool, const GUIDED: bool>(
    (scene, camera, light_path, camera_path, sampled, s, t, lambda, counts, guide): WeightArgs<'_>,
    mut pilot: Option<&mut PilotTerms>,
) -> f32 {
    // The same overrides as [`mis_weight_overrides`], written out here on purpose: calling it
    // (even `#[inline(always)]`, moving the `Overrides` with its two vertex copies) costs
    // +2.0% of bdpt's instructions on the Cornell box (callgrind, 1 spp: 2.639 G → 2.690 G).
    // Keep the two in step (except that the densities no weight reads are skipped here, see
    // below). Here the vertices are borrowed, not copied (nothing below changes
    // them; the copies cost 0.4% of bdpt's instructions in `memcpy`).
    // The (up to) four vertices whose reverse densities the connection changes.
    let pt: &Vertex = match (t, sampled) {
        (1, Some(v)) => v,
        _ => &camera_path[t - 1],
    };
    let qs: Option<&Vertex> = if s == 0 {
        None
    } else if s == 1 && t > 1 {
        sampled
    } else {
        Some(&light_path[s - 1])
    };
    let pt_minus = if t >= 2 {
        Some(&camera_path[t - 2])
    } else {
        None
    };
    let qs_minus = if s >= 2 {
        Some(&light_path[s - 2])
    } else {
        None
    };
    use TransportMode::{Importance, Radiance};
    // Only the camera vertices i ≥ 1 enter the chain below (the lens point is never sampled
    // from the light side): pt's density (i = t − 1) is read when t ≥ 2, pt_minus's
    // (i = t − 2) when t ≥ 3. The others are not asked for: the same weights, 1.1% fewer of
    // bdpt's instructions per camera sample on the Cornell box (callgrind).
    let pt_rev = if t >= 2 {
        match qs {
            Some(q) => q.pdf(scene, camera, qs_minus, pt, lambda, Importance),
            None => pt_minus.map_or(0.0, |m| pt.pdf_light_origin(scene, m)),
        }
    } else {
        0.0
    };
    let pt_minus_rev = pt_minus.filter(|_| t >= 3).map(|m| match qs {
        Some(q) => pt.pdf(scene, camera, Some(q), m, lambda, Importance),
        None => pt.pdf_light(scene, m),
    });
    let qs_rev = qs.map(|q| pt.pdf(scene, camera, pt_minus, q, lambda, Radiance));
    let qs_minus_rev = match (qs, qs_minus) {
        (Some(q), Some(m)) => Some(q.pdf(scene, camera, Some(pt), m, lambda, Radiance)),
        _ => None,
    };
    // (pdf_fwd, pdf_rev, delta) of camera vertex i and light vertex i after the overrides
    // (for i = 0 only the delta flag is read).
    let cam = |i: usize| -> (f32, f32, bool) {
        if i + 1 == t {
            (pt.pdf_fwd, pt_rev, false)
        } else if i + 2 == t {
            let v = &camera_path[i];
            (v.pdf_fwd, pt_minus_rev.unwrap_or(v.pdf_rev), v.delta)
        } else {
            let v = &camera_path[i];
            (v.pdf_fwd, v.pdf_rev, v.delta)
        }
    };
    let light_v = |i: usize| -> &Vertex {
        if i + 1 == s {
            qs.unwrap_or_else(|| &light_path[i])
        } else {
            &light_path[i]
        }
    };
    let light = |i: usize| -> (f32, f32, bool) {
        let v = light_v(i);
        if i + 1 == s {
            (v.pdf_fwd, qs_rev.unwrap_or(v.pdf_rev), false)
        } else if i + 2 == s {
            (v.pdf_fwd, qs_minus_rev.unwrap_or(v.pdf_rev), v.delta)
        } else {
            (v.pdf_fwd, v.pdf_rev, v.delta)
        }
    };
    let sq = |x: f32| x * x;
    // The s = 1 strategy's own density of the light vertex (next-event estimation), squared
    // and relative to the light subpath's start density in the chain (see `nee_correction`).
    // With the visibility guide, also times the guide's squared factor g(u(x₀), key(x₁)).
    let nee = if s + t >= 3 {
        // x₀, x₁ and x₂ of the path (light to camera), and x₀'s start density.
        let (y0, y1, origin) = match s {
            0 => (pt, &camera_path[t - 2], pt_rev),
            1 => (light_v(0), pt, light_v(0).pdf_fwd),
            _ => (light_v(0), light_v(1), light_v(0).pdf_fwd),
        };
        let k = nee_correction(scene, y0, y1, origin);
        match guide {
            Some(g) if GUIDED => {
                let y2 = match s {
                    0 => &camera_path[t - 3],
                    1 => &camera_path[t - 2],
                    2 => pt,
                    _ => light_v(2),
                };
                let f = s1_guide_factor(g, scene, y0, y1, y2);
                k * f * f
            }
            _ => k,
        }
    } else {
        1.0
    };
    // Strategies' squared densities relative to this one's, each times its heuristic scale.
    let own_scale = heuristic_scale(s, t, counts);
    // The scales of light tracing (t = 1) and of the joins (s ≥ 2, t ≥ 2); 1 for s = 0, 1.
    let t1_scale = heuristic_scale(1, 1, counts);
    let join_scale = if FRACTION {
        counts.fraction * counts.fraction
    } else {
        1.0
    };
    let mut sum = 0.0f32;
    let mut ri = 1.0f32;
    for i in (1..t).rev() {
        let (fwd, rev, delta) = cam(i);
        ri *= sq(remap0(rev) / remap0(fwd));
        if !delta && !cam(i - 1).2 {
            // (i = t − 1 with s = 0 is the s = 1 strategy.)
            let nee_here = if s == 0 && i + 1 == t { nee } else { 1.0 };
            // The alternative (s + t − i, i).
            let scale = if i == 1 {
                t1_scale
            } else if FRACTION && s + t - i >= 2 {
                join_scale
            } else {
                1.0
            };
            sum += ri * nee_here * scale / own_scale;
            if let Some(p) = pilot.as_deref_mut() {
                let r = ri * nee_here;
                if i == 1 {
                    p.t1 += r;
                } else if s + t - i >= 2 {
                    p.join += r;
                } else {
                    p.unit += r;
                }
                if s + t - i <= 1 {
                    p.pt_ratios[s + t - i] = r;
                }
            }
        }
    }
    ri = 1.0;
    for i in (0..s).rev() {
        let (fwd, rev, delta) = light(i);
        ri *= sq(remap0(rev) / remap0(fwd));
        let delta_before = if i > 0 {
            light(i - 1).2
        } else {
            light_v(0).is_unhittable_light(scene)
        };
        if !delta && !delta_before {
            // The alternative (i, t + s − i) has t + (s − i) ≥ 2 camera vertices.
            let nee_here = if i == 1 { nee } else { 1.0 };
            if let Some(p) = pilot.as_deref_mut() {
                let r = ri * nee_here;
                if i >= 2 {
                    p.join += r;
                } else {
                    p.unit += r;
                    p.pt_ratios[i] = r;
                }
            }
            if FRACTION && i >= 2 {
                sum += ri * nee_here * join_scale / own_scale;
            } else {
                sum += ri * nee_here / own_scale;
            }
        }
    }
    if s == 1 && t >= 2 && nee > 0.0 {
        // This strategy is next-event estimation: its own density carries the factor.
        sum /= nee;
        if let Some(p) = pilot.as_deref_mut() {
            p.pt_ratios[0] /= nee;
            p.own = nee;
        }
    }
    if let Some(p) = pilot.filter(|_| s <= 1 && t >= 2) {
        p.pt_ratios[s] = 1.0;
    }
    let w = 1.0 / (1.0 + sum);
    if w.is_finite() {
        w
    } else {
        0.0
    }
}

/// `(p_nee / p_origin)²` for light vertex `y0` of a path whose next vertex towards the camera
/// is `y1`: the squared ratio of the area density (1/m²) with which next-event estimation from
/// `y1` draws `y0` (light choice × [`Light::pdf_li`](crate::light::Light::pdf_li) converted to
/// area at `y0`) to `origin`, the density of `y0` as a light subpath's start (light choice ×
/// `pdf_le`'s positional density), which the vertices' densities in the MIS chain hold. 1 for
/// lights rays cannot hit (delta lights, surfaceless plugin lights) and for lights whose two
/// samplers draw points alike
/// ([`Light::li_points_as_le`](crate::light::Light::li_points_as_le)).
///
/// Why: BDPT's s = 1 strategy with t ≥ 2 is next-event estimation, which draws `y0` with its
/// own density, not the start density; weighing it with the start density keeps the weights
/// summing to one (the estimate stays unbiased) but misjudges the strategy wherever the two
/// differ. An environment map's next-event estimation follows its luminance while the start
/// density is uniform over the sphere around the scene: the sun and bright windows, which next-
/// event estimation samples well, were handed to the camera paths that happen to hit them
/// (s = 0). The s = 1 term of the heuristic sum (or this strategy's own density, for s = 1) is
/// multiplied by this factor; every other strategy's density stays as it is.
pub fn nee_correction(scene: &Scene, y0: &Vertex, y1: &Vertex, origin: f32) -> f32 {
    let Some(li) = y0.light_index(scene) else {
        return 1.0;
    };
    let light = &scene.lights.lights()[li as usize];
    // Only lights that rays can find answer `pdf_li` with next-event estimation's density
    // (a plugin light without a surface answers 0): the others keep the start density.
    let flags = light.flags();
    if !flags.can_be_hit() || flags.is_delta() || light.li_points_as_le() || !(origin > 0.0) {
        return 1.0;
    }
    let ctx = LightSampleContext {
        p: y1.p,
        p_error: y1.p_error,
        n: y1.ng,
    };
    let pdf = light.pdf_li(&ctx, y0.p, y0.ng);
    let nee = scene.lights.pmf(li as usize) * y1.convert_density(pdf, y0);
    let k = nee / origin;
    if k.is_finite() {
        k * k
    } else {
        1.0
    }
}

/// The visibility guide's key of camera vertex `x1` as the receiver of the s = 1 strategy
/// (next-event estimation from `x1`), lit from the side of `x2`, the vertex before it on the
/// camera subpath: what [`NeeGuide::key`] gives the path tracer's receiver.
/// [`NO_KEY`] (uniform) away from surfaces.
#[inline]
pub fn s1_guide_key(guide: &NeeGuide, x1: &Vertex, x2: &Vertex) -> u32 {
    if x1.on_surface() {
        guide.key(x1.p, x1.ng, x2.p - x1.p)
    } else {
        NO_KEY
    }
}

/// The factor `g` by which the visibility guide multiplies the s = 1 strategy's density of
/// light vertex `x0` drawn from camera vertex `x1` (whose own predecessor on the camera
/// subpath is `x2`): the guide's density of `u(x0)`, the light's sample numbers of `x0` seen
/// from `x1` ([`Light::sample_coords`](crate::light::Light::sample_coords)), in the table of
/// key [`s1_guide_key`]. 1 where `x0` is on no light, the light is not guided, the key has no
/// table or the light gives no numbers for the point (as the path tracer's weights do).
#[inline]
pub fn s1_guide_factor(
    guide: &NeeGuide,
    scene: &Scene,
    x0: &Vertex,
    x1: &Vertex,
    x2: &Vertex,
) -> f32 {
    let Some(li) = x0.light_index(scene) else {
        return 1.0;
    };
    let li = li as usize;
    if !guide.guides(li) {
        return 1.0;
    }
    let light = &scene.lights.lights()[li];
    let key = s1_guide_key(guide, x1, x2);
    guide.pdf_factor(li, key, light.as_ref(), x1.p, x0.p)
}

/// The light-tracing strategy's (t = 1) density in the power heuristic is counted as
/// `LIGHT_TRACING_MIS_SCALE` times its value (its squared density as the square).
///
/// Why: the power heuristic weighs strategies by their densities alone and does not see that
/// the camera-side strategies are stratified (each pixel's Sobol' points, one after the
/// other) while the light subpaths' splats land in random pixels in random numbers. Where both
/// reach a path with similar densities — the directly lit floor of the caustic scene, s = 2,
/// t = 1 against s = 1, t = 2 — the t = 1 share had 117× the per-pixel variance
/// (docs/performance.md, "The caustic"). Variance-aware MIS (Grittmann, Georgiev, Slusallek,
/// Křivánek 2019) scales each technique's density by an estimate of its variance for this
/// reason; a constant scale is its simplest form. Any positive scale keeps BDPT unbiased: every
/// strategy's weight is computed with the same scaled densities, so the weights of the
/// strategies that can make a path still sum to one. Where light tracing is the only
/// practical strategy (caustics seen on a diffuse surface: L S…S D E, whose other strategy is a
/// camera path that hits the light through the glass), its density exceeds the other's by
/// orders of magnitude and a scale of ¼ leaves its weight near 1.
///
/// Measured on `scenes/caustic.ron`, BDPT 64 spp, 8 seeds, MSE against the reference
/// (docs/performance.md): scales 1, ½, ¼, 0.1, 0.05 give caustic-region MSE 1.63, 0.63, 0.40,
/// 0.39, 0.38 (×10⁻⁶) and rest 3.52, 1.83, 1.49, 1.46, 1.46 (×10⁻⁶), the caustic's core
/// unchanged. ¼ takes nearly all of the gain and keeps more weight on light tracing for
/// caustics of large lights, where the camera paths that hit the light are less rare.
pub const LIGHT_TRACING_MIS_SCALE: f32 = 0.25;

/// How many samples one camera sample of BDPT takes of each strategy, on average: what the
/// power heuristic weighs the strategies' densities by (Veach 1997, §9.2.1: the heuristic
/// over `nᵢ·pᵢ`).
///
/// Each camera sample traces its light subpaths with probability `fraction` (`q`, see
/// `bdpt::light_fraction`), and then `light_paths` of them for the light-tracing strategy
/// (t = 1). The expected counts: `1` for s = 0 (the camera path hits a light) and s = 1 with
/// t ≥ 2 (a fresh light point, next-event estimation), which every camera sample runs; `q` for
/// the joins s ≥ 2, t ≥ 2; `q · light_paths` for t = 1. A traced strategy's contribution is
/// divided by its count (`bdpt::connect`), so each strategy's estimate stays unbiased (Wald's
/// identity: a random number of samples with that expectation) and the weights of the
/// strategies that can make a path still sum to one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleCounts {
    /// Light subpaths joined to the camera (t = 1) when a camera sample traces them.
    pub light_paths: u32,
    /// Probability `q ∈ (0, 1]` that a camera sample traces its light subpaths.
    pub fraction: f32,
}

impl SampleCounts {
    /// `light_paths` light subpaths in every camera sample (`q` = 1).
    pub const fn every_sample(light_paths: u32) -> Self {
        Self {
            light_paths,
            fraction: 1.0,
        }
    }

    /// Whether strategy (s, t) uses the light subpath (s ≥ 2 with t ≥ 2, or t = 1), whose
    /// count then includes [`fraction`](Self::fraction).
    #[inline]
    pub fn uses_light_subpath(s: usize, t: usize) -> bool {
        t == 1 || s >= 2
    }

    /// The expected number of samples of strategy (s, t) per camera sample.
    #[inline]
    pub fn count(&self, s: usize, t: usize) -> f32 {
        if t == 1 {
            self.fraction * self.light_paths.max(1) as f32
        } else if s >= 2 {
            self.fraction
        } else {
            1.0
        }
    }
}

impl From<u32> for SampleCounts {
    /// `light_paths` light subpaths in every camera sample.
    fn from(light_paths: u32) -> Self {
        Self::every_sample(light_paths)
    }
}

/// The factor of strategy (s, t)'s squared density in the power heuristic: the square of its
/// expected sample count per camera sample ([`SampleCounts::count`]), for t = 1 times
/// [`LIGHT_TRACING_MIS_SCALE`].
#[inline]
pub fn heuristic_scale(s: usize, t: usize, counts: SampleCounts) -> f32 {
    if t == 1 {
        let c = LIGHT_TRACING_MIS_SCALE * counts.light_paths.max(1) as f32 * counts.fraction;
        c * c
    } else if s >= 2 {
        counts.fraction * counts.fraction
    } else {
        1.0
    }
}
