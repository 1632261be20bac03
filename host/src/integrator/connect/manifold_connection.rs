//! The specular-chain ("manifold") connection of BDPT (after Hanika, Droske & Fascione 2015,
//! "Manifold Next Event Estimation"): for paths `camera → S+ → D → T+ → area light`, where
//! the camera side up to the first non-specular vertex `D` is all specular and `T+` is a chain
//! of refractions, the only ordinary strategy is `s = 0` (a camera path that happens to hit
//! the light through the glass: a rare event for a small light). This strategy samples a point
//! `y` on an area light by area, seeds the chain with the surfaces the straight segment
//! `D → y` crosses, solves it (`integrator::connect::specular_chain`) and checks the last segment's
//! visibility; its contribution is
//!
//! `β_D · f_D · |cos θ_D| · Π(R or T/η²) · L_e(y → x_k) · |dω0/dA_y| / p(y)`
//!
//! with `|dω0/dA_y|` the generalised geometry term (sr/m²) and `p(y)` = light pmf × 1/area.
//!
//! MIS (power heuristic) between the two strategies that make such a path, both densities in
//! area measure at `y` (1/m²): `p_s0 = p_D(ω0) · Π p_lobe · |dω0/dA_y|` (`p_D` the BSDF
//! sampling density at `D` in 1/sr, `p_lobe` the Fresnel-weighted lobe choices of the chain)
//! and `p_manifold = p(y) · 1[the solve from (D, y) gives this very chain]`. The indicator is
//! evaluated for an `s = 0` path by running the solve from its own `(D, y)` ([`s0_weight`]):
//! where the seed or Newton's method fails, or finds another of several solutions, `s = 0`
//! keeps the whole weight and nothing is lost. Russian roulette is left out of both densities
//! as in the rest of BDPT's weights: the weights still sum to one, so the estimate stays
//! unbiased.
//!
//! Seeds: the refractions the straight segment `D → y` crosses, one reflection per smooth
//! specular object (`integrator::connect::specular_seeds`: the bisector point of a round shape, the
//! mirror image through a quad; the lamp reflected by a glass ball onto `D`), and the `T T`
//! chains through every transmitting round shape found in closed form in the plane of `D`,
//! its centre and `y` (a ball lens joins a point near its focus to a light by up to three
//! such chains, of which the straight segment seeds one). Every distinct solution of the
//! seed set is one sample, each counted once; the indicator above asks the same seed set.
//!
//! Covered: chains of 1 to [`MAX_CHAIN_VERTICES`] smooth refractions (dielectrics), or one
//! reflection, between a non-specular `D` reached from the camera through specular vertices
//! only, and an area light whose surface is a scene object, within `max_depth`. Not covered
//! (left to `s = 0` and the other strategies): other chains with reflections (`T R T`, `T R R T`
//! from `D`), other solutions of refraction chains through more than one object, rough
//! glass, longer chains, paths the solve does not converge for, `D` seen directly (light
//! tracing makes those well), the camera itself as `D` (`integrator::connect::camera_chain`), and
//! scenes that render fluorescence.

use crate::camera::Camera;
use crate::geometry::spawn_ray_to;
use crate::integrator::connect::specular_chain::{
    seed_chain, solve, Chain, Endpoint, Solved, MAX_CHAIN_VERTICES,
};
use crate::integrator::connect::specular_seeds::{SolutionSet, SpecularShapes};
use crate::integrator::subpath::vertex::{Vertex, VertexKind};
use crate::integrator::PathStats;
use crate::material::TransportMode;
use crate::scene::Scene;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3A};

/// One contribution of the strategy.
#[derive(Clone, Copy, Debug)]
pub struct ManifoldSample {
    /// Unweighted contribution (radiance units per lane, before the wavelength pdfs).
    pub l: SampledSpectrum,
    /// Power-heuristic weight against `s = 0`.
    pub weight: f32,
    /// Lanes valid (the hero only after a dispersive vertex).
    pub lanes: LaneMask,
    /// The light sampled.
    pub emitter: u32,
    /// Every chain vertex's material is spectrally flat (for the exact flat-path colour).
    pub flat_chain: bool,
    /// Camera-subpath vertex count of the same path made by `s = 0` (`j + k + 2`).
    pub t_equivalent: usize,
    /// The chain's first vertex (tells apart the several solutions of one `(D, y)`).
    pub first: Vec3A,
}

/// Index `j ≥ 2` of the anchor vertex `D` of `camera_path`: its first vertex after the camera
/// that was not scattered by a delta lobe, when every vertex before it was and its material
/// has a non-specular lobe.
pub fn anchor(scene: &Scene, camera_path: &[Vertex]) -> Option<usize> {
    let j = (1..camera_path.len()).find(|&i| !camera_path[i].delta)?;
    let VertexKind::Surface { object } = camera_path[j].kind else {
        return None;
    };
    (j >= 2 && scene.objects.material(object).flags().has_non_specular()).then_some(j)
}

fn endpoint(v: &Vertex) -> Endpoint {
    Endpoint {
        p: v.p,
        p_error: v.p_error,
        n: v.ng,
    }
}

/// `p_s0` of the solved path (area measure at `y`, 1/m²): BSDF sampling at `D` (solid angle)
/// times the chain's lobe choices times `|dω0/dA_y|`.
fn s0_density(
    scene: &Scene,
    camera: &dyn Camera,
    camera_path: &[Vertex],
    j: usize,
    solved: &Solved,
    lambda: &SampledWavelengths,
) -> f32 {
    let d = &camera_path[j];
    let x1 = solved.chain.get(0).p;
    // A point vertex at x1: `pdf` then converts to 1/(sr·m²)·… without a cosine (see
    // `Vertex::convert_density`), and times d² gives the solid-angle density.
    let probe = Vertex::camera(x1, Vec3A::Z, SampledSpectrum::splat(1.0));
    let per_area = d.pdf(
        scene,
        camera,
        Some(&camera_path[j - 1]),
        &probe,
        lambda,
        TransportMode::Radiance,
    );
    per_area * (x1 - d.p).length_squared() * solved.lobe_pdf * solved.dir_per_area
}

/// `a² / (a² + b²)`, 0 when both vanish.
fn power(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    let w = a2 / (a2 + b2);
    if w.is_finite() {
        w
    } else {
        0.0
    }
}

/// The strategy from anchor `camera_path[j]` (see [`anchor`]) with the light choice `u_light`
/// and the point on it `u_point`; `None` when it gives nothing for this sample.
#[allow(clippy::too_many_arguments)]
pub fn connect_manifold(
    scene: &Scene,
    camera: &dyn Camera,
    camera_path: &[Vertex],
    j: usize,
    lambda: &SampledWavelengths,
    (u_light, u_point): (f32, Vec2),
    max_depth: usize,
    seeds: &mut Seeds<'_>,
    stats: &mut PathStats,
    out: &mut impl FnMut(ManifoldSample),
) -> Option<()> {
    let y = LightPoint::sample(scene, u_light, u_point)?;
    connect_to_point(
        scene,
        camera,
        camera_path,
        j,
        lambda,
        &y,
        max_depth,
        seeds,
        stats,
        out,
    );
    Some(())
}

/// The seeds of the connection: the straight segment's refractions, and with `shapes` the
/// reflection seeds of every smooth specular object (`integrator::connect::specular_seeds`); `set`
/// holds the distinct solutions of one `(D, y)`.
pub struct Seeds<'a> {
    /// The scene's specular shapes, for the reflection seeds (`None`: straight segment only).
    pub shapes: Option<&'a SpecularShapes>,
    /// Scratch: the solutions of the current `(D, y)`.
    pub set: &'a mut SolutionSet,
}

/// Solves every seed from `x0` to `y` (chains of at most `max_k` vertices) into `seeds.set`,
/// each solution once.
fn solve_seeds(
    scene: &Scene,
    x0: &Endpoint,
    y: &Endpoint,
    lambda: &SampledWavelengths,
    max_k: usize,
    seeds: &mut Seeds<'_>,
    stats: &mut PathStats,
) {
    let set = &mut *seeds.set;
    set.begin(x0.p, y.p);
    if let Some(seed) = seed_chain(scene, x0, y) {
        stats.shadow_rays += seed.len() as u64 + 1;
        if seed.len() <= max_k {
            if let Some(s) = solve(scene, x0, y, &seed, lambda) {
                set.add(s);
            }
        }
    }
    if let Some(shapes) = seeds.shapes {
        let mut add = |seed: &Chain| {
            if seed.len() <= max_k {
                if let Some(s) = solve(scene, x0, y, seed, lambda) {
                    set.add(s);
                }
            }
        };
        shapes.for_each_reflection_seed(x0.p, y.p, &mut add);
        shapes.for_each_through_seed(scene, x0.p, y.p, lambda, &mut add);
    }
}

/// A point on an area light and its density.
#[derive(Clone, Copy, Debug)]
pub struct LightPoint {
    /// Index of the light.
    pub light: usize,
    /// The point on its surface (geometric normal).
    pub p: Endpoint,
    /// Texture coordinates there.
    pub uv: Vec2,
    /// Density of choosing it (light pmf × 1/area, 1/m²).
    pub pdf: f32,
}

impl LightPoint {
    /// A light chosen by the scene's light distribution (`u_light`), a point on it by area
    /// (`u_point`); `None` for lights without a surface or of zero area.
    pub fn sample(scene: &Scene, u_light: f32, u_point: Vec2) -> Option<Self> {
        let (li, pmf) = scene.lights.sample(u_light)?;
        Self::sample_on(scene, li, pmf, u_point)
    }

    /// A point by area on light `li`, chosen with probability `pmf`.
    pub fn sample_on(scene: &Scene, li: usize, pmf: f32, u_point: Vec2) -> Option<Self> {
        let object = scene.lights.lights()[li].object()?;
        let smp = scene.geometry.sample_area(object, u_point)?;
        Some(Self {
            light: li,
            p: Endpoint {
                p: smp.point,
                p_error: smp.point_error,
                n: smp.normal,
            },
            uv: smp.uv,
            pdf: pmf * smp.pdf,
        })
    }
}

/// [`connect_manifold`] to a given light point `y`: `out` gets one sample per distinct
/// visible solution.
#[allow(clippy::too_many_arguments)]
pub fn connect_to_point(
    scene: &Scene,
    camera: &dyn Camera,
    camera_path: &[Vertex],
    j: usize,
    lambda: &SampledWavelengths,
    y: &LightPoint,
    max_depth: usize,
    seeds: &mut Seeds<'_>,
    stats: &mut PathStats,
    out: &mut impl FnMut(ManifoldSample),
) {
    let d = &camera_path[j];
    let light = &scene.lights.lights()[y.light];
    let x0 = endpoint(d);
    let lambda = &d.wavelengths(lambda);
    if j >= max_depth || !(y.pdf > 0.0) {
        return;
    }
    let max_k = (max_depth - j).min(MAX_CHAIN_VERTICES);
    solve_seeds(scene, &x0, &y.p, lambda, max_k, seeds, stats);
    for solved in &seeds.set.solved {
        let k = solved.chain.len();
        let last = solved.chain.get(k - 1);
        stats.shadow_rays += 1;
        let yp = &y.p;
        let (ray, t_max) = spawn_ray_to(last.p, last.p_error, last.ng, yp.p, yp.p_error, yp.n);
        if scene.geometry.occluded(&ray, t_max) {
            continue;
        }
        let mut le = light.radiance(yp.p, yp.n, y.uv, (last.p - yp.p).normalize(), lambda);
        scene.lights.keep_line_power_only(y.light, lambda, &mut le);
        if le.is_black() {
            continue;
        }
        let probe = Vertex::camera(solved.chain.get(0).p, Vec3A::Z, SampledSpectrum::splat(1.0));
        let f = d.f(scene, &probe, lambda, TransportMode::Radiance);
        let cos = solved.w0.dot(d.ns).abs();
        let l = d.beta * f * solved.weight * le * (cos * solved.dir_per_area / y.pdf);
        if l.is_black() {
            continue;
        }
        let p_s0 = s0_density(scene, camera, camera_path, j, solved, lambda);
        let lanes = if solved.dispersive {
            d.lanes.terminate_secondary()
        } else {
            d.lanes
        };
        let flat_chain = solved
            .chain
            .iter()
            .all(|v| scene.objects.material(v.object).spectrally_flat());
        out(ManifoldSample {
            l,
            weight: power(y.pdf, p_s0),
            lanes,
            emitter: y.light as u32,
            flat_chain,
            t_equivalent: j + k + 2,
            first: solved.chain.get(0).p,
        });
    }
}

/// The MIS weight of `s = 0` for the path `camera_path[..t]` when it is one this strategy can
/// make (`camera → S+ → D → T+ → area light`, `D` the anchor): `p_s0² / (p_s0² + p_manifold²)`,
/// with `p_manifold = 0` unless the solve from this path's `(D, y)` finds this very chain.
/// `None` for every other path (its weight is unchanged).
pub fn s0_weight(
    scene: &Scene,
    camera: &dyn Camera,
    camera_path: &[Vertex],
    t: usize,
    lambda: &SampledWavelengths,
    max_depth: usize,
    seeds: &mut Seeds<'_>,
) -> Option<f32> {
    let path = &camera_path[..t];
    let j = anchor(scene, path)?;
    // At least one chain vertex between D and the light, all of them delta.
    if j + 2 >= t || !path[j + 1..t - 1].iter().all(|v| v.delta) {
        return None;
    }
    let lv = &path[t - 1];
    let VertexKind::Surface { object } = lv.kind else {
        return None;
    };
    let li = scene.lights.light_of_object(object)? as usize;
    if scene.lights.lights()[li].object() != Some(object) {
        return None;
    }
    let x0 = endpoint(&path[j]);
    let y = endpoint(lv);
    let lambda = &path[j].wavelengths(lambda);
    if j >= max_depth {
        return Some(1.0);
    }
    let max_k = (max_depth - j).min(MAX_CHAIN_VERTICES);
    solve_seeds(
        scene,
        &x0,
        &y,
        lambda,
        max_k,
        seeds,
        &mut PathStats::default(),
    );
    // The same chain: the same surfaces, each vertex within 1e-3 of the segment's length
    // (distinct solutions lie centimetres apart; the solve's tolerance moves a vertex by far
    // less).
    let tolerance = 1e-3 * (y.p - x0.p).length();
    let chain = &path[j + 1..t - 1];
    // The nearest such solution: on a mesh with interpolated normals two solutions can lie
    // within the tolerance of each other, and only the nearest is this path.
    let found = seeds
        .set
        .solved
        .iter()
        .filter(|solved| {
            chain.len() == solved.chain.len()
                && chain.iter().zip(solved.chain.iter()).all(|(v, c)| {
                    v.kind == (VertexKind::Surface { object: c.object })
                        && (v.p - c.p).length() <= tolerance
                })
        })
        .min_by(|a, b| {
            let d = |s: &Solved| (chain[0].p - s.chain.get(0).p).length();
            d(a).total_cmp(&d(b))
        });
    let Some(solved) = found else {
        return Some(1.0);
    };
    let p_y = scene.lights.pmf(li) * scene.geometry.pdf_area(object);
    let p_s0 = s0_density(scene, camera, path, j, solved, lambda);
    Some(power(p_s0, p_y))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CameraSample;
    use crate::geometry::WorldShape;
    use crate::integrator::connect::specular_chain::{trace_chain, Lobe};
    use crate::integrator::test_support::for_each_camera_subpath;
    use crate::scene::{build_scene, parse_scene_str, BuiltinFactory};
    use std::path::Path;

    /// The caustic scene as shipped (source: scenes/caustic.ron) with a 0.8 m lamp, so that
    /// camera paths through the ball hit it often.
    fn big_lamp_caustic() -> Scene {
        let text = include_str!("../../../../scenes/caustic.ron").replace(
            "corner: (-0.025, 2.6, -0.025), edge0: (0.05, 0, 0), edge1: (0, 0, 0.05)",
            "corner: (-0.4, 2.6, -0.4), edge0: (0.8, 0, 0), edge1: (0, 0, 0.8)",
        );
        let file = Path::new("caustic.ron");
        let desc = parse_scene_str(&text, file).unwrap();
        build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
    }

    /// The caustic scene as shipped (source: scenes/caustic.ron).
    fn caustic() -> Scene {
        let text = include_str!("../../../../scenes/caustic.ron");
        let file = Path::new("caustic.ron");
        let desc = parse_scene_str(text, file).unwrap();
        build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
    }

    /// The `T T` solutions through the ball from `x0` to `y` found by a dense scan: `n` rays
    /// from `x0` aimed across the ball in the plane of `x0`, its centre and `y`, traced
    /// through the scene's glass, every sign change of the angle to `y` solved.
    fn dense_solutions(
        scene: &Scene,
        lobes: &[Lobe],
        (object, center, radius): (u32, Vec3A, f32),
        x0: &Endpoint,
        y: &Endpoint,
        lambda: &SampledWavelengths,
        n: usize,
    ) -> SolutionSet {
        let mut set = SolutionSet::default();
        set.begin(x0.p, y.p);
        let axis = (center - x0.p).normalize();
        let side = y.p - center;
        let u = (side - axis * side.dot(axis)).normalize();
        let normal = axis.cross(u);
        let d = (center - x0.p).length();
        let b_max = d / (d * d - radius * radius).sqrt();
        let tt: Vec<(u32, Lobe)> = lobes.iter().map(|&l| (object, l)).collect();
        let template = Chain::template(center, &tt);
        let mut prev: Option<(f32, f32)> = None;
        for i in 0..n {
            let b = b_max * (-1.0 + (i as f32 + 0.5) * 2.0 / n as f32);
            let dir = (center + u * (b * radius) - x0.p).normalize();
            let angle = trace_chain(scene, x0, dir, &template, lambda).and_then(|(c, out)| {
                let to_y = (y.p - c.get(c.len() - 1).p).normalize();
                (out.dot(to_y) > 0.0).then(|| out.cross(to_y).dot(normal))
            });
            if let (Some((pb, pa)), Some(a)) = (prev, angle) {
                if (pa <= 0.0) != (a <= 0.0) {
                    let bs = pb + (b - pb) * pa / (pa - a);
                    let seed = Chain::template(center + u * (bs * radius), &tt);
                    if let Some(s) = solve(scene, x0, y, &seed, lambda) {
                        set.add(s);
                    }
                }
            }
            prev = angle.map(|a| (b, a));
        }
        set
    }

    // The floor caustic seen *reflected* in the ball's lower rim (row 67, columns 77–82 of
    // the 160×120 image: camera → reflection off the glass → floor → glass → glass → lamp,
    // E R D T T L). For the floor point D seen by that reflection through two film points of
    // each pixel (y = 67.25 and 67.75) and a 6×6 grid of points on the 5 cm lamp, every T T
    // solution that a dense scan finds (4,096 rays traced across the ball in the plane of D,
    // its centre and y, each sign change solved) must be in the connection's solution set
    // (straight-segment, reflection and closed-form T T seeds; the same set the MIS indicator
    // asks). Quantity: dense solutions missing from the set, tolerance 0 (chains matched as
    // the indicator matches them, vertices within 1e-3 of |y − D|). Also checked, so that the
    // test means something: at least 500 solutions over the 432 (D, y) (measured 714), some
    // (D, y) with two or more (measured 141), and the straight-segment seed alone misses some
    // (it finds 146 of 714).
    #[test]
    fn seeds_find_every_solution_of_the_floor_caustic_through_the_ball() {
        let scene = caustic();
        let cam = scene.cameras.get(None).unwrap();
        let shapes = SpecularShapes::new(&scene);
        let ball = shapes.first_round().expect("the glass ball");
        let lambda = SampledWavelengths::sample_uniform(0.41, 380.0, 780.0);
        let pmf = scene.lights.pmf(0);
        let (mut dense_total, mut multi, mut straight_only, mut pairs) = (0, 0, 0, 0);
        let mut set = SolutionSet::default();
        let mut straight = SolutionSet::default();
        for (px, fy) in (77..=82).flat_map(|x| [(x, 67.25), (x, 67.75)]) {
            let cs = CameraSample {
                p_film: Vec2::new(px as f32 + 0.5, fy),
                p_lens: Vec2::splat(0.5),
            };
            let ray = cam.camera.generate_ray(&cs).unwrap().ray;
            let c = Endpoint {
                p: ray.origin,
                p_error: Vec3A::ZERO,
                n: ray.dir,
            };
            let Some((chain, out)) = trace_chain(
                &scene,
                &c,
                ray.dir,
                &Chain::template(ball.1, &[(ball.0, Lobe::Reflect)]),
                &lambda,
            ) else {
                continue;
            };
            let last = chain.get(0);
            let r = crate::geometry::spawn_ray(last.p, last.p_error, last.ng, out);
            let hit = scene.geometry.intersect(&r, f32::INFINITY).unwrap();
            let d = Endpoint {
                p: hit.point,
                p_error: hit.point_error,
                n: hit.geometric_normal,
            };
            for i in 0..36 {
                let u = Vec2::new((i % 6) as f32 + 0.5, (i / 6) as f32 + 0.5) / 6.0;
                let y = LightPoint::sample_on(&scene, 0, pmf, u).unwrap();
                let tt = [Lobe::Transmit, Lobe::Transmit];
                let dense = dense_solutions(&scene, &tt, ball, &d, &y.p, &lambda, 4096);
                let mut seeds = Seeds {
                    shapes: Some(&shapes),
                    set: &mut set,
                };
                solve_seeds(
                    &scene,
                    &d,
                    &y.p,
                    &lambda,
                    4,
                    &mut seeds,
                    &mut PathStats::default(),
                );
                let mut seeds = Seeds {
                    shapes: None,
                    set: &mut straight,
                };
                solve_seeds(
                    &scene,
                    &d,
                    &y.p,
                    &lambda,
                    4,
                    &mut seeds,
                    &mut PathStats::default(),
                );
                pairs += 1;
                dense_total += dense.solved.len();
                multi += usize::from(dense.solved.len() >= 2);
                for s in &dense.solved {
                    assert!(
                        set.find(&s.chain).is_some(),
                        "film point ({px}.5, {fy}), lamp point {u}: a dense-scan solution at {:?} is \
                         not in the seed set ({} of {} found)",
                        s.chain.get(0).p,
                        set.solved.len(),
                        dense.solved.len()
                    );
                    straight_only += usize::from(straight.find(&s.chain).is_some());
                }
            }
        }
        eprintln!(
            "{pairs} (D, y): {dense_total} dense solutions, {multi} pairs with two or more, \
             {straight_only} found by the straight segment alone"
        );
        assert!(
            pairs == 432 && dense_total >= 500,
            "{pairs} pairs, {dense_total}"
        );
        assert!(multi > 0 && straight_only < dense_total);
    }

    // For camera paths camera → glass → glass → floor → glass → glass → lamp sampled by
    // BSDF sampling (no roulette), the two strategies that can make such a path must
    // (1) have MIS weights summing to one: w_s0 from `s0_weight`, w_manifold from the
    //     strategy run to the same light point, |sum − 1| < 1e-5 (f32 arithmetic of one
    //     power-heuristic ratio);
    // (2) evaluate the same measurement contribution f(x) = (estimate × density): s = 0's
    //     β·Le times p_s0 against the strategy's unweighted value times p(y), to 1e-3 relative
    //     (the solve's tolerance of 2e-5 rad moves the chain by far less; f32 products).
    // Quantity checked on every such path among 40 000 camera rays through the ball's lower
    // half; at least 70 must be found where the solve reproduces the path (77 of 77 class
    // paths here with the closed-form T T seeds, 28 from the straight-line seed alone: the
    // others are other solutions of the same (D, y); a path not reproduced keeps w_s0 = 1,
    // which (1) does not test), 2 of them with the lamp reflected by the ball (D → R → lamp,
    // found from the reflection seed; both must be).
    #[test]
    fn weights_sum_to_one_and_contributions_agree() {
        check_weights_and_contributions(&big_lamp_caustic(), 70, 2);
    }

    /// The big-lamp caustic with the analytic ball replaced by the bench's triangle mesh
    /// (`scenes/bench/meshes/glass_sphere_r0.1.obj`: a 48 × 96 UV sphere with per-vertex
    /// normals, scaled to the same centre and radius): the connection must work on meshes
    /// with interpolated normals, not only on analytic spheres.
    fn big_lamp_mesh_caustic() -> Scene {
        let text = include_str!("../../../../scenes/caustic.ron")
            .replace(
                "corner: (-0.025, 2.6, -0.025), edge0: (0.05, 0, 0), edge1: (0, 0, 0.05)",
                "corner: (-0.4, 2.6, -0.4), edge0: (0.8, 0, 0), edge1: (0, 0, 0.8)",
            )
            .replace(
                r#"type: "sphere", material: "glass",
         params: (center: (0, 0.8, 0), radius: 0.5)"#,
                r#"type: "obj", material: "glass",
         params: (file: "meshes/glass_sphere_r0.1.obj"),
         transform: [Scale((5, 5, 5)), Translate((0, 0.3, 0))]"#,
            );
        assert!(
            text.contains("glass_sphere_r0.1.obj"),
            "the ball was not replaced"
        );
        let file = Path::new("caustic_mesh.ron");
        let desc = parse_scene_str(&text, file).unwrap();
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/bench");
        build_scene(&desc, &dir, file, &[&BuiltinFactory]).unwrap()
    }

    // The same checks as `weights_sum_to_one_and_contributions_agree` on the tessellated ball
    // (interpolated normals: the chain's constraint uses the shading normal and its
    // derivatives, `TriangleMesh::derivatives`). Measured on this mesh: 78 of 79 class paths
    // reproduced, 2 with the reflected lamp (the analytic ball: 77 of 77, 2); the bounds are
    // those of the analytic ball.
    #[test]
    fn the_connection_works_on_a_mesh_with_vertex_normals() {
        let scene = big_lamp_mesh_caustic();
        assert!(
            matches!(scene.geometry.shape(2), Some(WorldShape::Mesh(m)) if m.normals.is_some()),
            "object 2 must be the glass mesh with vertex normals"
        );
        check_weights_and_contributions(&scene, 70, 2);
    }

    fn check_weights_and_contributions(scene: &Scene, min_reproduced: usize, min_reflected: usize) {
        let cam = scene.cameras.get(None).unwrap();
        let camera = cam.camera.as_ref();
        let mut stats = PathStats::default();
        let shapes = SpecularShapes::new(scene);
        let mut set = SolutionSet::default();
        let (mut class, mut reproduced, mut reflected) = (0usize, 0usize, 0usize);
        let window = (Vec2::new(65.0, 55.0), Vec2::new(30.0, 15.0));
        for_each_camera_subpath(scene, 11, 40_000, window, (12, 100), |path, lambda| {
            for t in 2..=path.len() {
                let mut seeds = Seeds {
                    shapes: Some(&shapes),
                    set: &mut set,
                };
                let Some(w_s0) = s0_weight(scene, camera, path, t, lambda, 64, &mut seeds) else {
                    continue;
                };
                class += 1;
                if w_s0 == 1.0 {
                    continue;
                }
                let j = anchor(scene, &path[..t]).unwrap();
                let lv = &path[t - 1];
                let VertexKind::Surface { object } = lv.kind else {
                    unreachable!()
                };
                let li = scene.lights.light_of_object(object).unwrap() as usize;
                let y = LightPoint {
                    light: li,
                    p: endpoint(lv),
                    uv: lv.uv,
                    pdf: scene.lights.pmf(li) * scene.geometry.pdf_area(object),
                };
                let mut found: Option<ManifoldSample> = None;
                connect_to_point(
                    scene,
                    camera,
                    path,
                    j,
                    lambda,
                    &y,
                    64,
                    &mut seeds,
                    &mut stats,
                    &mut |m| {
                        // The chain `s0_weight` matched: within 1e-3 of the segment's length
                        // (an absolute 1e-3 missed a solution 1.5e-3 away on a 2.6 m segment).
                        let tolerance = 1e-3 * (y.p.p - path[j].p).length();
                        let d = (m.first - path[j + 1].p).length();
                        let nearer = found.is_none_or(|f| d < (f.first - path[j + 1].p).length());
                        if m.t_equivalent == t && d <= tolerance && nearer {
                            found = Some(m);
                        }
                    },
                );
                let m = found.expect("the solve that gave w_s0 < 1 must give a contribution");
                assert!(
                    (w_s0 + m.weight - 1.0).abs() < 1e-5,
                    "{w_s0} + {}",
                    m.weight
                );
                // f(x) both ways: s = 0's estimate is f/p_s0, the strategy's f/p(y); the
                // weights are p²/(p_s0² + p(y)²), so f = estimate · p follows from the ratio.
                // Compared in the lane the path carries most (a coloured wall may zero some).
                let le = lv.le(scene, &path[t - 2], lambda);
                let lane = (0..4).max_by(|&a, &b| m.l[a].total_cmp(&m.l[b])).unwrap();
                let l_s0 = (lv.beta * le)[lane];
                let ratio = (w_s0 / m.weight).sqrt(); // p_s0 / p(y)
                let f_s0 = l_s0 * ratio;
                let f_m = m.l[lane];
                assert!(
                    (f_s0 / f_m - 1.0).abs() < 1e-3,
                    "s = 0 gives f/p(y) = {f_s0}, the strategy {f_m} (t = {t}, j = {j})"
                );
                reproduced += 1;
                if m.t_equivalent == j + 3 {
                    reflected += 1;
                }
            }
        });
        eprintln!("{reproduced} of {class} paths reproduced, {reflected} reflected");
        assert!(
            reproduced >= min_reproduced,
            "{reproduced} of {class} paths reproduced"
        );
        assert!(
            reflected >= min_reflected,
            "{reflected} reflected-lamp paths reproduced"
        );
    }
}
