//! `bench accuracy` machinery on the small caustic scene (160×120, fast).

use spectrace::analysis::accuracy_bench::{
    available_configs, run_accuracy_bench, select_configs, to_csv, BenchSettings, CSV_HEADER,
};
use spectrace::analysis::RgbImage;
use spectrace::color::SRGB;
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::scene::{load_scene_file, BuiltinFactory};
use std::path::Path;
use std::time::Duration;

/// With the same-seed 2-spp render of the same configuration as the reference, the bench's
/// 2-spp point has exactly zero error (renders are deterministic, so any non-zero value would
/// mean the bench renders something else than it claims) while its 1-spp point does not; the
/// doubling stops at max_spp; the CSV has a header and one row per point.
#[test]
fn bench_points_are_what_they_claim() {
    let scene_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/caustic.ron");
    let scene = load_scene_file(&scene_path, &[&BuiltinFactory]).unwrap();
    let configs = select_configs(
        available_configs(scene.options.max_depth),
        Some(&["pt-depth4".to_string()]),
    )
    .unwrap();
    let reference = {
        let rs = RenderSettings {
            sampler: Default::default(),
            budget: SampleBudget::Spp(2),
            seed: 3,
            threads: Some(2),
            camera: None,
            tile_size: 16,
            tracer: PathTracer {
                max_depth: 4,
                ..PathTracer::default()
            },
        };
        let out = render_with(&scene, &rs, IntegratorKind::Pt, false, &|_, _| {}, None).unwrap();
        RgbImage::from_xyz(&out.result.image, &SRGB)
    };
    let settings = BenchSettings {
        budget: Duration::from_secs(600),
        max_spp: 2,
        seed: 3,
        threads: Some(2),
        exclude_specular: false,
    };
    let points = run_accuracy_bench(&scene, &reference, &configs, &settings, &|_| {}).unwrap();
    assert_eq!(points.iter().map(|p| p.spp).collect::<Vec<_>>(), [1, 2]);
    assert!(points[0].rmse > 0.0 && points[0].delta_e_mean > 0.0);
    assert_eq!((points[1].rmse, points[1].delta_e_mean), (0.0, 0.0));
    let csv = to_csv(&points);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines[0], CSV_HEADER);
    assert_eq!(lines.len(), 3);
    assert!(lines[2].starts_with("pt-depth4,2,"));
}
