//! bdpt's MIS weights in a scene that renders fluorescence: per lane, because each lane of a
//! subpath keeps or shifts its wavelength on its own at a fluorescent vertex (as in pt and lt,
//! [`super::fluorescence`]), so the lanes of one connection are different paths in the
//! wavelength-extended path space.
//!
//! The density of strategy (s, t) for lane k of a path is the product of
//! - the area densities of its vertices, each from the subpath that makes it (as without
//!   fluorescence),
//! - at every fluorescent vertex, the probability of its event (keep, or shift λᵢ → λₒ with
//!   the density of the new wavelength) for the subpath that makes the vertex: the camera's
//!   excitation draw (with its line/continuous mixture) or the light's emission draw. Each
//!   vertex stores both ([`Vertex::choice`] for its own subpath, [`Vertex::choice_rev`] for
//!   the other), so moving a vertex to the other side multiplies by `choice_rev / choice`,
//! - the density of the wavelength drawn at the end the strategy starts from: the pair's
//!   mixture density at the observed wavelength λ_obs for strategies that start at the camera
//!   (s = 0, s = 1), at the emitted wavelength λ_emit for t = 1.
//!
//! Both subpaths start at the pair's wavelength and a shift only lengthens it (Stokes), so a
//! lane that shifted anywhere on the path has λ_emit < λ_obs and can be made only by the
//! strategies that sample every vertex on one subpath (s = 0, s = 1: the camera subpath; t = 1:
//! the light subpath); for them the end densities differ and enter the ratio. Every other
//! (s, t) joins two subpaths that started at the same wavelength and has density 0 for such a
//! lane (its connection gives it nothing, see `bdpt::connect`). A lane that never shifted is
//! made by every strategy, all starting from the same pair wavelength (which cancels), with
//! the keep probabilities of both ends in the densities.
//!
//! The structure mirrors [`super::bdpt::mis_weight`] (the same overrides of the densities at
//! the joined vertices, the same scale of the light-tracing strategy's density,
//! [`super::bdpt::LIGHT_TRACING_MIS_SCALE`]) with a per-lane ratio and per-lane validity.

use super::bdpt::{heuristic_scale, mis_weight_overrides};
use super::vertex::{remap0, Vertex};
use super::wavelength_mixture::WavelengthMixture;
use crate::camera::Camera;
use crate::scene::Scene;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};

/// Per-lane power-heuristic weight of strategy (s, t) for the lane paths it produced, relative
/// to every strategy that can make the same lane path (module docs). `sampled` as for
/// [`super::bdpt::mis_weight`].
pub fn mis_weight_lanes(
    scene: &Scene,
    camera: &dyn Camera,
    mixture: &WavelengthMixture,
    (light_path, camera_path): (&[Vertex], &[Vertex]),
    sampled: Option<&Vertex>,
    (s, t): (usize, usize),
    lambda: &SampledWavelengths,
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
    let pt = o.pt;
    let qs = o.qs;
    // (pdf_fwd, pdf_rev, delta, choice, choice_rev) of camera vertex i and light vertex i.
    let cam = |i: usize| -> (f32, f32, bool, [f32; LANES], [f32; LANES]) {
        if i + 1 == t {
            (pt.pdf_fwd, o.pt_rev, false, pt.choice, pt.choice_rev)
        } else {
            let v = &camera_path[i];
            let rev = if i + 2 == t {
                o.pt_minus_rev.unwrap_or(v.pdf_rev)
            } else {
                v.pdf_rev
            };
            (v.pdf_fwd, rev, v.delta, v.choice, v.choice_rev)
        }
    };
    let light_v = |i: usize| -> &Vertex {
        match (&qs, i + 1 == s) {
            (Some(q), true) => q,
            _ => &light_path[i],
        }
    };
    let light = |i: usize| -> (f32, f32, bool) {
        let v = light_v(i);
        if i + 1 == s {
            (v.pdf_fwd, o.qs_rev.unwrap_or(v.pdf_rev), false)
        } else if i + 2 == s {
            (v.pdf_fwd, o.qs_minus_rev.unwrap_or(v.pdf_rev), v.delta)
        } else {
            (v.pdf_fwd, v.pdf_rev, v.delta)
        }
    };
    // The lanes shifted somewhere on this strategy's path, and the ratio of the end densities
    // (the other end's over this strategy's own) for them.
    let camera_start = t >= 2 && s <= 1;
    let (moved, far_end) = if camera_start {
        (pt.moved, Some(pt.wavelengths(lambda)))
    } else if t == 1 {
        let q = qs.as_ref().unwrap_or(&light_path[s - 1]);
        (q.moved, Some(q.wavelengths(lambda)))
    } else {
        (LaneMask::NONE, None)
    };
    let mut end_ratio = [1.0f32; LANES];
    if let Some(far) = far_end {
        for (k, r) in end_ratio.iter_mut().enumerate() {
            if moved.contains(k) && lambda.pdf[k] > 0.0 {
                *r = (mixture.lane_density(far.lambda[k]) / lambda.pdf[k] as f64) as f32;
            }
        }
    }
    let sq = |x: f32| x * x;
    // As in `mis_weight`: each strategy's squared density times its heuristic scale (t = 1's
    // is LIGHT_TRACING_MIS_SCALE²).
    let own_scale = heuristic_scale(t);
    let mut sum = [0.0f32; LANES];
    // Camera vertices moved to the light subpath, one at a time: strategy (s + t − i, i).
    let mut ri = [1.0f32; LANES];
    for i in (1..t).rev() {
        let (fwd, rev, delta, own, other) = cam(i);
        let structural = !delta && !cam(i - 1).2;
        let s_alt = s + t - i;
        for k in 0..LANES {
            ri[k] *= sq(remap0(rev) * other[k] / (remap0(fwd) * own[k]));
            if i == 1 && camera_start {
                ri[k] *= sq(end_ratio[k]);
            }
            if structural && (!moved.contains(k) || s_alt <= 1 || i == 1) {
                sum[k] += ri[k] * heuristic_scale(i) / own_scale;
            }
        }
    }
    // Light vertices moved to the camera subpath: strategy (i, s + t − i).
    ri = [1.0f32; LANES];
    for i in (0..s).rev() {
        let (fwd, rev, delta) = light(i);
        let v = light_v(i);
        let delta_before = if i > 0 {
            light(i - 1).2
        } else {
            light_v(0).is_unhittable_light(scene)
        };
        let structural = !delta && !delta_before;
        for k in 0..LANES {
            ri[k] *= sq(remap0(rev) * v.choice_rev[k] / (remap0(fwd) * v.choice[k]));
            if i + 1 == s && t == 1 {
                ri[k] *= sq(end_ratio[k]);
            }
            if structural && (!moved.contains(k) || i <= 1) {
                // The alternative has s + t − i ≥ 2 camera vertices: scale 1.
                sum[k] += ri[k] / own_scale;
            }
        }
    }
    SampledSpectrum(std::array::from_fn(|k| {
        let w = 1.0 / (1.0 + sum[k]);
        if w.is_finite() {
            w
        } else {
            0.0
        }
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CameraSample;
    use crate::integrator::fluorescence::{event_probability, Direction};
    use crate::integrator::random_walk::generate_camera_subpath;
    use crate::integrator::vertex::VertexKind;
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
        let mut path = Vec::new();
        let mut stats = PathStats::default();
        for k in 0..20_000u64 {
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
            for i in 1..n - 1 {
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
            let mut sum = [0.0f64; LANES];
            for s in 0..n {
                let t = n - s;
                let camera_start = t >= 2 && s <= 1;
                let pair = if t == 1 { emit } else { obs };
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
                        v.shifted = (seg[i] != pair.lambda).then_some(seg[i]);
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
                );
                for k in 0..LANES {
                    let moved = moved_all.contains(k);
                    let start_density = if camera_start || (s >= 2 && t >= 2) {
                        obs.pdf[k]
                    } else {
                        emit.pdf[k]
                    };
                    let possible = !moved || s <= 1 || t == 1;
                    if possible && start_density > 0.0 && live(k) {
                        sum[k] += w[k] as f64;
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
                    (sum[k] - 1.0).abs() < 2e-3,
                    "path {paths}: lane {k} weights sum to {} (n = {n}, shifted {})",
                    sum[k],
                    moved_all.contains(k)
                );
            }
        }
        println!("{paths} paths, {shifted_lanes} shifted lanes, {line_lanes} on the line; worst |Σw − 1| = {worst:.2e}");
        assert!(
            paths > 1000 && shifted_lanes > 200 && line_lanes > 20,
            "{paths} {shifted_lanes} {line_lanes}"
        );
    }
}
