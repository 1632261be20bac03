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

use super::mis::{heuristic_scale, mis_weight_overrides, nee_correction};
use crate::camera::Camera;
use crate::integrator::fluorescence::events::{event_probability, Direction};
use crate::integrator::fluorescence::join::{evaluated_event_possible, reradiation_at, LightMode};
use crate::integrator::subpath::vertex::{remap0, Vertex};
use crate::integrator::wavelengths::mixture::WavelengthMixture;
use crate::scene::Scene;
use crate::spectrum::spd::is_line_lane;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};

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
    light_paths: u32,
) -> SampledSpectrum {
    let o = mis_weight_overrides(
        scene,
        camera,
        light_path,
        camera_path,
        sampled,
        s,
        t,
        lambda,
    );
    let n = s + t;
    let own_mode = mode.own && s >= 2 && t >= 2;
    let base = &mode.lambda;
    // Path vertex x_i, with the copies of the joined vertices.
    let x = |i: usize| -> &Vertex {
        if i < s {
            match (&o.qs, i + 1 == s) {
                (Some(q), true) => q,
                _ => &light_path[i],
            }
        } else {
            let j = n - 1 - i;
            if j + 1 == t {
                &o.pt
            } else {
                &camera_path[j]
            }
        }
    };
    // (pdf_fwd, pdf_rev, delta) of camera vertex i and light vertex i after the overrides.
    let cam = |i: usize| -> (f32, f32, bool) {
        if i + 1 == t {
            (o.pt.pdf_fwd, o.pt_rev, false)
        } else {
            let v = &camera_path[i];
            let rev = if i + 2 == t {
                o.pt_minus_rev.unwrap_or(v.pdf_rev)
            } else {
                v.pdf_rev
            };
            (v.pdf_fwd, rev, v.delta)
        }
    };
    let light = |i: usize| -> (f32, f32, bool) {
        let v = x(i);
        if i + 1 == s {
            (v.pdf_fwd, o.qs_rev.unwrap_or(v.pdf_rev), false)
        } else if i + 2 == s {
            (v.pdf_fwd, o.qs_minus_rev.unwrap_or(v.pdf_rev), v.delta)
        } else {
            (v.pdf_fwd, v.pdf_rev, v.delta)
        }
    };
    let sq = |x: f64| x * x;
    SCRATCH.with(|scratch| {
        let mut guard = scratch.borrow_mut();
        let sc_ = &mut *guard;
        sc_.reset(n);
        let Scratch {
            area,
            fluorescent,
            seg,
            el,
            ec,
            pl,
            sc,
        } = sc_;
        // Squared area-density ratio of the split with s' light vertices to this one's, and
        // whether that split is a strategy at all (no delta vertex at its connection).
        area[s] = (1.0, true);
        let mut r = 1.0f64;
        for i in (1..t).rev() {
            let (fwd, rev, delta) = cam(i);
            r *= sq(remap0(rev) as f64 / remap0(fwd) as f64);
            area[n - i] = (r, !delta && !cam(i - 1).2);
        }
        r = 1.0;
        for i in (0..s).rev() {
            let (fwd, rev, delta) = light(i);
            r *= sq(remap0(rev) as f64 / remap0(fwd) as f64);
            let delta_before = if i > 0 {
                light(i - 1).2
            } else {
                x(0).is_unhittable_light(scene)
            };
            area[i] = (r, !delta && !delta_before);
        }
        if n >= 3 {
            // Split 1 (with t' ≥ 2) is next-event estimation, with its own density of x₀
            // (`nee_correction`); relative to this strategy's, so for s = 1 every other split
            // takes the inverse factor.
            let origin = if s == 0 { o.pt_rev } else { x(0).pdf_fwd };
            let nee = nee_correction(scene, x(0), x(1), origin) as f64;
            if nee > 0.0 {
                area[1].0 *= nee;
                if s == 1 {
                    area.iter_mut().for_each(|a| a.0 /= nee);
                }
            }
        }
        for (i, f) in fluorescent.iter_mut().enumerate() {
            *f = i > 0 && i < n - 1 && reradiation_at(scene, x(i)).is_some();
        }
        // The lane wavelengths on each edge x_e — x_{e+1}: the light subpath's below the
        // connection, the camera subpath's above it; on the connection edge the light side's
        // for t = 1 and where the own mode evaluated the camera-side endpoint, else the
        // camera side's.
        for (e, w) in seg.iter_mut().enumerate() {
            let light_side = e + 1 < s || (e + 1 == s && (t == 1 || (own_mode && fluorescent[s])));
            *w = if light_side {
                x(e).wavelengths(base).lambda
            } else {
                x(e + 1).wavelengths(lambda).lambda
            };
        }
        let lines = scene.lights.delta_lines();
        // The vertex whose event the own mode evaluates at split sp.
        let evaluated = |sp: usize| -> Option<usize> {
            if fluorescent[sp] {
                Some(sp)
            } else if fluorescent[sp - 1] {
                Some(sp - 1)
            } else {
                None
            }
        };
        let own_eval = if own_mode { evaluated(s) } else { None };
        // Event probabilities of x_i made from the light side (el) and the camera side (ec).
        for i in 1..n.saturating_sub(1) {
            if !fluorescent[i] {
                continue;
            }
            let v = x(i);
            if own_eval == Some(i) {
                if let Some(rri) = reradiation_at(scene, v) {
                    for k in 0..LANES {
                        let (a, b) = (seg[i - 1][k], seg[i][k]);
                        el[i][k] = event_probability(rri, a, b, Direction::Light, lines);
                        ec[i][k] = event_probability(rri, b, a, Direction::Camera, lines);
                    }
                }
            } else {
                for k in 0..LANES {
                    let (own, other) = (v.choice[k] as f64, v.choice_rev[k] as f64);
                    (el[i][k], ec[i][k]) = if i < s { (own, other) } else { (other, own) };
                }
            }
        }
        // Prefix products of the light side's, suffix products of the camera side's: the
        // event part of split s' is pl[s']·sc[s'].
        for j in 1..=n {
            for k in 0..LANES {
                pl[j][k] = pl[j - 1][k] * el[j - 1][k];
            }
        }
        for j in (0..n).rev() {
            for k in 0..LANES {
                sc[j][k] = sc[j + 1][k] * ec[j][k];
            }
        }
        let alpha = mode.alpha as f64;
        let li = x(0).light_index(scene).unwrap_or(u32::MAX);
        let mut out = SampledSpectrum::zero();
        let mut pair_light: Option<[f64; LANES]> = None;
        for k in 0..LANES {
            if !need.contains(k) {
                continue;
            }
            let (obs, emit) = (seg[n - 2][k], seg[0][k]);
            // The end densities, from what the pair and the mode already hold where the
            // wavelength is theirs.
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
            let p_t1 = alpha * p_emit + (1.0 - alpha) * p_light;
            let p_own_ends = (1.0 - alpha) * p_obs * p_light;
            // Density (without the area part) of split sp, shared (false) or own (true) mode.
            let density = |sp: usize, own: bool| -> f64 {
                let tp = n - sp;
                let events = pl[sp][k] * sc[sp][k];
                if tp == 1 {
                    events * p_t1
                } else if sp <= 1 {
                    if own {
                        0.0
                    } else {
                        events * p_obs
                    }
                } else if !own {
                    if emit == obs {
                        events * alpha * p_obs
                    } else {
                        0.0
                    }
                } else {
                    match evaluated(sp) {
                        Some(v) if evaluated_event_possible(seg[v - 1][k], seg[v][k], lines) => {
                            let events = if v == sp {
                                pl[sp][k] * sc[sp + 1][k]
                            } else {
                                pl[sp - 1][k] * sc[sp][k]
                            };
                            events * p_own_ends
                        }
                        Some(_) => 0.0,
                        None if is_line_lane(lines, seg[sp - 1][k]) => events * p_own_ends,
                        None => 0.0,
                    }
                }
            };
            #[allow(unused_mut)]
            let mut own_density = density(s, own_mode);
            #[cfg(test)]
            {
                let joined = s >= 2 && t >= 2;
                own_density /= match DROP_FACTOR.with(|d| d.get()) {
                    1 if joined && own_mode => 1.0 - alpha,
                    1 if joined => alpha,
                    2 if own_mode => p_light,
                    2 if t == 1 => p_t1 / (alpha * p_emit),
                    3 if own_mode => p_obs,
                    _ => 1.0,
                };
            }
            if !(own_density > 0.0) {
                continue;
            }
            let mut sum = 0.0f64;
            for (sp, &(ratio, ok)) in area.iter().enumerate() {
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
                    let d = density(sp, m);
                    if d > 0.0 {
                        sum +=
                            ratio * sq(d / own_density) * heuristic_scale(tp, light_paths) as f64;
                    }
                }
            }
            let w = heuristic_scale(t, light_paths) as f64 / sum;
            out[k] = if w.is_finite() { w as f32 } else { 0.0 };
        }
        out
    })
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
        let cam = scene.cameras.get(None).unwrap();
        let camera = cam.camera.as_ref();
        let mixture = WavelengthMixture::new(&scene);
        let lines = scene.lights.delta_lines();
        assert_eq!(lines.len(), 1);
        let (mut paths, mut shifted_lanes, mut line_lanes, mut worst) = (0, 0, 0, 0.0f64);
        let (mut own_joins, mut own_shifted) = (0, 0);
        let mut path = Vec::new();
        let mut stats = PathStats::default();
        for k in 0..count {
            let mut rng = SampleRng::for_sample(11, k, 0);
            let lambda = mixture.sample(&mut rng);
            let u = rng.next_2d();
            let cs = CameraSample {
                p_film: Vec2::new(8.0 * u.x, 8.0 * u.y),
                p_lens: rng.next_2d(),
            };
            let cray = camera.generate_ray(&cs).unwrap();
            generate_camera_subpath(
                &scene,
                camera,
                cray.ray,
                cray.weight,
                &lambda,
                &mut rng,
                6,
                99,
                &mut path,
                &mut stats,
            );
            let Some(j) = (1..path.len()).find(|&m| path[m].light_index(&scene).is_some()) else {
                continue;
            };
            if j < 2 {
                continue;
            }
            paths += 1;
            let n = j + 1;
            // x_i = path[j − i]; seg[i] = the lane wavelengths between x_i and x_{i+1}.
            let x: Vec<Vertex> = (0..n).map(|i| path[j - i]).collect();
            let seg: Vec<[f32; LANES]> = (0..n - 1)
                .map(|i| path[j - i - 1].wavelengths(&lambda).lambda)
                .collect();
            let live = |k: usize| path[j].beta[k] > 0.0;
            // Both ends' probabilities of the event at x_i (1 where nothing fluoresces).
            let events = |i: usize| -> ([f32; LANES], [f32; LANES]) {
                let (mut l, mut c) = ([1.0; LANES], [1.0; LANES]);
                if let VertexKind::Surface { object } = x[i].kind {
                    if let Some(rr) = scene.objects.reradiation(object) {
                        for k in 0..LANES {
                            let (a, b) = (seg[i - 1][k], seg[i][k]);
                            l[k] = event_probability(rr, a, b, Direction::Light, lines) as f32;
                            c[k] = event_probability(rr, b, a, Direction::Camera, lines) as f32;
                        }
                    }
                }
                (l, c)
            };
            // The walk's own record of each choice is the density evaluated afresh (the draw
            // and `event_probability` agree), and so is its record of the light side's.
            for i in (1..n - 1).filter(|_| strict) {
                let (l, c) = events(i);
                for k in (0..LANES).filter(|&k| live(k)) {
                    let v = &path[j - i];
                    let close = |a: f32, b: f32| (a - b).abs() <= 1e-4 * a.abs().max(b.abs());
                    assert!(close(v.choice[k], c[k]), "own {} vs {}", v.choice[k], c[k]);
                    assert!(
                        close(v.choice_rev[k], l[k]),
                        "other {} vs {}",
                        v.choice_rev[k],
                        l[k]
                    );
                }
            }
            let moved_at = |i: usize| -> LaneMask {
                (0..LANES)
                    .filter(|&k| seg[i - 1][k] != seg[i][k])
                    .fold(LaneMask::NONE, |m, k| m.with(k))
            };
            let moved_all = (1..n - 1).fold(LaneMask::NONE, |m, i| m.union(moved_at(i)));
            // Densities of each vertex from the light side and from the camera side.
            let li = x[0].light_index(&scene).unwrap();
            let mut x0_light = Vertex::light(li, x[0].p, x[0].p_error, x[0].ng, x[0].beta);
            x0_light.uv = x[0].uv;
            let from_light = |i: usize| -> f32 {
                match i {
                    0 => x0_light.pdf_light_origin(&scene, &x[1]),
                    1 => x0_light.pdf_light(&scene, &x[1]),
                    _ => x[i - 1].pdf(
                        &scene,
                        camera,
                        Some(&x[i - 2]),
                        &x[i],
                        &lambda,
                        TransportMode::Importance,
                    ),
                }
            };
            let from_camera = |i: usize| -> f32 {
                if i == n - 1 {
                    0.0
                } else if i == n - 2 {
                    x[n - 1].pdf(
                        &scene,
                        camera,
                        None,
                        &x[i],
                        &lambda,
                        TransportMode::Radiance,
                    )
                } else {
                    x[i + 1].pdf(
                        &scene,
                        camera,
                        Some(&x[i + 2]),
                        &x[i],
                        &lambda,
                        TransportMode::Radiance,
                    )
                }
            };
            let pair_at = |l: [f32; LANES]| SampledWavelengths {
                lambda: l,
                pdf: std::array::from_fn(|k| mixture.lane_density(l[k]) as f32),
                lanes: LaneMask::ALL,
            };
            let (obs, emit) = (pair_at(seg[n - 2]), pair_at(seg[0]));
            // The light subpath's own draw at the emitted wavelengths (the own mode).
            let light_own = SampledWavelengths {
                lambda: seg[0],
                pdf: std::array::from_fn(|k| {
                    mixture.light_lane_density(li as usize, seg[0][k]) as f32
                }),
                lanes: LaneMask::ALL,
            };
            let fluorescent = |i: usize| matches!(x[i].kind, VertexKind::Surface { object } if scene.objects.reradiation(object).is_some());
            let is_line = |l: f32| lines.iter().any(|d| d.lambda as f32 == l);
            let mut sum = [0.0f64; LANES];
            for s in 0..n {
                let t = n - s;
                let modes: &[bool] = if s >= 2 && t >= 2 {
                    &[false, true]
                } else if t == 1 {
                    // One strategy over both modes: both must give the same weight.
                    &[false, true]
                } else {
                    &[false]
                };
                let mut t1_weight: Option<SampledSpectrum> = None;
                for &own in modes {
                    // The pair: the observed wavelengths, except for t = 1 in the shared
                    // mode, whose light subpath started at the pair's (emitted) wavelengths.
                    let pair = if t == 1 && !own { emit } else { obs };
                    let start = if own { light_own } else { pair };
                    // The light subpath x_0 … x_{s−1}.
                    let light_path: Vec<Vertex> = (0..s)
                        .map(|i| {
                            let mut v = if i == 0 { x0_light } else { x[i] };
                            v.pdf_fwd = from_light(i);
                            v.pdf_rev = from_camera(i);
                            v.moved = (1..=i).fold(LaneMask::NONE, |m, a| m.union(moved_at(a)));
                            if i > 0 {
                                (v.choice, v.choice_rev) = events(i);
                            }
                            v.shifted = (seg[i] != start.lambda).then_some(seg[i]);
                            v
                        })
                        .collect();
                    // The camera subpath x_{n−1} … x_s.
                    let camera_path: Vec<Vertex> = (s..n)
                        .rev()
                        .map(|i| {
                            let mut v = x[i];
                            v.pdf_fwd = from_camera(i);
                            v.pdf_rev = if i == 0 { 0.0 } else { from_light(i) };
                            v.moved =
                                (i.max(1)..n - 1).fold(LaneMask::NONE, |m, a| m.union(moved_at(a)));
                            if i > 0 && i < n - 1 {
                                (v.choice_rev, v.choice) = events(i);
                            }
                            let after = if i == 0 { seg[0] } else { seg[i - 1] };
                            v.shifted = (after != pair.lambda).then_some(after);
                            v
                        })
                        .collect();
                    let mode = LightMode::new(own, start, ALPHA, &scene, &mixture, &light_path);
                    let sampled = match (s, t) {
                        (1, 2..) => {
                            let mut v = x0_light;
                            v.pdf_fwd = x0_light.pdf_light_origin(&scene, &x[1]);
                            Some(v)
                        }
                        (_, 1) => Some(x[n - 1]),
                        _ => None,
                    };
                    let w = mis_weight_lanes(
                        &scene,
                        camera,
                        &mixture,
                        (&light_path, &camera_path),
                        sampled.as_ref(),
                        (s, t),
                        &pair,
                        &mode,
                        LaneMask::ALL,
                        1,
                    );
                    if t == 1 {
                        if let Some(w0) = t1_weight {
                            for k in (0..LANES).filter(|&k| live(k)) {
                                let close = (w[k] - w0[k]).abs() <= 1e-5 * w0[k].max(1e-6);
                                assert!(close, "t = 1 over both modes: {} vs {}", w[k], w0[k]);
                            }
                            continue;
                        }
                        t1_weight = Some(w);
                    }
                    for k in 0..LANES {
                        let moved = moved_all.contains(k);
                        // Which strategies can make this lane path (module docs).
                        let possible = if t == 1 {
                            ALPHA as f64 * mixture.lane_density(seg[0][k])
                                + (1.0 - ALPHA as f64) * light_own.pdf[k] as f64
                                > 0.0
                        } else if s <= 1 {
                            obs.pdf[k] > 0.0
                        } else if !own {
                            !moved && obs.pdf[k] > 0.0
                        } else {
                            let ends = obs.pdf[k] > 0.0 && light_own.pdf[k] > 0.0;
                            let v = if fluorescent(s) {
                                Some(s)
                            } else if fluorescent(s - 1) {
                                Some(s - 1)
                            } else {
                                None
                            };
                            let through = match v {
                                Some(v) => {
                                    let (a, b) = (seg[v - 1][k], seg[v][k]);
                                    if a == b {
                                        is_line(a)
                                    } else {
                                        !is_line(b)
                                    }
                                }
                                None => is_line(seg[s - 1][k]),
                            };
                            if ends && through && live(k) {
                                own_joins += 1;
                                own_shifted += (v.is_some() && moved) as usize;
                            }
                            ends && through
                        };
                        if possible && live(k) {
                            sum[k] += w[k] as f64;
                        }
                    }
                }
            }
            for k in 0..LANES {
                if !live(k) || obs.pdf[k] == 0.0 {
                    continue;
                }
                shifted_lanes += moved_all.contains(k) as usize;
                line_lanes += (0..n - 1).any(|i| lines[0].lambda as f32 == seg[i][k]) as usize;
                worst = worst.max((sum[k] - 1.0).abs());
                assert!(
                    !strict || (sum[k] - 1.0).abs() < 2e-3,
                    "path {paths}: lane {k} weights sum to {} (n = {n}, shifted {})",
                    sum[k],
                    moved_all.contains(k)
                );
            }
        }
        Sums {
            paths,
            shifted_lanes,
            line_lanes,
            own_joins,
            own_shifted,
            worst,
        }
    }
}
