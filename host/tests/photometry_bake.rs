//! Baking lights into portable `luminaire` blobs (`spectrace luminaire bake`) and exporting
//! lights as IES/EULUMDAT (`spectrace luminaire export --scene/--light`, a blob): a baked light
//! renders like its original within the goniometric table's resolution, and IES → scene light
//! → IES gives the file's table back.
//! Run: `cargo test --release -p spectrace --test photometry_bake`.

use glam::{Vec2, Vec3A};
use spectrace::geometry::Ray;
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::light::measure::goniometer::{measure, GoniometerSettings};
use spectrace::light::{
    Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext, LightSourceManager,
};
use spectrace::photometry::load_luminaire;
use spectrace::scene::{build_scene, load_scene_file, parse_scene_str, BuiltinFactory, Scene};
use spectrace::spectrum::{BuiltinSpd, SampledSpectrum, SampledWavelengths, Spd};
use spectrace_plugin_api::{Beam, RandomSample, Vec3};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

const RES: u32 = 48;
const BLOCK: u32 = 8;

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spectrace-bake-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_spectrace")
}

fn run(args: &[&str]) -> String {
    let out = Command::new(bin()).args(args).output().unwrap();
    assert!(
        out.status.success(),
        "spectrace {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// A floor (ρ = 0.5) seen from straight above by a 48² camera, lit by `light` (scene syntax).
fn floor_scene_text(light: &str) -> String {
    format!(
        r#"(
        materials: [(name: "grey", type: "lambertian", params: (reflectance: 0.5))],
        objects: [(name: "floor", type: "quad", material: "grey",
                   params: (corner: (-20, 0, 20), edge0: (40, 0, 0), edge1: (0, 0, -40)))],
        lights: [{light}],
        cameras: [(name: "down", type: "pinhole",
                   params: (position: (0, 3, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 80,
                            resolution: ({RES}, {RES})))],
    )"#
    )
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

fn blocks(v: &[f64]) -> Vec<f64> {
    let nb = RES / BLOCK;
    let mut out = vec![0.0; (nb * nb) as usize];
    for y in 0..RES {
        for x in 0..RES {
            out[((y / BLOCK) * nb + x / BLOCK) as usize] += v[(y * RES + x) as usize];
        }
    }
    out
}

/// Relative RMSE of `b` against `a` (per pixel, over the mean of `a`) and the ratio of means.
fn rmse_and_ratio(a: &[f64], b: &[f64]) -> (f64, f64) {
    let n = a.len() as f64;
    let mean_a = a.iter().sum::<f64>() / n;
    let mean_b = b.iter().sum::<f64>() / n;
    let mse = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / n;
    (mse.sqrt() / mean_a, mean_b / mean_a)
}

/// A spot light (inner 20°, outer 30°, tilted 17° off the vertical) baked with the CLI at
/// 2.5° renders like the original in PT (direct light from a delta light: the noise is the
/// wavelength sampling, the same for both, so the comparison is nearly noise-free). Measured:
/// the floor's mean Y ratio (baked/original) and the relative per-pixel RMSE. Tolerances: mean
/// within 0.5% (the bake's flux is the trapezoid integral of the smoothstep falloff sampled
/// every 2.5°; −0.16% measured), RMSE under 3% of the mean (the bilinear table misses the
/// smoothstep's curvature by at most Δ²/8·|f''| ≈ 5% of the peak in the 10° falloff band, which
/// covers a fraction of the pixels), and every 8×8 block fully inside the inner cone within
/// 0.5% (flat intensity: only f32 and the 1 nm spectrum table differ).
#[test]
fn baked_spot_light_renders_like_the_original() {
    let spot = r#"(name: "spot", type: "spot", params: (position: (0.3, 2, -0.2),
        target: (0.9, 0, 0.3), inner_angle: 20, outer_angle: 30, power: 10, spd: "blackbody:3000"))"#;
    let scene_path = temp("spot.ron");
    std::fs::write(&scene_path, floor_scene_text(spot)).unwrap();
    let blob = temp("spot.blob");
    let report = run(&[
        "luminaire",
        "bake",
        scene_path.to_str().unwrap(),
        "--light",
        "spot",
        "-o",
        blob.to_str().unwrap(),
    ]);
    assert!(report.contains("measured flux"), "{report}");
    let baked_path = temp("spot_baked.ron");
    std::fs::write(
        &baked_path,
        floor_scene_text(r#"(name: "baked", type: "blob", params: (file: "spot.blob"))"#),
    )
    .unwrap();
    // The registry's factory with the built-in types only: no plugin is loaded.
    let factory = spectrace::plugin::factory::PluginFactory::new(
        Arc::new(spectrace::plugin::builtin_registry()),
        spectrace::plugin::adapter::PluginFaults::new(),
    );
    let original = load_scene_file(&scene_path, &[&factory]).unwrap();
    let baked = load_scene_file(&baked_path, &[&factory]).unwrap();
    let p0 = original.lights.lights()[0].power();
    let p1 = baked.lights.lights()[0].power();
    assert!((p1 / p0 - 1.0).abs() < 0.005, "flux {p1} W vs {p0} W");
    let a = render_y(&original, IntegratorKind::Pt, 8, 3);
    let b = render_y(&baked, IntegratorKind::Pt, 8, 3);
    let (rmse, ratio) = rmse_and_ratio(&a, &b);
    println!("spot: mean ratio {ratio:.5}, relative RMSE {rmse:.5}, flux {p1:.5} W vs {p0:.5} W");
    assert!((ratio - 1.0).abs() < 0.005, "mean ratio {ratio}");
    assert!(rmse < 0.03, "relative RMSE {rmse}");
    let (ba, bb) = (blocks(&a), blocks(&b));
    let peak = ba.iter().copied().fold(0.0, f64::max);
    let mut inner = 0;
    for (x, y) in ba.iter().zip(&bb) {
        // Blocks at the peak level are inside the inner cone (flat intensity, cos³ only).
        if *x > 0.9 * peak {
            inner += 1;
            assert!((y / x - 1.0).abs() < 0.005, "inner block: {y} vs {x}");
        }
    }
    assert!(inner >= 1);
}

/// A light that only hands out beams: uniform directions in a cone of half-angle 40° around
/// straight down, wavelengths from a 4000 K blackbody, every beam carrying the whole power
/// (the flux estimate of one sample), from a 0.2 m square.
#[derive(Debug)]
struct BeamCone {
    power: f64,
    spd: Arc<dyn Spd>,
}

const CONE_DEG: f64 = 40.0;
const CONE_POS: [f64; 3] = [0.1, 2.0, 0.0];

impl Light for BeamCone {
    fn flags(&self) -> LightFlags {
        LightFlags::BEAMS_ONLY
    }
    fn power(&self) -> f64 {
        self.power
    }
    fn spd(&self) -> Arc<dyn Spd> {
        self.spd.clone()
    }
    fn sample_li(
        &self,
        _c: &LightSampleContext,
        _u: Vec2,
        _l: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        None
    }
    fn pdf_li(&self, _c: &LightSampleContext, _p: Vec3A, _n: Vec3A) -> f32 {
        0.0
    }
    fn radiance(
        &self,
        _p: Vec3A,
        _n: Vec3A,
        _uv: Vec2,
        _w: Vec3A,
        _l: &SampledWavelengths,
    ) -> SampledSpectrum {
        SampledSpectrum::zero()
    }
    fn sample_le(&self, _a: Vec2, _b: Vec2, _l: &SampledWavelengths) -> Option<LightLeSample> {
        None
    }
    fn pdf_le(&self, _r: &Ray, _n: Vec3A) -> (f32, f32) {
        (0.0, 0.0)
    }
    fn next_beam(&self, s: &RandomSample) -> Option<Beam> {
        let cos_max = CONE_DEG.to_radians().cos();
        let cos = 1.0 - s.u[0] * (1.0 - cos_max);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = std::f64::consts::TAU * s.u[1];
        Some(Beam {
            origin: Vec3::new(
                CONE_POS[0] + 0.2 * (s.u[3] - 0.5),
                CONE_POS[1],
                CONE_POS[2] + 0.2 * (s.u[4] - 0.5),
            ),
            direction: Vec3::new(sin * phi.cos(), -cos, sin * phi.sin()),
            wavelength_nm: self.spd.sample(s.u[2]).lambda,
            power_w: self.power,
            source_id: 0,
        })
    }
}

/// A beams-only light baked (4·10⁶ beams, 5° grid) has the light's flux, intensity P/Ω inside
/// the cone, its spectrum's luminous efficacy, its emitter size, and renders (PT, baked) like
/// the original (LT, the only way to render it). Tolerances: flux exact up to the beams that
/// fall outside 0..2000 nm (none: 1e-9); each 5° cell wholly inside the cone within 5σ of
/// P/Ω, σ = I/√n (n beams in the cell, ≈ 1.7·10⁴, σ ≈ 0.8%); efficacy within 1% (the 1 nm
/// histogram of 4·10⁶ draws against the blackbody's own 1 nm integral); the rendered floor's
/// mean Y within 4 standard errors (of the LT image mean, over 4 seeds) + 1% (cells cut by the
/// cone's edge spread its 40° rim over ±2.5°, which moves light across the floor but keeps it).
#[test]
fn baked_beams_only_light_renders_like_the_original() {
    let spd: Arc<dyn Spd> = Arc::new(BuiltinSpd::blackbody(4000.0).unwrap());
    let light = BeamCone {
        power: 5.0,
        spd: spd.clone(),
    };
    let m = measure(
        &light,
        &GoniometerSettings {
            step_deg: 5.0,
            samples: 4_000_000,
            seed: 7,
        },
    )
    .unwrap();
    assert!((m.flux_w / 5.0 - 1.0).abs() < 0.01, "flux {} W", m.flux_w);
    let k_measured = m.flux_lm / m.flux_w;
    let k_true = spectrace::photometry::efficacy::luminous_efficacy_lm_per_w(spd.as_ref());
    assert!(
        (k_measured / k_true - 1.0).abs() < 0.01,
        "{k_measured} vs {k_true} lm/W"
    );
    assert!((m.size[0] - 0.2).abs() < 0.01 && (m.size[1] - 0.2).abs() < 0.01 && m.size[2] < 1e-6);
    let omega = std::f64::consts::TAU * (1.0 - CONE_DEG.to_radians().cos());
    let want_cd = 5.0 / omega * k_measured;
    let lum = &m.luminaire;
    let nv = lum.v_deg.len();
    let mut cells = 0;
    for ih in 0..lum.h_deg.len() - 1 {
        for (iv, &v) in lum.v_deg.iter().enumerate() {
            if v == 0.0 || v + 2.5 > CONE_DEG - 1e-9 {
                continue;
            }
            let cd = lum.candela[ih * nv + iv];
            let cell =
                5f64.to_radians() * ((v - 2.5).to_radians().cos() - (v + 2.5).to_radians().cos());
            let n = 4e6 * cell / omega;
            let sigma = want_cd / n.sqrt();
            assert!(
                (cd - want_cd).abs() < 5.0 * sigma,
                "cell h {} v {v}: {cd} cd vs {want_cd} ± {sigma}",
                lum.h_deg[ih]
            );
            cells += 1;
        }
    }
    assert!(cells > 300, "{cells}");

    // Render: the original with LT, the baked table (a luminaire light) with PT.
    let file = Path::new("floor.ron");
    let mut original = {
        let desc = parse_scene_str(
            &floor_scene_text(
                r#"(name: "p", type: "point", params: (position: (0, 2, 0), power: 1))"#,
            ),
            file,
        )
        .unwrap();
        build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
    };
    let cone: Arc<dyn Light> = Arc::new(light);
    original.lights = LightSourceManager::new(vec![cone], original.objects.len());
    let table = ron::to_string(&m.table("test")).unwrap();
    let spectrum = ron::to_string(&m.spectrum).unwrap();
    let baked_text = floor_scene_text(&format!(
        r#"(name: "baked", type: "luminaire", params: (table: {table}, position: ({}, {}, {}), spd: {spectrum}))"#,
        m.centre[0], m.centre[1], m.centre[2]
    ));
    let desc = parse_scene_str(&baked_text, file).unwrap();
    let baked = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap();
    let b = render_y(&baked, IntegratorKind::Pt, 8, 3);
    let means: Vec<f64> = (0..4)
        .map(|s| {
            let a = render_y(&original, IntegratorKind::Lt, 64, 20 + s);
            a.iter().sum::<f64>() / a.len() as f64
        })
        .collect();
    let mean_a = means.iter().sum::<f64>() / 4.0;
    let se = (means.iter().map(|x| (x - mean_a).powi(2)).sum::<f64>() / 3.0 / 4.0).sqrt();
    let mean_b = b.iter().sum::<f64>() / b.len() as f64;
    println!(
        "beams: baked (PT) / original (LT) floor mean = {:.4} ± {:.4}",
        mean_b / mean_a,
        se / mean_a
    );
    assert!(
        (mean_b / mean_a - 1.0).abs() < 4.0 * se / mean_a + 0.01,
        "baked {mean_b} vs original {mean_a} ± {se}"
    );
}

/// IES → a `luminaire` light of a scene → `luminaire export --scene --light` → IES gives the
/// file's table back exactly (angles, candela, flux, tilt); so does a blob of that light
/// (`blob pack`, then `luminaire export X.blob`); a measured light (the spot) exports its
/// measured table, which reads back equal to the bake's (shortest round-trip decimals).
#[test]
fn scene_lights_and_blobs_export_their_tables() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    for (i, file) in [
        "data/photometry/infinity_arealight_lm63-1995_bilateral.ies",
        "data/photometry/anon_sample07_isym4.ldt",
        "tests/data/photometry/tilt_include_lm63_1995.ies",
    ]
    .iter()
    .enumerate()
    {
        let path = root.join(file);
        let scene = temp(&format!("export{i}.ron"));
        std::fs::write(
            &scene,
            floor_scene_text(&format!(
                r#"(name: "lum", type: "luminaire", params: (file: "{}", position: (0, 2, 0)))"#,
                path.display()
            )),
        )
        .unwrap();
        let want = load_luminaire(&path).unwrap();
        let out = temp(&format!("export{i}.ies"));
        run(&[
            "luminaire",
            "export",
            "--scene",
            scene.to_str().unwrap(),
            "--light",
            "lum",
            "--format",
            "ies",
            "-o",
            out.to_str().unwrap(),
        ]);
        let blob = temp(&format!("export{i}.blob"));
        run(&[
            "blob",
            "pack",
            "--scene",
            scene.to_str().unwrap(),
            "--light",
            "lum",
            "-o",
            blob.to_str().unwrap(),
        ]);
        let out2 = temp(&format!("export{i}_blob.ies"));
        run(&[
            "luminaire",
            "export",
            blob.to_str().unwrap(),
            "--format",
            "ies",
            "-o",
            out2.to_str().unwrap(),
        ]);
        for o in [&out, &out2] {
            let got = load_luminaire(o).unwrap();
            assert_eq!(got.h_deg, want.h_deg, "{file}");
            assert_eq!(got.v_deg, want.v_deg, "{file}");
            assert_eq!(got.candela, want.candela, "{file}");
            assert_eq!(got.tilt.is_some(), want.tilt.is_some(), "{file}");
            assert!((got.flux_lm() / want.flux_lm() - 1.0).abs() < 1e-12);
        }
    }
    // A spot light: measured, exported as IES and EULUMDAT.
    let scene = temp("export_spot.ron");
    std::fs::write(
        &scene,
        floor_scene_text(
            r#"(name: "spot", type: "spot", params: (position: (0, 2, 0), target: (0, 0, 0), power: 10))"#,
        ),
    )
    .unwrap();
    for (fmt, ext) in [("ies", "ies"), ("ldt", "ldt")] {
        let out = temp(&format!("spot.{ext}"));
        run(&[
            "luminaire",
            "export",
            "--scene",
            scene.to_str().unwrap(),
            "--light",
            "spot",
            "--format",
            fmt,
            "-o",
            out.to_str().unwrap(),
        ]);
        let got = load_luminaire(&out).unwrap();
        // 10 W of equal energy: 10 W × 683·Σȳ/470 lm/W; the table's trapezoid flux within 0.5%.
        let spd = spectrace::spectrum::parse_spd_spec("e").unwrap();
        let want = 10.0 * spectrace::photometry::efficacy::luminous_efficacy_lm_per_w(&spd);
        assert!(
            (got.flux_lm() / want - 1.0).abs() < 0.005,
            "{fmt}: {} lm vs {want} lm",
            got.flux_lm()
        );
        // Rotationally symmetric about the vertical axis: the same in the C0 and C90 planes
        // (point samples at grid nodes; f32 directions: 1e-5).
        assert!((got.candela_at(0.0, 10.0) / got.candela_at(90.0, 10.0) - 1.0).abs() < 1e-5);
    }
}
