//! bdpt's connections through a fluorescent vertex between two independently drawn
//! wavelengths, in a scene that renders fluorescence.
//!
//! A shift only lengthens a wavelength (Stokes), so a lane that shifted anywhere on a path was
//! emitted at a shorter wavelength than it is observed at: two subpaths that start at the
//! pair's wavelength can join only lanes that never shifted. So each camera/light pair draws
//! a **mode** (a one-sample mixture):
//!
//! - **shared**, probability α ([`SHARED_MODE_PROBABILITY`]): the light subpath starts at the
//!   pair's wavelengths, and connections s ≥ 2, t ≥ 2 join the lanes that never shifted, as
//!   without the mixture (their contribution divided by α);
//! - **own**, probability 1 − α: the light subpath draws its own wavelengths λ_L from the
//!   spectrum of the light it starts on ([`WavelengthMixture::sample_light`], density
//!   p_L(λ_L | light)), and a connection s ≥ 2, t ≥ 2 ([`connect_own`]) evaluates the
//!   re-radiation r(λ_light → λ_camera)/π at its camera-side endpoint when that is
//!   fluorescent, else at its light-side endpoint when that is, instead of the endpoint's own
//!   keep/shift choice (ρ/π when the two wavelengths are equal, which happens only when both
//!   are discrete draws of the same delta line); with no fluorescent endpoint it joins only
//!   lanes on the same delta line (discrete × discrete). Its contribution is divided by
//!   (1 − α)·p_L(λ_L).
//!
//! s = 0 and s = 1 use the camera subpath alone and are the same in both modes. t = 1 (the
//! light subpath splatted) is one strategy over both modes: the marginal density of its start
//! wavelength is α·p_mix(λ) + (1 − α)·p_L(λ | light) ([`t1_wavelengths`]), which the splat
//! divides by. The MIS weights of all of them are per lane, in
//! [`crate::integrator::bdpt::fluorescent_mis::mis_weight_lanes`].
//!
//! Why α = ½: the two modes serve different lane paths (shared: the lanes that never shift,
//! which are most of what a scene with a few fluorescent objects shows; own: the lanes that
//! shift between a light subpath and a camera subpath, which only it joins), and t = 1 gains
//! from both. With no knowledge of which matters more in a scene, ½ bounds the loss of either
//! to a factor of 2 in its strategies' samples (docs/effects.md has the measurements).

use crate::integrator::fluorescence::events::Direction;
use crate::integrator::subpath::vertex::{geometry_term, unoccluded, Vertex, VertexKind};
use crate::integrator::wavelengths::mixture::WavelengthMixture;
use crate::integrator::PathStats;
use crate::material::TransportMode;
use crate::scene::Scene;
use crate::spectrum::reradiation::Reradiation;
use crate::spectrum::spd::is_line_lane;
use crate::spectrum::{DeltaLine, SampledSpectrum, SampledWavelengths, LANES};
use std::cell::Cell;

/// α: the probability that a pair's light subpath starts at the pair's wavelengths (module
/// docs). Scenes without fluorescence draw no mode (all shared, α = 1 in effect).
pub const SHARED_MODE_PROBABILITY: f32 = 0.5;

/// How the light subpath of a pair started, in a scene that renders fluorescence, with the
/// densities of its start wavelengths that the MIS weights and the t = 1 splats need (computed
/// once per pair instead of per connection).
#[derive(Clone, Debug)]
pub struct LightMode {
    /// The light subpath drew its own wavelengths (the "own" mode) instead of the pair's.
    pub own: bool,
    /// The wavelengths the light subpath started with (the light vertices' `shifted` are
    /// relative to these): the pair's in the shared mode, its own draw (pdf p_L) otherwise.
    pub lambda: SampledWavelengths,
    /// α, the probability of the shared mode.
    pub alpha: f32,
    /// The light the subpath started on (`u32::MAX` without a subpath).
    pub start_light: u32,
    /// p_mix at `lambda`, per lane.
    pub start_mix_pdf: [f64; LANES],
    /// p_L(`lambda` | `start_light`), per lane.
    pub start_light_pdf: [f64; LANES],
    /// p_L(pair's wavelengths | light), per lane, for the last lights asked (s ≤ 1 strategies
    /// whose light is not the subpath's): (light, densities), a small direct-mapped cache.
    pair_light_pdf: Cell<[(u32, [f64; LANES]); 4]>,
}

impl LightMode {
    /// The mode of a pair whose light subpath `light_path` started at `lambda` (the pair's
    /// wavelengths `pair` in the shared mode).
    pub fn new(
        own: bool,
        lambda: SampledWavelengths,
        alpha: f32,
        scene: &Scene,
        mixture: &WavelengthMixture,
        light_path: &[Vertex],
    ) -> Self {
        let start_light = light_path
            .first()
            .and_then(|v| v.light_index(scene))
            .unwrap_or(u32::MAX);
        let mut start_mix_pdf = [0.0; LANES];
        let mut start_light_pdf = [0.0; LANES];
        if start_light != u32::MAX {
            for k in 0..LANES {
                let l = lambda.lambda[k];
                (start_mix_pdf[k], start_light_pdf[k]) = if own {
                    (mixture.lane_density(l), lambda.pdf[k] as f64)
                } else {
                    (
                        lambda.pdf[k] as f64,
                        mixture.light_lane_density(start_light as usize, l),
                    )
                };
            }
        }
        Self {
            own,
            lambda,
            alpha,
            start_light,
            start_mix_pdf,
            start_light_pdf,
            pair_light_pdf: Cell::new([(u32::MAX, [0.0; LANES]); 4]),
        }
    }

    /// p_L(λ | `light`) of the lanes of the pair's wavelengths `pair` (cached per light).
    pub fn pair_light_pdf(
        &self,
        mixture: &WavelengthMixture,
        light: u32,
        pair: &SampledWavelengths,
    ) -> [f64; LANES] {
        let mut cache = self.pair_light_pdf.get();
        let slot = (light & 3) as usize;
        if cache[slot].0 != light {
            let d =
                std::array::from_fn(|j| mixture.light_lane_density(light as usize, pair.lambda[j]));
            cache[slot] = (light, d);
            self.pair_light_pdf.set(cache);
        }
        cache[slot].1
    }
}

/// The re-radiation of a fluorescent surface at vertex `v`, if any.
#[inline]
pub fn reradiation_at<'a>(scene: &'a Scene, v: &Vertex) -> Option<&'a dyn Reradiation> {
    match v.kind {
        VertexKind::Surface { object } => scene.objects.reradiation(object),
        _ => None,
    }
}

/// The value an evaluated fluorescent event gives for light arriving at `a` and leaving
/// towards the camera at `b` (nm, as lanes store them): r(a → b) for a Stokes shift onto a
/// continuous camera wavelength, ρ(a) for a = b on a delta line (both ends discrete draws of
/// it), 0 otherwise: a camera lane on a line carries only line light (nothing re-radiated is
/// a line), and a = b off the lines has probability zero.
#[inline]
pub fn evaluated_event(rr: &dyn Reradiation, a: f32, b: f32, lines: &[DeltaLine]) -> f64 {
    if a == b {
        if is_line_lane(lines, a) {
            rr.reflectance(a as f64).max(0.0)
        } else {
            0.0
        }
    } else if a < b && !is_line_lane(lines, b) {
        rr.reradiation(a as f64, b as f64).max(0.0)
    } else {
        0.0
    }
}

/// True when an evaluated event `a → b` ([`evaluated_event`]) can be non-zero: the lane paths
/// the own mode makes through such a vertex.
#[inline]
pub fn evaluated_event_possible(a: f32, b: f32, lines: &[DeltaLine]) -> bool {
    if a == b {
        is_line_lane(lines, a)
    } else {
        !is_line_lane(lines, b)
    }
}

/// `v.beta` without the weight of the keep/shift choice its subpath made on arrival (at
/// `arrive`, leaving at `after`): that weight is value/probability of the event (ρ or r over
/// [`Vertex::choice`]), see [`crate::integrator::fluorescence::events::shift_lanes_recorded`]. Lanes whose choice
/// weighed 0 (nothing arrives there, or the draw failed) give 0.
fn before_event(
    rr: &dyn Reradiation,
    v: &Vertex,
    arrive: &[f32; LANES],
    after: &[f32; LANES],
    dir: Direction,
) -> SampledSpectrum {
    let mut out = SampledSpectrum::zero();
    for k in 0..LANES {
        let (a, b) = (arrive[k] as f64, after[k] as f64);
        let value = if arrive[k] == after[k] {
            rr.reflectance(a).max(0.0)
        } else {
            match dir {
                Direction::Camera => rr.reradiation(b, a),
                Direction::Light => rr.reradiation(a, b),
            }
        };
        let w = value / v.choice[k] as f64;
        if w > 0.0 && w.is_finite() {
            out[k] = (v.beta[k] as f64 / w) as f32;
        }
    }
    out
}

/// The own mode's connection s ≥ 2, t ≥ 2 (module docs): the unweighted contribution per lane,
/// divided by the light wavelengths' density (1 − α)·p_L (the pair's density is the film's),
/// or `None` when it gives nothing.
#[allow(clippy::too_many_arguments)]
pub fn connect_own(
    scene: &Scene,
    light_path: &[Vertex],
    camera_path: &[Vertex],
    s: usize,
    t: usize,
    pair: &SampledWavelengths,
    mode: &LightMode,
    stats: &mut PathStats,
) -> Option<SampledSpectrum> {
    let qs = &light_path[s - 1];
    let pt = &camera_path[t - 1];
    if !qs.connectible(scene) || !pt.connectible(scene) {
        return None;
    }
    let g = geometry_term(qs, pt);
    if !(g > 0.0) {
        return None;
    }
    let lines = scene.lights.delta_lines();
    let lam_l = qs.wavelengths(&mode.lambda);
    let lam_c = pt.wavelengths(pair);
    use TransportMode::{Importance, Radiance};
    let mut c = SampledSpectrum::zero();
    if let Some(rr) = reradiation_at(scene, pt) {
        // Evaluated at the camera-side endpoint: light at λ_l arrives, the camera subpath
        // arrived there with λ_ca.
        let arrive = camera_path[t - 2].wavelengths(pair).lambda;
        let before = before_event(rr, pt, &arrive, &lam_c.lambda, Direction::Camera);
        let f_q = qs.f(scene, pt, &lam_l, Importance);
        let f_p = pt.f(scene, qs, &lam_c, Radiance);
        for k in 0..LANES {
            let e = evaluated_event(rr, lam_l.lambda[k], arrive[k], lines) as f32;
            c[k] = qs.beta[k] * f_q[k] * f_p[k] * e * before[k];
        }
    } else if let Some(rr) = reradiation_at(scene, qs) {
        // Evaluated at the light-side endpoint: the light subpath arrived there with λ_la,
        // the camera subpath carries λ_c.
        let arrive = light_path[s - 2].wavelengths(&mode.lambda).lambda;
        let before = before_event(rr, qs, &arrive, &lam_l.lambda, Direction::Light);
        let f_q = qs.f(scene, pt, &lam_l, Importance);
        let f_p = pt.f(scene, qs, &lam_c, Radiance);
        for k in 0..LANES {
            let e = evaluated_event(rr, arrive[k], lam_c.lambda[k], lines) as f32;
            c[k] = before[k] * e * f_q[k] * f_p[k] * pt.beta[k];
        }
    } else {
        // No fluorescent endpoint: only lanes on the same delta line join.
        let f_q = qs.f(scene, pt, &lam_c, Importance);
        let f_p = pt.f(scene, qs, &lam_c, Radiance);
        for k in 0..LANES {
            let l = lam_c.lambda[k];
            if lam_l.lambda[k] == l && is_line_lane(lines, l) {
                c[k] = qs.beta[k] * f_q[k] * f_p[k] * pt.beta[k];
            }
        }
    }
    let own = 1.0 - mode.alpha as f64;
    for k in 0..LANES {
        let p = own * mode.lambda.pdf[k] as f64;
        c[k] = if p > 0.0 && c[k] != 0.0 {
            (c[k] as f64 * g as f64 / p) as f32
        } else {
            0.0
        };
    }
    if c.is_black() || c.has_non_finite() {
        return None;
    }
    stats.shadow_rays += 1;
    if !unoccluded(scene, qs, pt) {
        return None;
    }
    Some(c)
}

/// What the film weighs a t = 1 splat of light vertex `q` with: the wavelengths that reach the
/// camera, each divided by its lane's start density over both modes,
/// α·p_mix(λ) + (1 − α)·p_L(λ | light) (a line lane gets the discrete probabilities of both).
pub fn t1_wavelengths(mode: &LightMode, q: &Vertex) -> SampledWavelengths {
    let mut w = q.wavelengths(&mode.lambda);
    let a = mode.alpha as f64;
    for k in 0..LANES {
        w.pdf[k] = (a * mode.start_mix_pdf[k] + (1.0 - a) * mode.start_light_pdf[k]) as f32;
    }
    w
}
