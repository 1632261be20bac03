//! The lamp seen in the glass ball of `scenes/caustic.ron`, against a value computed from the
//! geometry alone. With the floor and wall taken out, a pixel that sees the lamp in the ball
//! sees nothing else, and its value is a deterministic integral: over the pixel's area, the
//! lamp's luminance times the Fresnel factors of every specular chain from the pinhole that
//! ends on the lamp (reflection at the top, the two T R R T images). This test computes that
//! integral by tracing every branch of a fine grid of camera rays through the sphere (no
//! Monte Carlo, no code of the renderer's transport), and checks BDPT (with its camera-side
//! specular chains, which render these pixels) against it. Mitsuba's path-traced reference
//! lies 3–4% below this value at the reflection (its noise there); this is the check that
//! decides which is right.
//!
//! The second test does the same for the lamp's image at the grazing edge of the bench's glass
//! sphere (scenes/bench/glass_sphere.ron), where Mitsuba 3's reference departs from the
//! integral by its ray-origin offsets.
//! Run: `cargo test --release -p spectrace --test caustic_lamp_images`.

mod common_render;
use glam::DVec3;
use spectrace::film::XyzImage;
use spectrace::integrator::select::render_planned;
use spectrace::integrator::IntegratorKind;
use spectrace::integrator::RenderPlan;
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::spectrum::spd::Spd;
use std::path::Path;

/// The shipped caustic scene (source: scenes/caustic.ron) without its floor and wall.
const FLOOR_AND_WALL: &str = r#"        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
        (name: "back", type: "quad", material: "wall",
         params: (corner: (-2, 0, -2), edge0: (4, 0, 0), edge1: (0, 3, 0))),
"#;

fn scene() -> Scene {
    let text = include_str!("../../scenes/caustic.ron");
    assert!(text.contains(FLOOR_AND_WALL), "caustic.ron changed");
    let text = text.replace(FLOOR_AND_WALL, "");
    let file = Path::new("caustic_ball_only.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// One scene's geometry as the integral needs it: a pinhole camera (horizontal field of view,
/// y up), a smooth dielectric sphere in vacuum and a square lamp facing down (units: metres).
struct Geometry {
    eye: DVec3,
    look_at: DVec3,
    fov_x_deg: f64,
    resolution: (f64, f64),
    centre: DVec3,
    radius: f64,
    ior: f64,
    /// The lamp's plane height and its x and z extents (it emits downwards).
    lamp_y: f64,
    lamp_x: (f64, f64),
    lamp_z: (f64, f64),
    /// How far a spawned ray's origin moves off the surface along the normal, as a multiple
    /// of `1 + max |pᵢ|` (m): 0 for the exact integral; Mitsuba 3 moves it by
    /// `(1 + max |pᵢ|)·1500·2⁻²⁴` (its `Interaction::offset_p`, single precision).
    origin_offset: f64,
    /// The frame the renderer sees the scene in, `x' = scale·(x − centre)`: the offset is
    /// `origin_offset·(1 + max |x'ᵢ|)` there, so `/ scale` here. `(0, 1)`: the scene's own;
    /// the bench's anchors use the ball's centre and a scale that makes its bounding box's
    /// diagonal 100 (scripts/anchors/anchor_render.py, `anchor_frame`).
    frame: (DVec3, f64),
}

/// scenes/caustic.ron (a change there fails `scene()` or the lamp check). The lamp: a 5 cm
/// square at y = 2.6 m centred on the y axis.
const CAUSTIC: Geometry = Geometry {
    eye: DVec3::new(0.0, 1.6, 4.5),
    look_at: DVec3::new(0.0, 0.5, 0.0),
    fov_x_deg: 45.0,
    resolution: (160.0, 120.0),
    centre: DVec3::new(0.0, 0.8, 0.0),
    radius: 0.5,
    ior: 1.5,
    lamp_y: 2.6,
    lamp_x: (-0.025, 0.025),
    lamp_z: (-0.025, 0.025),
    origin_offset: 0.0,
    frame: (DVec3::ZERO, 1.0),
};
/// Its radiance scale (W/(m²·sr)) times the normalised D65 spectrum.
const LAMP_SCALE: f64 = 480000.0;

/// Unpolarised Fresnel reflectance for cosine `c` (> 0) of incidence and relative index
/// `eta` = n_t / n_i, with the cosine of refraction (`None` at total internal reflection).
fn fresnel(c: f64, eta: f64) -> (f64, Option<f64>) {
    let sin_t2 = (1.0 - c * c) / (eta * eta);
    if sin_t2 >= 1.0 {
        return (1.0, None);
    }
    let ct = (1.0 - sin_t2).sqrt();
    let rs = (c - eta * ct) / (c + eta * ct);
    let rp = (eta * c - ct) / (eta * c + ct);
    (0.5 * (rs * rs + rp * rp), Some(ct))
}

/// The sum of Fresnel weights of every specular chain from `origin` along `dir` that leaves
/// the sphere towards the lamp (branches below 1e-9 dropped; at most 12 surface events).
fn lamp_weight(
    g: &Geometry,
    origin: DVec3,
    dir: DVec3,
    inside: bool,
    weight: f64,
    depth: u32,
) -> f64 {
    let oc = origin - g.centre;
    let b = oc.dot(dir);
    let disc = b * b - (oc.length_squared() - g.radius * g.radius);
    let t = if disc > 0.0 {
        if inside {
            -b + disc.sqrt()
        } else {
            -b - disc.sqrt()
        }
    } else {
        -1.0
    };
    if t <= 1e-9 {
        if dir.y <= 0.0 {
            return 0.0;
        }
        let q = origin + dir * ((g.lamp_y - origin.y) / dir.y);
        let on_lamp =
            (g.lamp_x.0..=g.lamp_x.1).contains(&q.x) && (g.lamp_z.0..=g.lamp_z.1).contains(&q.z);
        return if on_lamp { weight } else { 0.0 };
    }
    if depth == 12 {
        return 0.0;
    }
    let p = origin + dir * t;
    let n = if inside {
        (g.centre - p) / g.radius
    } else {
        (p - g.centre) / g.radius
    };
    let c = -dir.dot(n);
    let eta = if inside { 1.0 / g.ior } else { g.ior };
    let (r, cos_t) = fresnel(c, eta);
    // The spawned origin, moved along ±n to the side the new ray leaves on.
    let (frame_centre, frame_scale) = g.frame;
    let offset = g.origin_offset * (1.0 + (frame_scale * (p - frame_centre)).abs().max_element())
        / frame_scale;
    let mut sum = 0.0;
    if weight * r > 1e-9 {
        let reflected = (dir + 2.0 * c * n).normalize();
        let o = p + n * offset;
        sum += lamp_weight(g, o, reflected, inside, weight * r, depth + 1);
    }
    if let Some(ct) = cos_t.filter(|_| weight * (1.0 - r) > 1e-9) {
        let refracted = (dir / eta + (c / eta - ct) * n).normalize();
        let o = p - n * offset;
        sum += lamp_weight(g, o, refracted, !inside, weight * (1.0 - r), depth + 1);
    }
    sum
}

/// Camera ray through raster position (x, y) (pixels from the top-left corner), pinhole,
/// horizontal field of view, y up.
fn camera_ray(g: &Geometry, x: f64, y: f64) -> DVec3 {
    let forward = (g.look_at - g.eye).normalize();
    let right = forward.cross(DVec3::Y).normalize();
    let up = right.cross(forward);
    let tan_x = (g.fov_x_deg.to_radians() * 0.5).tan();
    let tan_y = tan_x * g.resolution.1 / g.resolution.0;
    let cx = (2.0 * x / g.resolution.0 - 1.0) * tan_x;
    let cy = (1.0 - 2.0 * y / g.resolution.1) * tan_y;
    (forward + right * cx + up * cy).normalize()
}

/// Mean of the lamp weight over the raster rectangle [x0, x1] × [y0, y1] on an n × n grid of
/// cell centres, times the rectangle's area (pixels²).
fn grid_integral(
    g: &Geometry,
    (x0, x1, y0, y1): (f64, f64, f64, f64),
    n: usize,
) -> (f64, Option<[f64; 4]>) {
    let mut sum = 0.0;
    let mut bounds: Option<[f64; 4]> = None;
    for j in 0..n {
        let y = y0 + (j as f64 + 0.5) / n as f64 * (y1 - y0);
        for i in 0..n {
            let x = x0 + (i as f64 + 0.5) / n as f64 * (x1 - x0);
            let w = lamp_weight(g, g.eye, camera_ray(g, x, y), false, 1.0, 0);
            if w > 0.0 {
                sum += w;
                let b = bounds.get_or_insert([x, x, y, y]);
                *b = [b[0].min(x), b[1].max(x), b[2].min(y), b[3].max(y)];
            }
        }
    }
    (sum / (n * n) as f64 * (x1 - x0) * (y1 - y0), bounds)
}

/// The pixel's mean lamp weight: a `coarse`² grid finds where the lamp's image lies in the
/// pixel (grown by two cells), a `fine`² grid over that box integrates it. The images in
/// scenes/caustic.ron are slivers (the grazing one 0.035 pixel tall), which a grid over the
/// whole pixel resolves only to about 1% (measured: 0.8494 at 600² against 0.8582 over the
/// box).
fn pixel_lamp_weight(g: &Geometry, px: u32, py: u32, coarse: usize, fine: usize) -> f64 {
    let (x, y) = (px as f64, py as f64);
    let Some(b) = grid_integral(g, (x, x + 1.0, y, y + 1.0), coarse).1 else {
        return 0.0;
    };
    let grow = 2.0 / coarse as f64;
    let (x0, x1) = ((b[0] - grow).max(x), (b[1] + grow).min(x + 1.0));
    let (y0, y1) = ((b[2] - grow).max(y), (b[3] + grow).min(y + 1.0));
    grid_integral(g, (x0, x1, y0, y1), fine).0
}

/// The lamp's luminance Y (film convention, Y = Σ L ȳ / Σ ȳ over integer nm): `scale` times
/// the spectrum `spec` normalised to unit area, integrated against the scene's observer.
fn lamp_luminance(scene: &Scene, spec: &str, scale: f64) -> f64 {
    let spd = spectrace::spectrum::spec::parse_spd_spec(spec).unwrap();
    let (lo, hi) = spd.range();
    let steps = ((hi - lo) * 10.0) as usize;
    let area: f64 = (0..steps)
        .map(|k| {
            let l = lo + k as f64 * 0.1;
            0.05 * (spd.value(l) + spd.value(l + 0.1))
        })
        .sum();
    let obs = &scene.observer;
    let (a, b) = obs.range();
    let (mut num, mut den) = (0.0, 0.0);
    for l in (a.ceil() as i64)..=(b.floor() as i64) {
        let y_bar = obs.xyz_bar(l as f64)[1];
        num += spd.value(l as f64) / area * y_bar;
        den += y_bar;
    }
    scale * num / den
}

/// `scene` rendered by `kind` under `plan`, `spp` samples per pixel at `seed`, all threads, the
/// scene's own depth.
fn render(scene: &Scene, plan: &RenderPlan, kind: IntegratorKind, spp: u32, seed: u64) -> XyzImage {
    let settings = common_render::spp_settings(scene, spp, seed);
    render_planned(scene, plan, &settings, kind, false, &|_, _| {}, None)
        .unwrap()
        .result
        .image
}

/// Mean and standard error of the mean of per-seed values.
fn mean_se(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

/// Quantity: the luminance Y of the two pixel pairs where the lamp appears in the ball
/// (rows 31 and 26, columns 79–80: the reflection at the top with a T R R T image in the same
/// pixels, and the grazing T R R T image), BDPT with its camera-side specular chains, 8
/// seeds × 64 spp, against the geometric integral times the lamp's luminance.
/// Tolerance: 4 standard errors of the seeds' mean (measured about 0.7% of the value for
/// each pair) plus 0.3% for the integral's grid (its 700² and 1400² boxes differ by 0.01%);
/// the seeds' standard error must itself stay under 1.2% so that a 3% error (the Mitsuba
/// reference's shortfall at the reflection) cannot pass. Measured: +0.99% and +1.04% (seeds
/// 1–8; over 64 seeds × 64 spp, +0.11% ± 0.15% and +0.14% ± 0.15%).
#[test]
fn lamp_images_match_the_geometric_integral() {
    let scene = scene();
    let y_lamp = lamp_luminance(&scene, "d65", LAMP_SCALE);
    // The lamp is 480,000 × D65 normalised to unit area: Y ≈ 1253 (spectrace's own render of
    // the lamp seen directly gives the same within its noise; here it is computed apart).
    assert!((y_lamp - 1253.4).abs() < 1.0, "lamp luminance {y_lamp}");
    let pixels = [(79u32, 31u32), (80, 31), (79, 26), (80, 26)];
    let expected: Vec<f64> = pixels
        .iter()
        .map(|&(x, y)| y_lamp * pixel_lamp_weight(&CAUSTIC, x, y, 300, 700))
        .collect();
    let plan = RenderPlan::new(&scene, &common_render::every_light_subpath());
    assert!(
        plan.camera_chain(),
        "the plan must render the lamp images by chains"
    );
    let seeds = 8;
    let mut pairs = vec![[0.0f64; 2]; seeds];
    for (s, pair) in pairs.iter_mut().enumerate() {
        let img = &render(&scene, &plan, IntegratorKind::Bdpt, 64, s as u64 + 1);
        let y_at = |(x, y): (u32, u32)| img.xyz[(y * img.width + x) as usize][1];
        *pair = [
            y_at(pixels[0]) + y_at(pixels[1]),
            y_at(pixels[2]) + y_at(pixels[3]),
        ];
    }
    for (k, what) in ["the reflection (row 31)", "the grazing image (row 26)"]
        .iter()
        .enumerate()
    {
        let want = expected[2 * k] + expected[2 * k + 1];
        let xs: Vec<f64> = pairs.iter().map(|p| p[k]).collect();
        let (mean, se) = mean_se(&xs);
        eprintln!(
            "{what}: BDPT {mean:.4} ± {se:.4} (8 seeds × 64 spp), geometric integral {want:.4}, \
             {:+.2}%",
            100.0 * (mean / want - 1.0)
        );
        assert!(
            want > 0.5,
            "{what}: the integral found no lamp image ({want})"
        );
        assert!(
            se < 0.012 * want,
            "{what}: too noisy to decide ({se} of {want})"
        );
        assert!(
            (mean - want).abs() <= 4.0 * se + 0.003 * want,
            "{what}: BDPT {mean} ± {se} against {want}"
        );
    }
}

/// scenes/bench/glass_sphere.ron's camera (a change there fails `bench_scene()`).
const BENCH: Geometry = Geometry {
    eye: DVec3::new(-0.5, 0.2, 0.3),
    look_at: DVec3::new(-0.04, 0.05, 0.0),
    fov_x_deg: 30.0,
    resolution: (160.0, 120.0),
    centre: DVec3::new(0.0, 0.1, 0.0),
    radius: 0.1,
    ior: 1.5,
    lamp_y: 0.8,
    lamp_x: (0.45, 0.55),
    lamp_z: (-0.05, 0.05),
    origin_offset: 0.0,
    frame: (DVec3::ZERO, 1.0),
};
/// The bench camera's raster window (x0, y0, width, height in its pixels) that the zoomed
/// camera covers: the lamp's image at the sphere's lower grazing edge (bench pixels
/// x 71–77, y 77–79), where Mitsuba 3's reference departs from this integral.
const WINDOW: (f64, f64, f64, f64) = (68.5, 75.5, 12.0, 6.0);
/// Zoomed pixels per bench pixel.
const ZOOM: f64 = 4.0;

/// The zoomed camera: same eye, looking at the window's centre, its width as field of view.
fn zoomed() -> Geometry {
    let (x0, y0, w, h) = WINDOW;
    let centre = BENCH.eye + camera_ray(&BENCH, x0 + 0.5 * w, y0 + 0.5 * h);
    let tan_x = (BENCH.fov_x_deg.to_radians() * 0.5).tan() * w / BENCH.resolution.0;
    Geometry {
        look_at: centre,
        fov_x_deg: 2.0 * tan_x.atan().to_degrees(),
        resolution: (w * ZOOM, h * ZOOM),
        ..BENCH
    }
}

/// scenes/bench/glass_sphere.ron without its floor, seen by the zoomed camera.
fn bench_scene(g: &Geometry) -> Scene {
    const FLOOR: &str = r#"        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
"#;
    const CAMERA: &str = "params: (position: (-0.5, 0.2, 0.3), look_at: (-0.04, 0.05, 0), \
                          fov: 30,\n                  resolution: (160, 120))";
    let text = include_str!("../../scenes/bench/glass_sphere.ron");
    assert!(
        text.contains(FLOOR) && text.contains(CAMERA),
        "bench/glass_sphere.ron changed"
    );
    for needle in [
        "center: (0, 0.1, 0), radius: 0.1",
        "ior: 1.5",
        "corner: (0.45, 0.8, -0.05), edge0: (0.1, 0, 0), edge1: (0, 0, 0.1)",
        "radiance: \"e\", scale: 50000.0",
    ] {
        assert!(
            text.contains(needle),
            "bench/glass_sphere.ron changed: {needle}"
        );
    }
    let camera = format!(
        "params: (position: (-0.5, 0.2, 0.3), look_at: ({:.9}, {:.9}, {:.9}), fov: {:.9}, \
         resolution: ({}, {}))",
        g.look_at.x, g.look_at.y, g.look_at.z, g.fov_x_deg, g.resolution.0, g.resolution.1
    );
    let text = text.replace(FLOOR, "").replace(CAMERA, &camera);
    let file = Path::new("bench_glass_sphere_ball_only.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// Quantity: the luminance Y of every pixel of the lamp's image at the bench glass sphere's
/// lower grazing edge (scenes/bench/glass_sphere.ron without its floor, a camera zoomed 4× on
/// bench pixels x 68.5–80.5, y 75.5–81.5), path tracing and BDPT, 16 seeds × 256 spp each,
/// against the geometric integral times the lamp's luminance, in the (about 40) pixels whose
/// integral is at least 20% of the largest; and the image's sum.
/// Statistic and tolerance: per pixel z = (mean − integral) / √(SE² + (0.5%·integral)²), the
/// 0.5% for the integral's grid (120² cells over the image's box in a pixel; 1000² cells over
/// the whole pixel, computed apart, differ by 0.01%). The mean of z² must be ≤ 2: with SEs
/// from 16 seeds it is 15/13 ≈ 1.15 in expectation, with a standard deviation of about 0.25
/// over 40 pixels (most of a pixel's noise is the Fresnel choice at grazing incidence, not
/// its area), so 2 is a 3.5σ bound; no single |z| may exceed 6. The sum must agree within 4
/// SE + 0.5%.
/// Why: in these pixels a Mitsuba 3 reference rendered in the scene's own frame departs from
/// this integral by −23% to +37% (bench pixels x 75 y 78 and x 74 y 79, four seeds × 16k spp,
/// ±2–4%), and the same integral with origins moved off the surface as Mitsuba 3 moves them
/// reproduces its values within 3% (docs/performance.md). The test computes that integral too
/// and requires the renders' mean z² against it to be ≥ 10, so an error of that kind cannot
/// pass; and it checks that the frame the bench's anchors render in shrinks that error to a
/// few percent.
#[test]
fn bench_sphere_grazing_image_matches_the_geometric_integral() {
    let g = zoomed();
    let scene = bench_scene(&g);
    let y_lamp = lamp_luminance(&scene, "e", 50000.0);
    let (w, h) = (g.resolution.0 as u32, g.resolution.1 as u32);
    let exact: Vec<f64> = (0..w * h)
        .map(|i| y_lamp * pixel_lamp_weight(&g, i % w, i / w, 40, 120))
        .collect();
    let peak = exact.iter().cloned().fold(0.0, f64::max);
    let checked: Vec<usize> = (0..exact.len())
        .filter(|&i| exact[i] >= 0.2 * peak)
        .collect();
    assert!(
        checked.len() >= 40,
        "the lamp image covers {} pixels",
        checked.len()
    );
    // The same integral with Mitsuba 3's origin offsets.
    let offset = Geometry {
        origin_offset: 1500.0 * 2f64.powi(-24),
        ..zoomed()
    };
    let moved: Vec<f64> = checked
        .iter()
        .map(|&i| y_lamp * pixel_lamp_weight(&offset, i as u32 % w, i as u32 / w, 40, 120))
        .collect();
    let worst_offset = checked
        .iter()
        .zip(&moved)
        .map(|(&i, m)| (m / exact[i] - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "{} pixels checked, peak Y {peak:.2}; with Mitsuba 3's origin offsets the integral \
         departs by up to {:.0}%",
        checked.len(),
        100.0 * worst_offset
    );
    assert!(
        worst_offset > 0.15,
        "offsets change the image by only {worst_offset}"
    );
    // The same offsets in the frame the bench's anchors render in (centred on the ball,
    // scaled so its box's diagonal is 100; the offset is then about 1e-4 of the radius, the
    // least Mitsuba 3's relative epsilon allows): every checked pixel within 5% of the exact
    // integral (3.4% measured, 41% in the scene's own frame; at the bench's own pixels, printed
    // below, at most 3% against 35%), so the bench's reference no longer carries that error.
    let anchor_frame = Geometry {
        frame: (g.centre, 100.0 / (2.0 * g.radius * 3f64.sqrt())),
        ..offset
    };
    let worst_frame = checked
        .iter()
        .map(|&i| {
            let m = y_lamp * pixel_lamp_weight(&anchor_frame, i as u32 % w, i as u32 / w, 40, 120);
            (m / exact[i] - 1.0).abs()
        })
        .fold(0.0, f64::max);
    eprintln!(
        "in the anchors' frame the offset integral departs by up to {:.2}%",
        100.0 * worst_frame
    );
    assert!(
        worst_frame < 0.05,
        "the anchors' frame leaves a departure of {worst_frame}"
    );

    // The bench camera's own pixels of that image, exact and with the offsets (printed for
    // docs/performance.md's table; the renders above are checked on the zoomed pixels).
    let bench_offset = Geometry {
        origin_offset: offset.origin_offset,
        ..BENCH
    };
    let bench_frame = Geometry {
        frame: anchor_frame.frame,
        ..bench_offset
    };
    for (x, y) in [(75, 78), (74, 79), (72, 77), (75, 79), (74, 78)] {
        let exact = y_lamp * pixel_lamp_weight(&BENCH, x, y, 300, 700);
        let moved = y_lamp * pixel_lamp_weight(&bench_offset, x, y, 300, 700);
        let framed = y_lamp * pixel_lamp_weight(&bench_frame, x, y, 300, 700);
        eprintln!(
            "bench pixel ({x}, {y}): Y {exact:.3}, with Mitsuba 3's offsets {moved:.3} ({:+.1}%), \
             in the anchors' frame {framed:.3} ({:+.2}%)",
            100.0 * (moved / exact - 1.0),
            100.0 * (framed / exact - 1.0)
        );
    }
    let plan = RenderPlan::new(&scene, &common_render::every_light_subpath());
    const SPP: u32 = 256;
    for kind in [IntegratorKind::Pt, IntegratorKind::Bdpt] {
        let seeds = 16;
        let images: Vec<Vec<f64>> = (0..seeds)
            .map(|s| {
                render(&scene, &plan, kind, SPP, s as u64 + 1)
                    .xyz
                    .iter()
                    .map(|p| p[1])
                    .collect()
            })
            .collect();
        // z of each pixel against the exact integral and against the offset one; the
        // integral's own grid error (0.5% of the value) is added to the standard error.
        let (mut z2, mut z2_offset, mut worst) = (0.0, 0.0, 0.0f64);
        for (&i, m) in checked.iter().zip(&moved) {
            let (mean, se) = mean_se(&images.iter().map(|im| im[i]).collect::<Vec<_>>());
            let sd = se.hypot(0.005 * exact[i]);
            let z = (mean - exact[i]) / sd;
            assert!(
                z.abs() <= 6.0,
                "{kind:?}: pixel ({}, {}) Y {mean:.3} ± {se:.3}, integral {:.3}",
                i as u32 % w,
                i as u32 / w,
                exact[i]
            );
            z2 += z * z;
            z2_offset += ((mean - m) / sd).powi(2);
            worst = worst.max((mean / exact[i] - 1.0).abs());
        }
        let n = checked.len() as f64;
        let (z2, z2_offset) = (z2 / n, z2_offset / n);
        eprintln!(
            "{kind:?}: mean z² {z2:.2} against the integral, {z2_offset:.1} against the one with \
             Mitsuba 3's offsets; largest pixel departure {:.1}%",
            100.0 * worst
        );
        assert!(z2 <= 2.0, "{kind:?}: mean z² {z2}");
        assert!(
            z2_offset >= 10.0,
            "{kind:?}: cannot tell the offsets apart ({z2_offset})"
        );
        let sums: Vec<f64> = images.iter().map(|im| im.iter().sum()).collect();
        let (sum, se) = mean_se(&sums);
        let want: f64 = exact.iter().sum();
        eprintln!(
            "{kind:?}: image sum {sum:.2} ± {se:.2} against {want:.2} ({:+.2}%)",
            100.0 * (sum / want - 1.0)
        );
        assert!((sum - want).abs() <= 4.0 * se + 0.005 * want);
    }
}

/// Quantity: the sum of luminance Y over every pixel of the bench camera that sees the lamp in
/// the ball (scenes/bench/glass_sphere.ron without its floor, at the bench's own 160 × 120
/// camera: 54 pixels), BDPT and the path tracer, 16 seeds × 64 spp each, against the
/// geometric integral times the lamp's luminance.
/// Tolerance: 4 standard errors of the seeds' mean plus 0.5% for the integral's grid.
/// Why: in the bench, BDPT's "lamp images" region sat 1.6–3.2% below Mitsuba 3's reference
/// (z −2.0 to −3.5) over four three-seed runs, Mitsuba's own renders 0.4–1.6% and the path
/// tracer 0.2–2.2%, while the region was drawn from the reference it was compared with (the
/// selection docs/performance.md describes; now it is not). That region is mostly the floor's
/// caustic seen through the ball (light, glass, floor, glass, camera); the lamp's own images
/// are these 54 pixels, which this checks (measured: BDPT +0.80% ± 0.21%).
/// A measurement (about a minute on two cores): `cargo test --release -p spectrace --test
/// caustic_lamp_images -- --ignored --nocapture`.
#[test]
#[ignore = "measurement, a minute: run with --ignored"]
fn bench_sphere_whole_lamp_image_matches_the_geometric_integral() {
    let g = BENCH;
    let scene = bench_scene(&g);
    let y_lamp = lamp_luminance(&scene, "e", 50000.0);
    let w = g.resolution.0 as u32;
    // The ball covers about x 40–120, y 30–100 of the bench image; the lamp's images lie in it.
    let window: Vec<(u32, u32)> = (30..100)
        .flat_map(|y| (40..120).map(move |x| (x, y)))
        .collect();
    let exact: Vec<(u32, u32, f64)> = window
        .iter()
        .map(|&(x, y)| (x, y, y_lamp * pixel_lamp_weight(&g, x, y, 40, 120)))
        .filter(|p| p.2 > 0.0)
        .collect();
    let want: f64 = exact.iter().map(|p| p.2).sum();
    let plan = RenderPlan::new(&scene, &common_render::every_light_subpath());
    for kind in [IntegratorKind::Bdpt, IntegratorKind::Pt] {
        let sums: Vec<f64> = (0..16)
            .map(|s| {
                let im = render(&scene, &plan, kind, 64, s as u64 + 1);
                exact
                    .iter()
                    .map(|p| im.xyz[(p.1 * w + p.0) as usize][1])
                    .sum()
            })
            .collect();
        let (sum, se) = mean_se(&sums);
        eprintln!(
            "{kind:?}: {} pixels, Y sum {sum:.2} ± {se:.2} against {want:.2} ({:+.2}% ± {:.2}%)",
            exact.len(),
            100.0 * (sum / want - 1.0),
            100.0 * se / want
        );
        assert!(
            (sum - want).abs() <= 4.0 * se + 0.005 * want,
            "{kind:?}: {sum} ± {se} against {want}"
        );
    }
}
