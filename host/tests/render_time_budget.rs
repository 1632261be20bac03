//! `render --time`: a pass still running when the time budget ends is stopped after the units
//! of work in flight (so the budget is honoured within a fraction of a pass, not overrun by a
//! whole pass) and dropped, and the result says so. No timed assertions: the budget's end is
//! forced to fall inside the second pass by holding the progress callback of that pass's first
//! unit until the deadline has passed.

use spectrace::integrator::{render_with, IntegratorKind, RenderSettings, SampleBudget};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

const SCENE: &str = r#"(
    materials: [
        (name: "floor", type: "lambertian", params: (reflectance: 0.5)),
        (name: "lamp", type: "emissive", params: (radiance: "d65", scale: 10.0)),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-1, -1, 0), edge0: (2, 0, 0), edge1: (0, 2, 0))),
        (name: "lamp", type: "quad", material: "lamp",
         params: (corner: (-0.2, -0.2, 2), edge0: (0, 0.4, 0), edge1: (0.4, 0, 0))),
    ],
    cameras: [(name: "c", type: "pinhole",
               params: (position: (0, 0, 5), look_at: (0, 0, 0), resolution: (128, 128))) ],
)"#;

/// For PT, BDPT and LT with a 1 s budget on one thread (128×128 pixels: 64 tiles of 16×16, 4
/// chunks of light paths per spp): the progress callback
/// of the first unit of the second pass sleeps until the budget is over. Checked: the result
/// holds exactly the first pass (1 spp), reports the dropped pass (its size ≥ 1 spp), and its
/// image is bit-identical to a 1 spp render with the same seed: none of the dropped pass's
/// samples leaked into the film.
#[test]
fn a_pass_running_at_the_end_of_the_time_budget_is_stopped_and_dropped() {
    let file = Path::new("t.ron");
    let desc = parse_scene_str(SCENE, file).unwrap();
    let scene = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap();
    let budget = Duration::from_secs(1);
    for kind in [IntegratorKind::Pt, IntegratorKind::Bdpt, IntegratorKind::Lt] {
        let settings = |budget| RenderSettings {
            budget,
            seed: 9,
            threads: Some(1),
            tile_size: 16,
            ..RenderSettings::default()
        };
        let start = Instant::now();
        let first_total = AtomicU64::new(0);
        let held = AtomicU64::new(0);
        let progress = |_done: u64, total: u64| {
            let first =
                match first_total.compare_exchange(0, total, Ordering::SeqCst, Ordering::SeqCst) {
                    Ok(_) => total,
                    Err(v) => v,
                };
            // The units of a later pass raise the total: hold the first of them past the end.
            if total > first && held.fetch_add(1, Ordering::SeqCst) == 0 {
                while start.elapsed() <= budget + Duration::from_millis(50) {
                    std::thread::sleep(Duration::from_millis(10));
                }
            }
        };
        let timed = render_with(
            &scene,
            &settings(SampleBudget::Time(budget)),
            kind,
            false,
            &progress,
            None,
        )
        .unwrap()
        .result;
        let one = render_with(
            &scene,
            &settings(SampleBudget::Spp(1)),
            kind,
            false,
            &|_, _| {},
            None,
        )
        .unwrap()
        .result;
        println!(
            "{kind}: {} spp kept, dropped {:?}, {:.2} s",
            timed.spp,
            timed.dropped_pass,
            timed.elapsed.as_secs_f64()
        );
        assert!(
            held.load(Ordering::SeqCst) > 0,
            "{kind}: no second pass started"
        );
        assert_eq!(timed.spp, 1, "{kind}");
        let dropped = timed
            .dropped_pass
            .unwrap_or_else(|| panic!("{kind}: no dropped pass"));
        assert!(dropped.spp >= 1, "{kind}: {dropped:?}");
        assert_eq!(
            timed.image.xyz, one.image.xyz,
            "{kind}: image differs from 1 spp"
        );
    }
}
