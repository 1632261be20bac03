//! The path tracer's visibility guide (`integrator::nee_guide`) on environment lights: a room
//! lit only by the sky outside its one window (the bench's window room with its sky panel
//! replaced by an environment: the constant sky, an image map with a sun, a CIE sky). The
//! environment's sample numbers must come back from its points (`Light::sample_coords`), the
//! guide must switch itself on, give the MIS weight of a path that escapes through the window
//! the density next-event estimation had, keep the image's expectation and lower the
//! variance of direct light. The map is written as OpenEXR into a temporary directory.
//! Run: `cargo test --release -p spectrace --test integrators_nee_guide_env`

use glam::{Vec2, Vec3A};
use spectrace::camera::CameraSample;
use spectrace::geometry::spawn_ray;
use spectrace::integrator::nee_guide::{NeeGuide, NO_KEY};
use spectrace::light::LightSampleContext;
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::spectrum::SampledWavelengths;

mod common_nee_guide;
mod common_sun_sky;
use common_nee_guide::{assert_guided_mean_equals_uniform, per_pixel_variance};

/// The window room (`scenes/bench/window_room.ron`: a closed 4 × 2.5 × 4 m room whose only
/// opening is a 1.2 × 1.0 m window in its +x wall) at 40 × 30 pixels, lit by `light` (a scene
/// light entry) instead of the sky panel.
const ROOM: &str = r#"(
    observer: "cie1931-2",
    materials: [
        (name: "wall", type: "lambertian", params: (reflectance: 0.6)),
        (name: "floor", type: "lambertian", params: (reflectance: 0.3)),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
        (name: "ceiling", type: "quad", material: "wall",
         params: (corner: (-2, 2.5, -2), edge0: (4, 0, 0), edge1: (0, 0, 4))),
        (name: "back", type: "quad", material: "wall",
         params: (corner: (-2, 0, -2), edge0: (4, 0, 0), edge1: (0, 2.5, 0))),
        (name: "front", type: "quad", material: "wall",
         params: (corner: (2, 0, 2), edge0: (-4, 0, 0), edge1: (0, 2.5, 0))),
        (name: "left", type: "quad", material: "wall",
         params: (corner: (-2, 0, 2), edge0: (0, 0, -4), edge1: (0, 2.5, 0))),
        (name: "window_below", type: "quad", material: "wall",
         params: (corner: (2, 0, -2), edge0: (0, 0, 4), edge1: (0, 0.9, 0))),
        (name: "window_above", type: "quad", material: "wall",
         params: (corner: (2, 1.9, -2), edge0: (0, 0, 4), edge1: (0, 0.6, 0))),
        (name: "window_left", type: "quad", material: "wall",
         params: (corner: (2, 0.9, -2), edge0: (0, 0, 1.4), edge1: (0, 1.0, 0))),
        (name: "window_right", type: "quad", material: "wall",
         params: (corner: (2, 0.9, 0.6), edge0: (0, 0, 1.4), edge1: (0, 1.0, 0))),
    ],
    lights: [LIGHT],
    cameras: [
        (name: "inside", type: "perspective",
         params: (position: (1.6, 1.4, 1.6), look_at: (-2, 0.9, -0.8), fov: 65,
                  resolution: (40, 30))),
    ],
)"#;

/// The constant sky (D65, 30 W/(m²·sr)).
const CONSTANT: &str =
    r#"(name: "sky", type: "environment", params: (radiance: "d65", scale: 30.0))"#;
/// The sun-and-sky image map of `common_sun_sky` (+y up): its sun, at u ≈ 0.33 and about 40°
/// up, lies towards +x and shines in at the window onto the floor.
const MAP: &str = r#"(name: "sky", type: "envmap", params: (file: "sky.exr", scale: 1))"#;
/// The CIE clear sky, sun 40° up.
const CIE: &str = r#"(name: "sky", type: "cie_sky", params: (sky_type: 12, sun_altitude: 40,
                     sun_azimuth: 90, horizontal_illuminance_lx: 10000))"#;

/// The room lit by `light`, files (the map) in a fresh temporary directory.
fn room(light: &str, tag: &str) -> Scene {
    let dir = common_sun_sky::temp_dir("neeguideenv", tag);
    common_sun_sky::write_sun_sky(&dir.join("sky.exr"));
    let file = dir.join("room.ron");
    let text = ROOM.replace("LIGHT", light);
    let desc = parse_scene_str(&text, &file).unwrap();
    build_scene(&desc, &dir, &file, &[&BuiltinFactory]).unwrap()
}

/// The index of the scene's environment light.
fn env_index(scene: &Scene) -> usize {
    scene.lights.environment().expect("an environment light") as usize
}

/// Distance between two numbers of [0, 1) taken around the circle (an environment's numbers
/// wrap in azimuth: just below 1 and 0 are the same direction).
fn wrapped(a: f32, b: f32) -> f32 {
    let d = (a - b).abs();
    d.min(1.0 - d)
}

/// Quantity: `sample_coords(receiver, sample_li(receiver, u).p_light)` against `u`, for a
/// 64 × 64 grid of `u` (cell centres) at 4 receivers in the room, for the constant sky, the
/// image map and the CIE sky: every direction drawn, back to its numbers. Tolerance 1e-4 per
/// coordinate (around the circle): the point on the sphere around the scene is f32 (relative
/// rounding ~1e-7 of a radius of 3.3 m), the direction from it is good to ~1e-7 rad, which the
/// azimuth divides by sin θ (the map's first row of cells reaches 6° from the pole, where a
/// 1e-7 error in φ is 1e-6 in u): 1e-4 leaves a margin of ~100 while a wrong cell or offset
/// (the cell width is 1/64 to 1/31) is off by far more. The CIE sky draws only above the
/// horizon; numbers whose direction it gives no point for are skipped (counted: at least 90%
/// must be checked).
#[test]
fn sample_coords_invert_sample_li() {
    let lambda = SampledWavelengths::sample_visible(0.4);
    for (name, light) in [("constant", CONSTANT), ("map", MAP), ("cie", CIE)] {
        let scene = room(light, &format!("coords-{name}"));
        let li = env_index(&scene);
        let l = scene.lights.lights()[li].as_ref();
        assert!(NeeGuide::can_guide(l), "{name}");
        let (mut worst, mut checked) = (0.0f32, 0);
        for p in [
            Vec3A::new(0.0, 1.0, 0.0),
            Vec3A::new(1.9, 0.1, -1.9),
            Vec3A::new(-1.5, 2.4, 1.0),
            Vec3A::new(1.99, 1.4, 0.0),
        ] {
            let ctx = LightSampleContext {
                p,
                p_error: Vec3A::ZERO,
                n: Vec3A::Y,
            };
            for a in 0..64 {
                for b in 0..64 {
                    let u = Vec2::new((a as f32 + 0.5) / 64.0, (b as f32 + 0.5) / 64.0);
                    let Some(ls) = l.sample_li(&ctx, u, &lambda) else {
                        continue;
                    };
                    let back = l
                        .sample_coords(p, ls.p_light)
                        .unwrap_or_else(|| panic!("{name}: no numbers for {u:?}"));
                    let err = wrapped(back.x, u.x).max(wrapped(back.y, u.y));
                    assert!(err < 1e-4, "{name}: u {u:?} came back as {back:?}");
                    worst = worst.max(err);
                    checked += 1;
                }
            }
        }
        eprintln!("{name}: {checked} points, largest round-trip error {worst:.2e}");
        assert!(checked >= 4 * 64 * 64 * 9 / 10, "{name}: {checked} points");
    }
}

/// Quantity: the density factor next-event estimation divides by (drawn with the guide) against
/// the one the MIS weight of a path escaping along the same direction evaluates
/// (`NeeGuide::pdf_factor` at the escape point of the ray spawned from the receiver, as the
/// path tracer's `add_escaped` asks it, seen from the previous vertex), at 200 receivers seen
/// by the camera × 64 draws, constant sky and image map. Left to itself the guide must switch
/// on (the window shows the room a small part of the sky: occluded share above 0.6).
/// Tolerance: equal as f32, except for points within 1e-3 of a cell edge in u (the spawned
/// ray's offset origin may put them in the neighbour cell: a set of measure zero), at most 5%
/// of the points. The light's own `pdf_li` at the sampled point must match the sample's
/// density to 1e-3 relative (one density, two computations; the map's is f32 from f64). Guarded against passing vacuously: most draws must come from learned
/// densities.
#[test]
fn mis_weight_of_escaped_paths_uses_the_sampled_density() {
    for (name, light) in [("constant", CONSTANT), ("map", MAP)] {
        let scene = room(light, &format!("mis-{name}"));
        let li = env_index(&scene);
        let cam = scene.cameras.get(None).unwrap();
        let guide = NeeGuide::build(&scene, cam.camera.as_ref(), 9, None, Some(2))
            .unwrap_or_else(|| panic!("{name}: the sky is mostly hidden: the guide must be on"));
        let report = guide.reports().iter().find(|r| r.light == li).unwrap();
        eprintln!("{name}: occluded share {:.3}", report.occluded_share);
        assert!(report.on && report.occluded_share > 0.6, "{report:?}");
        assert!(guide.guides(li));
        let light = scene.lights.lights()[li].as_ref();
        let lambda = SampledWavelengths::sample_visible(0.3);
        let (mut checked, mut learned, mut edge) = (0, 0, 0);
        let mut rng = spectrace::integrator::PixelSampler::new(11, 0, 0);
        for k in 0..200u32 {
            rng.restart(0, k);
            let film = rng.next_2d();
            let ray = cam
                .camera
                .generate_ray(&CameraSample {
                    p_film: Vec2::new(film.x * 40.0, film.y * 30.0),
                    p_lens: Vec2::ZERO,
                })
                .unwrap()
                .ray;
            let Some(hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
                continue;
            };
            let key = guide.key(hit.point, hit.geometric_normal, -ray.dir);
            assert_ne!(key, NO_KEY);
            let ctx = LightSampleContext {
                p: hit.point,
                p_error: hit.point_error,
                n: hit.geometric_normal,
            };
            for _ in 0..64 {
                let (u, factor) = guide.sample(li, key, rng.next_2d());
                if factor != 1.0 {
                    learned += 1;
                }
                let Some(ls) = light.sample_li(&ctx, u, &lambda) else {
                    continue;
                };
                let out = spawn_ray(hit.point, hit.point_error, hit.geometric_normal, ls.wi);
                let (p_env, _) = light.escape_point(&out).unwrap();
                let back = guide.pdf_factor(li, key, light, ctx.p, p_env);
                let near_edge = common_nee_guide::near_cell_edge(u);
                if near_edge {
                    edge += 1;
                } else {
                    assert_eq!(back, factor, "{name}: u {u:?}");
                }
                let pdf = light.pdf_li(&ctx, ls.p_light, ls.n_light);
                assert!(
                    (pdf / ls.pdf - 1.0).abs() < 1e-3,
                    "{name}: pdf_li {pdf} vs sampled {}",
                    ls.pdf
                );
                checked += 1;
            }
        }
        eprintln!("{name}: {checked} points, {learned} learned, {edge} near an edge");
        assert!(checked > 5_000, "{name}: only {checked} points checked");
        assert!(learned > checked / 2, "{name}: only {learned} learned");
        assert!(
            edge < checked / 20,
            "{name}: {edge} of {checked} near an edge"
        );
    }
}

/// Quantity: the image mean of Y over 16 seeds × 32 spp, guided and uniform (independent
/// seeds), whole paths (depth 16) for the constant sky and direct light only (depth 1) for the
/// image map (its sun through the window: the guide and the map's own importance sampling
/// combined). Tolerance: 4 standard errors of the difference, each side's error from its 16
/// seed means: a factor missing from the escaped path's MIS weight (sampling guided, weight
/// uniform) moved the area-light version of this test by 5.5 standard errors.
#[test]
fn guided_mean_equals_uniform_mean() {
    for (name, light, depth) in [("constant", CONSTANT, 16), ("map", MAP, 1)] {
        let scene = room(light, &format!("mean-{name}"));
        assert_guided_mean_equals_uniform(name, &scene, 32, depth);
    }
}

/// Quantity: the mean over pixels of the per-pixel variance across 8 seeds (16 spp each),
/// uniform over guided, constant sky, direct light (depth 1) and whole paths (depth 16); the
/// wall-clock time of the 8 renders, guided over uniform, is printed (not asserted: a timed
/// test on a shared machine proves nothing). Bound for direct light: above 1.5 (each of the
/// 1 200 pixel variances comes from 8 renders, so their mean is known to a few per cent; a
/// guide that learned nothing gives 1.0 ± 0.05; the window shows each receiver at most about
/// a tenth of the sky, so uniform directions are mostly occluded).
#[test]
fn guide_lowers_the_variance_of_sky_light() {
    let scene = room(CONSTANT, "var");
    for depth in [1, 16] {
        let (v0, t0) = per_pixel_variance(&scene, false, depth);
        let (v1, t1) = per_pixel_variance(&scene, true, depth);
        eprintln!(
            "constant sky, depth {depth}: per-pixel variance uniform/guided {:.3}, time guided/uniform {:.3}, efficiency gain {:.2}",
            v0 / v1,
            t1 / t0,
            (v0 * t0) / (v1 * t1)
        );
        if depth == 1 {
            assert!(
                v0 / v1 > 1.5,
                "variance ratio uniform/guided {:.3}",
                v0 / v1
            );
        }
    }
}
