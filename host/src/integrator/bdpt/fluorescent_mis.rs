//! bdpt's MIS weights in a scene that renders fluorescence: per lane, because each lane of a
//! subpath keeps or shifts its wavelength on its own at a fluorescent vertex (as in pt and lt,
//! [`crate::integrator::fluorescence::events`]), so the lanes of one connection are different paths in the
//! wavelength-extended path space.
//!
//! A lane path x₀ … x_{n−1} (light to camera) carries a wavelength on each edge; at a
//! fluorescent vertex it keeps it or lengthens it. The density of a strategy for lane k is
//! the product of
//! - the area densities of its vertices, each from the subpath that makes it (as without
//!   fluorescence),
//! - at every fluorescent vertex, the probability of its event (keep, or shift λᵢ → λₒ with
//!   the density of the new wavelength) for the subpath that makes the vertex: the camera's
//!   excitation draw (with its line/continuous mixture) or the light's emission draw. Each
//!   vertex stores both ([`Vertex::choice`] for its own subpath, [`Vertex::choice_rev`] for
//!   the other); at a vertex whose event a connection evaluated (below) both are computed
//!   afresh ([`event_probability`]) for the wavelengths the lane path has there,
//! - the density of the wavelengths the strategy drew at its ends (the pair's mode, see
//!   [`crate::integrator::fluorescence::join`]):
//!   - s = 0, s = 1: the pair's mixture density p_mix(λ_obs) at the observed wavelength;
//!   - t = 1: α·p_mix(λ_emit) + (1 − α)·p_L(λ_emit | light of x₀), both modes together;
//!   - s ≥ 2, t ≥ 2, shared mode: α·p_mix(λ_obs), only for lanes that never shift
//!     (λ_emit = λ_obs: both subpaths start at the pair's wavelength);
//!   - s ≥ 2, t ≥ 2, own mode: (1 − α)·p_mix(λ_obs)·p_L(λ_emit | light), without the event
//!     probability of the evaluated vertex (x_s if fluorescent, else x_{s−1} if fluorescent),
//!     only where that evaluation can be non-zero
//!     ([`crate::integrator::fluorescence::join::evaluated_event_possible`]); with no fluorescent endpoint
//!     only for a lane on a delta line at the connection (discrete × discrete).
//!
//! The area parts are the same for every lane; they are taken relative to this strategy's as
//! in [`super::mis::mis_weight`] (the same overrides of the densities at the joined vertices,
//! the same scale of the light-tracing strategy's density,
//! [`super::mis::LIGHT_TRACING_MIS_SCALE`]). The event parts are products over the vertices
//! (prefix products on the light side, suffix products on the camera side), so an event
//! probability of 0 on one side needs no division.
//!
//! The direction densities (and so the area parts) are assumed equal across lanes: every
//! material's direction sampling in bdpt is wavelength-independent except a dispersive
//! event's, after which only the hero lane is left (`Vertex::lanes`), and a fluorescent
//! surface samples the cosine lobe whatever the wavelength.

use super::mis::{
    heuristic_scale, mis_weight_overrides, nee_correction, s1_guide_factor, Overrides, SampleCounts,
};
use crate::camera::Camera;
use crate::integrator::fluorescence::events::{event_probability, Direction};
use crate::integrator::fluorescence::join::{evaluated_event_possible, reradiation_at, LightMode};
use crate::integrator::nee_guide::NeeGuide;
use crate::integrator::subpath::vertex::{remap0, Vertex};
use crate::integrator::wavelengths::mixture::WavelengthMixture;
use crate::scene::Scene;
use crate::spectrum::spd::is_line_lane;
use crate::spectrum::{DeltaLine, LaneMask, SampledSpectrum, SampledWavelengths, LANES};

#[cfg(test)]
thread_local! {
    /// Tests only: leave one factor out of this strategy's own density while the other
    /// strategies' keep it, to show the sum-to-one test sees the inconsistency (1: the mode
    /// probability α or 1 − α, 2: the light's own wavelength density p_L, 3: the observed
    /// wavelength's density in the own mode).
    pub static DROP_FACTOR: std::cell::Cell<u8> = const { std::cell::Cell::new(0) };
}

/// Per-lane power-heuristic weight of strategy (s, t) for the lane paths it produced, relative
/// to every strategy that can make the same lane path (module docs). `sampled` as for
/// [`super::mis::mis_weight`]; `lambda` is the pair's wavelengths, `mode` how the light
/// subpath started. Only the lanes in `need` are weighed (the others get 0: the connection
/// gives them nothing).
#[allow(clippy::too_many_arguments)]
pub fn mis_weight_lanes(
    scene: &Scene,
    camera: &dyn Camera,
    mixture: &WavelengthMixture,
    (light_path, camera_path): (&[Vertex], &[Vertex]),
    sampled: Option<&Vertex>,
    (s, t): (usize, usize),
    lambda: &SampledWavelengths,
    mode: &LightMode,
    need: LaneMask,
    counts: SampleCounts,
    guide: Option<&NeeGuide>,
) -> SampledSpectrum {
    let path = Joined {
        o: mis_weight_overrides(
            scene,
            camera,
            light_path,
            camera_path,
            sampled,
            s,
            t,
            lambda,
        ),
        light_path,
        camera_path,
        s,
        t,
        guide,
    };
    let n = s + t;
    let own_mode = mode.own && s >= 2 && t >= 2;
    SCRATCH.with(|scratch| {
        let mut guard = scratch.borrow_mut();
        let sc = &mut *guard;
        sc.reset(n);
        sc.area_ratios(scene, &path);
        sc.lane_wavelengths(scene, &path, lambda, &mode.lambda, own_mode);
        let lines = scene.lights.delta_lines();
        sc.event_products(scene, &path, own_mode, lines);
        let li = path.x(0).light_index(scene).unwrap_or(u32::MAX);
        let mut out = SampledSpectrum::zero();
        let mut pair_light: Option<[f64; LANES]> = None;
        for k in 0..LANES {
            if !need.contains(k) {
                continue;
            }
            let lane = Lane::new(sc, (mixture, mode, lambda, lines), k, li, &mut pair_light);
            out[k] = lane.weight(s, own_mode, counts);
        }
        out
    })
}

/// The path of strategy (s, t) as the weights see it: its vertices x₀ … x_{n−1} (light to
/// camera) with the copies of the joined vertices and the densities the connection gives them.
struct Joined<'a> {
    o: Overrides,
    light_path: &'a [Vertex],
    camera_path: &'a [Vertex],
    s: usize,
    t: usize,
    /// The visibility guide of the s = 1 strategy's light points, if any.
    guide: Option<&'a NeeGuide>,
}

impl Joined<'_> {
    /// Path vertex x_i, with the copies of the joined vertices.
    #[inline]
    fn x(&self, i: usize) -> &Vertex {
        let (s, n) = (self.s, self.s + self.t);
        if i < s {
            match (&self.o.qs, i + 1 == s) {
                (Some(q), true) => q,
                _ => &self.light_path[i],
            }
        } else {
            let j = n - 1 - i;
            if j + 1 == self.t {
                &self.o.pt
            } else {
                &self.camera_path[j]
            }
        }
    }

    /// (pdf_fwd, pdf_rev, delta) of camera vertex i after the overrides.
    #[inline]
    fn cam(&self, i: usize) -> (f32, f32, bool) {
        if i + 1 == self.t {
            (self.o.pt.pdf_fwd, self.o.pt_rev, false)
        } else {
            let v = &self.camera_path[i];
            let rev = if i + 2 == self.t {
                self.o.pt_minus_rev.unwrap_or(v.pdf_rev)
            } else {
                v.pdf_rev
            };
            (v.pdf_fwd, rev, v.delta)
        }
    }

    /// (pdf_fwd, pdf_rev, delta) of light vertex i after the overrides.
    #[inline]
    fn light(&self, i: usize) -> (f32, f32, bool) {
        let v = self.x(i);
        if i + 1 == self.s {
            (v.pdf_fwd, self.o.qs_rev.unwrap_or(v.pdf_rev), false)
        } else if i + 2 == self.s {
            (v.pdf_fwd, self.o.qs_minus_rev.unwrap_or(v.pdf_rev), v.delta)
        } else {
            (v.pdf_fwd, v.pdf_rev, v.delta)
        }
    }
}

fn sq(x: f64) -> f64 {
    x * x
}

impl Scratch {
    /// Squared area-density ratio of the split with s' light vertices to this one's, and
    /// whether that split is a strategy at all (no delta vertex at its connection).
    #[inline]
    fn area_ratios(&mut self, scene: &Scene, path: &Joined<'_>) {
        let (s, t) = (path.s, path.t);
        let n = s + t;
        let area = &mut self.area;
        area[s] = (1.0, true);
        let mut r = 1.0f64;
        for i in (1..t).rev() {
            let (fwd, rev, delta) = path.cam(i);
            r *= sq(remap0(rev) as f64 / remap0(fwd) as f64);
            area[n - i] = (r, !delta && !path.cam(i - 1).2);
        }
        r = 1.0;
        for i in (0..s).rev() {
            let (fwd, rev, delta) = path.light(i);
            r *= sq(remap0(rev) as f64 / remap0(fwd) as f64);
            let delta_before = if i > 0 {
                path.light(i - 1).2
            } else {
                path.x(0).is_unhittable_light(scene)
            };
            area[i] = (r, !delta && !delta_before);
        }
        if n >= 3 {
            // Split 1 (with t' ≥ 2) is next-event estimation, with its own density of x₀
            // (`nee_correction`); relative to this strategy's, so for s = 1 every other split
            // takes the inverse factor.
            let origin = if s == 0 {
                path.o.pt_rev
            } else {
                path.x(0).pdf_fwd
            };
            let mut nee = nee_correction(scene, path.x(0), path.x(1), origin) as f64;
            if let Some(g) = path.guide {
                // The guide's factor of x₀ drawn from x₁ (`mis::s1_guide_factor`).
                let f = s1_guide_factor(g, scene, path.x(0), path.x(1), path.x(2)) as f64;
                nee *= f * f;
            }
            if nee > 0.0 {
                area[1].0 *= nee;
                if s == 1 {
                    area.iter_mut().for_each(|a| a.0 /= nee);
                }
            }
        }
    }

    /// Which vertices fluoresce, and the lane wavelengths on each edge x_e — x_{e+1}: the light
    /// subpath's below the connection, the camera subpath's above it; on the connection edge
    /// the light side's for t = 1 and where the own mode evaluated the camera-side endpoint,
    /// else the camera side's.
    #[inline]
    fn lane_wavelengths(
        &mut self,
        scene: &Scene,
        path: &Joined<'_>,
        lambda: &SampledWavelengths,
        base: &SampledWavelengths,
        own_mode: bool,
    ) {
        let (s, t) = (path.s, path.t);
        let n = s + t;
        for (i, f) in self.fluorescent.iter_mut().enumerate() {
            *f = i > 0 && i < n - 1 && reradiation_at(scene, path.x(i)).is_some();
        }
        let fluorescent = &self.fluorescent;
        for (e, w) in self.seg.iter_mut().enumerate() {
            let light_side = e + 1 < s || (e + 1 == s && (t == 1 || (own_mode && fluorescent[s])));
            *w = if light_side {
                path.x(e).wavelengths(base).lambda
            } else {
                path.x(e + 1).wavelengths(lambda).lambda
            };
        }
    }

    /// The vertex whose event the own mode evaluates at split sp.
    #[inline]
    fn evaluated(&self, sp: usize) -> Option<usize> {
        if self.fluorescent[sp] {
            Some(sp)
        } else if self.fluorescent[sp - 1] {
            Some(sp - 1)
        } else {
            None
        }
    }

    /// Event probabilities of x_i made from the light side (el) and the camera side (ec), then
    /// the prefix products of the light side's and the suffix products of the camera side's:
    /// the event part of split s' is pl[s']·sc[s'].
    #[inline]
    fn event_products(
        &mut self,
        scene: &Scene,
        path: &Joined<'_>,
        own_mode: bool,
        lines: &[DeltaLine],
    ) {
        let s = path.s;
        let n = s + path.t;
        let own_eval = if own_mode { self.evaluated(s) } else { None };
        for i in 1..n.saturating_sub(1) {
            if !self.fluorescent[i] {
                continue;
            }
            let v = path.x(i);
            if own_eval == Some(i) {
                if let Some(rri) = reradiation_at(scene, v) {
                    for k in 0..LANES {
                        let (a, b) = (self.seg[i - 1][k], self.seg[i][k]);
                        self.el[i][k] = event_probability(rri, a, b, Direction::Light, lines);
                        self.ec[i][k] = event_probability(rri, b, a, Direction::Camera, lines);
                    }
                }
            } else {
                for k in 0..LANES {
                    let (own, other) = (v.choice[k] as f64, v.choice_rev[k] as f64);
                    (self.el[i][k], self.ec[i][k]) =
                        if i < s { (own, other) } else { (other, own) };
                }
            }
        }
        for j in 1..=n {
            for k in 0..LANES {
                self.pl[j][k] = self.pl[j - 1][k] * self.el[j - 1][k];
            }
        }
        for j in (0..n).rev() {
            for k in 0..LANES {
                self.sc[j][k] = self.sc[j + 1][k] * self.ec[j][k];
            }
        }
    }
}

/// One lane's densities of every split, without the area parts (module docs).
struct Lane<'a> {
    sc: &'a Scratch,
    lines: &'a [DeltaLine],
    k: usize,
    alpha: f64,
    /// The observed and the emitted wavelength.
    obs: f32,
    emit: f32,
    /// Density of the observed wavelength (the pair's mixture).
    p_obs: f64,
    /// Density of the emitted wavelength by light tracing, over both modes.
    p_t1: f64,
    /// The own mode's end densities.
    p_own_ends: f64,
    /// The light's own wavelength density at the emitted wavelength (tests only).
    #[cfg_attr(not(test), allow(dead_code))]
    p_light: f64,
    /// The pair's mixture density at the emitted wavelength (tests only).
    #[cfg_attr(not(test), allow(dead_code))]
    p_emit: f64,
}

impl<'a> Lane<'a> {
    /// The end densities of lane `k` of a path that starts on light `li`, from what the pair
    /// and the mode already hold where the wavelength is theirs.
    #[inline]
    fn new(
        sc: &'a Scratch,
        (mixture, mode, lambda, lines): (
            &WavelengthMixture,
            &LightMode,
            &SampledWavelengths,
            &'a [DeltaLine],
        ),
        k: usize,
        li: u32,
        pair_light: &mut Option<[f64; LANES]>,
    ) -> Self {
        let n = sc.seg.len() + 1;
        let base = &mode.lambda;
        let (obs, emit) = (sc.seg[n - 2][k], sc.seg[0][k]);
        let p_obs = if obs == lambda.lambda[k] {
            lambda.pdf[k] as f64
        } else if obs == base.lambda[k] {
            mode.start_mix_pdf[k]
        } else {
            mixture.lane_density(obs)
        };
        let (p_emit, p_light) = if emit == base.lambda[k] && li == mode.start_light {
            (mode.start_mix_pdf[k], mode.start_light_pdf[k])
        } else if emit == lambda.lambda[k] && li != u32::MAX {
            let p = *pair_light.get_or_insert_with(|| mode.pair_light_pdf(mixture, li, lambda));
            (lambda.pdf[k] as f64, p[k])
        } else {
            (
                mixture.lane_density(emit),
                mixture.light_lane_density(li as usize, emit),
            )
        };
        let alpha = mode.alpha as f64;
        Lane {
            sc,
            lines,
            k,
            alpha,
            obs,
            emit,
            p_obs,
            p_t1: alpha * p_emit + (1.0 - alpha) * p_light,
            p_own_ends: (1.0 - alpha) * p_obs * p_light,
            p_light,
            p_emit,
        }
    }

    /// Density (without the area part) of split sp, shared (false) or own (true) mode.
    #[inline]
    fn density(&self, sp: usize, own: bool) -> f64 {
        let (sc, k) = (self.sc, self.k);
        let n = sc.seg.len() + 1;
        let tp = n - sp;
        let events = sc.pl[sp][k] * sc.sc[sp][k];
        if tp == 1 {
            events * self.p_t1
        } else if sp <= 1 {
            if own {
                0.0
            } else {
                events * self.p_obs
            }
        } else if !own {
            if self.emit == self.obs {
                events * self.alpha * self.p_obs
            } else {
                0.0
            }
        } else {
            match sc.evaluated(sp) {
                Some(v) if evaluated_event_possible(sc.seg[v - 1][k], sc.seg[v][k], self.lines) => {
                    let events = if v == sp {
                        sc.pl[sp][k] * sc.sc[sp + 1][k]
                    } else {
                        sc.pl[sp - 1][k] * sc.sc[sp][k]
                    };
                    events * self.p_own_ends
                }
                Some(_) => 0.0,
                None if is_line_lane(self.lines, sc.seg[sp - 1][k]) => events * self.p_own_ends,
                None => 0.0,
            }
        }
    }

    /// The weight of split s (own mode or not) against every split and mode that can make
    /// this lane path, with the area parts.
    #[inline]
    fn weight(&self, s: usize, own_mode: bool, counts: SampleCounts) -> f32 {
        let n = self.sc.seg.len() + 1;
        let t = n - s;
        #[allow(unused_mut)]
        let mut own_density = self.density(s, own_mode);
        #[cfg(test)]
        {
            let alpha = self.alpha;
            let joined = s >= 2 && t >= 2;
            own_density /= match DROP_FACTOR.with(|d| d.get()) {
                1 if joined && own_mode => 1.0 - alpha,
                1 if joined => alpha,
                2 if own_mode => self.p_light,
                2 if t == 1 => self.p_t1 / (alpha * self.p_emit),
                3 if own_mode => self.p_obs,
                _ => 1.0,
            };
        }
        if !(own_density > 0.0) {
            return 0.0;
        }
        let mut sum = 0.0f64;
        for (sp, &(ratio, ok)) in self.sc.area.iter().enumerate() {
            if !ok {
                continue;
            }
            let tp = n - sp;
            let modes: &[bool] = if sp >= 2 && tp >= 2 {
                &[false, true]
            } else {
                &[false]
            };
            for &m in modes {
                let d = self.density(sp, m);
                if d > 0.0 {
                    sum += ratio * sq(d / own_density) * heuristic_scale(sp, tp, counts) as f64;
                }
            }
        }
        let w = heuristic_scale(s, t, counts) as f64 / sum;
        if w.is_finite() {
            w as f32
        } else {
            0.0
        }
    }
}

/// Per-thread buffers of [`mis_weight_lanes`], sized to the path (no allocation per call once
/// they have grown).
#[derive(Default)]
struct Scratch {
    /// Per split s': the squared area-density ratio to this strategy's, and whether s' is a
    /// strategy.
    area: Vec<(f64, bool)>,
    /// Per vertex: a fluorescent surface (not the path's ends).
    fluorescent: Vec<bool>,
    /// Per edge: the lane wavelengths (nm).
    seg: Vec<[f32; LANES]>,
    /// Per vertex: event probabilities from the light side and from the camera side.
    el: Vec<[f64; LANES]>,
    ec: Vec<[f64; LANES]>,
    /// Prefix products of `el`, suffix products of `ec` (n + 1 entries).
    pl: Vec<[f64; LANES]>,
    sc: Vec<[f64; LANES]>,
}

impl Scratch {
    fn reset(&mut self, n: usize) {
        self.area.clear();
        self.area.resize(n, (0.0, false));
        self.fluorescent.clear();
        self.fluorescent.resize(n, false);
        self.seg.clear();
        self.seg.resize(n - 1, [0.0; LANES]);
        for v in [&mut self.el, &mut self.ec] {
            v.clear();
            v.resize(n, [1.0; LANES]);
        }
        for v in [&mut self.pl, &mut self.sc] {
            v.clear();
            v.resize(n + 1, [1.0; LANES]);
        }
    }
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CameraSample;
    use crate::integrator::fluorescence::events::{event_probability, Direction};
    use crate::integrator::fluorescence::join::LightMode;
    use crate::integrator::subpath::random_walk::generate_camera_subpath;
    use crate::integrator::subpath::vertex::VertexKind;
    use crate::integrator::{PathStats, SampleRng};
    use crate::material::TransportMode;
    use crate::scene::{build_scene, parse_scene_str, BuiltinFactory};
    use glam::Vec2;
    use std::path::Path;

    /// Two fluorescent walls (parametric model: UV/blue absorbed, re-emitted around 520 and
    /// 600 nm) in a corner, a large D65 panel and a large panel emitting only the 365 nm
    /// mercury line, so camera paths hit both lamps and excitation draws land on the line.
    const SCENE: &str = r#"(
        materials: [
            (name: "a", type: "fluorescent",
             params: (reflectance: 0.4, absorption: [(300, 0), (320, 0.6), (470, 0.6), (480, 0)],
                      emission: "gaussian:520:30", quantum_yield: 0.8)),
            (name: "b", type: "fluorescent",
             params: (reflectance: 0.4, absorption: [(340, 0), (350, 0.5), (540, 0.5), (550, 0)],
                      emission: "gaussian:600:40", quantum_yield: 0.9)),
            (name: "sky", type: "emissive", params: (radiance: "d65", scale: 5)),
            (name: "uv", type: "emissive", params: (radiance: "line:365", scale: 5)),
        ],
        objects: [
            (name: "floor", type: "quad", material: "a",
             params: (corner: (-2, -1, -4), edge0: (4, 0, 0), edge1: (0, 0, 4))),
            (name: "back", type: "quad", material: "b",
             params: (corner: (-2, -1, -3), edge0: (4, 0, 0), edge1: (0, 3, 0))),
            (name: "sky", type: "quad", material: "sky",
             params: (corner: (-2, 1.5, -3), edge0: (2, 0, 0), edge1: (0, 0, 4))),
            (name: "uv", type: "quad", material: "uv",
             params: (corner: (0, 1.5, -3), edge0: (2, 0, 0), edge1: (0, 0, 4))),
        ],
        cameras: [ (name: "c", type: "perspective",
             params: (position: (0, 0, 1), look_at: (0, -0.5, -2), fov: 60, resolution: (8, 8))) ],
    )"#;

    /// Sum to one, per lane: for camera subpaths traced in [`SCENE`] up to the vertex where
    /// they hit a lamp (x₀ … x_{n−1} from the lamp to the lens, n ≤ 6), the subpaths of every
    /// split (s, t), s + t = n, are rebuilt independently from the vertices alone (area
    /// densities from the materials and lights in both directions; at each fluorescent vertex
    /// both ends' event probabilities from the lane's wavelengths on either side, via
    /// [`event_probability`]; the pair wavelengths and their mixture densities at the end
    /// each strategy starts from), and [`mis_weight_lanes`] of every strategy that can make
    /// the lane path — all of them for a lane that never shifted, s ≤ 1 and t = 1 for a lane
    /// that did, those whose start wavelength has mixture density 0 left out — must sum to 1.
    /// Inconsistent densities (an event probability missing on one side, the end densities
    /// on the wrong strategies, a strategy counted that cannot make the path) break the sum.
    /// The walk's recorded probabilities (of its own choice and of the other end's) must equal
    /// the fresh evaluation within 1e-4 relative (f32 storage of f64 densities).
    /// Tolerance 2e-3 relative: f32 products of up to 6 density ratios squared. The counts of
    /// shifted lanes and of lanes on the line are asserted so the test exercises both.
    #[test]
    fn weights_of_every_strategy_sum_to_one_per_lane() {
        let r = sum_over_strategies(20_000, true);
        println!(
            "{} paths, {} shifted lanes, {} on the line, {} own-mode joins ({} through a shift); \
             worst |Σw − 1| = {:.2e}",
            r.paths, r.shifted_lanes, r.line_lanes, r.own_joins, r.own_shifted, r.worst
        );
        assert!(r.worst < 2e-3, "worst |Σw − 1| = {}", r.worst);
        assert!(
            r.paths > 1000
                && r.shifted_lanes > 200
                && r.line_lanes > 20
                && r.own_joins > 1000
                && r.own_shifted > 200,
            "{r:?}"
        );
        // Each factor of the densities matters: left out of one strategy's own density while
        // the others keep it, the sums leave 1 by far more than the tolerance. (Left out of
        // every strategy alike, a factor changes only the variance: the power heuristic sums
        // to one for any densities used consistently.)
        for (drop, what) in [(1, "α"), (2, "p_L"), (3, "p_mix(λ_obs) in the own mode")] {
            DROP_FACTOR.with(|d| d.set(drop));
            let r = sum_over_strategies(4_000, false);
            DROP_FACTOR.with(|d| d.set(0));
            println!("without {what}: worst |Σw − 1| = {:.3}", r.worst);
            assert!(r.worst > 0.05, "dropping {what} went unseen: {}", r.worst);
        }
    }

    /// What [`sum_over_strategies`] saw.
    #[derive(Debug, Default)]
    struct Sums {
        paths: usize,
        shifted_lanes: usize,
        line_lanes: usize,
        own_joins: usize,
        own_shifted: usize,
        worst: f64,
    }

    /// α of the test (not ½, so that a density that mixes up α and 1 − α shows).
    const ALPHA: f32 = 0.3;

    /// The body of [`weights_of_every_strategy_sum_to_one_per_lane`] over `count` camera
    /// samples; `strict` asserts each lane's sum and the walk's records.
    fn sum_over_strategies(count: u64, strict: bool) -> Sums {
        let file = Path::new("mis-test.ron");
        let desc = parse_scene_str(SCENE, file).unwrap();
        let scene = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap();
        assert!(scene.objects.fluorescence());
        let mixture = WavelengthMixture::new(&scene);
        assert_eq!(scene.lights.delta_lines().len(), 1);
        let mut sums = Sums::default();
        let mut path = Vec::new();
        let mut stats = PathStats::default();
        for k in 0..count {
            let Some(lp) = LampPath::trace(&scene, &mixture, k, &mut path, &mut stats) else {
                continue;
            };
            sums.paths += 1;
            if strict {
                lp.check_records();
            }
            let sum = lp.sum_of_weights(&mut sums);
            lp.tally(&sum, strict, &mut sums);
        }
        sums
    }

    /// A camera subpath traced up to the vertex where it hits a lamp, read from the lamp:
    /// x₀ … x_{n−1}, with the lane wavelengths on each edge.
    struct LampPath<'a> {
        scene: &'a Scene,
        mixture: &'a WavelengthMixture,
        camera: &'a dyn crate::camera::Camera,
        lines: &'a [crate::spectrum::DeltaLine],
        lambda: SampledWavelengths,
        /// x_i = path[j − i].
        x: Vec<Vertex>,
        /// seg[i] = the lane wavelengths between x_i and x_{i+1}.
        seg: Vec<[f32; LANES]>,
        /// The lanes the camera subpath still carries at the lamp.
        live: [bool; LANES],
        /// The lamp's light index and x₀ as a light vertex.
        li: u32,
        x0_light: Vertex,
    }

    impl<'a> LampPath<'a> {
        /// Camera sample `k` of the test's 8×8 image, if its subpath reaches a lamp after two
        /// or more bounces.
        fn trace(
            scene: &'a Scene,
            mixture: &'a WavelengthMixture,
            k: u64,
            path: &mut Vec<Vertex>,
            stats: &mut PathStats,
        ) -> Option<Self> {
            let camera = scene.cameras.get(None).unwrap().camera.as_ref();
            let mut rng = SampleRng::for_sample(11, k, 0);
            let lambda = mixture.sample(&mut rng);
            let u = rng.next_2d();
            let cs = CameraSample {
                p_film: Vec2::new(8.0 * u.x, 8.0 * u.y),
                p_lens: rng.next_2d(),
            };
            let cray = camera.generate_ray(&cs).unwrap();
            generate_camera_subpath(
                scene,
                camera,
                cray.ray,
                cray.weight,
                &lambda,
                &mut rng,
                6,
                99,
                path,
                stats,
            );
            let j = (1..path.len()).find(|&m| path[m].light_index(scene).is_some())?;
            if j < 2 {
                return None;
            }
            let n = j + 1;
            let x: Vec<Vertex> = (0..n).map(|i| path[j - i]).collect();
            let seg = (0..n - 1)
                .map(|i| path[j - i - 1].wavelengths(&lambda).lambda)
                .collect();
            let li = x[0].light_index(scene).unwrap();
            let mut x0_light = Vertex::light(li, x[0].p, x[0].p_error, x[0].ng, x[0].beta);
            x0_light.uv = x[0].uv;
            Some(LampPath {
                scene,
                mixture,
                camera,
                lines: scene.lights.delta_lines(),
                lambda,
                live: std::array::from_fn(|k| path[j].beta[k] > 0.0),
                x,
                seg,
                li,
                x0_light,
            })
        }

        fn n(&self) -> usize {
            self.x.len()
        }

        /// Both ends' probabilities of the event at x_i (1 where nothing fluoresces).
        fn events(&self, i: usize) -> ([f32; LANES], [f32; LANES]) {
            let (mut l, mut c) = ([1.0; LANES], [1.0; LANES]);
            if let VertexKind::Surface { object } = self.x[i].kind {
                if let Some(rr) = self.scene.objects.reradiation(object) {
                    for k in 0..LANES {
                        let (a, b) = (self.seg[i - 1][k], self.seg[i][k]);
                        l[k] = event_probability(rr, a, b, Direction::Light, self.lines) as f32;
                        c[k] = event_probability(rr, b, a, Direction::Camera, self.lines) as f32;
                    }
                }
            }
            (l, c)
        }

        /// The walk's own record of each choice is the density evaluated afresh (the draw
        /// and `event_probability` agree), and so is its record of the light side's.
        fn check_records(&self) {
            let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * a.abs().max(b.abs());
            for i in 1..self.n() - 1 {
                let (l, c) = self.events(i);
                for k in (0..LANES).filter(|&k| self.live[k]) {
                    let v = &self.x[i];
                    assert!(close(v.choice[k], c[k]), "own {} vs {}", v.choice[k], c[k]);
                    assert!(
                        close(v.choice_rev[k], l[k]),
                        "other {} vs {}",
                        v.choice_rev[k],
                        l[k]
                    );
                }
            }
        }

        /// The lanes whose wavelength changes at x_i.
        fn moved_at(&self, i: usize) -> LaneMask {
            (0..LANES)
                .filter(|&k| self.seg[i - 1][k] != self.seg[i][k])
                .fold(LaneMask::NONE, |m, k| m.with(k))
        }

        fn moved_all(&self) -> LaneMask {
            (1..self.n() - 1).fold(LaneMask::NONE, |m, i| m.union(self.moved_at(i)))
        }

        /// Density of x_i from the light side.
        fn density_from_light(&self, i: usize) -> f32 {
            let x = &self.x;
            match i {
                0 => self.x0_light.pdf_light_origin(self.scene, &x[1]),
                1 => self.x0_light.pdf_light(self.scene, &x[1]),
                _ => x[i - 1].pdf(
                    self.scene,
                    self.camera,
                    Some(&x[i - 2]),
                    &x[i],
                    &self.lambda,
                    TransportMode::Importance,
                ),
            }
        }

        /// Density of x_i from the camera side.
        fn density_from_camera(&self, i: usize) -> f32 {
            let (x, n) = (&self.x, self.n());
            if i == n - 1 {
                0.0
            } else if i == n - 2 {
                x[n - 1].pdf(
                    self.scene,
                    self.camera,
                    None,
                    &x[i],
                    &self.lambda,
                    TransportMode::Radiance,
                )
            } else {
                x[i + 1].pdf(
                    self.scene,
                    self.camera,
                    Some(&x[i + 2]),
                    &x[i],
                    &self.lambda,
                    TransportMode::Radiance,
                )
            }
        }

        /// Wavelengths `l` as a pair drawn from the mixture.
        fn pair_at(&self, l: [f32; LANES]) -> SampledWavelengths {
            SampledWavelengths {
                lambda: l,
                pdf: std::array::from_fn(|k| self.mixture.lane_density(l[k]) as f32),
                lanes: LaneMask::ALL,
            }
        }

        /// The light subpath's own draw at the emitted wavelengths (the own mode).
        fn light_own(&self) -> SampledWavelengths {
            SampledWavelengths {
                lambda: self.seg[0],
                pdf: std::array::from_fn(|k| {
                    self.mixture
                        .light_lane_density(self.li as usize, self.seg[0][k])
                        as f32
                }),
                lanes: LaneMask::ALL,
            }
        }

        fn fluorescent(&self, i: usize) -> bool {
            matches!(self.x[i].kind, VertexKind::Surface { object }
                if self.scene.objects.reradiation(object).is_some())
        }

        fn is_line(&self, l: f32) -> bool {
            self.lines.iter().any(|d| d.lambda as f32 == l)
        }

        /// The light subpath x_0 … x_{s−1} of split s, rebuilt from the vertices alone, for a
        /// light subpath that started at `start`.
        fn light_subpath(&self, s: usize, start: &SampledWavelengths) -> Vec<Vertex> {
            (0..s)
                .map(|i| {
                    let mut v = if i == 0 { self.x0_light } else { self.x[i] };
                    v.pdf_fwd = self.density_from_light(i);
                    v.pdf_rev = self.density_from_camera(i);
                    v.moved = (1..=i).fold(LaneMask::NONE, |m, a| m.union(self.moved_at(a)));
                    if i > 0 {
                        (v.choice, v.choice_rev) = self.events(i);
                    }
                    v.shifted = (self.seg[i] != start.lambda).then_some(self.seg[i]);
                    v
                })
                .collect()
        }

        /// The camera subpath x_{n−1} … x_s of split s, for a pair at `pair`.
        fn camera_subpath(&self, s: usize, pair: &SampledWavelengths) -> Vec<Vertex> {
            let n = self.n();
            (s..n)
                .rev()
                .map(|i| {
                    let mut v = self.x[i];
                    v.pdf_fwd = self.density_from_camera(i);
                    v.pdf_rev = if i == 0 {
                        0.0
                    } else {
                        self.density_from_light(i)
                    };
                    v.moved =
                        (i.max(1)..n - 1).fold(LaneMask::NONE, |m, a| m.union(self.moved_at(a)));
                    if i > 0 && i < n - 1 {
                        (v.choice_rev, v.choice) = self.events(i);
                    }
                    let after = if i == 0 { self.seg[0] } else { self.seg[i - 1] };
                    v.shifted = (after != pair.lambda).then_some(after);
                    v
                })
                .collect()
        }

        /// The weights of split s in mode `own`, from the rebuilt subpaths.
        fn weights(&self, s: usize, own: bool) -> SampledSpectrum {
            let n = self.n();
            let t = n - s;
            let (obs, emit) = (self.pair_at(self.seg[n - 2]), self.pair_at(self.seg[0]));
            // The pair: the observed wavelengths, except for t = 1 in the shared mode, whose
            // light subpath started at the pair's (emitted) wavelengths.
            let pair = if t == 1 && !own { emit } else { obs };
            let start = if own { self.light_own() } else { pair };
            let light_path = self.light_subpath(s, &start);
            let camera_path = self.camera_subpath(s, &pair);
            let mode = LightMode::new(own, start, ALPHA, self.scene, self.mixture, &light_path);
            let sampled = match (s, t) {
                (1, 2..) => {
                    let mut v = self.x0_light;
                    v.pdf_fwd = self.x0_light.pdf_light_origin(self.scene, &self.x[1]);
                    Some(v)
                }
                (_, 1) => Some(self.x[n - 1]),
                _ => None,
            };
            mis_weight_lanes(
                self.scene,
                self.camera,
                self.mixture,
                (&light_path, &camera_path),
                sampled.as_ref(),
                (s, t),
                &pair,
                &mode,
                LaneMask::ALL,
                SampleCounts::every_sample(1),
                None,
            )
        }

        /// Whether split s in mode `own` can make lane k's path (module docs); counts the own
        /// mode's joins in `sums`.
        fn possible(&self, s: usize, own: bool, k: usize, sums: &mut Sums) -> bool {
            let n = self.n();
            let t = n - s;
            let obs = self.pair_at(self.seg[n - 2]);
            let light_own = self.light_own();
            let moved = self.moved_all().contains(k);
            if t == 1 {
                ALPHA as f64 * self.mixture.lane_density(self.seg[0][k])
                    + (1.0 - ALPHA as f64) * light_own.pdf[k] as f64
                    > 0.0
            } else if s <= 1 {
                obs.pdf[k] > 0.0
            } else if !own {
                !moved && obs.pdf[k] > 0.0
            } else {
                let ends = obs.pdf[k] > 0.0 && light_own.pdf[k] > 0.0;
                let v = if self.fluorescent(s) {
                    Some(s)
                } else if self.fluorescent(s - 1) {
                    Some(s - 1)
                } else {
                    None
                };
                let through = match v {
                    Some(v) => {
                        let (a, b) = (self.seg[v - 1][k], self.seg[v][k]);
                        if a == b {
                            self.is_line(a)
                        } else {
                            !self.is_line(b)
                        }
                    }
                    None => self.is_line(self.seg[s - 1][k]),
                };
                if ends && through && self.live[k] {
                    sums.own_joins += 1;
                    sums.own_shifted += (v.is_some() && moved) as usize;
                }
                ends && through
            }
        }

        /// Per lane, the sum of the weights of every split and mode that can make the path.
        /// The t = 1 strategy is one over both modes: both must give the same weight.
        fn sum_of_weights(&self, sums: &mut Sums) -> [f64; LANES] {
            let n = self.n();
            let mut sum = [0.0f64; LANES];
            for s in 0..n {
                let t = n - s;
                let modes: &[bool] = if (s >= 2 && t >= 2) || t == 1 {
                    &[false, true]
                } else {
                    &[false]
                };
                let mut t1_weight: Option<SampledSpectrum> = None;
                for &own in modes {
                    let w = self.weights(s, own);
                    if t == 1 {
                        if let Some(w0) = t1_weight {
                            for k in (0..LANES).filter(|&k| self.live[k]) {
                                let close = (w[k] - w0[k]).abs() <= 1e-5 * w0[k].max(1e-6);
                                assert!(close, "t = 1 over both modes: {} vs {}", w[k], w0[k]);
                            }
                            continue;
                        }
                        t1_weight = Some(w);
                    }
                    for k in 0..LANES {
                        if self.possible(s, own, k, sums) && self.live[k] {
                            sum[k] += w[k] as f64;
                        }
                    }
                }
            }
            sum
        }

        /// Count the lanes and check each lane's sum (`strict`), keeping the worst.
        // `k` indexes five per-lane arrays at once: an index reads clearer than a zip of five.
        #[allow(clippy::needless_range_loop)]
        fn tally(&self, sum: &[f64; LANES], strict: bool, sums: &mut Sums) {
            let n = self.n();
            let obs = self.pair_at(self.seg[n - 2]);
            let moved_all = self.moved_all();
            let line = self.lines[0].lambda as f32;
            for k in 0..LANES {
                if !self.live[k] || obs.pdf[k] == 0.0 {
                    continue;
                }
                sums.shifted_lanes += moved_all.contains(k) as usize;
                sums.line_lanes += (0..n - 1).any(|i| line == self.seg[i][k]) as usize;
                sums.worst = sums.worst.max((sum[k] - 1.0).abs());
                assert!(
                    !strict || (sum[k] - 1.0).abs() < 2e-3,
                    "path {}: lane {k} weights sum to {} (n = {n}, shifted {})",
                    sums.paths,
                    sum[k],
                    moved_all.contains(k)
                );
            }
        }
    }
}
