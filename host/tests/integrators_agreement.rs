//! Independent estimators agree: BDPT, path tracing (PT) and light tracing (LT) converge to the
//! same image on the diffuse Cornell box, a glass-sphere caustic and a spot light reflected by a
//! mirror. Run in release: `cargo test --release -p spectrace --test integrators_agreement`.
//!
//! The test, for each pair of estimators A, B on a scene (pixels each can render: see below):
//! * every estimator renders K images with independent seeds;
//! * per channel, the image means (over the K renders) agree within 0.5%, and the standard
//!   error of that difference (from the seed-to-seed spread) is below 0.5%/2, so the 0.5%
//!   check is at least a 2σ statement and cannot pass by noise alone (test-suite budgets use
//!   "within 4 standard errors" where 0.5% would need minutes; the `--ignored` runs use 0.5%);
//! * per 8×8 tile and per channel, `z = (Ā − B̄)/√(s²_A/K + s²_B/K)` with the sample variances
//!   `s²` of the K seed means; at most 2% of tiles (at least 2 tiles on small images) may have
//!   |z| > 4. With K = 8 the statistic is
//!   close to Student-t with ≥ 7 degrees of freedom, for which P(|t| > 4) ≈ 0.5%: a correct
//!   pair passes, a bias of a few standard errors spread over many tiles fails. Not applied to
//!   path tracing on the caustic: its estimator there is heavy-tailed (rare BSDF-sampled paths
//!   through the glass onto the small lamp), so 8-seed variances understate its spread and the
//!   z-statistic is not Student-t; its image mean is still compared (within 4 standard errors).
//!
//! Which pixels: light tracing cannot render what the camera sees through a delta BSDF (a
//! mirror or smooth glass seen directly: the t = 1 connection needs a BSDF that can be
//! evaluated), and path tracing cannot render paths from a point light via a mirror (neither
//! next-event estimation nor BSDF sampling can find them). Such pixels are masked out of the
//! comparisons that involve that estimator, and the test asserts PT's deficit where it exists.

use spectrace::film::XyzImage;
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::material::MaterialFlags;
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
            let out = render_with(scene, &settings, kind, false, &|_, _| {}, None).unwrap();
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
    let cam = scene.cameras.get(None).unwrap();
    let (w, h) = cam.camera.resolution();
    let mut mask = vec![true; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            'grid: for j in 0..3 {
                for i in 0..3 {
                    let p = glam::Vec2::new(x as f32 - 0.5 + i as f32, y as f32 - 0.5 + j as f32);
                    let s = spectrace::camera::CameraSample {
                        p_film: p,
                        p_lens: glam::Vec2::splat(0.5),
                    };
                    let Some(r) = cam.camera.generate_ray(&s) else {
                        continue;
                    };
                    if let Some(hit) = scene.geometry.intersect(&r.ray, f32::INFINITY) {
                        if scene.objects.material(hit.object).flags().is_specular()
                            || scene
                                .objects
                                .material(hit.object)
                                .flags()
                                .contains(MaterialFlags::SPECULAR)
                        {
                            mask[(y * w + x) as usize] = false;
                            break 'grid;
                        }
                    }
                }
            }
        }
    }
    mask
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
                if se >= tol / 2.0 {
                    failures.push(format!("channel {c}: too noisy to test (se {se:.4})"));
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
                tiles += 1;
                worst = worst.max(z.abs());
                if z.abs() > 4.0 {
                    outliers += 1;
                }
            }
        }
    }
    eprintln!("{name}: {outliers} of {tiles} tile-channels with |z| > 4 (max |z| {worst:.2})");
    assert!(failures.is_empty(), "{name}: {}", failures.join("; "));
    if !tile_test {
        return;
    }
    assert!(tiles > 0);
    assert!(
        outliers as f64 <= (0.02 * tiles as f64).max(2.0),
        "{name}: {outliers} of {tiles} tile-channels differ by more than 4σ"
    );
}

const K: u64 = 8;

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

/// Glass-sphere caustic under a small area light, on the pixels that do not look at the glass
/// (see below). `spp_scale` multiplies the sample counts.
fn caustic(spp_scale: u32, mean_tol: Option<f64>) {
    let scene = small(include_str!("../../scenes/caustic.ron"));
    let mask = non_specular_mask(&scene);
    assert!(
        mask.iter().filter(|&&m| !m).count() > 20,
        "the glass is visible"
    );
    let bdpt = render_seeds(&scene, IntegratorKind::Bdpt, 32 * spp_scale, K);
    // PT gets 8× the samples: it is the noisy one here (and it is the fastest per sample).
    let pt = render_seeds(&scene, IntegratorKind::Pt, 512 * spp_scale, K);
    let lt = render_seeds(&scene, IntegratorKind::Lt, 64 * spp_scale, K);
    assert_agree("caustic bdpt/lt", &bdpt, &lt, &mask, mean_tol, true);
    assert_agree("caustic pt/lt", &pt, &lt, &mask, None, false);
    // Off the glass too: pixels that see the floor through the sphere carry specular–diffuse–
    // specular paths (a caustic seen through glass) that no connection can sample; PT and BDPT
    // both find them only by camera paths hitting the 5 cm lamp, a heavy-tailed estimate whose
    // typical sample mean lies below its expectation by an amount that depends on the sample
    // count, so the two are not comparable there at test budgets.
    assert_agree("caustic bdpt/pt", &bdpt, &pt, &mask, None, false);
}

/// Caustic, test-suite budget: means within 4 standard errors, tile z-test.
#[test]
fn caustic_bdpt_pt_lt_agree() {
    caustic(1, None);
}

/// Caustic, long run (minutes): BDPT and LT means within 0.5%. PT stays at "within 4 standard
/// errors": its caustic estimate through the 5 cm lamp has a seed-to-seed spread of ~3.5% at
/// 512 spp × 8 seeds, so a 0.5% check would need hours.
#[test]
#[ignore = "long: run with --ignored in release"]
fn caustic_means_within_half_percent() {
    caustic(10, Some(0.005));
}

/// Spot light reflected by a mirror onto the back wall: BDPT and LT agree (LT off the mirror);
/// PT misses the mirrored spot entirely, so its image is darker by the reflected part.
fn spot_mirror(spp_scale: u32, mean_tol: Option<f64>) {
    let scene = small(include_str!("../../scenes/spot_mirror.ron"));
    let mask = non_specular_mask(&scene);
    let bdpt = render_seeds(&scene, IntegratorKind::Bdpt, 32 * spp_scale, K);
    let lt = render_seeds(&scene, IntegratorKind::Lt, 64 * spp_scale, K);
    assert_agree("spot_mirror bdpt/lt", &bdpt, &lt, &mask, mean_tol, true);
    // PT: the point light seen via the mirror is a zero-density path for it. Its image lacks
    // that light; the deficit (tens of %) is far beyond the seed spread printed above (< 1%).
    let pt = render_seeds(&scene, IntegratorKind::Pt, 32, 2);
    let m_pt = seed_means(&pt, &mask)[0][1];
    let m_bdpt = seed_means(&bdpt, &mask)[0][1];
    eprintln!("spot_mirror Y: pt {m_pt:.6}, bdpt {m_bdpt:.6}");
    assert!(m_pt < 0.8 * m_bdpt, "PT should miss the mirrored spot");
}

/// Spot/mirror, test-suite budget: means within 4 standard errors, tile z-test.
#[test]
fn spot_mirror_bdpt_lt_agree_and_pt_misses_the_reflection() {
    spot_mirror(1, None);
}

/// Spot/mirror, long run: means within 0.5%.
#[test]
#[ignore = "long: run with --ignored in release"]
fn spot_mirror_means_within_half_percent() {
    spot_mirror(8, Some(0.005));
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
    let lt = render_seeds(&scene, IntegratorKind::Lt, 128, K);
    assert_agree("sun bdpt/pt", &bdpt, &pt, &all, Some(0.005), true);
    assert_agree("sun lt/pt", &lt, &pt, &all, Some(0.005), true);
}
