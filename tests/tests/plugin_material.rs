//! A material shipped as a plugin (`plugins/rough-diffuse`, type `oren_nayar`) behaves like a
//! host material: the loaded library computes exactly what the same code computes in process,
//! the host adapter keeps its sampling weights, at zero roughness it renders the image the
//! built-in `lambertian` renders, and it shares a scene with lights and SPDs from two other
//! plugin crates (`scenes/plugin_mix.ron`).

use glam::{Vec2, Vec3A};
use spectrace::integrator::{render, PathTracer, RenderSettings, SampleBudget};
use spectrace::material::{Material as HostMaterial, ShadingContext, TransportMode};
use spectrace::plugin::adapter::{Origin, PluginFaults, PluginMaterial};
use spectrace::plugin::factory::PluginFactory;
use spectrace::plugin::Registry;
use spectrace::scene::{load_scene_file, BuiltinFactory, ObjectFactory};
use spectrace::spectrum::SampledWavelengths;
use spectrace_plugin_api::abi::std_types::RStr;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::{
    Material, Scatter, Surface, TransportMode as AbiMode, Vec3, Vec4f, Wavelengths,
};
use spectrace_rough_diffuse::oren_nayar::{OrenNayar, OrenNayarParams, Reflectance};
use spectrace_tests::plugin_library;
use std::path::{Path, PathBuf};
use std::sync::Arc;

const PLUGINS: [&str; 3] = [
    "spectrace-point-light",
    "spectrace-sensor-spectra",
    "spectrace-rough-diffuse",
];

fn registry() -> Registry {
    let mut r = spectrace::plugin::builtin_registry();
    for lib in PLUGINS {
        r.load_plugin(&plugin_library(lib)).unwrap();
    }
    r
}

fn loaded(params: &str) -> spectrace_plugin_api::MaterialObject {
    registry()
        .create_plugin_material("oren_nayar", ObjectSource::Params(RStr::from_str(params)))
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The root module's `take_error` of the loaded rough-diffuse library.
fn take_error() -> spectrace::plugin::adapter::TakeError {
    let r = registry();
    let p = r
        .plugins()
        .iter()
        .find(|p| p.info.name.as_str() == "rough-diffuse")
        .expect("loaded")
        .clone();
    p.module.take_error()
}

/// Deterministic directions spread over the upper hemisphere.
fn directions(n: usize) -> Vec<Vec3> {
    (0..n)
        .map(|i| {
            let u = (i as f64 * 0.618_033_988_75).fract();
            let v = (i as f64 * 0.414_213_562_37 + 0.1).fract();
            let z = 0.02 + 0.98 * u;
            let r = (1.0 - z * z).sqrt();
            let phi = 2.0 * std::f64::consts::PI * v;
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

// The library loaded through the ABI and the same crate linked in process evaluate the same
// arithmetic, so `eval`, `pdf` and `sample` must agree bit for bit over 40×40 direction pairs:
// any difference would mean the ABI reordered or converted arguments.
#[test]
fn loaded_library_computes_exactly_what_the_crate_computes() {
    let params = "(reflectance: [(400, 0.2), (700, 0.9)], roughness: 0.8)";
    let abi = loaded(params);
    let host = spectrace_plugin_api::host::NoHost;
    let services: spectrace_plugin_api::HostRef<'_> =
        spectrace_plugin_api::host::AbiHost_TO::from_ptr(
            &host,
            spectrace_plugin_api::abi::sabi_trait::TD_Opaque,
        );
    let native = <OrenNayar as spectrace_plugin_api::PluginType>::new(
        OrenNayarParams {
            reflectance: Reflectance(vec![(400.0, 0.2), (700.0, 0.9)]),
            roughness: 0.8,
        },
        &spectrace_plugin_api::Host::new(&services),
    )
    .unwrap();
    let abi = abi.material;
    let ctx = Surface::default();
    let lambda = Wavelengths::at([420.0, 510.0, 600.0, 690.0]);
    let dirs: Vec<Vec4f> = directions(40).into_iter().map(Vec4f::from_f64).collect();
    for wo in &dirs {
        for wi in &dirs {
            let a = abi.eval(wo, wi, &ctx, &lambda, AbiMode::Radiance);
            let b = native
                .eval(wo, wi, &ctx, &lambda, AbiMode::Radiance)
                .unwrap();
            assert_eq!(a.v, b);
            let pa = abi.pdf(wo, wi, &ctx, &lambda, AbiMode::Radiance);
            let pb = native
                .pdf(wo, wi, &ctx, &lambda, AbiMode::Radiance)
                .unwrap();
            assert_eq!(pa, pb);
        }
    }
    let (mut sa, mut sb) = (Scatter::default(), Scatter::default());
    let status = abi.sample(
        &dirs[3],
        &ctx,
        &lambda,
        0.5,
        0.3,
        0.7,
        AbiMode::Radiance,
        &mut sa,
    );
    assert_eq!(status, spectrace_plugin_api::status::WRITTEN);
    let written = native
        .sample(
            &dirs[3],
            &ctx,
            &lambda,
            [0.5, 0.3, 0.7],
            AbiMode::Radiance,
            &mut sb,
        )
        .unwrap();
    assert!(written);
    assert_eq!(sa, sb);
}

// Through the host adapter (f32 host types): looking straight down, every sampled weight
// f·cos/pdf equals the directional albedo π·A·R (the plugin's module docs derive it: the rough
// term vanishes at normal incidence). Checked for 1 000 stratified samples at 1e-5 relative,
// the f32 rounding of the adapter's conversions; also the adapter keeps the DIFFUSE flag and
// `pdf` agrees with the sampled pdf.
#[test]
fn adapter_keeps_the_sampling_weights() {
    let faults = PluginFaults::new();
    let m = PluginMaterial::new(
        loaded("(reflectance: [(555, 0.6)], roughness: 1.0)"),
        take_error(),
        Origin {
            label: "material `oren_nayar`".into(),
            faults: faults.clone(),
        },
        "floor",
    )
    .unwrap();
    assert!(m.flags().has_non_specular());
    let (a, _) = OrenNayar::coefficients(1.0);
    let expected = (std::f64::consts::PI * a * 0.6) as f32;
    let lambda = SampledWavelengths::sample_visible(0.37);
    let ctx = ShadingContext::default();
    let wo = Vec3A::Z;
    for i in 0..1000 {
        let u = Vec2::new(
            ((i % 40) as f32 + 0.5) / 40.0,
            ((i / 40) as f32 + 0.5) / 25.0,
        );
        let s = m
            .sample(wo, &ctx, &lambda, 0.5, u, TransportMode::Radiance)
            .expect("a diffuse sample");
        let pdf = m.pdf(wo, s.wi, &ctx, &lambda, TransportMode::Radiance);
        assert!((pdf - s.pdf).abs() <= 1e-5 * s.pdf, "{pdf} vs {}", s.pdf);
        for lane in 0..4 {
            let w = s.f[lane] * s.wi.z / s.pdf;
            assert!((w - expected).abs() <= 1e-5 * expected, "{w} vs {expected}");
        }
    }
    assert_eq!(faults.count(), 0);
}

fn mix_scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/plugin_mix.ron")
}

fn render_mean(path: &Path, spp: u32) -> ([f64; 3], usize, Arc<PluginFaults>) {
    let faults = PluginFaults::new();
    let plugins = PluginFactory::new(Arc::new(registry()), faults.clone());
    let factories: [&dyn ObjectFactory; 2] = [&BuiltinFactory, &plugins];
    let scene = load_scene_file(path, &factories).unwrap_or_else(|e| panic!("{e}"));
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed: 11,
        threads: Some(2),
        tracer: PathTracer::default(),
        ..RenderSettings::default()
    };
    let r = render(&scene, &settings, &|_, _| {}, None).unwrap();
    (r.image.mean_xyz(), r.image.non_finite_count(), faults)
}

// Three plugin crates (a light, an SPD the light asks the host for, a material) and built-ins
// in one scene: it loads, renders finite, lit pixels and no plugin call fails.
#[test]
fn plugins_from_three_crates_share_one_scene() {
    let (mean, non_finite, faults) = render_mean(&mix_scene(), 4);
    assert_eq!(non_finite, 0);
    assert_eq!(faults.count(), 0, "{:?}", faults.first());
    assert!(mean[1] > 0.0, "the scene is lit: {mean:?}");
}

// At roughness 0 the plugin is Lambertian, so replacing it by the built-in `lambertian` with the
// same constant reflectance must give the same image. Both sample the cosine hemisphere with the
// same concentric map (f64 in the plugin, f32 in the host) and the render uses the same seed, so
// the images differ only where a rounding difference flips a Russian-roulette decision: 0.5% on
// the mean, far below what a wrong 1/π or cosine would cause (tens of percent).
#[test]
fn zero_roughness_renders_like_the_builtin_lambertian() {
    let text = std::fs::read_to_string(mix_scene()).unwrap();
    let plaster = r#"(name: "plaster", type: "oren_nayar",
         params: (reflectance: [(400, 0.55), (550, 0.75), (700, 0.8)], roughness: 0.9)),"#;
    assert!(text.contains(plaster), "the scene's plaster entry changed");
    let write = |name: &str, replacement: &str| {
        let p = std::env::temp_dir().join(format!(
            "spectrace-plugin-material-{name}-{}.ron",
            std::process::id()
        ));
        std::fs::write(&p, text.replace(plaster, replacement)).unwrap();
        p
    };
    let plugin = write(
        "plugin",
        r#"(name: "plaster", type: "oren_nayar", params: (reflectance: [(555, 0.7)], roughness: 0)),"#,
    );
    let builtin = write(
        "builtin",
        r#"(name: "plaster", type: "lambertian", params: (reflectance: 0.7)),"#,
    );
    let (a, _, fa) = render_mean(&plugin, 8);
    let (b, _, _) = render_mean(&builtin, 8);
    assert_eq!(fa.count(), 0);
    for c in 0..3 {
        let rel = (a[c] - b[c]).abs() / b[c];
        assert!(
            rel < 5e-3,
            "channel {c}: plugin {} vs built-in {}",
            a[c],
            b[c]
        );
    }
    // And roughness matters: the rough floor renders differently (not a no-op parameter).
    let rough = write(
        "rough",
        r#"(name: "plaster", type: "oren_nayar", params: (reflectance: [(555, 0.7)], roughness: 1)),"#,
    );
    let (r, _, _) = render_mean(&rough, 8);
    assert!(
        (r[1] - a[1]).abs() / a[1] > 0.01,
        "rough {} vs smooth {}",
        r[1],
        a[1]
    );
    for p in [plugin, builtin, rough] {
        let _ = std::fs::remove_file(p);
    }
}
