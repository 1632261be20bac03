//! What the plugin boundary costs: the same point light's `next_beam` and a trivial call
//! (`total_power_w`), (a) called as plain Rust on the type itself, (b) through the stable-ABI
//! trait object built in-process, (c) through the library loaded from disk.
//!
//! Run: `cargo build --release --workspace && cargo bench -p spectrace-tests --bench plugin_boundary`
//! (the loaded case needs the release-built library beside the bench binary).
//! The light's SPD is lent by the host through the ABI in all three cases, so `next_beam`
//! includes one SPD sample call across the boundary each time; `total_power_w` is the pure
//! per-call overhead.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use spectrace::plugin::services::HostServices;
use spectrace::plugin::{LoadedPlugin, Registry};
use spectrace_plugin_api::abi::std_types::RStr;
use spectrace_plugin_api::module::ObjectSource;
use spectrace_plugin_api::{Host, LightSource, PluginType, RandomSample};
use spectrace_point_light::PointLight;
use spectrace_tests::plugin_library;

const PARAMS: &str = "(position: (0, 1, 0), power_w: 10, spd: \"d65\")";

fn bench(c: &mut Criterion) {
    let registry = Registry::new();
    let services = HostServices::new(&registry);
    let host_ref = services.as_ref();
    let host = Host::new(&host_ref);
    let params = spectrace_plugin_api::export::parse_params(PointLight::TYPE_NAME, PARAMS).unwrap();
    let direct = PointLight::new(params, &host).unwrap();
    let direct: &dyn LightSource = &direct;

    let mut in_process = Registry::new();
    in_process
        .add_plugin(
            LoadedPlugin::from_module(spectrace_point_light::root_module(), "in-process").unwrap(),
        )
        .unwrap();
    let abi_in_process = in_process
        .create_plugin_light(
            "isotropic_point",
            ObjectSource::Params(RStr::from_str(PARAMS)),
        )
        .unwrap()
        .light;

    let mut loaded = Registry::new();
    loaded
        .load_plugin(&plugin_library("spectrace-point-light"))
        .unwrap();
    let abi_loaded = loaded
        .create_plugin_light(
            "isotropic_point",
            ObjectSource::Params(RStr::from_str(PARAMS)),
        )
        .unwrap()
        .light;

    let sample = RandomSample {
        u: [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8],
    };

    let mut g = c.benchmark_group("next_beam");
    g.bench_function("built_in", |b| {
        b.iter(|| direct.next_beam(black_box(&sample)).unwrap())
    });
    g.bench_function("abi_in_process", |b| {
        b.iter(|| abi_in_process.next_beam(black_box(&sample)).unwrap())
    });
    g.bench_function("abi_loaded_library", |b| {
        b.iter(|| abi_loaded.next_beam(black_box(&sample)).unwrap())
    });
    g.finish();

    let mut g = c.benchmark_group("total_power_w");
    g.bench_function("built_in", |b| {
        b.iter(|| black_box(direct).total_power_w().unwrap())
    });
    g.bench_function("abi_loaded_library", |b| {
        b.iter(|| black_box(&abi_loaded).total_power_w().unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
