//! SPDs and observers through the plugin API (plugins/sensor-spectra): a Lorentzian line SPD and
//! a Gaussian three-channel sensor used as the colour observer, seen through the host adapters,
//! lent to another plugin's light, and used by a scene.

use spectrace::color::Observer;
use spectrace::integrator::{render, RenderSettings, SampleBudget};
use spectrace::plugin::adapter::{Origin, PluginFaults, PluginObserver, PluginSpd};
use spectrace::plugin::factory::PluginFactory;
use spectrace::plugin::Registry;
use spectrace::scene::{load_scene_file, BuiltinFactory, ObjectFactory};
use spectrace::spectrum::Spd;
use spectrace_plugin_api::abi::std_types::RStr;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::RandomSample;
use spectrace_tests::plugin_library;
use std::path::Path;
use std::sync::Arc;

fn registry() -> Registry {
    let mut r = spectrace::plugin::builtin_registry();
    r.load_plugin(&plugin_library("spectrace-sensor-spectra"))
        .unwrap();
    r.load_plugin(&plugin_library("spectrace-point-light"))
        .unwrap();
    r
}

fn origin() -> Origin {
    Origin {
        label: "test".into(),
        faults: PluginFaults::new(),
    }
}

fn lcg(n: usize, mut state: u64) -> Vec<f64> {
    (0..n)
        .map(|_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect()
}

#[test]
fn lorentzian_spd_is_normalised_and_samples_itself() {
    let r = registry();
    let spd = PluginSpd::new(
        r.create_plugin_spd(
            "lorentzian",
            ObjectSource::Params(RStr::from_str("(centre_nm: 550, fwhm_nm: 20)")),
        )
        .unwrap(),
        origin(),
    );
    assert_eq!(spd.range(), (360.0, 830.0));
    // ∫ value dλ by the midpoint rule with h = 0.01 nm: its error (h²/24 · ∫|f''|) is < 1e-7
    // here, so 1e-6 checks the normalisation itself.
    let h = 0.01;
    let n = ((830.0 - 360.0) / h) as usize;
    let integral: f64 = (0..n)
        .map(|i| spd.value(360.0 + (i as f64 + 0.5) * h) * h)
        .sum();
    assert!((integral - 1.0).abs() < 1e-6, "∫ = {integral}");

    // Chi-square of 200 000 draws over 40 bins of equal width against the bins' exact
    // probabilities (integrated with the same midpoint rule). 39 degrees of freedom; the 0.1%
    // critical value is 72.05. The draws come from a fixed generator, so the test is
    // deterministic; a correct sampler fails it for one seed in a thousand.
    let bins = 40;
    let width = (830.0 - 360.0) / bins as f64;
    let mut counts = vec![0u64; bins];
    let draws = 200_000;
    for u in lcg(draws, 17) {
        let s = spd.sample(u);
        assert!(s.pdf > 0.0 && s.pdf.is_finite());
        assert!(
            (s.pdf - spd.value(s.lambda)).abs() <= 1e-12 * s.pdf,
            "pdf equals value"
        );
        let b = (((s.lambda - 360.0) / width) as usize).min(bins - 1);
        counts[b] += 1;
    }
    let mut chi2 = 0.0;
    for (b, &c) in counts.iter().enumerate() {
        let lo = 360.0 + b as f64 * width;
        let p: f64 = (0..1000)
            .map(|i| spd.value(lo + (i as f64 + 0.5) * width / 1000.0) * width / 1000.0)
            .sum();
        let expected = p * draws as f64;
        if expected > 5.0 {
            chi2 += (c as f64 - expected).powi(2) / expected;
        }
    }
    assert!(chi2 < 72.05, "chi-square {chi2} over 39 dof");
}

#[test]
fn one_plugins_light_uses_another_plugins_spd() {
    // isotropic_point (plugin point-light) asks the host for "lorentzian(...)" (plugin
    // sensor-spectra). A Cauchy line has its quartiles at centre ± FWHM/2, so over 20 000 beams
    // the median must sit at the centre and the interquartile range equal the FWHM: the
    // standard error of a quartile is ≈ 1.6·γ/√n ≈ 0.006 nm here, so 0.05 nm is > 8σ.
    let r = registry();
    let light = r
        .create_plugin_light(
            "isotropic_point",
            ObjectSource::Params(RStr::from_str(
                "(position: (0,0,0), power_w: 1, spd: \"lorentzian(centre_nm: 589.3, fwhm_nm: 1.2)\")",
            )),
        )
        .unwrap();
    let mut nm: Vec<f64> = lcg(20_000, 3)
        .into_iter()
        .map(|u| {
            let mut s = RandomSample::default();
            s.u[4] = u;
            light.light.next_beam(&s).unwrap().colour[0]
        })
        .collect();
    nm.sort_by(|a, b| a.partial_cmp(b).unwrap());
    let q = |f: f64| nm[(f * nm.len() as f64) as usize];
    assert!((q(0.5) - 589.3).abs() < 0.05, "median {}", q(0.5));
    assert!(
        ((q(0.75) - q(0.25)) - 1.2).abs() < 0.05,
        "IQR {}",
        q(0.75) - q(0.25)
    );
}

#[test]
fn sensor_observer_through_the_adapter() {
    let r = registry();
    let obs = PluginObserver::new(
        r.create_plugin_observer(
            "gaussian_sensor",
            ObjectSource::Params(RStr::from_str("()")),
        )
        .unwrap(),
        origin(),
    );
    assert_eq!(obs.name(), "gaussian-sensor");
    assert_eq!(obs.range(), (360.0, 830.0));
    let v = obs.xyz_bar(600.0);
    // Channels peak at 600/540/450 nm with σ 40/40/30 nm: closed form at 600 nm.
    let expect = [
        1.0,
        (-0.5f64 * 1.5 * 1.5).exp(),
        (-0.5f64 * 5.0 * 5.0).exp(),
    ];
    for c in 0..3 {
        assert!((v[c] - expect[c]).abs() < 1e-15, "{v:?} vs {expect:?}");
    }
    assert_eq!(obs.xyz_bar(900.0), [0.0; 3]);
    // Σȳ on the 1 nm grid ≈ σ√(2π) = 100.27: sampling a σ = 40 nm Gaussian at 1 nm is exact to
    // e^(−2π²σ²), but the range starts 4.5σ below the peak, cutting off a tail of 3.4e-6 of the
    // mass (3.4e-4 absolute); 1e-3 allows that and nothing more.
    assert!((obs.integral_y() - 40.0 * (2.0 * std::f64::consts::PI).sqrt()).abs() < 1e-3);
}

#[test]
fn a_scene_can_render_with_a_plugin_observer() {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/plugin_spot.ron");
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("observer: \"cie1931-2\"", "observer: \"gaussian_sensor\"");
    let path = std::env::temp_dir().join(format!("spectrace-sensor-{}.ron", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(registry()), faults.clone());
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let s = load_scene_file(&path, &factories).unwrap_or_else(|e| panic!("{e}"));
    let settings = RenderSettings {
        budget: SampleBudget::Spp(2),
        threads: Some(2),
        ..RenderSettings::default()
    };
    let img = render(&s, &settings, &|_, _| {}, None).unwrap().image;
    assert_eq!(img.non_finite_count(), 0);
    let m = img.mean_xyz();
    assert!(m.iter().all(|&c| c > 0.0), "{m:?}");
    assert_eq!(faults.count(), 0);

    // An observer nobody provides is an error naming it and the built-in ones.
    let bad = std::fs::read_to_string(&path)
        .unwrap()
        .replace("gaussian_sensor", "no_such_eye");
    std::fs::write(&path, bad).unwrap();
    let e = load_scene_file(&path, &factories)
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("no_such_eye") && e.contains("cie1931-2"), "{e}");
}

// Built-in objects take a plugin's SPD type: a built-in `point` light given the `lorentzian`
// spec string and a built-in `emissive` material given `(type: "lorentzian", params: …)` both
// light a white floor with a 589.3 nm line 1.2 nm wide, so the floor's chromaticity must be the
// spectral locus at 589.3 nm (CIE 1931 table, interpolated). Tolerance 0.01 in x and y: the
// Lorentzian's tails hold ≈ 1.5% of its power beyond ±25 nm and pull the colour slightly inwards
// (a tail-weighted estimate gives a shift of a few 1e-3); any other spectrum (a failed lookup
// falling back to something else, a wrong normalisation of lanes) lands far away.
#[test]
fn builtin_light_and_material_take_a_plugin_spd() {
    let scene = |light: &str, lamp_material: &str| {
        format!(
            r#"(
    observer: "cie1931-2",
    output: (spp: 4, max_depth: 4),
    materials: [
        (name: "white", type: "lambertian", params: (reflectance: 0.8)),
        (name: "lamp", type: "emissive", params: {lamp_material}),
    ],
    objects: [
        (name: "floor", type: "quad", material: "white",
         params: (corner: (-1, 0, 1), edge0: (2, 0, 0), edge1: (0, 0, -2))),
        (name: "panel", type: "quad", material: "lamp",
         params: (corner: (-0.2, 1.5, -0.2), edge0: (0.4, 0, 0), edge1: (0, 0, 0.4))),
    ],
    lights: [{light}],
    cameras: [(name: "c", type: "perspective",
               params: (position: (0, 1, 2), look_at: (0, 0, 0), fov: 40, resolution: (24, 24)))],
)"#
        )
    };
    let line = "lorentzian(centre_nm: 589.3, fwhm_nm: 1.2)";
    let cases = [
        (
            "point",
            scene(
                &format!(
                    r#"(name: "p", type: "point", params: (position: (0, 1, 0), power: 50, spd: "{line}"))"#
                ),
                r#"(radiance: "d65", scale: 0)"#,
            ),
        ),
        (
            "emissive",
            scene(
                "",
                r#"(radiance: (type: "lorentzian", params: (centre_nm: 589.3, fwhm_nm: 1.2)), scale: 40)"#,
            ),
        ),
    ];
    let cie = spectrace::color::CieObserverKind::Cie1931_2.get();
    let bar = cie.xyz_bar(589.3);
    let locus = [
        bar[0] / (bar[0] + bar[1] + bar[2]),
        bar[1] / (bar[0] + bar[1] + bar[2]),
    ];
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(registry()), faults.clone());
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    for (what, text) in cases {
        let path = std::env::temp_dir().join(format!(
            "spectrace-builtin-plugin-spd-{what}-{}.ron",
            std::process::id()
        ));
        std::fs::write(&path, text).unwrap();
        let s = load_scene_file(&path, &factories).unwrap_or_else(|e| panic!("{what}: {e}"));
        let settings = RenderSettings {
            budget: SampleBudget::Spp(16),
            threads: Some(2),
            ..RenderSettings::default()
        };
        let m = render(&s, &settings, &|_, _| {}, None)
            .unwrap()
            .image
            .mean_xyz();
        let xy = [m[0] / (m[0] + m[1] + m[2]), m[1] / (m[0] + m[1] + m[2])];
        assert!(
            (xy[0] - locus[0]).abs() < 0.01 && (xy[1] - locus[1]).abs() < 0.01,
            "{what}: xy {xy:?} vs spectral locus at 589.3 nm {locus:?}"
        );
        let _ = std::fs::remove_file(&path);
    }
    assert_eq!(faults.count(), 0, "{:?}", faults.first());
}

/// Extension v7: an observer that declares its colour-matching functions to be a 1 nm table
/// (`plugins/fixtures/lying-fluorescent`, `table_observer.rs`) is evaluated from the host's own
/// copy once the claim is checked, and one whose table disagrees with its own `xyz_bar` or
/// `range_nm` is refused with the plugin, the type and what is off named. Quantities: the
/// honest observer's x̄, ȳ, z̄ at nine wavelengths against the linear functions its table
/// samples (x̄ = (λ − 400)/300, ȳ = 1 − |λ − 550|/150, z̄ = (700 − λ)/300), to 1e-12: the
/// table's straight lines reproduce them up to a few roundings of numbers below 1; the first
/// wavelength each lie is caught at (the checks go node by node, then half-way between).
#[test]
fn a_declared_observer_table_is_checked_then_used() {
    let mut r = spectrace::plugin::builtin_registry();
    r.load_plugin(&plugin_library("spectrace-fixture-lying-fluorescent"))
        .unwrap_or_else(|e| panic!("{}", e.verbose()));
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(r), faults.clone());
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/materials.ron");
    let text = std::fs::read_to_string(&scene).unwrap();
    let load = |observer: &str| {
        let path =
            std::env::temp_dir().join(format!("spectrace-{observer}-{}.ron", std::process::id()));
        let t = text.replace(
            "observer: \"cie1931-2\"",
            &format!("observer: \"{observer}\""),
        );
        std::fs::write(&path, t).unwrap();
        let s = load_scene_file(&path, &factories).map_err(|e| e.to_string());
        let _ = std::fs::remove_file(&path);
        s
    };

    let s = load("table_observer").unwrap_or_else(|e| panic!("{e}"));
    assert!(
        format!("{:?}", s.observer).contains("GridObserver"),
        "the host's copy is used: {:?}",
        s.observer
    );
    assert_eq!(s.observer.range(), (400.0, 700.0));
    for nm in [
        400.0, 433.25, 500.5, 549.9, 550.0, 551.75, 612.125, 699.5, 700.0,
    ] {
        let want = [
            (nm - 400.0) / 300.0,
            1.0 - (nm - 550.0f64).abs() / 150.0,
            (700.0 - nm) / 300.0,
        ];
        let got = s.observer.xyz_bar(nm);
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() < 1e-12,
                "{nm} nm: {got:?} vs {want:?}"
            );
        }
    }
    assert_eq!(s.observer.xyz_bar(399.5), [0.0; 3]);
    assert_eq!(faults.count(), 0);

    for (ty, what) in [
        ("table_liar_value", "at 601 nm its xyz_bar gives"),
        ("table_liar_between", "at 400.5 nm its xyz_bar gives"),
        (
            "table_liar_range",
            "its range_nm is 380..700 nm where its table covers 400..700 nm",
        ),
    ] {
        let Err(e) = load(ty) else {
            panic!("{ty}: a wrong table is refused");
        };
        for want in ["lying-fluorescent", ty, "ColorObserver::table", what] {
            assert!(e.contains(want), "{ty}: missing {want:?} in: {e}");
        }
    }
}
