//! Fluorescent plugin materials (`Material::reradiation` of the plugin API): an honest one re-radiates
//! through the host's wavelength shifting, and one that lies (energy-creating re-radiation,
//! NaN, negative densities, anti-Stokes draws, panics) gets a clear error or a counted warning
//! naming the plugin and the scene's material, never a crash. The fixture is
//! `plugins/fixtures/lying-fluorescent` (`liar`: ρ = 0.3, absorbs 0.5 of 350–450 nm and
//! re-emits it uniformly over 500–600 nm). That a fluorescent plugin material renders exactly
//! like the built-in one is `standard_library`'s bit-for-bit test on `scenes/fluorescence.ron`.

use spectrace::integrator::{IntegratorKind, RenderSettings, SampleBudget};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::RegistryFactory;
use spectrace::scene::{build_scene, parse_scene_str, ObjectFactory, Scene};
use spectrace_tests::plugin_library;
use std::path::Path;
use std::sync::Arc;

/// A 0.4 m patch of `patch` (params `params`) on the floor under a 1 m² panel 1 m above it
/// emitting a Gaussian at `light_nm` (FWHM 10 nm), seen from above.
fn scene_text(patch: &str, params: &str, light_nm: u32) -> String {
    format!(
        r#"(
    observer: "cie1931-2",
    output: (spp: 16, max_depth: 4, rgb_space: "srgb"),
    materials: [
        (name: "patch", type: "{patch}", params: {params}),
        (name: "panel", type: "emissive", params: (radiance: "gaussian:{light_nm}:10", scale: 100)),
    ],
    objects: [
        (name: "patch", type: "quad", material: "patch",
         params: (corner: (-0.2, 0, 0.2), edge0: (0.4, 0, 0), edge1: (0, 0, -0.4))),
        (name: "panel", type: "quad", material: "panel",
         params: (corner: (-0.5, 1, 0.5), edge0: (0, 0, -1), edge1: (1, 0, 0))),
    ],
    cameras: [
        (name: "top", type: "perspective",
         params: (position: (0, 0.9, 0.01), look_at: (0, 0, 0), fov: 20, resolution: (16, 16))),
    ],
)"#
    )
}

fn factory() -> RegistryFactory {
    let mut r = spectrace::plugin::builtin_registry();
    r.load_plugin(&plugin_library("spectrace-fixture-lying-fluorescent"))
        .unwrap_or_else(|e| panic!("{}", e.verbose()));
    RegistryFactory::new(Arc::new(r), PluginFaults::new())
}

fn build(f: &RegistryFactory, text: &str) -> Result<Scene, String> {
    let desc = parse_scene_str(text, Path::new("liar.ron")).map_err(|e| e.to_string())?;
    let factories: [&dyn ObjectFactory; 1] = [f];
    build_scene(&desc, Path::new("."), Path::new("liar.ron"), &factories).map_err(|e| e.to_string())
}

/// Mean Y of the image (16 spp, seed 3, 2 threads); the render must finish and be finite.
fn render_y(scene: &Scene, kind: IntegratorKind) -> f64 {
    let settings = RenderSettings {
        budget: SampleBudget::Spp(16),
        seed: 3,
        threads: Some(2),
        ..RenderSettings::default()
    };
    let out = spectrace_tests::render_every_light_subpath(scene, &settings, kind)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(out.result.image.non_finite_count(), 0);
    out.result.image.mean_xyz()[1]
}

/// An honest fluorescent plugin material is used as one: the scene gets no "declares
/// FLUORESCENT but gives no data" warning, the analysis finds fluorescence, and under a 400 nm
/// panel (where Y sees little) the patch re-emits at 500–600 nm (where Y sees much): with PT
/// and with LT its mean Y is more than 100 times that of the same patch reflecting only (the
/// built-in Lambertian ρ = 0.3 in its place). Expected ratio ≈ 0.5·ȳ(500–600 nm, mean ≈ 0.8)
/// over 0.3·ȳ(400 ± 10 nm, ≈ 5e-4) ≈ 2700 (measured 3300 with PT, 3200 with LT at 16 spp), so
/// 100 leaves a wide margin for noise while a lost shift (ratio 1) fails. No plugin call fails
/// or is dropped.
#[test]
fn an_honest_fluorescent_plugin_material_reradiates() {
    let f = factory();
    let scene = build(&f, &scene_text("liar", "(lie: \"none\")", 400)).unwrap();
    assert!(
        scene.warnings().iter().all(|w| !w.contains("FLUORESCENT")),
        "{:?}",
        scene.warnings()
    );
    assert!(scene.objects.fluorescence());
    let twin = build(&f, &scene_text("lambertian", "(reflectance: 0.3)", 400)).unwrap();
    for kind in [IntegratorKind::Pt, IntegratorKind::Lt] {
        let (y, y_twin) = (render_y(&scene, kind), render_y(&twin, kind));
        eprintln!("{kind}: fluorescent {y:.4e}, reflecting only {y_twin:.4e}");
        assert!(
            y_twin > 0.0 && y > 100.0 * y_twin,
            "{kind}: {y} vs {y_twin}"
        );
    }
    assert_eq!(f.faults().count(), 0, "{:?}", f.faults().report());
    assert_eq!(f.faults().invalid_count(), 0, "{:?}", f.faults().report());
}

/// Lies found when the material is built refuse it, with the plugin, the scene's material and
/// the wavelength named: re-radiation three times what the material reports (ρ + ∫ r dλₒ =
/// 1.8 at every excitation wavelength of its band, far above the 1% tolerance), a NaN
/// reflectance, and a claim to be spectrally flat (`SPECTRALLY_FLAT`) by a material that shifts
/// wavelengths.
#[test]
fn energy_creating_or_nan_reradiation_is_refused_when_built() {
    let f = factory();
    let Err(e) = build(&f, &scene_text("liar", "(lie: \"energy\")", 400)) else {
        panic!("an energy-creating material is refused");
    };
    eprintln!("{e}");
    for want in [
        "lying-fluorescent",
        "material \"patch\"",
        "creates energy",
        "350 nm",
        "1.8000",
    ] {
        assert!(e.contains(want), "missing {want:?} in: {e}");
    }
    let Err(e) = build(&f, &scene_text("liar", "(lie: \"nan_reflectance\")", 400)) else {
        panic!("a NaN reflectance is refused");
    };
    for want in [
        "lying-fluorescent",
        "material \"patch\"",
        "reflectance",
        "NaN",
    ] {
        assert!(e.contains(want), "missing {want:?} in: {e}");
    }
    let Err(e) = build(&f, &scene_text("liar", "(lie: \"flat\")", 400)) else {
        panic!("a false claim of spectral flatness is refused");
    };
    for want in [
        "lying-fluorescent",
        "material \"patch\"",
        "spectrally flat",
        "fluoresces",
    ] {
        assert!(e.contains(want), "missing {want:?} in: {e}");
    }
}

/// A false claim of the cosine-weighted density (`COSINE_PDF`: the host would compute `pdf`
/// itself and never see the material's own) is refused when the material is built, naming the
/// plugin, the type, the scene's material, the declaration and the density found against the
/// cosine's. The liar's `sample` and `pdf` say 1/(2π) = 0.159 1/sr, where the cosine density
/// of its first probe direction is far from it; the honest liar keeps the claim off and its
/// density is asked for as before (`cosine_weighted_pdf` false on the built scene).
#[test]
fn a_false_cosine_density_claim_is_refused_when_built() {
    let f = factory();
    let Err(e) = build(&f, &scene_text("liar", "(lie: \"cosine\")", 400)) else {
        panic!("a false claim of the cosine-weighted density is refused");
    };
    eprintln!("{e}");
    for want in [
        "lying-fluorescent",
        "material `liar`",
        "material \"patch\"",
        "cosine-weighted density",
        "COSINE_PDF",
        "`sample`",
        "0.15915",
    ] {
        assert!(e.contains(want), "missing {want:?} in: {e}");
    }
    let scene = build(&f, &scene_text("liar", "(lie: \"none\")", 400)).unwrap();
    let patch = &scene.objects.objects()[0];
    assert_eq!(patch.name, "patch");
    assert!(!patch.material.cosine_weighted_pdf());
}

/// Lies that only show while rendering: the render finishes with a finite image, the bad
/// results are dropped (they contribute nothing) and counted per plugin object and reason, and
/// the report names the plugin, the scene's material and what was wrong. NaN densities of
/// emission draws show on light paths (LT), negative densities of excitation draws on camera
/// paths (PT), emission drawn below the excitation on light paths; a panic while drawing an
/// excitation is a failed call (PT), reported with the call and the panic's message.
#[test]
fn lies_while_rendering_are_dropped_and_reported_never_a_crash() {
    let cases = [
        ("nan_pdf", IntegratorKind::Lt, "wavelength density NaN"),
        ("negative_pdf", IntegratorKind::Pt, "wavelength density NaN"),
        ("anti_stokes", IntegratorKind::Lt, "anti-Stokes"),
    ];
    for (lie, kind, reason) in cases {
        let f = factory();
        let scene = build(&f, &scene_text("liar", &format!("(lie: \"{lie}\")"), 400)).unwrap();
        render_y(&scene, kind);
        let report = f.faults().report().join("\n");
        eprintln!("{lie}: {report}");
        assert_eq!(f.faults().count(), 0, "{lie}: {report}");
        assert!(f.faults().invalid_count() > 0, "{lie}: nothing was dropped");
        assert!(
            f.faults()
                .invalid()
                .iter()
                .any(|(who, why, _)| who.contains("lying-fluorescent")
                    && who.contains("material \"patch\"")
                    && why.contains(reason)),
            "{lie}: {report}"
        );
    }
    let f = factory();
    let scene = build(&f, &scene_text("liar", "(lie: \"panic\")", 400)).unwrap();
    render_y(&scene, IntegratorKind::Pt);
    assert!(f.faults().count() > 0, "the panics were recorded");
    let e = f.faults().outcome().unwrap_err();
    for want in [
        "lying-fluorescent",
        "material \"patch\"",
        "sample_excitation panicked",
        "the liar panics",
    ] {
        assert!(e.contains(want), "missing {want:?} in: {e}");
    }
}

/// The per-sample material calls (`sample`, `eval`, `pdf` in the host's layout, the host's
/// records by reference, the plugin's guard without a thread-local, no error slot) keep the
/// boundary's guarantees: a BSDF sample
/// with a NaN value is dropped and counted per plugin object and reason ("value NaN, infinite or
/// negative", with its call), and a panic while sampling is caught on the plugin's side and
/// reported with its call (`sample`), the panic's location (taken from the report the
/// library's hook deferred) and its message; the render finishes either way (PT, 16 spp).
#[test]
fn lies_in_the_fast_material_calls_are_dropped_or_reported() {
    let f = factory();
    let scene = build(&f, &scene_text("liar", "(lie: \"nan_sample\")", 400)).unwrap();
    render_y(&scene, IntegratorKind::Pt);
    let report = f.faults().report().join("\n");
    assert_eq!(f.faults().count(), 0, "{report}");
    assert!(
        f.faults()
            .invalid()
            .iter()
            .any(|(who, why, n)| who.contains("lying-fluorescent")
                && who.contains("material `liar`")
                && why.contains("sample: value NaN")
                && *n > 0),
        "{report}"
    );
    let f = factory();
    let scene = build(&f, &scene_text("liar", "(lie: \"panic_sample\")", 400)).unwrap();
    render_y(&scene, IntegratorKind::Pt);
    assert!(f.faults().count() > 0, "the panics were recorded");
    let e = f.faults().outcome().unwrap_err();
    for want in [
        "lying-fluorescent",
        "sample panicked at plugins/fixtures/lying-fluorescent/src/lib.rs:",
        "the liar panics while sampling",
    ] {
        assert!(e.contains(want), "missing {want:?} in: {e}");
    }
}

/// A failed per-sample call keeps its error on the plugin's side (no error slot in the call)
/// and the host takes it from the library only when the call answers a failure (ERROR from
/// `sample`, NaN from `eval` or `pdf`). Through the library, with `lying_diffuse` (the liar
/// without fluorescence, so that the integrators call its BSDF while rendering): an error
/// returned by `sample` or `eval` and a panic in `pdf` are each reported naming the plugin, the
/// material and the call (`sample: …`, `eval: …`, `pdf panicked at …`) with the
/// plugin's own message; a NaN value from `sample` or `eval` and an infinite density from `pdf`
/// are dropped and counted with their call. The render finishes every time (PT, BDPT and LT,
/// 16 spp, two threads: each thread takes its own errors), and nothing else is reported.
#[test]
fn a_plugin_s_failures_are_reported_with_plugin_object_and_call() {
    let kinds = [IntegratorKind::Pt, IntegratorKind::Bdpt, IntegratorKind::Lt];
    let lying = |lie: &str| scene_text("lying_diffuse", &format!("(lie: \"{lie}\")"), 400);
    for (lie, call, message) in [
        (
            "error_sample",
            "sample",
            "error: sample: the liar refuses to sample a direction",
        ),
        (
            "error_eval",
            "eval",
            "error: eval: the liar refuses to evaluate",
        ),
        (
            "panic_pdf",
            "pdf panicked at plugins/fixtures/lying-fluorescent/src/lib.rs:",
            "the liar panics while giving a density",
        ),
    ] {
        for kind in kinds {
            let f = factory();
            let scene = build(&f, &lying(lie)).unwrap();
            render_y(&scene, kind);
            let sites = f.faults().sites();
            assert!(
                !sites.is_empty(),
                "{lie} {kind}: the failures were recorded"
            );
            for (who, site, n, first) in &sites {
                assert_eq!(
                    who, "material `lying_diffuse` (plugin lying-fluorescent 0.1.0)",
                    "{lie} {kind}"
                );
                assert!(site.starts_with(call), "{lie} {kind}: {site}");
                assert!(*n > 0 && first.contains(message), "{lie} {kind}: {first}");
            }
            assert_eq!(f.faults().invalid_count(), 0, "{:?}", f.faults().report());
            let e = f.faults().outcome().unwrap_err();
            assert!(e.contains(message), "{lie} {kind}: {e}");
        }
    }
    for (lie, why) in [
        ("nan_sample", "sample: value NaN, infinite or negative"),
        ("nan_eval", "eval: value NaN, infinite or negative"),
        ("infinite_pdf", "pdf: pdf NaN, infinite or negative"),
    ] {
        for kind in kinds {
            let f = factory();
            let scene = build(&f, &lying(lie)).unwrap();
            render_y(&scene, kind);
            let report = f.faults().report().join("\n");
            assert_eq!(f.faults().count(), 0, "{lie} {kind}: {report}");
            let invalid = f.faults().invalid();
            assert!(!invalid.is_empty(), "{lie} {kind}: dropped and counted");
            for (who, reason, n) in invalid {
                assert_eq!(
                    who, "material `lying_diffuse` (plugin lying-fluorescent 0.1.0)",
                    "{lie} {kind}"
                );
                assert!(reason == why && n > 0, "{lie} {kind}: {reason} {n}");
            }
        }
    }
}
