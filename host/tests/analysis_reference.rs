//! Resumable reference renders: stopping and resuming loses no sample and changes nothing.

use spectrace::analysis::{run_reference, state_path, ReferenceSettings, ReferenceState};
use spectrace::integrator::{IntegratorKind, PathTracer};
use spectrace::scene::default_scene;
use std::sync::atomic::AtomicBool;

fn settings(target: u64) -> ReferenceSettings {
    ReferenceSettings {
        pass_spp: 1,
        seed: 7,
        integrator: IntegratorKind::Pt,
        // Short paths keep the test fast; the property checked does not depend on depth.
        tracer: PathTracer {
            max_depth: 3,
            ..PathTracer::default()
        },
        threads: Some(2),
        target_spp: Some(target),
        time: None,
        scene_name: "default Cornell box".into(),
    }
}

/// 2 passes, stop, resume for 2 more == 4 passes in one run: the f64 sums are bitwise equal
/// (same passes, same seeds, added in the same order: no tolerance is needed). The 4-pass sums
/// are not twice the 2-pass sums (each pass draws new samples), and a state made with another
/// key (different depth) is refused with a message naming the state file.
#[test]
fn resumed_equals_straight() {
    let dir = std::env::temp_dir().join(format!("spectrace-ref-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = default_scene().unwrap();
    let nothing = |_: &ReferenceState| {};

    let straight = dir.join("straight.exr");
    let a = run_reference(&scene, &straight, &settings(4), None, &nothing).unwrap();
    assert_eq!(a.state.spp(), 4);
    assert_eq!(a.passes_resumed, 0);

    let resumed = dir.join("resumed.exr");
    let b1 = run_reference(&scene, &resumed, &settings(2), None, &nothing).unwrap();
    assert_eq!((b1.passes_added, b1.state.spp()), (2, 2));
    let two_pass_sums = b1.state.sums.clone();
    let b2 = run_reference(&scene, &resumed, &settings(4), None, &nothing).unwrap();
    assert_eq!((b2.passes_resumed, b2.passes_added), (2, 2));
    let on_disk = ReferenceState::load(&state_path(&resumed)).unwrap();
    assert_eq!(on_disk, b2.state);
    assert!(
        a.state
            .sums
            .iter()
            .zip(&b2.state.sums)
            .all(|(x, y)| x.map(f64::to_bits) == y.map(f64::to_bits)),
        "resumed sums differ from the straight run's"
    );
    let doubled = two_pass_sums
        .iter()
        .zip(&a.state.sums)
        .filter(|(h, f)| h.map(|v| 2.0 * v) == **f)
        .count();
    assert!(doubled < a.state.sums.len() / 2, "passes repeat samples");

    let mut other = settings(6);
    other.tracer.max_depth = 5;
    let e = run_reference(&scene, &resumed, &other, None, &nothing)
        .unwrap_err()
        .to_string();
    assert!(e.contains("resumed.exr.state"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}

/// A cancel flag set before the run adds no pass and reports the interruption (the state on
/// disk stays as it was: nothing is lost, nothing half-made is saved).
#[test]
fn cancelled_run_keeps_state() {
    let dir = std::env::temp_dir().join(format!("spectrace-refc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = default_scene().unwrap();
    let out = dir.join("r.exr");
    let cancel = AtomicBool::new(true);
    let r = run_reference(&scene, &out, &settings(4), Some(&cancel), &|_| {}).unwrap();
    assert!(r.interrupted);
    assert_eq!(r.passes_added, 0);
    assert!(!state_path(&out).exists());
    std::fs::remove_dir_all(&dir).ok();
}
