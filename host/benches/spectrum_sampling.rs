//! Wavelength-sampling throughput: dense (1 nm) and sparse tables, piecewise-linear and
//! piecewise-constant inversion, plus visible-importance sampling. Criterion reports
//! elements (samples) per second.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use spectrace::spectrum::wavelength_sampling::visible_sample;
use spectrace::spectrum::{Interpolation, Spd, TabulatedSpd};

const BATCH: u64 = 10_000;

/// A smooth-ish but irregular test spectrum, values ≥ 0.
fn shape(l: f64) -> f64 {
    let g = |c: f64, w: f64| (-0.5 * ((l - c) / w).powi(2)).exp();
    0.2 + g(450.0, 15.0) + 2.0 * g(545.0, 5.0) + 0.7 * g(610.0, 30.0)
}

fn tables() -> Vec<(&'static str, Vec<f64>, Vec<f64>)> {
    let dense: Vec<f64> = (360..=830).map(|l| l as f64).collect();
    let sparse: Vec<f64> = vec![360.0, 400.0, 450.0, 500.0, 545.0, 600.0, 700.0, 830.0];
    vec![
        (
            "dense_1nm_471",
            dense.clone(),
            dense.iter().map(|&l| shape(l)).collect(),
        ),
        (
            "sparse_8",
            sparse.clone(),
            sparse.iter().map(|&l| shape(l)).collect(),
        ),
    ]
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("spectrum_sampling");
    group.throughput(Throughput::Elements(BATCH));
    for (name, x, f) in tables() {
        for (kind, interp) in [
            ("linear", Interpolation::Linear),
            ("constant", Interpolation::Step),
        ] {
            let spd = TabulatedSpd::new(name, &x, &f, interp).unwrap();
            group.bench_function(format!("{name}/{kind}"), |b| {
                b.iter(|| {
                    let mut acc = 0.0;
                    for i in 0..BATCH {
                        // Low-discrepancy stream (golden-ratio sequence): cheap and covers [0,1).
                        let u = (i as f64 * 0.618_033_988_749_894_9).fract();
                        let s = spd.sample(black_box(u));
                        acc += s.lambda * s.pdf;
                    }
                    black_box(acc)
                })
            });
        }
    }
    group.bench_function("visible_importance", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for i in 0..BATCH {
                let u = (i as f64 * 0.618_033_988_749_894_9).fract();
                acc += visible_sample(black_box(u));
            }
            black_box(acc)
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
