//! The `luminaire` light against its candela table: a diffuse floor (reflectance ρ) under a
//! tilted, rotated real luminaire (IES LM-63-1995, bilateral, uneven angles), seen by a camera
//! looking straight down. Each floor point x receives E = I(ω)·cos θ/d² (= I·cos³θ/h² for a
//! level luminaire), I from the table in the direction ω from the light to x expressed in the
//! luminaire's frame, and sends L = ρE/π to the camera. Film Y of a spectral radiance with
//! luminous value L_v is L_v / (683·Σȳ), whatever the SPD (the light converts cd to W with its
//! SPD's efficacy 683·ΣSȳ). The expected pixel is L averaged over the pixel footprint (4×4
//! sub-points through the camera's own rays; box filter), compared per 4×4-pixel block in PT,
//! BDPT and LT. Run: `cargo test --release -p spectrace --test render_luminaire`.

use spectrace::camera::CameraSample;
use spectrace::color::{CieObserverKind, Observer};
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::photometry::efficacy::luminous_efficacy_lm_per_w;
use spectrace::photometry::load_luminaire;
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::{Path, PathBuf};

const RHO: f64 = 0.5;
const RES: u32 = 24;
const BLOCK: u32 = 4;
const FILE: &str = "infinity_arealight_lm63-1995_bilateral.ies";
const LIGHT_POS: [f64; 3] = [0.2, 2.0, -0.1];
const AIM: [f64; 3] = [0.3, -1.0, 0.2];
const C0: [f64; 3] = [1.0, 0.0, 0.5];

fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/photometry")
}

fn scene(light_params: &str) -> Scene {
    let text = format!(
        r#"(
        materials: [(name: "grey", type: "lambertian", params: (reflectance: {RHO}))],
        objects: [(name: "floor", type: "quad", material: "grey",
                   params: (corner: (-20, 0, 20), edge0: (40, 0, 0), edge1: (0, 0, -40)))],
        lights: [(name: "lum", type: "luminaire", params: {light_params})],
        cameras: [(name: "down", type: "pinhole",
                   params: (position: (0, 3, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 70,
                            resolution: ({RES}, {RES})))],
    )"#
    );
    let file = data_dir().join("floor.ron");
    let desc = parse_scene_str(&text, &file).unwrap();
    build_scene(&desc, &data_dir(), &file, &[&BuiltinFactory]).unwrap()
}

fn tilted_scene() -> Scene {
    scene(&format!(
        r#"(file: "{FILE}", position: ({}, {}, {}), aim: ({}, {}, {}), c0: ({}, {}, {}), spd: "blackbody:3000")"#,
        LIGHT_POS[0], LIGHT_POS[1], LIGHT_POS[2], AIM[0], AIM[1], AIM[2], C0[0], C0[1], C0[2]
    ))
}

fn norm(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Expected film Y per pixel: ρ/π · I·cos θ/d² / (683·Σȳ), averaged over 4×4 sub-points.
fn expected_y(scene: &Scene) -> Vec<f64> {
    let lum = load_luminaire(&data_dir().join(FILE)).unwrap();
    // The luminaire frame written out here (independently of the light's code): −y = aim,
    // x = c0 made perpendicular, z = x × y; type C angles γ = acos(−y), C = atan2(−z, x).
    let y_axis = norm(AIM.map(|a| -a));
    let c = dot(C0, y_axis);
    let x_axis = norm([
        C0[0] - c * y_axis[0],
        C0[1] - c * y_axis[1],
        C0[2] - c * y_axis[2],
    ]);
    let z_axis = [
        x_axis[1] * y_axis[2] - x_axis[2] * y_axis[1],
        x_axis[2] * y_axis[0] - x_axis[0] * y_axis[2],
        x_axis[0] * y_axis[1] - x_axis[1] * y_axis[0],
    ];
    let sum_y = CieObserverKind::Cie1931_2.get().integral_y();
    let cam = &scene.cameras.cameras()[0].camera;
    let mut out = Vec::new();
    for py in 0..RES {
        for px in 0..RES {
            let mut acc = 0.0;
            for s in 0..16 {
                let p_film = glam::Vec2::new(
                    px as f32 + ((s % 4) as f32 + 0.5) / 4.0,
                    py as f32 + ((s / 4) as f32 + 0.5) / 4.0,
                );
                let ray = cam
                    .generate_ray(&CameraSample {
                        p_film,
                        p_lens: glam::Vec2::ZERO,
                    })
                    .unwrap()
                    .ray;
                let t = -ray.origin.y as f64 / ray.dir.y as f64;
                let p = [
                    ray.origin.x as f64 + t * ray.dir.x as f64,
                    0.0,
                    ray.origin.z as f64 + t * ray.dir.z as f64,
                ];
                let d = [
                    p[0] - LIGHT_POS[0],
                    p[1] - LIGHT_POS[1],
                    p[2] - LIGHT_POS[2],
                ];
                let d2 = dot(d, d);
                let w = norm(d);
                let local = [dot(w, x_axis), dot(w, y_axis), dot(w, z_axis)];
                let gamma = (-local[1]).clamp(-1.0, 1.0).acos().to_degrees();
                let c_deg = (-local[2]).atan2(local[0]).to_degrees().rem_euclid(360.0);
                let cd = lum.candela_at(c_deg, gamma);
                let cos_floor = -w[1];
                acc += RHO / std::f64::consts::PI * cd * cos_floor / d2 / (683.0 * sum_y);
            }
            out.push(acc / 16.0);
        }
    }
    out
}

fn block_sums(v: &[f64]) -> Vec<f64> {
    let nb = RES / BLOCK;
    let mut out = vec![0.0; (nb * nb) as usize];
    for y in 0..RES {
        for x in 0..RES {
            out[((y / BLOCK) * nb + x / BLOCK) as usize] += v[(y * RES + x) as usize];
        }
    }
    out
}

fn render_y(scene: &Scene, kind: IntegratorKind, spp: u32, seed: u64) -> Vec<f64> {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed,
        threads: Some(2),
        tracer: PathTracer {
            max_depth: 4,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let out = render_with(scene, &settings, kind, false, &|_, _| {}, None).unwrap();
    assert_eq!(out.result.image.non_finite_count(), 0);
    out.result.image.xyz.iter().map(|p| p[1]).collect()
}

/// Every 4×4-pixel block of the rendered floor equals the candela table's ρE/π within
/// 4 standard errors + 0.5%, in PT, BDPT and LT; blocks the luminaire barely lights (expected
/// below 2% of the brightest) are skipped, since their relative error says nothing. Standard
/// errors come from 8 independent seeds. The 0.5% covers what is not noise: 16 sub-points per
/// pixel against the film's continuous box filter over a bilinear table with kinks (< 0.2%),
/// and f32 directions at the table's cell edges. A wrong axis, a mirrored C angle, a missing
/// cos θ or a wrong cd → W conversion is off by 10% or more somewhere on the floor.
#[test]
fn floor_illuminance_matches_the_candela_table_in_pt_bdpt_lt() {
    let scene = tilted_scene();
    let want = block_sums(&expected_y(&scene));
    let peak = want.iter().copied().fold(0.0, f64::max);
    assert!(peak > 0.0);
    for (kind, spp) in [
        (IntegratorKind::Pt, 16),
        (IntegratorKind::Bdpt, 32),
        (IntegratorKind::Lt, 512),
    ] {
        let runs: Vec<Vec<f64>> = (0..8)
            .map(|seed| block_sums(&render_y(&scene, kind, spp, 11 + seed)))
            .collect();
        let mut worst = (0.0f64, 0.0f64, 0usize);
        let mut checked = 0;
        for b in 0..want.len() {
            if want[b] < 0.02 * peak {
                continue;
            }
            checked += 1;
            let r: Vec<f64> = runs.iter().map(|run| run[b] / want[b]).collect();
            let mean = r.iter().sum::<f64>() / r.len() as f64;
            let var = r.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (r.len() - 1) as f64;
            let se = (var / r.len() as f64).sqrt();
            let dev = (mean - 1.0).abs();
            assert!(
                dev < 4.0 * se + 0.005,
                "{kind}: block {b}: rendered/table = {mean:.4} ± {se:.4} (expected {:.3e})",
                want[b]
            );
            if dev > worst.0 {
                worst = (dev, se, b);
            }
        }
        println!(
            "{kind}: {checked} blocks, worst |rendered/table − 1| = {:.4} ± {:.4} (block {})",
            worst.0, worst.1, worst.2
        );
        assert!(checked >= 16, "{kind}: only {checked} lit blocks");
    }
}

/// The light's flux: radiant power × the SPD's efficacy is the file's integrated flux (lm)
/// (1e-6: exact up to f32 directions, which move a tilt angle by ~1e-6°), `flux_lm` overrides it, `multiplier`
/// scales it, and the TILT=INCLUDE table scales it by its factor at the tilt angle (the test
/// file's factors 1, 0.95, 0.8, 0.6 at 0, 30, 60, 90°: aimed 30° off the nadir → 0.95; 45° →
/// 0.875 by linear interpolation).
#[test]
fn flux_in_watts_and_lumens_matches_the_file() {
    let check = |params: &str, file: &Path, factor: f64| {
        let s = scene(params);
        let light = s.lights.lights()[0].clone();
        let spd = light.spd();
        let lm = light.power() * luminous_efficacy_lm_per_w(spd.as_ref());
        let want = load_luminaire(file).unwrap().flux_lm() * factor;
        assert!(
            (lm / want - 1.0).abs() < 1e-6,
            "{params}: {lm} lm vs {want} lm"
        );
        lm
    };
    let file = data_dir().join(FILE);
    check(
        &format!(r#"(file: "{FILE}", position: (0, 2, 0))"#),
        &file,
        1.0,
    );
    check(
        &format!(
            r#"(file: "{FILE}", position: (0, 2, 0), spd: "phosphor_led_yag", multiplier: 2.5)"#
        ),
        &file,
        2.5,
    );
    let lm = check(
        &format!(r#"(file: "{FILE}", position: (0, 2, 0), flux_lm: 1234.5)"#),
        &file,
        1234.5 / load_luminaire(&file).unwrap().flux_lm(),
    );
    assert!((lm - 1234.5).abs() < 1e-6);
    let tilt = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/photometry/tilt_include_lm63_1995.ies");
    let t = tilt.display();
    let a30 = 30f64.to_radians();
    check(
        &format!(r#"(file: "{t}", position: (0, 2, 0))"#),
        &tilt,
        1.0,
    );
    check(
        &format!(
            r#"(file: "{t}", position: (0, 2, 0), aim: ({}, {}, 0))"#,
            a30.sin(),
            -a30.cos()
        ),
        &tilt,
        0.95,
    );
    check(
        &format!(r#"(file: "{t}", position: (0, 2, 0), tilt_deg: 45)"#),
        &tilt,
        0.875,
    );
}

/// Bad parameters are errors naming the parameter (and the file for a broken file).
#[test]
fn bad_luminaire_parameters_are_named() {
    let err = |params: &str| {
        let text = format!(
            r#"(materials: [(name: "grey", type: "lambertian", params: (reflectance: 0.5))],
               objects: [(name: "floor", type: "quad", material: "grey",
                          params: (corner: (-1, 0, 1), edge0: (2, 0, 0), edge1: (0, 0, -2)))],
               lights: [(name: "lum", type: "luminaire", params: {params})],
               cameras: [(name: "c", type: "pinhole", params: (position: (0, 1, 0), look_at: (0, 0, 0), up: (0, 0, -1), resolution: (4, 4)))])"#
        );
        let file = data_dir().join("bad.ron");
        let desc = parse_scene_str(&text, &file).unwrap();
        build_scene(&desc, &data_dir(), &file, &[&BuiltinFactory])
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    };
    assert!(err(r#"(position: (0, 2, 0))"#).contains("file"));
    assert!(err(r#"(file: "missing.ies", position: (0, 2, 0))"#).contains("missing.ies"));
    assert!(err(&format!(
        r#"(file: "{FILE}", position: (0, 2, 0), aim: (0, 0, 0))"#
    ))
    .contains("aim"));
    assert!(err(&format!(
        r#"(file: "{FILE}", position: (0, 2, 0), aim: (1, 0, 0), c0: (1, 0, 0))"#
    ))
    .contains("c0"));
    assert!(err(&format!(
        r#"(file: "{FILE}", position: (0, 2, 0), flux_lm: -3)"#
    ))
    .contains("flux_lm"));
    assert!(err(&format!(
        r#"(file: "{FILE}", position: (0, 2, 0), tilt_deg: 10)"#
    ))
    .contains("tilt_deg"));
    assert!(err(&format!(
        r#"(file: "{FILE}", position: (0, 2, 0), spd: "line:1000")"#
    ))
    .contains("spd"));
}
