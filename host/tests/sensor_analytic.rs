//! Illuminance sensors against analytic lighting cases in the spirit of CIE 171:2006 (test
//! cases for lighting simulation software), in lux, for each sensor estimator: sensor path
//! tracing (used by `--integrator pt` and `bdpt`) and light tracing (`--integrator lt`).
//!
//! Every case compares each point with the closed form within `4σ + 0.1 %`: σ is the point's
//! own standard error (samples are independent), so an unbiased estimator passes with
//! probability > 0.9999 per point; the 0.1 % covers the reference's 1 nm quadrature of
//! ∫ spd·V dλ against the renderer's interpolated observer table, and f32 geometry. Each case
//! also requires σ below 2 % of the value, so the tolerance is tight enough to catch a missing
//! cos θ, π or 683 (errors of 10 % and more). Light is spectrally flat (`e`), so the reference
//! is `683 lm/W × radiometric × Σ spd(λ)·ȳ(λ)` over the CIE 1931 2° table.

use spectrace::color::{CieObserverKind, Observer};
use spectrace::integrator::{IntegratorKind, PathTracer};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use spectrace::sensor::{measure, Estimator, MeasureSettings, SensorReading, KM_LM_PER_W};
use spectrace::spectrum::{parse_spd_spec, Spd};
use std::f64::consts::PI;
use std::path::Path;

/// `K_m ∫ spd(λ) V(λ) dλ` of the normalised spectrum `spec` (1 nm sum): lumens per watt of it.
fn efficacy(spec: &str) -> f64 {
    let spd = parse_spd_spec(spec).unwrap();
    let obs = CieObserverKind::Cie1931_2.get();
    let (lo, hi) = obs.range();
    let mut s = 0.0;
    let mut l = lo.ceil();
    while l <= hi {
        s += spd.value(l) * obs.xyz_bar(l)[1];
        l += 1.0;
    }
    KM_LM_PER_W * s
}

fn scene(text: &str) -> Scene {
    let desc = parse_scene_str(text, Path::new("sensor_case.ron")).unwrap();
    build_scene(
        &desc,
        Path::new("."),
        Path::new("sensor_case.ron"),
        &[&BuiltinFactory],
    )
    .unwrap()
}

fn read(scene: &Scene, name: &str, estimator: Estimator, samples: u32) -> SensorReading {
    let grid = scene.sensors.iter().find(|g| g.name == name).unwrap();
    let settings = MeasureSettings {
        estimator,
        samples,
        seed: 7,
        threads: None,
        tracer: PathTracer::default(),
    };
    measure(scene, grid, &settings).unwrap()
}

/// The estimators of the three integrators (bdpt measures with the sensor path tracer).
fn estimators() -> [(&'static str, Estimator); 2] {
    [
        ("pt/bdpt", Estimator::for_integrator(IntegratorKind::Pt)),
        ("lt", Estimator::for_integrator(IntegratorKind::Lt)),
    ]
}

/// Each point of `r` within 4σ + 0.1 % of `want[k]`, with σ < 2 % of it.
fn check(case: &str, r: &SensorReading, want: &[f64]) {
    assert_eq!(r.lux.len(), want.len());
    assert_eq!(r.non_finite, 0, "{case}");
    for (k, ((&got, &se), &w)) in r.lux.iter().zip(&r.stderr).zip(want).enumerate() {
        let tol = 4.0 * se + 1e-3 * w;
        println!(
            "{case} point {k}: {got:.4} lx (σ {se:.4}), analytic {w:.4} lx, off {:+.3} %",
            (got / w - 1.0) * 100.0
        );
        assert!(se < 0.02 * w, "{case} point {k}: σ {se} too large for {w}");
        assert!(
            (got - w).abs() <= tol,
            "{case} point {k}: {got} lx vs analytic {w} lx (σ {se})"
        );
    }
}

/// Bdpt renders measure with the sensor path tracer, lt with light tracing, pt with the sensor
/// path tracer: the run-time line names them.
#[test]
fn integrators_choose_their_estimator() {
    assert_eq!(
        Estimator::for_integrator(IntegratorKind::Bdpt),
        Estimator::SensorPathTracing
    );
    assert_eq!(
        Estimator::for_integrator(IntegratorKind::Pt),
        Estimator::SensorPathTracing
    );
    assert_eq!(
        Estimator::for_integrator(IntegratorKind::Lt),
        Estimator::LightTracing
    );
}

/// CIE 171 point source over a plane: an isotropic 100 W point light 2 m above a black floor,
/// five points on the floor at 0, 0.75, 1.5, 2.25 and 3 m from the nadir:
/// E = I·cos³θ / h², I = 683·Φ/(4π)·∫spd V.
#[test]
fn point_source_over_a_plane() {
    let h = 2.0;
    let s = scene(
        r#"(
        materials: [(name: "black", type: "lambertian", params: (reflectance: 0))],
        objects: [(name: "floor", type: "quad", material: "black",
                   params: (corner: (-10, 0, 10), edge0: (20, 0, 0), edge1: (0, 0, -20)))],
        lights: [(name: "p", type: "point", params: (position: (0, 2, 0), power: 100, spd: "e"))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (4, 4)))],
        sensors: [(name: "row", type: "illuminance_grid",
                   params: (corner: (-0.375, 0, 0.01), edge0: (3.75, 0, 0), edge1: (0, 0, -0.02),
                            resolution: (5, 1)))],
    )"#,
    );
    let i_cd = efficacy("e") * 100.0 / (4.0 * PI);
    let want: Vec<f64> = (0..5)
        .map(|k| {
            let r = 0.75 * k as f64;
            let cos = h / (h * h + r * r).sqrt();
            i_cd * cos.powi(3) / (h * h)
        })
        .collect();
    for (name, est) in estimators() {
        check(
            &format!("point source ({name})"),
            &read(&s, "row", est, 4096),
            &want,
        );
    }
}

/// CIE 171 directional source on a tilted plane: E⊥ = 10 W/m² straight down; receivers
/// tilted by 0°, 30°, 60° and 80° from the horizontal read E = E⊥·cos θ (683·10·∫spd V lx
/// facing the light).
#[test]
fn directional_source_on_tilted_planes() {
    let tilts = [0.0f64, 30.0, 60.0, 80.0];
    let sensors: Vec<String> = tilts
        .iter()
        .enumerate()
        .map(|(k, t)| {
            let (s, c) = t.to_radians().sin_cos();
            let e = 0.01;
            // edge0 × edge1 = (sin θ, cos θ, 0): the normal tilted from +y towards +x.
            format!(
                r#"(name: "tilt{k}", type: "illuminance_grid",
                    params: (corner: ({x}, 1, 0), edge0: (0, 0, {e}), edge1: ({c1}, {s1}, 0),
                             resolution: (1, 1)))"#,
                x = k as f64 * 0.5,
                c1 = c * e,
                s1 = -s * e
            )
        })
        .collect();
    let s = scene(&format!(
        r#"(
        materials: [(name: "black", type: "lambertian", params: (reflectance: 0))],
        objects: [(name: "floor", type: "quad", material: "black",
                   params: (corner: (-10, 0, 10), edge0: (20, 0, 0), edge1: (0, 0, -20)))],
        lights: [(name: "sun", type: "directional",
                  params: (direction: (0, -1, 0), irradiance: 10, spd: "e"))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (4, 4)))],
        sensors: [{}],
    )"#,
        sensors.join(",")
    ));
    let e_perp = efficacy("e") * 10.0;
    for (name, est) in estimators() {
        for (k, t) in tilts.iter().enumerate() {
            let want = e_perp * t.to_radians().cos();
            check(
                &format!("directional, tilt {t}° ({name})"),
                &read(&s, &format!("tilt{k}"), est, 1024),
                &[want],
            );
        }
    }
}

/// The configuration factor of a point to a polygon by Lambert's contour formula
/// (F = 1/(2π) Σ γᵢ n·(Rᵢ × Rᵢ₊₁)/|Rᵢ × Rᵢ₊₁|, the polygon wholly in front of the receiver).
fn polygon_factor(p: [f64; 3], n: [f64; 3], verts: &[[f64; 3]]) -> f64 {
    let unit = |v: [f64; 3]| {
        let d = [v[0] - p[0], v[1] - p[1], v[2] - p[2]];
        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        [d[0] / l, d[1] / l, d[2] / l]
    };
    let mut s = 0.0;
    for i in 0..verts.len() {
        let (a, b) = (unit(verts[i]), unit(verts[(i + 1) % verts.len()]));
        let c = [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ];
        let cl = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        let g = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
            .clamp(-1.0, 1.0)
            .acos();
        s += g * (n[0] * c[0] + n[1] * c[1] + n[2] * c[2]) / cl;
    }
    s.abs() / (2.0 * PI)
}

/// Point below a corner of a parallel a×b rectangle at distance c (Howell's catalogue of
/// configuration factors): F = 1/(2π)[X/√(1+X²)·atan(Y/√(1+X²)) + Y/√(1+Y²)·atan(X/√(1+Y²))],
/// X = a/c, Y = b/c.
fn parallel_corner_factor(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

/// Point on a plane perpendicular to an a×b rectangle, on the line of its edge of length b, at
/// distance c from the rectangle's plane, facing along its sides of length a (Howell):
/// F = 1/(2π)[atan(1/Y) − Y/√(X²+Y²)·atan(1/√(X²+Y²))], X = a/b, Y = c/b.
fn perpendicular_corner_factor(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / b, c / b);
    let r = (x * x + y * y).sqrt();
    ((1.0 / y).atan() - y / r * (1.0 / r).atan()) / (2.0 * PI)
}

/// The two closed forms agree with Lambert's polygon formula (1e-12): the references of
/// [`diffuse_rectangle_and_receivers`] are checked against an independent formula.
#[test]
fn form_factor_formulas_agree() {
    let (a, b, c) = (1.0, 2.0, 1.5);
    let par = polygon_factor(
        [0.0; 3],
        [0.0, 1.0, 0.0],
        &[[0.0, c, 0.0], [a, c, 0.0], [a, c, b], [0.0, c, b]],
    );
    assert!((par - parallel_corner_factor(a, b, c)).abs() < 1e-12);
    let perp = polygon_factor(
        [c, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        &[[0.0, 0.0, 0.0], [0.0, a, 0.0], [0.0, a, b], [0.0, 0.0, b]],
    );
    assert!((perp - perpendicular_corner_factor(a, b, c)).abs() < 1e-12);
}

/// CIE 171 diffuse area source: a 1 m × 2 m Lambertian rectangle of radiance 10 W/(m²·sr)
/// (luminance L = 683·10·∫spd V cd/m²), one receiver point 1.5 m below a corner facing it
/// (parallel) and one in a perpendicular plane 0.8 m in front of it: E = π·L·F.
#[test]
fn diffuse_rectangle_and_receivers() {
    let (a, b, c) = (1.0, 2.0, 1.5);
    let d = 0.8;
    let e = 1e-3;
    // Parallel: the rectangle at y = 1.5 over x ∈ [0, 1], z ∈ [0, 2], emitting downwards; the
    // receiver at the origin facing up (edge0 × edge1 = +y).
    let parallel = scene(&format!(
        r#"(
        materials: [(name: "lamp", type: "emissive", params: (radiance: "e", scale: 10))],
        objects: [(name: "lamp", type: "quad", material: "lamp",
                   params: (corner: (0, {c}, 0), edge0: ({a}, 0, 0), edge1: (0, 0, {b})))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0.5, 0.5, 5), look_at: (0.5, 0.5, 0), resolution: (4, 4)))],
        sensors: [(name: "under_corner", type: "illuminance_grid",
                   params: (corner: (-{h}, 0, -{h}), edge0: (0, 0, {e}), edge1: ({e}, 0, 0),
                            resolution: (1, 1)))],
    )"#,
        h = e / 2.0
    ));
    // Perpendicular: the rectangle in the plane x = 0 over y ∈ [0, 1], z ∈ [0, 2], emitting
    // towards +x; the receiver at (0.8, 0, 0) facing +y.
    let perpendicular = scene(&format!(
        r#"(
        materials: [(name: "lamp", type: "emissive", params: (radiance: "e", scale: 10))],
        objects: [(name: "lamp", type: "quad", material: "lamp",
                   params: (corner: (0, 0, 0), edge0: (0, {a}, 0), edge1: (0, 0, {b})))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (3, 0.5, 1), look_at: (0, 0.5, 1), resolution: (4, 4)))],
        sensors: [(name: "beside", type: "illuminance_grid",
                   params: (corner: ({x0}, 0, -{h}), edge0: (0, 0, {e}), edge1: ({e}, 0, 0),
                            resolution: (1, 1)))],
    )"#,
        x0 = d - e / 2.0,
        h = e / 2.0
    ));
    let lum = efficacy("e") * 10.0;
    let want_par = PI * lum * parallel_corner_factor(a, b, c);
    let want_perp = PI * lum * perpendicular_corner_factor(a, b, d);
    for (name, est) in estimators() {
        check(
            &format!("rectangle, parallel receiver ({name})"),
            &read(&parallel, "under_corner", est, 65536),
            &[want_par],
        );
        check(
            &format!("rectangle, perpendicular receiver ({name})"),
            &read(&perpendicular, "beside", est, 65536),
            &[want_perp],
        );
    }
}

/// An integrating sphere of radius 1 m with diffuse reflectance ρ and a 100 W point source
/// at its centre: every point of the wall reads E = Φ/(S·(1 − ρ)), S = 4πR² (direct Φ/S plus
/// the inter-reflected ρΦ/(S(1 − ρ)), uniform in a sphere). Six receivers on the wall facing
/// inwards.
fn enclosure(rho: f64, samples: u32) {
    let r = 1.0 - 1e-5;
    let dirs = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let e = 1e-3;
    let sensors: Vec<String> = dirs
        .iter()
        .enumerate()
        .map(|(k, d)| {
            // Inward normal −d = edge0 × edge1 with edge0, edge1 ⟂ d.
            let n = glam::DVec3::from_array(*d) * -1.0;
            let t = if n.x.abs() < 0.5 {
                glam::DVec3::X
            } else {
                glam::DVec3::Y
            };
            let u = n.cross(t).normalize() * e;
            let v = n.cross(u).normalize() * e;
            assert!((u.cross(v).normalize() - n).length() < 1e-12);
            let p = glam::DVec3::from_array(*d) * r - (u + v) * 0.5;
            format!(
                r#"(name: "wall{k}", type: "illuminance_grid",
                    params: (corner: ({}, {}, {}), edge0: ({}, {}, {}), edge1: ({}, {}, {}),
                             resolution: (1, 1)))"#,
                p.x, p.y, p.z, u.x, u.y, u.z, v.x, v.y, v.z
            )
        })
        .collect();
    let s = scene(&format!(
        r#"(
        materials: [(name: "wall", type: "lambertian", params: (reflectance: {rho}))],
        objects: [(name: "sphere", type: "sphere", material: "wall", params: (radius: 1))],
        lights: [(name: "p", type: "point", params: (position: (0, 0, 0), power: 100, spd: "e"))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 0, 0.5), look_at: (0, 0, -1), resolution: (4, 4)))],
        sensors: [{}],
    )"#,
        sensors.join(",")
    ));
    let phi = efficacy("e") * 100.0;
    let want = phi / (4.0 * PI * (1.0 - rho));
    for (name, est) in estimators() {
        let readings: Vec<SensorReading> = (0..dirs.len())
            .map(|k| read(&s, &format!("wall{k}"), est, samples))
            .collect();
        for (k, rd) in readings.iter().enumerate() {
            check(&format!("sphere ρ = {rho}, wall {k} ({name})"), rd, &[want]);
        }
    }
}

/// The enclosure with ρ = 0.5 (half the light is inter-reflected).
#[test]
fn enclosure_with_uniform_reflectance() {
    enclosure(0.5, 4096);
}

/// The enclosure with ρ = 0.9 (90 % inter-reflected, long paths): about 13 s on 2 cores, run with
/// `--ignored`.
#[test]
#[ignore]
fn enclosure_with_high_reflectance() {
    enclosure(0.9, 65536);
}

/// Same seed, same reading for 1 and 3 threads (bit for bit), for both estimators.
#[test]
fn readings_do_not_depend_on_threads() {
    let s = scene(
        r#"(
        materials: [(name: "grey", type: "lambertian", params: (reflectance: 0.5))],
        objects: [(name: "floor", type: "quad", material: "grey",
                   params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
                  (name: "wall", type: "quad", material: "grey",
                   params: (corner: (-2, 0, -1), edge0: (4, 0, 0), edge1: (0, 2, 0)))],
        lights: [(name: "p", type: "point", params: (position: (0, 1, 0), power: 10, spd: "e"))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (4, 4)))],
        sensors: [(name: "g", type: "illuminance_grid",
                   params: (corner: (-1, 0, 1), edge0: (2, 0, 0), edge1: (0, 0, -2), resolution: (3, 3)))],
    )"#,
    );
    for (_, est) in estimators() {
        let run = |threads| {
            let settings = MeasureSettings {
                estimator: est,
                samples: 700,
                seed: 3,
                threads: Some(threads),
                tracer: PathTracer::default(),
            };
            measure(&s, &s.sensors[0], &settings).unwrap()
        };
        assert_eq!(run(1), run(3));
    }
}

/// Luminance from a camera (`--luminance-out`): a Lambertian floor of reflectance 0.5 under a
/// 100 W point light 2 m above, seen straight down by a 4×4 pinhole of 0.5° field, reads
/// L = ρ·E/π cd/m² with E = I/h² (the floor is lit uniformly to < 0.01 % over the ~9 mm
/// viewed). Direct light only, 1024 spp. Tolerance: 4× the standard error of the 16 pixels'
/// mean plus 0.1 % (quadrature, as above); with stratified wavelengths the pixels agree far
/// better than independent samples would (measured: 2e-6 off), so the 0.1 % is what binds and
/// a missing 683, π or ∫ȳ (factors of 2 and more) cannot pass.
#[test]
fn luminance_of_a_lit_floor() {
    use spectrace::integrator::{render, RenderSettings, SampleBudget};
    let s = scene(
        r#"(
        materials: [(name: "white", type: "lambertian", params: (reflectance: 0.5))],
        objects: [(name: "floor", type: "quad", material: "white",
                   params: (corner: (-50, 0, 50), edge0: (100, 0, 0), edge1: (0, 0, -100)))],
        lights: [(name: "p", type: "point", params: (position: (0, 2, 0), power: 100, spd: "e"))],
        cameras: [(name: "down", type: "pinhole",
                   params: (position: (0, 1, 0.001), look_at: (0, 0, 0), fov: 0.5, resolution: (4, 4)))],
    )"#,
    );
    let settings = RenderSettings {
        budget: SampleBudget::Spp(1024),
        seed: 5,
        threads: None,
        tracer: PathTracer {
            direct_only: true,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let img = render(&s, &settings, &|_, _| {}, None).unwrap().image;
    let lv = spectrace::sensor::luminance::luminance_cd_m2(&img, s.observer.as_ref()).unwrap();
    let n = lv.len() as f64;
    let mean = lv.iter().sum::<f64>() / n;
    let var = lv.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    let se = (var / n).sqrt();
    let want = 0.5 / PI * efficacy("e") * 100.0 / (4.0 * PI) / 4.0;
    println!("luminance {mean:.4} cd/m² (σ {se:.4}), analytic {want:.4}");
    assert!(se < 0.02 * want, "σ {se} too large for {want}");
    assert!(
        (mean - want).abs() <= 4.0 * se + 1e-3 * want,
        "{mean} cd/m² vs analytic {want} (σ {se})"
    );
}

/// A film with another observer has no luminance channel: the request is refused, naming it.
#[test]
fn luminance_needs_the_photopic_observer() {
    let s = scene(
        r#"(
        observer: "cie1964-10",
        materials: [(name: "white", type: "lambertian", params: (reflectance: 0.5))],
        objects: [(name: "floor", type: "quad", material: "white",
                   params: (corner: (-5, 0, 5), edge0: (10, 0, 0), edge1: (0, 0, -10)))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 1, 1), look_at: (0, 0, 0), resolution: (2, 2)))],
    )"#,
    );
    let img = spectrace::film::XyzImage {
        width: 1,
        height: 1,
        xyz: vec![[1.0; 3]],
    };
    let e = spectrace::sensor::luminance::luminance_cd_m2(&img, s.observer.as_ref()).unwrap_err();
    assert!(e.contains("cie1964-10") && e.contains("1931"), "{e}");
}

/// A real luminaire over a plane: the EULUMDAT LED downlight of `host/data/photometry/`
/// (quadrant symmetric, 2729 cd at the nadir) 2.5 m above a black floor, five points along
/// the C0 plane (+x) and five along C90 (−z): E = I(C, γ)·cos³γ / h² with I read from the
/// candela table by the reader's own bilinear interpolation (`Luminaire::candela_at`). The
/// light is the `luminaire` type (its table importance-sampled); the SPD only sets W per cd.
#[test]
fn real_luminaire_over_a_plane() {
    let file =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("data/photometry/anon_sample07_isym4.ldt");
    let lum = spectrace::photometry::load_luminaire(&file).unwrap();
    let h = 2.5;
    let s = scene(&format!(
        r#"(
        materials: [(name: "black", type: "lambertian", params: (reflectance: 0))],
        objects: [(name: "floor", type: "quad", material: "black",
                   params: (corner: (-10, 0, 10), edge0: (20, 0, 0), edge1: (0, 0, -20)))],
        lights: [(name: "downlight", type: "luminaire",
                  params: (file: "{}", position: (0, {h}, 0), spd: "phosphor_led_yag"))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (4, 4)))],
        sensors: [(name: "c0", type: "illuminance_grid",
                   params: (corner: (-0.4, 0, 0.01), edge0: (4, 0, 0), edge1: (0, 0, -0.02),
                            resolution: (5, 1))),
                  (name: "c90", type: "illuminance_grid",
                   params: (corner: (0.01, 0, 0.4), edge0: (0, 0, -4), edge1: (-0.02, 0, 0),
                            resolution: (5, 1)))],
    )"#,
        file.display()
    ));
    for (sensor, c_deg) in [("c0", 0.0), ("c90", 90.0)] {
        let want: Vec<f64> = (0..5)
            .map(|k| {
                let r = 0.4 + 0.8 * k as f64 - 0.4;
                let gamma = (r / h).atan();
                lum.candela_at(c_deg, gamma.to_degrees()) * gamma.cos().powi(3) / (h * h)
            })
            .collect();
        for (name, est) in estimators() {
            check(
                &format!("luminaire {sensor} ({name})"),
                &read(&s, sensor, est, 4096),
                &want,
            );
        }
    }
}

/// The standard error of a grid's mean illuminance is honest for both estimators: over 16
/// seeds, the spread (sample standard deviation) of the grid means over the mean reported
/// standard error lies in [0.5, 1.6] (a χ² with 15 degrees of freedom puts the ratio of a
/// correct σ there with probability > 0.99). Light tracing adds one path to every point, so
/// its points' errors are correlated: `√Σσᵢ²/n` would claim a standard error several times too
/// small (measured: 6× on `scenes/sensors_downlight.ron`).
#[test]
fn grid_mean_standard_error_is_honest() {
    let s = scene(
        r#"(
        materials: [(name: "grey", type: "lambertian", params: (reflectance: 0.5))],
        objects: [(name: "floor", type: "quad", material: "grey",
                   params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
                  (name: "wall", type: "quad", material: "grey",
                   params: (corner: (-2, 0, -1), edge0: (4, 0, 0), edge1: (0, 2, 0)))],
        lights: [(name: "p", type: "point", params: (position: (0, 1, 0), power: 10, spd: "e"))],
        cameras: [(name: "c", type: "pinhole",
                   params: (position: (0, 1, 5), look_at: (0, 0, 0), resolution: (4, 4)))],
        sensors: [(name: "g", type: "illuminance_grid",
                   params: (corner: (-1, 0, 1), edge0: (2, 0, 0), edge1: (0, 0, -2), resolution: (4, 4)))],
    )"#,
    );
    for (name, est) in estimators() {
        let (mut means, mut ses) = (Vec::new(), Vec::new());
        for seed in 0..16 {
            let settings = MeasureSettings {
                estimator: est,
                samples: 256,
                seed,
                threads: None,
                tracer: PathTracer::default(),
            };
            let (m, se) = measure(&s, &s.sensors[0], &settings).unwrap().mean();
            means.push(m);
            ses.push(se);
        }
        let n = means.len() as f64;
        let avg = means.iter().sum::<f64>() / n;
        let sd = (means.iter().map(|m| (m - avg).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
        let se = ses.iter().sum::<f64>() / n;
        println!("{name}: grid mean {avg:.4} lx, seed spread {sd:.4}, reported σ {se:.4}");
        assert!(
            (0.5..=1.6).contains(&(sd / se)),
            "{name}: seed spread {sd} vs reported standard error {se}"
        );
    }
}
