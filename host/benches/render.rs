//! Render throughput on the default scene (the measured Cornell box, 256×256): camera samples
//! per second and rays per second, with the path tracer as `spectrace render` runs it.
//!
//! `cargo bench -p spectrace --bench render` (criterion reports samples/s as "elem/s"); a
//! one-line summary with rays/s is printed first.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use spectrace::integrator::{render, RenderSettings, SampleBudget};
use spectrace::scene::default_scene;

fn bench_render(c: &mut Criterion) {
    let scene = default_scene().expect("embedded Cornell box");
    let spp = 4;
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed: 3,
        threads: None,
        ..RenderSettings::default()
    };
    // One untimed warm-up render for the summary line.
    let r = render(&scene, &settings, &|_, _| {}, None).unwrap();
    let s = r.elapsed.as_secs_f64();
    println!(
        "cornell 256x256 @ {spp} spp on {} threads: {:.3} M samples/s, {:.3} M rays/s ({:.2} rays/sample)",
        rayon::current_num_threads(),
        r.samples as f64 / s / 1e6,
        r.rays as f64 / s / 1e6,
        r.rays as f64 / r.samples as f64
    );
    let mut g = c.benchmark_group("render");
    g.sample_size(10);
    g.throughput(Throughput::Elements(r.samples));
    g.bench_function("cornell_256x256_4spp", |b| {
        b.iter(|| render(&scene, &settings, &|_, _| {}, None).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench_render);
criterion_main!(benches);
