//! Independent estimators agree: BDPT, path tracing (PT) and light tracing (LT) converge to the
//! same image on the diffuse Cornell box, a glass-sphere caustic (as shipped, and with a larger
//! lamp that PT can resolve in the budget), a spot light reflected by a mirror (and by a diffuse
//! panel instead, which PT can render) and a directional light through a thin lens.
//! Run in release: `cargo test --release -p spectrace --test integrators_agreement`
//! (about 2 minutes of CPU on 2 cores; `-- --ignored` adds the long runs).
//!
//! The test, for each pair of estimators A, B on a scene (pixels each can render: see below):
//! * every estimator renders K images with independent seeds;
//! * per channel, the image means (over the K renders) agree within 0.5%, and the standard
//!   error of each estimator's mean (from the seed-to-seed spread) is below 0.15%, so 0.5% is
//!   more than 3σ of either and the check cannot pass by noise alone ("within 4 standard
//!   errors" only where 0.5% is out of reach: path tracing on the shipped caustic, see there);
//! * per 8×8 tile and per channel, `z = (Ā − B̄)/√(s²_A/K + s²_B/K)` with the sample variances
//!   `s²` of the K seed means; at most 2% of tiles (at least 2 tiles on small images) may have
//!   |z| > 4. With K = 8 the statistic is
//!   close to Student-t with ≥ 7 degrees of freedom, for which P(|t| > 4) ≈ 0.5%: a correct
//!   pair passes, a bias of a few standard errors spread over many tiles fails. Not applied to
//!   path tracing on the shipped caustic: its estimator there is heavy-tailed (rare
//!   BSDF-sampled paths through the glass onto the 5 cm lamp), so 8-seed variances understate
//!   its spread and the z-statistic is not Student-t; its image mean is still compared (within
//!   4 standard errors).
//!
//! Which pixels: light tracing cannot render what the camera sees through a delta BSDF (a
//! mirror or smooth glass seen directly: the t = 1 connection needs a BSDF that can be
//! evaluated), and path tracing cannot render paths from a point light via a mirror (neither
//! next-event estimation nor BSDF sampling can find them). Such pixels are masked out of the
//! comparisons that involve that estimator, and the test asserts PT's deficit where it exists.

use spectrace::film::XyzImage;
use spectrace::integrator::select::render_planned;
use spectrace::integrator::{
    EffectsRequest, IntegratorKind, LightSubpaths, PathTracer, RenderPlan, RenderSettings,
    SampleBudget,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::Path;

/// Build a scene from RON text with the camera resolution replaced.
fn scene_from(text: &str, from: &str, to: &str) -> Scene {
    assert!(
        text.contains(from),
        "resolution pattern {from} not in scene"
    );
    let text = text.replace(from, to);
    let file = Path::new("test.ron");
    let desc = parse_scene_str(&text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

fn render_seeds(scene: &Scene, kind: IntegratorKind, spp: u32, k: u64) -> Vec<XyzImage> {
    (0..k)
        .map(|seed| {
            let settings = RenderSettings {
                sampler: Default::default(),
                budget: SampleBudget::Spp(spp),
                seed: 1000 + seed,
                threads: None,
                camera: None,
                tile_size: 16,
                tracer: PathTracer {
                    max_depth: scene.options.max_depth,
                    ..PathTracer::default()
                },
            };
            // BDPT with every camera sample tracing light subpaths: the auto fraction may
            // path trace every camera sample (q = 0), and its agreement with pt would then be
            // pt's with itself.
            let request = EffectsRequest {
                light_subpaths: LightSubpaths::Fraction(1.0),
                ..Default::default()
            };
            let plan = RenderPlan::new(scene, &request);
            let out =
                render_planned(scene, &plan, &settings, kind, false, &|_, _| {}, None).unwrap();
            assert_eq!(
                out.result.image.non_finite_count(),
                0,
                "{kind}: non-finite pixels"
            );
            out.result.image
        })
        .collect()
}

/// Pixels whose whole footprint (a 3×3 grid over the pixel and half its neighbours, covering
/// the reconstruction filter) sees a non-delta surface or nothing: LT can render those.
fn non_specular_mask(scene: &Scene) -> Vec<bool> {
    spectrace::analysis::specular_view_mask(scene)
        .into_iter()
        .map(|specular| !specular)
        .collect()
}

/// Mean over masked pixels of each seed's image, per channel.
fn seed_means(images: &[XyzImage], mask: &[bool]) -> Vec<[f64; 3]> {
    images
        .iter()
        .map(|img| {
            let mut m = [0.0; 3];
            let mut n = 0.0;
            for (p, &keep) in img.xyz.iter().zip(mask) {
                if keep {
                    for c in 0..3 {
                        m[c] += p[c];
                    }
                    n += 1.0;
                }
            }
            m.map(|v| v / n)
        })
        .collect()
}

fn mean_var(xs: &[f64]) -> (f64, f64) {
    let k = xs.len() as f64;
    let m = xs.iter().sum::<f64>() / k;
    let v = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (k - 1.0);
    (m, v)
}

/// The comparison described in the module docs; panics with the numbers on failure. With
/// `mean_tol = None` the image means must agree within 4 standard errors of their difference
/// (used where the 0.5% criterion would need minutes of rendering; see the ignored long tests).
fn assert_agree(
    name: &str,
    a: &[XyzImage],
    b: &[XyzImage],
    mask: &[bool],
    mean_tol: Option<f64>,
    tile_test: bool,
) {
    let k = a.len() as f64;
    let (ma, mb) = (seed_means(a, mask), seed_means(b, mask));
    let mut failures = Vec::new();
    for c in 0..3 {
        let (m_a, v_a) = mean_var(&ma.iter().map(|m| m[c]).collect::<Vec<_>>());
        let (m_b, v_b) = mean_var(&mb.iter().map(|m| m[c]).collect::<Vec<_>>());
        let rel = m_a / m_b - 1.0;
        let (se_a, se_b) = ((v_a / k).sqrt() / m_b, (v_b / k).sqrt() / m_b);
        let se = (se_a * se_a + se_b * se_b).sqrt();
        eprintln!(
            "{name} channel {c}: means {m_a:.6} vs {m_b:.6}, diff {rel:+.4}, se {se:.4} ({se_a:.4}, {se_b:.4})"
        );
        match mean_tol {
            Some(tol) => {
                if rel.abs() >= tol {
                    failures.push(format!(
                        "channel {c}: mean differs by {rel:+.4} (tolerance {tol})"
                    ));
                }
                if se_a.max(se_b) >= MAX_SE {
                    failures.push(format!(
                        "channel {c}: too noisy to test (se {se_a:.4}, {se_b:.4} ≥ {MAX_SE})"
                    ));
                }
            }
            None => {
                if rel.abs() >= 4.0 * se {
                    failures.push(format!(
                        "channel {c}: mean differs by {rel:+.4} > 4 se ({se:.4})"
                    ));
                }
            }
        }
    }
    let (w, h) = (a[0].width as usize, a[0].height as usize);
    let tile = 8;
    // Outliers are counted per tile, as the module docs state: a tile's three channels share
    // their paths, so one unusual tile often moves all three together and is one event.
    let (mut tiles, mut outliers, mut worst) = (0usize, 0usize, 0.0f64);
    for ty in (0..h).step_by(tile) {
        for tx in (0..w).step_by(tile) {
            let idx: Vec<usize> = (ty..(ty + tile).min(h))
                .flat_map(|y| (tx..(tx + tile).min(w)).map(move |x| y * w + x))
                .filter(|&i| mask[i])
                .collect();
            if idx.len() < tile * tile / 2 {
                continue;
            }
            let (mut tested, mut out) = (false, false);
            for c in 0..3 {
                let tm = |imgs: &[XyzImage]| -> Vec<f64> {
                    imgs.iter()
                        .map(|img| {
                            idx.iter().map(|&i| img.xyz[i][c]).sum::<f64>() / idx.len() as f64
                        })
                        .collect()
                };
                let (m_a, v_a) = mean_var(&tm(a));
                let (m_b, v_b) = mean_var(&tm(b));
                let se = ((v_a + v_b) / k).sqrt();
                if se == 0.0 {
                    assert_eq!(m_a, m_b, "{name}: noiseless tile differs");
                    continue;
                }
                let z = (m_a - m_b) / se;
                tested = true;
                worst = worst.max(z.abs());
                if z.abs() > 4.0 {
                    out = true;
                    eprintln!(
                        "{name}: tile ({tx}, {ty}) channel {c}: {m_a:.6} vs {m_b:.6}, z {z:.2}"
                    );
                }
            }
            tiles += usize::from(tested);
            outliers += usize::from(out);
        }
    }
    eprintln!("{name}: {outliers} of {tiles} tiles with a channel at |z| > 4 (max |z| {worst:.2})");
    assert!(failures.is_empty(), "{name}: {}", failures.join("; "));
    if !tile_test {
        return;
    }
    assert!(tiles > 0);
    assert!(
        outliers as f64 <= (0.02 * tiles as f64).max(2.0),
        "{name}: {outliers} of {tiles} tiles differ by more than 4σ in a channel"
    );
}

const K: u64 = 8;

/// Largest relative standard error of one estimator's image mean for a 0.5% check: 0.5% is then
/// more than 3 standard errors of each estimator.
const MAX_SE: f64 = 0.0015;

fn cornell() -> Scene {
    scene_from(
        include_str!("../../scenes/cornell_box.ron"),
        "\"resolution\": [256.0, 256.0]",
        "\"resolution\": [64.0, 64.0]",
    )
}

fn small(text: &str) -> Scene {
    scene_from(text, "resolution: (160, 120)", "resolution: (48, 36)")
}

/// The measured diffuse Cornell box at 64×64: every estimator renders every pixel; means within
/// 0.5% per channel (the budget gives a standard error of the difference below 0.15%).
#[test]
fn cornell_box_bdpt_pt_lt_agree() {
    let scene = cornell();
    let all = vec![true; 64 * 64];
    let bdpt = render_seeds(&scene, IntegratorKind::Bdpt, 32, K);
    let pt = render_seeds(&scene, IntegratorKind::Pt, 64, K);
    let lt = render_seeds(&scene, IntegratorKind::Lt, 64, K);
    assert_agree("cornell bdpt/pt", &bdpt, &pt, &all, Some(0.005), true);
    assert_agree("cornell lt/pt", &lt, &pt, &all, Some(0.005), true);
    assert_agree("cornell bdpt/lt", &bdpt, &lt, &all, Some(0.005), true);
}

/// The shipped caustic scene at 48×36 (same camera), optionally with the 5 cm lamp replaced by
/// a `lamp_m`-wide one of the same power (same position and spectrum).
fn caustic_scene(lamp_m: Option<f64>) -> Scene {
    let mut text = include_str!("../../scenes/caustic.ron").to_string();
    if let Some(a) = lamp_m {
        let lamp = "corner: (-0.025, 2.6, -0.025), edge0: (0.05, 0, 0), edge1: (0, 0, 0.05)";
        assert!(text.contains(lamp) && text.contains("scale: 480000.0"));
        let h = a / 2.0;
        text = text
            .replace(
                lamp,
                &format!(
                    "corner: ({}, 2.6, {}), edge0: ({a}, 0, 0), edge1: (0, 0, {a})",
                    -h, -h
                ),
            )
            // Radiance × area constant: the same power, so the same total caustic flux.
            .replace(
                "scale: 480000.0",
                &format!("scale: {}", 480000.0 * 0.05 * 0.05 / (a * a)),
            );
    }
    small(&text)
}

/// The glass-sphere caustic as shipped (5 cm lamp). Off the glass (pixels LT can render) BDPT
/// and LT agree within 0.5% with standard errors below 0.15%, plus the tile z-test. PT only
/// within 4 standard errors: its caustic estimate (a BSDF-sampled ray from the floor through
/// the sphere onto the 5 cm lamp) has a relative standard error of its image mean of ~3.6% at
/// 512 spp × 8 seeds (7·10⁶ samples, 4 s); 0.15% would need ~600× that, about 40 minutes on
/// 2 cores, and its heavy tail makes 8-seed variances unreliable for a tile z-test. On the
/// glass pixels LT has no strategy, and BDPT and PT both rely on the same unweighted s = 0
/// paths (the lamp's reflection in the sphere and its images through it, about 1.3% of the
/// image mean, hit by ~0.3% of the samples of the pixels showing it), so no 0.5% statement is
/// possible there at test budgets. See [`caustic_larger_lamp_bdpt_pt_lt_within_half_percent`]
/// for PT at 0.5%.
fn caustic(spp_scale: u32) {
    let scene = caustic_scene(None);
    let mask = non_specular_mask(&scene);
    assert!(
        mask.iter().filter(|&&m| !m).count() > 20,
        "the glass is visible"
    );
    let bdpt = render_seeds(&scene, IntegratorKind::Bdpt, 32 * spp_scale, K);
    let lt = render_seeds(&scene, IntegratorKind::Lt, 192 * spp_scale, K);
    let pt = render_seeds(&scene, IntegratorKind::Pt, 512 * spp_scale, K);
    assert_agree("caustic bdpt/lt", &bdpt, &lt, &mask, Some(0.005), true);
    assert_agree("caustic pt/lt", &pt, &lt, &mask, None, false);
    assert_agree("caustic bdpt/pt", &bdpt, &pt, &mask, None, false);
}

/// Caustic as shipped, test-suite budget (~8 s in release on 2 cores).
#[test]
fn caustic_bdpt_lt_within_half_percent_pt_within_4se() {
    caustic(1);
}

/// Caustic as shipped, long run (minutes): the same checks at 10× the samples (PT's standard
/// error ~1.1%, still far from what a 0.5% check needs).
#[test]
#[ignore = "long: run with --ignored in release"]
fn caustic_long_run() {
    caustic(10);
}

/// The caustic scene with a 50 cm lamp of the same power (still a focused caustic under the
/// sphere) that path tracing can resolve in the test budget: its standard error drops roughly
/// in proportion to the lamp's width (3.6%, 1.0%, 0.5% at 5, 20, 40 cm for 512 spp × 8 seeds,
/// off the glass). All three estimators agree within 0.5% off the glass, standard errors below
/// 0.15% each, tile z-test for every pair; BDPT and PT also over all pixels, means only (on and
/// through the glass, where LT has no strategy and both rely on camera paths that hit the
/// lamp). About 45 s of CPU in release, most of it PT's 4096 spp.
#[test]
fn caustic_larger_lamp_bdpt_pt_lt_within_half_percent() {
    let scene = caustic_scene(Some(0.5));
    let mask = non_specular_mask(&scene);
    let all = vec![true; mask.len()];
    // BDPT's 512 spp are for the all-pixel check: the lamp's reflection in the sphere (s = 0
    // only) dominates its spread there.
    let bdpt = render_seeds(&scene, IntegratorKind::Bdpt, 512, K);
    let lt = render_seeds(&scene, IntegratorKind::Lt, 384, K);
    let pt = render_seeds(&scene, IntegratorKind::Pt, 4096, K);
    assert_agree(
        "caustic 50 cm bdpt/lt",
        &bdpt,
        &lt,
        &mask,
        Some(0.005),
        true,
    );
    assert_agree("caustic 50 cm pt/lt", &pt, &lt, &mask, Some(0.005), true);
    assert_agree(
        "caustic 50 cm bdpt/pt",
        &bdpt,
        &pt,
        &mask,
        Some(0.005),
        true,
    );
    assert_agree(
        "caustic 50 cm bdpt/pt all pixels",
        &bdpt,
        &pt,
        &all,
        Some(0.005),
        // No tile test here: on the glass both rely on the lamp's reflection in the sphere
        // (s = 0 only), a heavy-tailed estimate whose 8-seed variances are unreliable.
        false,
    );
}

/// Spot light reflected by a mirror onto the back wall: BDPT and LT agree within 0.5% off the
/// mirror (standard errors below 0.15%, tile z-test). PT cannot render this scene at all: the
/// spot's cone falls entirely on the mirror, and a path from a point light via a mirror has
/// zero density for both of PT's strategies (next-event estimation cannot connect through the
/// mirror, BSDF sampling never hits a point), so its image is black; the test asserts that
/// deficit. PT's handling of the spot itself is checked in [`spot_diffuse_panel_bdpt_pt_lt_agree`].
fn spot_mirror(bdpt_spp: u32, lt_spp: u32) {
    let scene = small(include_str!("../../scenes/spot_mirror.ron"));
    let mask = non_specular_mask(&scene);
    let bdpt = render_seeds(&scene, IntegratorKind::Bdpt, bdpt_spp, K);
    let lt = render_seeds(&scene, IntegratorKind::Lt, lt_spp, K);
    assert_agree("spot_mirror bdpt/lt", &bdpt, &lt, &mask, Some(0.005), true);
    let pt = render_seeds(&scene, IntegratorKind::Pt, 32, 2);
    let m_pt = seed_means(&pt, &mask)[0][1];
    let m_bdpt = seed_means(&bdpt, &mask)[0][1];
    eprintln!("spot_mirror Y: pt {m_pt:.6}, bdpt {m_bdpt:.6}");
    assert!(m_pt < 0.8 * m_bdpt, "PT should miss the mirrored spot");
}

/// Spot/mirror, test-suite budget (~10 s in release). LT gets 8× BDPT's samples: in the dark
/// tiles lit only by long paths its splats are sparse and heavy-tailed (at 160 spp two such
/// tiles showed |z| ≈ 4–6 with BDPT 5–9% brighter; at 1280 spp none exceeds 3.8).
#[test]
fn spot_mirror_bdpt_lt_within_half_percent_pt_misses_the_reflection() {
    spot_mirror(160, 1280);
}

/// Spot/mirror, long run: 8× the samples.
#[test]
#[ignore = "long: run with --ignored in release"]
fn spot_mirror_long_run() {
    spot_mirror(1280, 10240);
}

/// The spot/mirror scene with the mirror replaced by a white Lambertian panel of the same
/// reflectance (0.95): the spot's light now reaches the wall by a diffuse bounce, which PT can
/// sample (next-event estimation to the spot from the panel). All three estimators agree within
/// 0.5% on every pixel, standard errors below 0.15%, tile z-test: the delta light's densities
/// and MIS weights match PT where PT has a strategy.
#[test]
fn spot_diffuse_panel_bdpt_pt_lt_agree() {
    let text = include_str!("../../scenes/spot_mirror.ron");
    let mirror = r#"type: "mirror", params: (reflectance: 0.95)"#;
    assert!(text.contains(mirror));
    let scene = small(&text.replace(mirror, r#"type: "lambertian", params: (reflectance: 0.95)"#));
    let all = vec![true; 48 * 36];
    let bdpt = render_seeds(&scene, IntegratorKind::Bdpt, 256, K);
    let pt = render_seeds(&scene, IntegratorKind::Pt, 1024, K);
    let lt = render_seeds(&scene, IntegratorKind::Lt, 384, K);
    assert_agree("spot_panel bdpt/pt", &bdpt, &pt, &all, Some(0.005), true);
    assert_agree("spot_panel lt/pt", &lt, &pt, &all, Some(0.005), true);
    assert_agree("spot_panel bdpt/lt", &bdpt, &lt, &all, Some(0.005), true);
}

/// A directional light (delta direction, positional density on a disk across the scene) seen
/// through a thin-lens camera (finite aperture: the lens point is part of every strategy's
/// density): all three estimators render every pixel; means within 0.5%, tile z-test.
#[test]
fn directional_light_thin_lens_bdpt_pt_lt_agree() {
    let text = r#"(
    observer: "cie1931-2",
    output: (spp: 16, max_depth: 16, rgb_space: "srgb"),
    materials: [
        (name: "grey", type: "lambertian", params: (reflectance: 0.6)),
        (name: "red", type: "lambertian", params: (reflectance: "colorchecker:15")),
    ],
    objects: [
        (name: "floor", type: "quad", material: "grey",
         params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
        (name: "back", type: "quad", material: "grey",
         params: (corner: (-2, 0, -2), edge0: (4, 0, 0), edge1: (0, 3, 0))),
        (name: "ball", type: "sphere", material: "red",
         params: (center: (0.3, 0.4, -0.5), radius: 0.4)),
    ],
    lights: [
        (name: "sun", type: "directional",
         params: (direction: (-0.3, -1, -0.5), irradiance: 5, spd: "d65")),
    ],
    cameras: [
        (name: "front", type: "thin_lens",
         params: (position: (0, 1.2, 4), look_at: (0, 0.6, 0), fov: 45, resolution: (48, 32),
                  lens_radius: 0.1, focus_distance: 3.0)),
    ],
)"#;
    let scene = scene_from(text, "resolution: (48, 32)", "resolution: (48, 32)");
    let all = vec![true; 48 * 32];
    let bdpt = render_seeds(&scene, IntegratorKind::Bdpt, 64, K);
    let pt = render_seeds(&scene, IntegratorKind::Pt, 128, K);
    let lt = render_seeds(&scene, IntegratorKind::Lt, 256, K);
    assert_agree("sun bdpt/pt", &bdpt, &pt, &all, Some(0.005), true);
    assert_agree("sun lt/pt", &lt, &pt, &all, Some(0.005), true);
}
