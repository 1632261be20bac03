//! Spectral representation switches (`RepresentationOptions`): the defaults change nothing, and
//! each switch changes exactly the spectra it claims to, checked against closed forms: a
//! Lambertian patch of reflectance R lit head-on by a directional light of irradiance E and SPD
//! S has radiance R(λ)·E·S(λ)/π, so the film's XYZ is E/π · Σ R S x̄ / Σ ȳ (1 nm sums). Direct
//! lighting from a delta light: the only noise is the wavelength sampling.

use spectrace::analysis::accuracy_bench::{
    available_configs, run_accuracy_bench, select_configs, BenchSettings,
};
use spectrace::analysis::{delta_e_2000, xyz_to_lab, RgbImage};
use spectrace::color::{
    chromaticity, reflectance_xyz, CieObserverKind, Observer, ResampledObserver, SRGB,
};
use spectrace::integrator::{render, render_with, PathTracer, RenderSettings, SampleBudget};
use spectrace::scene::{
    build_scene_with, default_scene, default_scene_with, parse_scene_str, BuiltinFactory,
    ReflectanceSource, RepresentationOptions, Scene, SceneSource,
};
use spectrace::scene_file::representation::{step_value, uplift_of};
use spectrace::spectrum::{Interpolation, Spd, SpectralCurve, TabulatedSpd};
use std::path::Path;
use std::time::Duration;

/// The measured Cornell box data. Source: host/data/scenes/cornell_box.json (Cornell "Cornell Box Data", see its `sources`).
const CORNELL_JSON: &str = include_str!("../data/scenes/cornell_box.json");

/// `(λ nm, value)` table of a Cornell spectrum (`white`, `red`, `green`, `light_emission`).
fn cornell_table(name: &str) -> (Vec<f64>, Vec<f64>) {
    let d: serde_json::Value = serde_json::from_str(CORNELL_JSON).unwrap();
    d["spectra"][name]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .unzip()
}

fn ron_pairs(t: &(Vec<f64>, Vec<f64>)) -> String {
    let items: Vec<String> =
        t.0.iter()
            .zip(&t.1)
            .map(|(l, v)| format!("({l}, {v})"))
            .collect();
    format!("[{}]", items.join(", "))
}

/// Mean film XYZ of a patch with `reflectance` (RON value) lit head-on with irradiance 1 W/m²
/// of SPD `light` (RON value), 4×4 pixels, `spp` samples, under `opts`.
fn render_patch(
    reflectance: &str,
    light: &str,
    opts: &RepresentationOptions,
    spp: u32,
) -> [f64; 3] {
    let text = format!(
        r#"(
        materials: [(name: "m", type: "lambertian", params: (reflectance: {reflectance}))],
        objects: [(name: "floor", type: "quad", material: "m",
                   params: (corner: (-50, 0, 50), edge0: (100, 0, 0), edge1: (0, 0, -100)))],
        lights: [(name: "sun", type: "directional",
                  params: (direction: (0, -1, 0), irradiance: 1, spd: {light}))],
        cameras: [(name: "down", type: "pinhole",
                   params: (position: (0, 1, 0.001), look_at: (0, 0, 0), fov: 0.5, resolution: (4, 4)))],
    )"#
    );
    let file = Path::new("patch.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    let scene = build_scene_with(&desc, Path::new("."), file, &[&BuiltinFactory], opts).unwrap();
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed: 11,
        threads: Some(2),
        tracer: PathTracer {
            direct_only: true,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    render(&scene, &settings, &|_, _| {}, None)
        .unwrap()
        .image
        .mean_xyz()
}

/// Closed form of [`render_patch`]: E/π · ∫ R S x̄ dλ / Σ ȳ with E = 1, S normalised. The
/// integral is a 0.05 nm midpoint sum, since step spectra jump at their nodes: a 1 nm point sum
/// would misplace every jump by up to half a nanometre, a ~1 % error on 10 nm steps.
fn expected_patch(r: &dyn Fn(f64) -> f64, light: &dyn Spd, obs: &dyn Observer) -> [f64; 3] {
    let (lo, hi) = obs.range();
    let h = 0.05;
    let n = ((hi - lo) / h).round() as usize;
    let mut acc = [0.0; 3];
    for i in 0..n {
        let l = lo + (i as f64 + 0.5) * h;
        let c = obs.xyz_bar(l);
        let w = r(l) * light.value(l) / std::f64::consts::PI * h;
        for k in 0..3 {
            acc[k] += w * c[k];
        }
    }
    acc.map(|v| v / obs.integral_y())
}

/// Render vs closed form: Y within 5e-4 relative and chromaticity within 1e-4. Why: direct
/// light from a delta light on a uniform patch leaves only the wavelength-sampling noise, and
/// 4×4 px × 1024 spp × 4 stratified lanes bring it to ≤ 7.4e-5 on Y and ≤ 1.4e-5 on xy
/// (measured on these patches); the bounds are several times that yet 10× below the
/// representation effects required by [`differ`] (Y ≥ 0.5 % or Δxy ≥ 1e-3).
fn assert_close(what: &str, got: [f64; 3], want: [f64; 3]) {
    let (g, w) = (chromaticity(got), chromaticity(want));
    let dxy = (g.0 - w.0).hypot(g.1 - w.1);
    let dy = got[1] / want[1] - 1.0;
    assert!(
        dy.abs() < 5e-4 && dxy < 1e-4,
        "{what}: {got:?} vs {want:?} (ΔY/Y {dy:.2e}, Δxy {dxy:.2e})"
    );
}

/// Two closed forms differ clearly: Y by ≥ 0.5 % or chromaticity by ≥ 1e-3.
fn differ(a: [f64; 3], b: [f64; 3]) -> bool {
    let (p, q) = (chromaticity(a), chromaticity(b));
    let dxy = (p.0 - q.0).hypot(p.1 - q.1);
    (a[1] / b[1] - 1.0).abs() >= 5e-3 || dxy >= 1e-3
}

fn obs() -> &'static dyn Observer {
    CieObserverKind::Cie1931_2.get()
}

fn cornell_lamp() -> TabulatedSpd {
    let t = cornell_table("light_emission");
    TabulatedSpd::new("lamp", &t.0, &t.1, Interpolation::Linear).unwrap()
}

/// Default options are the scene as written: the Cornell box built by `default_scene`,
/// `default_scene_with(default)` and `SceneSource::Default` renders to the same image, bit for
/// bit (same seed and spp; rendering is deterministic, so any difference is a changed scene).
#[test]
fn default_options_reproduce_default_scene_exactly() {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(1),
        seed: 7,
        threads: Some(2),
        ..RenderSettings::default()
    };
    let img = |s: &Scene| render(s, &settings, &|_, _| {}, None).unwrap().image.xyz;
    let a = img(&default_scene().unwrap());
    let b = img(&default_scene_with(&RepresentationOptions::default()).unwrap());
    let c = img(&SceneSource::Default.build(&Default::default()).unwrap());
    assert!(a == b && a == c, "default representation changed the image");
    // And a switch does change it (else the comparison above proves nothing).
    let step = RepresentationOptions {
        observer_step_nm: 10,
        ..Default::default()
    };
    assert!(img(&default_scene_with(&step).unwrap()) != a);
}

/// RGB uplift of the measured Cornell reflectances keeps their colour under D65 — ΔE00 < 0.01
/// (measured < 5e-5), since the uplift reproduces the linear sRGB (D65, CIE 1931) to ~1e-5 for
/// colours inside the sRGB gamut, as these are — while the spectra differ (max |ΔR| on 400–700
/// nm measured 0.40 white, 0.34 red, 0.15 green; bound > 0.05) and so do the colours under the
/// Cornell lamp (ΔE00 measured 0.71, 0.78, 1.47; the largest must exceed 1): the metamerism
/// an RGB pipeline cannot represent.
#[test]
fn rgb_uplift_keeps_d65_colour_but_not_the_spectrum() {
    let d65 = spectrace::spectrum::parse_spd_spec("d65").unwrap();
    let lamp = cornell_lamp();
    let mut worst_lamp: f64 = 0.0;
    for name in ["white", "red", "green"] {
        let t = cornell_table(name);
        let measured = SpectralCurve::tabulated(t.0.clone(), t.1.clone()).unwrap();
        let m = |l: f64| measured.value(l);
        let up = uplift_of(&m);
        let u = |l: f64| up.value(l);
        let lab = |r: &dyn Fn(f64) -> f64, light: &dyn Spd| {
            let white = reflectance_xyz(|_| 1.0, light, obs());
            xyz_to_lab(reflectance_xyz(r, light, obs()), white)
        };
        let de_d65 = delta_e_2000(lab(&m, &d65), lab(&u, &d65));
        let de_lamp = delta_e_2000(lab(&m, &lamp), lab(&u, &lamp));
        let max_diff = (400..=700)
            .map(|l| (m(l as f64) - u(l as f64)).abs())
            .fold(0.0, f64::max);
        assert!(de_d65 < 0.01, "{name}: ΔE00 under D65 {de_d65}");
        assert!(
            max_diff > 0.05,
            "{name}: uplift ≈ measured spectrum ({max_diff})"
        );
        worst_lamp = worst_lamp.max(de_lamp);
    }
    assert!(worst_lamp > 1.0, "largest ΔE00 under the lamp {worst_lamp}");
}

/// In a render, `ReflectanceSource::RgbUplift` replaces the measured red by its uplift: under the
/// Cornell lamp the patch matches the uplift's closed form, the measured render matches the
/// measured closed form, and the two differ by more than the tolerance.
#[test]
fn rgb_uplift_applies_in_renders() {
    let red = cornell_table("red");
    let lamp_t = cornell_table("light_emission");
    let lamp = cornell_lamp();
    let measured = SpectralCurve::tabulated(red.0.clone(), red.1.clone()).unwrap();
    let m = |l: f64| measured.value(l);
    let up = uplift_of(&m);
    let uplift = RepresentationOptions {
        reflectance: ReflectanceSource::RgbUplift,
        ..Default::default()
    };
    let (refl, light) = (ron_pairs(&red), ron_pairs(&lamp_t));
    let got_m = render_patch(&refl, &light, &Default::default(), 1024);
    let got_u = render_patch(&refl, &light, &uplift, 1024);
    let want_m = expected_patch(&m, &lamp, obs());
    let want_u = expected_patch(&|l| up.value(l), &lamp, obs());
    assert_close("measured", got_m, want_m);
    assert_close("uplift", got_u, want_u);
    assert!(differ(want_m, want_u), "{want_m:?} vs {want_u:?}");
}

/// `Interpolation::Step` reads reflectance tables as steps (seed §5) in renders: the ColorChecker
/// red (10 nm table) under illuminant A matches the step closed form, not the linear one.
/// Emission tables too: the Cornell lamp (entries every 100 nm) emits, as steps, exactly the
/// entry at 400 nm (0) on [400, 500) and the 500 nm entry (8.0) on [500, 600), while the linear
/// reading gives 4.0 at 450 nm (f32 scale, so 1e-5 relative).
#[test]
fn step_interpolation_applies_to_reflectance_and_emission() {
    let step = RepresentationOptions {
        spd_interpolation: Interpolation::Step,
        ..Default::default()
    };
    let cc = SpectralCurve::parse("colorchecker:red").unwrap();
    let SpectralCurve::Tabulated { lambda, value } = cc.clone() else {
        panic!("table expected")
    };
    let a_step = spectrace::spectrum::spec::parse_spd_spec_with("a", Interpolation::Step).unwrap();
    let a_lin = spectrace::spectrum::parse_spd_spec("a").unwrap();
    let got = render_patch("\"colorchecker:red\"", "\"a\"", &step, 1024);
    let want_step = expected_patch(&|l| step_value(&lambda, &value, l), &a_step, obs());
    let want_lin = expected_patch(&|l| cc.value(l), &a_lin, obs());
    assert_close("step", got, want_step);
    assert!(differ(want_step, want_lin), "{want_step:?} vs {want_lin:?}");

    let radiance = |opts: &RepresentationOptions, l: f64| {
        let s = default_scene_with(opts).unwrap();
        let e = s
            .objects
            .objects()
            .iter()
            .find_map(|o| o.material.emission())
            .unwrap();
        e.scale as f64 * e.spd.value(l)
    };
    let near = |a: f64, b: f64| (a - b).abs() <= 1e-5 * b.abs().max(1e-9);
    assert_eq!(radiance(&step, 450.0), 0.0);
    assert!(
        near(radiance(&step, 550.0), 8.0),
        "{}",
        radiance(&step, 550.0)
    );
    assert!(near(radiance(&step, 599.0), 8.0));
    let lin = radiance(&Default::default(), 450.0);
    assert!(near(lin, 4.0), "{lin}");
}

/// A coarser observer step replaces the scene's observer by the resampled one (its Σȳ exactly),
/// and the film integrates with it: the patch under D65 matches the closed form computed with
/// the 10 nm observer (same tolerance as above).
#[test]
fn observer_step_applies_in_renders() {
    let ten = RepresentationOptions {
        observer_step_nm: 10,
        ..Default::default()
    };
    let scene = default_scene_with(&ten).unwrap();
    let coarse = ResampledObserver::new(obs(), 10).unwrap();
    assert_eq!(scene.observer.name(), coarse.name());
    assert_eq!(scene.observer.integral_y(), coarse.integral_y());
    assert!(scene.observer.integral_y() != obs().integral_y());
    let cc = SpectralCurve::parse("colorchecker:green").unwrap();
    let d65 = spectrace::spectrum::parse_spd_spec("d65").unwrap();
    let got = render_patch("\"colorchecker:green\"", "\"d65\"", &ten, 1024);
    assert_close(
        "10 nm observer",
        got,
        expected_patch(&|l| cc.value(l), &d65, &coarse),
    );
}

/// The bench builds the scene of a representation config itself: with a reference rendered
/// (2 spp, same seed) from the 10 nm-observer caustic scene, the bench's 2-spp point of
/// `pt-observer-10nm` has exactly zero error (deterministic renders: any other scene would not),
/// and its 1-spp point does not. A prebuilt scene refuses such a config instead of silently
/// rendering the default representation.
#[test]
fn bench_runs_a_representation_config_end_to_end() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/caustic.ron");
    let source = SceneSource::File(path);
    let base = source.build(&Default::default()).unwrap();
    let configs = select_configs(
        available_configs(4),
        Some(&["pt-observer-10nm".to_string()]),
    )
    .unwrap();
    let cfg = &configs[0];
    let scene = source.build(&cfg.representation).unwrap();
    let rs = RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(2),
        seed: 3,
        threads: Some(2),
        camera: None,
        tile_size: 16,
        tracer: cfg.tracer,
    };
    let out = render_with(&scene, &rs, cfg.integrator, false, &|_, _| {}, None).unwrap();
    let reference = RgbImage::from_xyz(&out.result.image, &SRGB);
    let settings = BenchSettings {
        budget: Duration::from_secs(600),
        max_spp: 2,
        seed: 3,
        threads: Some(2),
        exclude_specular: false,
    };
    let points = run_accuracy_bench(&source, &reference, &configs, &settings, &|_| {}).unwrap();
    assert_eq!(points.iter().map(|p| p.spp).collect::<Vec<_>>(), [1, 2]);
    assert!(points[0].rmse > 0.0);
    assert_eq!((points[1].rmse, points[1].delta_e_mean), (0.0, 0.0));
    let err = run_accuracy_bench(&base, &reference, &configs, &settings, &|_| {}).unwrap_err();
    assert!(err.to_string().contains("pt-observer-10nm"), "{err}");
}
