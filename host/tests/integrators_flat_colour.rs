//! The exact colour of spectrally flat paths (`integrator::flat_colour`, render-plan switch
//! `flat-path-colour`): the same expected image as the four-wavelength estimate, with less
//! noise, and no change at all where paths touch a coloured surface; bdpt, lt and pt.
//! Run: `cargo test --release -p spectrace --test integrators_flat_colour` (a few seconds).

mod common_render;
use spectrace::film::XyzImage;
use spectrace::integrator::select::render_planned;
use spectrace::integrator::IntegratorKind;
use spectrace::integrator::{EffectsMode, EffectsRequest, RenderPlan, Switch};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

/// The glass-sphere caustic as shipped (source: scenes/caustic.ron), with `edits` applied.
fn caustic(edits: &[(&str, &str)]) -> Scene {
    let mut text = include_str!("../../scenes/caustic.ron").to_string();
    for (from, to) in edits {
        assert!(text.contains(from), "{from} not in caustic.ron");
        text = text.replace(from, to);
    }
    let file = Path::new("caustic.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// A render by `kind` (with `per_path` wavelengths a camera path where it is `pt`), the switch
/// forced to `flat`.
fn render(
    scene: &Scene,
    (kind, per_path): (IntegratorKind, u32),
    flat: bool,
    spp: u32,
    seed: u64,
) -> XyzImage {
    let plan = RenderPlan::new(
        scene,
        &EffectsRequest {
            mode: EffectsMode::Auto,
            forced: vec![(Switch::FlatPathColour, flat)],
            ..Default::default()
        },
    );
    assert_eq!(plan.flat_path_colour(), flat);
    let mut settings = common_render::spp_settings(scene, spp, seed);
    settings.tracer.wavelengths_per_path = per_path;
    let out = render_planned(scene, &plan, &settings, kind, false, &|_, _| {}, None).unwrap();
    assert_eq!(out.result.image.non_finite_count(), 0);
    out.result.image
}

fn mean_var(xs: &[f64]) -> (f64, f64) {
    let k = xs.len() as f64;
    let m = xs.iter().sum::<f64>() / k;
    (
        m,
        xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (k - 1.0),
    )
}

/// Largest distance over pixels (with some light) of the chromaticity (x, y) from `white`.
fn chromaticity_spread(images: &[XyzImage], white: [f64; 2]) -> f64 {
    let mut worst = 0.0f64;
    for img in images {
        for p in &img.xyz {
            let sum = p[0] + p[1] + p[2];
            if sum > 1e-9 {
                let (x, y) = (p[0] / sum, p[1] / sum);
                worst = worst.max((x - white[0]).abs()).max((y - white[1]).abs());
            }
        }
    }
    worst
}

/// A spectrally flat caustic (grey floor and wall, constant-IOR glass, one D65 lamp), 40×30,
/// K = 8 seeds × 16 spp, bdpt, lt and pt (pt also with 8 wavelengths a path: two groups, each
/// its own exact colour), switch on against off.
/// Quantities: (1) per channel, the image mean over the K renders: on and off must agree
/// within 4 standard errors of their difference (the SE from the seed-to-seed spread of each);
/// a bias as small as the SE fails often, a correct estimator fails with probability about
/// 0.5% per channel (Student-t, 7 degrees of freedom). (2) Colour noise: every path here is
/// flat and the lamp is the only emitter, so with the switch on every contribution has the
/// lamp's own colour and every pixel's chromaticity (x, y) is D65's (0.3127, 0.3290 for CIE
/// 1931 2°) to float rounding (tolerance 1e-4, rounding of f32 lanes summed in f64 is far
/// below); off, the four-wavelength estimate scatters it by more than 0.005 somewhere (the
/// check that the quantity can fail).
#[test]
fn flat_scene_agrees_and_loses_the_wavelength_noise() {
    let scene = caustic(&[
        ("\"colorchecker:13\"", "0.5"),
        ("resolution: (160, 120)", "resolution: (40, 30)"),
    ]);
    let k = 8u64;
    for kind in [
        (IntegratorKind::Bdpt, 4),
        (IntegratorKind::Lt, 4),
        (IntegratorKind::Pt, 4),
        (IntegratorKind::Pt, 8),
    ] {
        let on: Vec<XyzImage> = (0..k)
            .map(|s| render(&scene, kind, true, 16, 50 + s))
            .collect();
        let off: Vec<XyzImage> = (0..k)
            .map(|s| render(&scene, kind, false, 16, 50 + s))
            .collect();
        for c in 0..3 {
            let (m_on, v_on) = mean_var(&on.iter().map(|i| i.mean_xyz()[c]).collect::<Vec<_>>());
            let (m_off, v_off) = mean_var(&off.iter().map(|i| i.mean_xyz()[c]).collect::<Vec<_>>());
            let se = ((v_on + v_off) / k as f64).sqrt();
            eprintln!(
                "{kind:?} channel {c}: on {m_on:.6} off {m_off:.6} diff {:+.6} se {se:.6}",
                m_on - m_off
            );
            assert!(
                (m_on - m_off).abs() < 4.0 * se,
                "{kind:?} channel {c}: on {m_on} vs off {m_off}, 4 SE = {}",
                4.0 * se
            );
        }
        let white = [0.312_72, 0.329_03];
        let (spread_on, spread_off) = (
            chromaticity_spread(&on, white),
            chromaticity_spread(&off, white),
        );
        eprintln!("{kind:?}: chromaticity spread on {spread_on:.2e} off {spread_off:.2e}");
        assert!(
            spread_on < 1e-4,
            "{kind:?}: colour noise {spread_on} with the switch on"
        );
        assert!(
            spread_off > 5e-3,
            "{kind:?}: colour noise only {spread_off} with it off"
        );
    }
}

/// Paths that touch a coloured surface keep the ordinary estimate. Quantity: every pixel's
/// XYZ, bit for bit, switch on against off, for a camera that sees only the coloured back wall
/// (every camera path's first surface is the wall, and every t = 1 connection ends on it), bdpt,
/// lt and pt. Tolerance: none (the switch changes no random numbers, only how a flat path's lanes
/// become XYZ).
#[test]
fn paths_through_a_coloured_wall_are_unchanged() {
    let scene = caustic(&[
        ("position: (0, 1.6, 4.5)", "position: (0, 2.0, -1.0)"),
        ("look_at: (0, 0.5, 0)", "look_at: (0, 2.0, -2.0)"),
        ("resolution: (160, 120)", "resolution: (24, 18)"),
    ]);
    for kind in [IntegratorKind::Bdpt, IntegratorKind::Lt, IntegratorKind::Pt] {
        let on = render(&scene, (kind, 4), true, 8, 3);
        let off = render(&scene, (kind, 4), false, 8, 3);
        assert!(off.mean_xyz()[1] > 0.0, "{kind}: the wall is black");
        assert_eq!(on.xyz, off.xyz, "{kind}: the coloured wall changed");
    }
}
