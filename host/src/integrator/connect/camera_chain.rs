//! The camera-side specular-chain connection of BDPT: paths `pinhole → S+ → area light`
//! (a small lamp seen reflected in, or refracted through, a glass ball), which otherwise only
//! `s = 0` makes (a camera ray that happens to reach the lamp's tiny image: a rare event).
//! This strategy samples a point `y` on an area light by area, solves every chain of the
//! deterministic seed set from the pinhole `c` to `y` (`integrator::connect::specular_seeds`, solve in
//! `integrator::connect::specular_chain`), keeps each distinct solution once, checks the last segment's
//! visibility and splats each solution at the raster position of its first direction `ω0`,
//! like the `t = 1` connection. Its contribution, per camera sample,
//!
//! `We(ω0) · cos θ_c · |dω0/dA_y| · Π(R or T/η²) · L_e(y → x_k) / (q · p(y))`
//!
//! (`We` the camera's importance, 1/(m²·sr), with the pinhole's unit lens area;
//! `|dω0/dA_y|` the generalised geometry term, sr/m²; `p(y)` = light pmf × 1/area; `q` =
//! [`CAMERA_CHAIN_RATE`], the probability that a camera sample runs the strategy at all — the
//! lamp's images are a few hundred pixels, so a fraction of the samples puts many splats in
//! each and the solves cost little).
//!
//! MIS (power heuristic) against `s = 0`, both densities in area measure at `y`:
//! `p_s0 = p_c(ω0) · Π p_lobe · |dω0/dA_y|` (`p_c` the camera's image-wide directional
//! density, as the `t = 1` weights use it) and `p_chain = q · p(y) · 1[the seed set's solve
//! from (c, y) finds this very chain]`, the indicator evaluated for an `s = 0` path by solving
//! from its own `(c, y)` ([`CameraChain::s0_weight`]): where no seed converges to it, `s = 0`
//! keeps the whole weight, so nothing is lost and nothing counted twice. No other strategy
//! makes these paths (every join would meet a delta vertex; light paths never reach a
//! pinhole). Russian roulette is left out of both densities as in BDPT's other weights.
//!
//! Wavelengths: the chain is solved for the hero wavelength; a dispersive vertex leaves the
//! hero lane only, as after a sampled dispersive event. Only for pinhole cameras (a thin lens
//! has no single `c`; such renders leave these paths to `s = 0`, and the render plan's summary
//! says so) and scenes without fluorescence.
//!
//! | constant            | value | meaning                                                    |
//! |---------------------|-------|------------------------------------------------------------|
//! | `CAMERA_CHAIN_RATE` | 1/256 | probability that a camera sample runs the strategy         |

use crate::camera::Camera;
use crate::geometry::{spawn_ray_to, Ray};
use crate::integrator::connect::manifold_connection::{LightPoint, ManifoldSample};
use crate::integrator::connect::specular_chain::{Endpoint, Solved, MAX_CHAIN_VERTICES};
use crate::integrator::connect::specular_seeds::{ScanTable, SolutionSet, SpecularShapes};
use crate::integrator::subpath::vertex::{Vertex, VertexKind};
use crate::integrator::PathStats;
use crate::scene::Scene;
use crate::spectrum::{LaneMask, SampledWavelengths};
use glam::{Vec2, Vec3A};

/// Lights (in scene order) whose points the per-render scan aims at.
pub const MAX_SCANNED_LIGHTS: usize = 16;
/// Points of each light (area-sampling coordinates) the per-render scan aims at.
const SCAN_LIGHT_POINTS: [(f32, f32); 5] = [
    (0.5, 0.5),
    (0.15, 0.15),
    (0.85, 0.15),
    (0.15, 0.85),
    (0.85, 0.85),
];

/// Probability that a camera sample runs the strategy (it then counts `1/q` times). One run
/// costs about 100k instructions (three Newton solves on the caustic scene), 6× a whole BDPT
/// sample there; at 1/256 a 160×120 image still gets 75 runs per pass of one sample per
/// pixel, and each run splats once into each lamp image (a few pixels), so they converge long
/// before the rest of the image (measured: docs/performance.md, "The lamp seen in the ball").
pub const CAMERA_CHAIN_RATE: f32 = 1.0 / 256.0;

/// One splat of the strategy: where it lands and what it carries (the same record as the
/// diffuse-vertex connection's, so bdpt treats both alike).
#[derive(Clone, Copy, Debug)]
pub struct ChainSplat {
    /// Raster position (pixels).
    pub raster: Vec2,
    /// The chain's first vertex (world).
    pub first: Vec3A,
    /// Contribution, weight, lanes, light and path length.
    pub sample: ManifoldSample,
}

/// The strategy for one render: the pinhole and the scene's specular shapes.
#[derive(Clone, Debug)]
pub struct CameraChain {
    shapes: SpecularShapes,
    c: Endpoint,
    /// The scan's seeds from the pinhole (see [`SpecularShapes::scan_table`]).
    table: ScanTable,
}

/// Reusable scratch of one worker thread.
#[derive(Clone, Debug, Default)]
pub struct ChainScratch {
    set: SolutionSet,
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

impl CameraChain {
    /// The strategy for `camera` in `scene`; `None` for a camera that is not a pinhole or a
    /// scene without smooth specular objects.
    pub fn new(scene: &Scene, camera: &dyn Camera) -> Option<Self> {
        if !camera.pinhole() {
            return None;
        }
        let shapes = SpecularShapes::new(scene);
        if shapes.is_empty() {
            return None;
        }
        let c = Endpoint {
            p: camera.position(),
            p_error: Vec3A::ZERO,
            n: Vec3A::ZERO,
        };
        // The scan towards the centre and four inner points of every area light, at 560 nm.
        let mut ys = Vec::new();
        for light in scene.lights.lights().iter().take(MAX_SCANNED_LIGHTS) {
            let Some(object) = light.object() else {
                continue;
            };
            for u in SCAN_LIGHT_POINTS {
                if let Some(smp) = scene.geometry.sample_area(object, Vec2::from(u)) {
                    ys.push(smp.point);
                }
            }
        }
        let lambda = SampledWavelengths::sample_uniform(0.45, 380.0, 780.0);
        let table = shapes.scan_table(scene, &c, &ys, &lambda, MAX_CHAIN_VERTICES);
        Some(Self { shapes, c, table })
    }

    /// Longest chain that fits in `max_depth` bounces.
    fn max_len(max_depth: usize) -> usize {
        max_depth.min(MAX_CHAIN_VERTICES)
    }

    /// `p_s0` of solved chain `s` (area measure at `y`, 1/m²).
    fn s0_density(&self, camera: &dyn Camera, s: &Solved) -> f32 {
        let (_, dir_pdf) = camera.pdf_we(&Ray::new(self.c.p, s.w0));
        dir_pdf * s.lobe_pdf * s.dir_per_area
    }

    /// Runs the strategy with the choice `u_run` (runs when below [`CAMERA_CHAIN_RATE`]),
    /// the light choice `u_light` and the point on it `u_point`; calls `splat` for each
    /// visible solution.
    #[allow(clippy::too_many_arguments)]
    pub fn connect(
        &self,
        scene: &Scene,
        camera: &dyn Camera,
        lambda: &SampledWavelengths,
        (u_run, u_light, u_point): (f32, f32, Vec2),
        max_depth: usize,
        scratch: &mut ChainScratch,
        stats: &mut PathStats,
        mut splat: impl FnMut(&ChainSplat),
    ) {
        if u_run >= CAMERA_CHAIN_RATE {
            return;
        }
        let Some(y) = LightPoint::sample(scene, u_light, u_point) else {
            return;
        };
        self.connect_at(
            scene, camera, lambda, &y, max_depth, scratch, stats, &mut splat,
        );
    }

    /// [`connect`](Self::connect) to a given light point `y`, once the run was chosen.
    #[allow(clippy::too_many_arguments)]
    pub fn connect_at(
        &self,
        scene: &Scene,
        camera: &dyn Camera,
        lambda: &SampledWavelengths,
        y: &LightPoint,
        max_depth: usize,
        scratch: &mut ChainScratch,
        stats: &mut PathStats,
        splat: &mut impl FnMut(&ChainSplat),
    ) {
        let li = y.light;
        let light = &scene.lights.lights()[li];
        if !(y.pdf > 0.0) {
            return;
        }
        let p_chain = CAMERA_CHAIN_RATE * y.pdf;
        let set = &mut scratch.set;
        set.solve_all(
            scene,
            &self.shapes,
            &self.c,
            &y.p,
            lambda,
            Self::max_len(max_depth),
            Some(&self.table),
        );
        for s in &set.solved {
            // Each solve traces its chain from the pinhole; count about two rays per vertex.
            stats.shadow_rays += 2 * s.chain.len() as u64;
            let k = s.chain.len();
            let last = s.chain.get(k - 1);
            let yp = &y.p;
            let (ray, t_max) = spawn_ray_to(last.p, last.p_error, last.ng, yp.p, yp.p_error, yp.n);
            stats.shadow_rays += 1;
            if scene.geometry.occluded(&ray, t_max) {
                continue;
            }
            let Some(cs) = camera.sample_wi(s.chain.get(0).p, Vec2::splat(0.5)) else {
                continue;
            };
            if !(cs.pdf > 0.0 && cs.importance > 0.0) {
                continue;
            }
            let mut le = light.radiance(yp.p, yp.n, y.uv, (last.p - yp.p).normalize(), lambda);
            scene.lights.keep_line_power_only(li, lambda, &mut le);
            if le.is_black() {
                continue;
            }
            // We·cos/d² from the camera, times d² gives We·cos (per sr at c).
            let d2 = (s.chain.get(0).p - self.c.p).length_squared();
            let cam = cs.importance / cs.pdf * d2;
            let l = s.weight * le * (cam * s.dir_per_area / p_chain);
            if l.is_black() {
                continue;
            }
            let p_s0 = self.s0_density(camera, s);
            let lanes = if s.dispersive {
                LaneMask::ALL.terminate_secondary()
            } else {
                LaneMask::ALL
            };
            let flat_chain = s
                .chain
                .iter()
                .all(|v| scene.objects.material(v.object).spectrally_flat());
            splat(&ChainSplat {
                raster: cs.p_raster,
                first: s.chain.get(0).p,
                sample: ManifoldSample {
                    l,
                    weight: power(p_chain, p_s0),
                    lanes,
                    emitter: li as u32,
                    flat_chain,
                    t_equivalent: k + 2,
                    first: s.chain.get(0).p,
                },
            });
        }
    }

    /// The MIS weight of `s = 0` for `camera_path[..t]` when it is a path this strategy can
    /// make (`pinhole → S+ → area light`, every vertex between delta, on the seeded shapes):
    /// `p_s0² / (p_s0² + p_chain²)`, with `p_chain = 0` unless the seed set's solve from this
    /// path's `(c, y)` finds this very chain. `None` for every other path.
    #[allow(clippy::too_many_arguments)]
    pub fn s0_weight(
        &self,
        scene: &Scene,
        camera: &dyn Camera,
        camera_path: &[Vertex],
        t: usize,
        lambda: &SampledWavelengths,
        max_depth: usize,
        scratch: &mut ChainScratch,
    ) -> Option<f32> {
        let path = &camera_path[..t];
        let k = t.checked_sub(2)?;
        if k == 0 || k > Self::max_len(max_depth) || !path[1..t - 1].iter().all(|v| v.delta) {
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
        let y = Endpoint {
            p: lv.p,
            p_error: lv.p_error,
            n: lv.ng,
        };
        let set = &mut scratch.set;
        set.solve_all(
            scene,
            &self.shapes,
            &self.c,
            &y,
            lambda,
            Self::max_len(max_depth),
            Some(&self.table),
        );
        let chain = &path[1..t - 1];
        let tolerance = 1e-3 * (y.p - self.c.p).length();
        let found = set.solved.iter().find(|s| {
            s.chain.len() == chain.len()
                && chain.iter().zip(s.chain.iter()).all(|(v, c)| {
                    v.kind == (VertexKind::Surface { object: c.object })
                        && (v.p - c.p).length() <= tolerance
                })
        });
        let Some(s) = found else {
            return Some(1.0);
        };
        let p_chain = CAMERA_CHAIN_RATE * scene.lights.pmf(li) * scene.geometry.pdf_area(object);
        Some(power(self.s0_density(camera, s), p_chain))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::CameraSample;
    use crate::integrator::connect::specular_chain::solve;
    use crate::integrator::subpath::random_walk::generate_camera_subpath;
    use crate::integrator::wavelengths::mixture::WavelengthMixture;
    use crate::integrator::SampleRng;
    use crate::scene::{build_scene, parse_scene_str, BuiltinFactory};
    use glam::DVec3;
    use std::path::Path;

    /// The caustic scene as shipped (source: scenes/caustic.ron).
    fn caustic() -> Scene {
        let text = include_str!("../../../../scenes/caustic.ron");
        let file = Path::new("caustic.ron");
        let desc = parse_scene_str(text, file).unwrap();
        build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
    }

    fn lamp_point(scene: &Scene, u: Vec2) -> LightPoint {
        LightPoint::sample_on(scene, 0, scene.lights.pmf(0), u).unwrap()
    }

    // The seed set from the pinhole to a lamp point finds the lamp's three images in the ball
    // (the reflection at its top and two chains in, twice reflected inside, out: measured by
    // tracing camera rays through the lamp images' pixels, docs/performance.md), each once.
    // For each, |dω0/dA_y| against central differences of the solved first direction over
    // the lamp (its x and z axes, step 2 mm, the chain solved from its own solution as seed):
    // the truncation error is O(h²) relative to the ball's scale (0.5 m), ≈ 1e-5, the solved
    // directions exact to f32 (≈ 1e-7 in differences of ≈ 1e-3): tolerance 1%.
    #[test]
    fn finds_the_lamp_images_and_their_geometry_terms() {
        let scene = caustic();
        let cam = scene.cameras.get(None).unwrap();
        let cc = CameraChain::new(&scene, cam.camera.as_ref()).expect("pinhole, glass ball");
        let lambda = SampledWavelengths::sample_uniform(0.37, 380.0, 780.0);
        let y = lamp_point(&scene, Vec2::new(0.3, 0.6));
        let mut set = SolutionSet::default();
        set.solve_all(
            &scene,
            &cc.shapes,
            &cc.c,
            &y.p,
            &lambda,
            MAX_CHAIN_VERTICES,
            Some(&cc.table),
        );
        let lens: Vec<usize> = set.solved.iter().map(|s| s.chain.len()).collect();
        assert_eq!(lens, vec![1, 4, 4], "solutions {lens:?}");
        let h = 2e-3f32;
        for s in &set.solved {
            let w0 = |dx: f32, dz: f32| -> DVec3 {
                let mut yy = y.p;
                yy.p += Vec3A::new(dx, 0.0, dz);
                solve(&scene, &cc.c, &yy, &s.chain, &lambda)
                    .expect("converges from the neighbouring solution")
                    .w0
                    .as_dvec3()
            };
            let dx = (w0(h, 0.0) - w0(-h, 0.0)) / (2.0 * h as f64);
            let dz = (w0(0.0, h) - w0(0.0, -h)) / (2.0 * h as f64);
            let fd = dx.cross(dz).length();
            let rel = (s.dir_per_area as f64 - fd).abs() / fd;
            assert!(
                rel < 0.01,
                "{} vertices: analytic {} fd {fd}",
                s.chain.len(),
                s.dir_per_area
            );
        }
    }

    // For camera paths pinhole → glass ×k → lamp sampled by BSDF sampling (no roulette)
    // through the lamp images' pixels, the two strategies that make such a path must
    // (1) have MIS weights summing to one: w_s0 from `s0_weight`, w_chain from the strategy
    //     run to the same light point, |sum − 1| < 1e-5 (f32 arithmetic of one ratio);
    // (2) evaluate the same f(x): s = 0's β·Le times p_s0 against the strategy's unweighted
    //     value times p_chain, to 1e-3 relative (the solve's 2e-5 rad tolerance moves the
    //     chain by far less; f32 products).
    // At least 30 such paths must be found and reproduced among the 300 000 camera rays (about
    // one in 6 000 reaches the 5 cm lamp; every one found so far is reproduced).
    #[test]
    fn weights_sum_to_one_and_contributions_agree() {
        let scene = caustic();
        let cam = scene.cameras.get(None).unwrap();
        let camera = cam.camera.as_ref();
        let cc = CameraChain::new(&scene, camera).unwrap();
        let mixture = WavelengthMixture::new(&scene);
        let mut path = Vec::new();
        let mut stats = PathStats::default();
        let mut scratch = ChainScratch::default();
        let (mut class, mut reproduced) = (0usize, 0usize);
        for k in 0..300_000u64 {
            let mut rng = SampleRng::for_sample(5, k, 0);
            let lambda = mixture.sample(&mut rng);
            let u = rng.next_2d();
            // Rows 25–32, columns 78–82: both lamp images (rows 26 and 31).
            let cs = CameraSample {
                p_film: Vec2::new(78.0 + 4.0 * u.x, 25.0 + 7.0 * u.y),
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
                12,
                100,
                &mut path,
                &mut stats,
            );
            for t in 3..=path.len() {
                let Some(w_s0) = cc.s0_weight(&scene, camera, &path, t, &lambda, 16, &mut scratch)
                else {
                    continue;
                };
                class += 1;
                if w_s0 == 1.0 {
                    continue;
                }
                let lv = &path[t - 1];
                let y = LightPoint {
                    light: 0,
                    p: Endpoint {
                        p: lv.p,
                        p_error: lv.p_error,
                        n: lv.ng,
                    },
                    uv: lv.uv,
                    pdf: scene.lights.pmf(0)
                        * scene.geometry.pdf_area(match lv.kind {
                            VertexKind::Surface { object } => object,
                            _ => unreachable!(),
                        }),
                };
                let mut found = None;
                cc.connect_at(
                    &scene,
                    camera,
                    &lambda,
                    &y,
                    16,
                    &mut scratch,
                    &mut stats,
                    &mut |m| {
                        if m.sample.t_equivalent == t && (m.first - path[1].p).length() < 1e-3 {
                            found = Some(m.sample);
                        }
                    },
                );
                let m = found.expect("the solve that gave w_s0 < 1 must give a splat");
                assert!(
                    (w_s0 + m.weight - 1.0).abs() < 1e-5,
                    "{w_s0} + {}",
                    m.weight
                );
                let le = lv.le(&scene, &path[t - 2], &lambda);
                let l_s0 = (lv.beta * le)[0];
                let ratio = (w_s0 / m.weight).sqrt(); // p_s0 / p_chain
                let f_s0 = l_s0 * ratio;
                assert!(
                    (f_s0 / m.l[0] - 1.0).abs() < 1e-3,
                    "s = 0 gives f/p_chain = {f_s0}, the strategy {} (t = {t})",
                    m.l[0]
                );
                reproduced += 1;
            }
        }
        assert!(reproduced >= 30, "{reproduced} of {class} paths reproduced");
    }
}
