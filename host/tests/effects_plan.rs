//! The render plan (`integrator::plan`): switching an effect off is the same render as a scene
//! without it, and `--effects all` renders what `auto` renders where the scene has none of the
//! switchable effects. Run: `cargo test --release -p spectrace --test effects_plan`.

use spectrace::integrator::select::render_planned;
use spectrace::integrator::{EffectsMode, EffectsRequest, RenderPlan};
use spectrace::integrator::{IntegratorKind, PathTracer, RenderSettings, SampleBudget};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

/// A floor, a ball and a lamp; the ball is `dielectric` with `glass_ior`, or diffuse when
/// `glass_ior` is empty.
fn scene(glass_ior: &str, light: &str) -> Scene {
    let ior = if glass_ior.is_empty() {
        "1.5"
    } else {
        glass_ior
    };
    let ball = if glass_ior.is_empty() {
        "wall".to_string()
    } else {
        "glass".to_string()
    };
    let text = format!(
        r#"(
        output: (spp: 16, max_depth: 8),
        materials: [
            (name: "wall", type: "lambertian", params: (reflectance: "colorchecker:13")),
            (name: "glass", type: "dielectric", params: (ior: {ior})),
            (name: "lamp", type: "emissive", params: (radiance: "{light}", scale: 50)),
        ],
        objects: [
            (name: "floor", type: "quad", material: "wall",
             params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
            (name: "ball", type: "sphere", material: "{ball}", params: (center: (0, 0.6, 0), radius: 0.5)),
            (name: "lamp", type: "quad", material: "lamp",
             params: (corner: (-0.5, 2.5, -0.5), edge0: (1, 0, 0), edge1: (0, 0, 1))),
        ],
        cameras: [ (name: "c", type: "perspective",
             params: (position: (0, 1.2, 3), look_at: (0, 0.5, 0), fov: 45, resolution: (24, 16))) ],
    )"#
    );
    let file = Path::new("plan_test.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

fn render(
    scene: &Scene,
    plan: &RenderPlan,
    kind: IntegratorKind,
    spp: u32,
    seed: u64,
) -> Vec<[f64; 3]> {
    let settings = RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(spp),
        seed,
        threads: None,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth: 8,
            ..PathTracer::default()
        },
    };
    render_planned(scene, plan, &settings, kind, false, &|_, _| {}, None)
        .unwrap()
        .result
        .image
        .xyz
}

fn request(mode: EffectsMode, forced: &[&str]) -> EffectsRequest {
    let forced: Vec<String> = forced.iter().map(|s| s.to_string()).collect();
    EffectsRequest::parse(mode, &forced).unwrap()
}

/// Quantity: every pixel's XYZ, bit for bit. N-BK7 with `--effect dispersion=off` must render
/// exactly the scene whose glass has N-BK7's IOR at 550 nm as a constant (the plan replaces the
/// material by that constant-IOR dielectric, so no per-wavelength IOR is evaluated and no lane
/// is dropped), and a constant-IOR glass renders the same whether dispersion is on (auto, all,
/// forced) or off: pt, bdpt and lt. Tolerance 0: the same arithmetic on the same numbers.
#[test]
fn dispersion_off_is_the_constant_ior_render() {
    let bk7 = scene("\"N-BK7\"", "d65");
    let n550 = spectrace::material::SpectralIor::glass("N-BK7")
        .unwrap()
        .eval(550.0);
    let constant = scene(&format!("{n550:?}"), "d65");
    let off = RenderPlan::new(&bk7, &request(EffectsMode::Auto, &["dispersion=off"]));
    assert!(!off.dispersion());
    assert!(
        off.notes()
            .iter()
            .any(|n| n.contains("ball") && n.contains("550 nm")),
        "{:?}",
        off.notes()
    );
    for kind in [IntegratorKind::Pt, IntegratorKind::Bdpt, IntegratorKind::Lt] {
        let a = render(&bk7, &off, kind, 4, 1);
        let b = render(&constant, &RenderPlan::auto(&constant), kind, 4, 1);
        assert!(
            a == b,
            "{kind}: dispersion off differs from the constant IOR"
        );
        // `all` also changes pt's wavelength draws (see the next test), so only bdpt and lt
        // are compared bit for bit under it.
        let all = (kind != IntegratorKind::Pt).then(|| request(EffectsMode::All, &[]));
        for req in all.into_iter().chain([
            request(EffectsMode::Auto, &["dispersion=on"]),
            request(EffectsMode::Auto, &["dispersion=off"]),
        ]) {
            let c = render(&constant, &RenderPlan::new(&constant, &req), kind, 4, 1);
            assert!(c == b, "{kind} {req:?}: constant IOR changed");
        }
        // And the dispersive render does differ (the switch is not a no-op).
        let d = render(&bk7, &RenderPlan::auto(&bk7), kind, 4, 1);
        assert!(d != b, "{kind}: dispersion on rendered like off");
    }
}

/// Quantities: with a diffuse ball and a D65 lamp (no dispersion, fluorescence, thin film or
/// narrowband light), `--effects all` against `auto`. bdpt and lt: every pixel bit for bit
/// (they draw from the same wavelength density, chosen from the scene's properties; the other
/// switches find nothing to act on). pt: all draws wavelengths half from the lamp's spectrum
/// instead of from the observer alone, so the images differ sample by sample but must have the same expectation: the image-mean Y over 8
/// seeds at 64 spp each must agree within 3 standard errors of the difference (from the seed
/// spread), and that standard error must be below 0.5% (so the check can see a 1.5% bias).
#[test]
fn effects_all_renders_what_auto_renders_without_effects() {
    let s = scene("", "d65");
    let auto = RenderPlan::auto(&s);
    let all = RenderPlan::new(&s, &request(EffectsMode::All, &[]));
    assert!(!auto.emission_wavelengths() && all.emission_wavelengths());
    // `all` also forces the visibility guide on, which draws bdpt's s = 1 light points from
    // its learned density (an unbiased change, tested in `integrators_bdpt_guide.rs`): off
    // here, so every other switch is compared bit for bit.
    // And bdpt's light subpaths in every camera sample: auto's pilot may path trace them all
    // (q = 0), and the path tracer's wavelengths differ under `all`.
    let all_unguided = RenderPlan::new(
        &s,
        &request(
            EffectsMode::All,
            &["visibility-guide=off", "light-subpaths=1"],
        ),
    );
    // The guide off in auto's plan too: its pre-pass decides from a few random paths whether
    // the lamp is worth guiding here, and either answer is right.
    let auto_q1 = RenderPlan::new(
        &s,
        &request(
            EffectsMode::Auto,
            &["visibility-guide=off", "light-subpaths=1"],
        ),
    );
    for kind in [IntegratorKind::Bdpt, IntegratorKind::Lt] {
        assert!(
            render(&s, &auto_q1, kind, 4, 2) == render(&s, &all_unguided, kind, 4, 2),
            "{kind}: all differs from auto"
        );
    }
    let mean_y = |plan: &RenderPlan| -> Vec<f64> {
        (1..=8u64)
            .map(|seed| {
                let img = render(&s, plan, IntegratorKind::Pt, 64, seed);
                img.iter().map(|p| p[1]).sum::<f64>() / img.len() as f64
            })
            .collect()
    };
    let stats = |v: &[f64]| {
        let k = v.len() as f64;
        let m = v.iter().sum::<f64>() / k;
        let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (k - 1.0);
        (m, (var / k).sqrt())
    };
    let (ma, sa) = stats(&mean_y(&auto));
    let (mb, sb) = stats(&mean_y(&all));
    let se = (sa * sa + sb * sb).sqrt() / ma;
    let diff = mb / ma - 1.0;
    eprintln!("pt all vs auto: {:+.3}% ± {:.3}%", 100.0 * diff, 100.0 * se);
    assert!(se < 0.005, "standard error {se} too large");
    assert!(diff.abs() < 3.0 * se.max(1e-4), "all {mb} vs auto {ma}");
}
