//! The API-only plugin (`plugins/api-only`): the built-in rough conductor and spot light written
//! again against `spectrace-plugin-api` alone, loaded from its library file like any third-party
//! plugin. It must not link the host crate, its objects must answer what the built-ins answer
//! (to f32 rounding), and scenes with its types must render within noise of the built-ins.

mod support;

use glam::{Vec2, Vec3A};
use spectrace::geometry::{Aabb, Ray};
use spectrace::integrator::IntegratorKind;
use spectrace::light::LightSampleContext;
use spectrace::material::{ShadingContext, TransportMode};
use spectrace::plugin::adapter::PluginFaults;
use spectrace::plugin::factory::RegistryFactory;
use spectrace::plugin::Registry;
use spectrace::scene::{FactoryContext, ObjectFactory};
use spectrace::spectrum::SampledWavelengths;
use spectrace_tests::{plugin_library, render_auto_xyz};
use std::collections::{BTreeMap, BTreeSet};
use std::sync::Arc;
use support::{mean_and_se, repo};

/// The built-ins and the API-only library's types (none of which shadows a built-in).
fn registry() -> Registry {
    let mut r = spectrace::plugin::builtin_registry();
    r.load_plugin(&plugin_library("spectrace-api-only"))
        .unwrap_or_else(|e| panic!("{e}"));
    r
}

fn factory(r: Registry) -> RegistryFactory {
    RegistryFactory::new(Arc::new(r), PluginFaults::new())
}

fn ctx(f: &RegistryFactory) -> FactoryContext {
    f.context(std::path::Path::new("."), "test".into())
}

/// Quantity: the packages `spectrace-api-only` depends on, from its `Cargo.toml` and,
/// transitively, from the workspace's `Cargo.lock` (what `cargo tree -p spectrace-api-only`
/// prints). Tolerance: none: the host crate `spectrace` (and `spectrace-standard`, which links
/// it) must be nowhere in the tree, and `spectrace-plugin-api` must be in it.
#[test]
fn depends_on_the_plugin_api_alone() {
    let manifest = std::fs::read_to_string(repo().join("plugins/api-only/Cargo.toml")).unwrap();
    let deps: Vec<&str> = manifest
        .split("[dependencies]")
        .nth(1)
        .expect("a [dependencies] table")
        .lines()
        .take_while(|l| !l.trim_start().starts_with('['))
        .filter_map(|l| l.split('=').next())
        .map(str::trim)
        .filter(|k| !k.is_empty() && !k.starts_with('#'))
        .collect();
    assert_eq!(deps, ["spectrace-plugin-api.workspace", "serde.workspace"]);
    // The lock file: package name -> the names it depends on.
    let lock = std::fs::read_to_string(repo().join("Cargo.lock")).unwrap();
    let mut graph: BTreeMap<String, Vec<String>> = BTreeMap::new();
    for block in lock.split("[[package]]").skip(1) {
        let name = block
            .lines()
            .find_map(|l| l.strip_prefix("name = "))
            .map(|s| s.trim_matches('"').to_string())
            .unwrap();
        let deps: Vec<String> = block
            .split("dependencies = [")
            .nth(1)
            .map(|d| {
                d.split(']')
                    .next()
                    .unwrap_or_default()
                    .lines()
                    .filter_map(|l| {
                        let l = l.trim().trim_end_matches(',').trim_matches('"');
                        l.split_whitespace().next().map(str::to_string)
                    })
                    .filter(|s| !s.is_empty())
                    .collect()
            })
            .unwrap_or_default();
        graph.entry(name).or_default().extend(deps);
    }
    let mut seen = BTreeSet::new();
    let mut todo = vec!["spectrace-api-only".to_string()];
    while let Some(p) = todo.pop() {
        if seen.insert(p.clone()) {
            todo.extend(graph.get(&p).cloned().unwrap_or_default());
        }
    }
    assert!(seen.contains("spectrace-plugin-api"), "{seen:?}");
    assert!(seen.contains("abi_stable"), "{seen:?}");
    for host in ["spectrace", "spectrace-standard", "glam", "rayon"] {
        assert!(!seen.contains(host), "the plugin's tree contains `{host}`");
    }
}

/// A small LCG: deterministic inputs in [0, 1).
fn rng(seed: u64) -> impl FnMut() -> f32 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// `|a − b|` relative to `scale` (the larger magnitude of the quantity at hand, so values far
/// below it are compared absolutely at that scale).
fn rel(a: f32, b: f32, scale: f32) -> f64 {
    ((a - b).abs() / scale.max(f32::MIN_POSITIVE)) as f64
}

/// The largest difference of two samples: direction (absolute), density and value per lane
/// (relative to the larger, the value to the larger lane).
fn sample_diff(x: &spectrace::material::BsdfSample, y: &spectrace::material::BsdfSample) -> f64 {
    let scale = x.f.max_value().max(y.f.max_value());
    let mut d = ((x.wi - y.wi).abs().max_element() as f64).max(rel(x.pdf, y.pdf, x.pdf.max(y.pdf)));
    for k in 0..4 {
        d = d.max(rel(x.f.0[k], y.f.0[k], scale));
    }
    d
}

/// The 99th percentile and the largest of `d`.
fn spread(d: &mut [f64]) -> (f64, f64) {
    d.sort_by(f64::total_cmp);
    (d[d.len() * 99 / 100], d[d.len() - 1])
}

/// Quantity: `sample` (direction, value per lane, density, event bits), `eval` and `pdf` of the
/// plugin's `api_conductor` against the built-in `conductor` with the same parameters (four
/// metals and explicit n, k tables; α from 0.01 to 0.8 through `alpha` and `roughness`; a
/// smooth one), over 2,000 random `wo`, `wi`, wavelengths and random numbers each, both
/// through the host's `Material` trait (the plugin through the adapter and the ABI).
///
/// Tolerance: relative to the larger of the two values (values far below it compared at that
/// scale): `eval` and `pdf` 1e-5 for 99% of the values; a sample's direction, value and density
/// 1e-5 for the median and 1e-4 for 99% (α ≥ 0.05 and smooth); every value 5e-3 (α = 0.01
/// included). Both
/// compute in f32 with the same
/// formulas, but not bit for bit in the same order (glam's SIMD vectors against scalar code), so
/// a sampled normal or a half vector can differ by an ulp or two, and GGX magnifies that: ln D
/// changes by up to about 2/α per radian, so at α = 0.01 an ulp of direction (6e-8 rad) is
/// ~1e-5 of the value. A sample goes through more roundings (the visible-normal warp, the
/// unstretch, two normalisations), and at small α its normal lies near the macro normal, where
/// D's tan²θ = (1 − cos²θ)/cos²θ loses digits: one ulp of cos θm (6e-8) is 6e-8/(1 − cos²θm) of
/// tan²θm, ~1e-3 of D at α = 0.01. The built-in has the same conditioning; the two agree as
/// well as single precision lets them (measured, printed: median, 99th percentile, largest),
/// far below Monte Carlo noise, and the renders agree (below and `docs/plugins.md`). Whether a sample exists must agree except where the test's own rounding decides it
/// (wi within 1e-6 of the horizon): at most 0.1% of draws.
#[test]
fn the_conductor_answers_as_the_builtin() {
    let builtin = factory(spectrace::plugin::builtin_registry());
    let lib = factory(registry());
    let mut rnd = rng(0x9e37_79b9_7f4a_7c15);
    let cases = [
        "(metal: \"gold\", roughness: 0.3)",
        "(metal: \"silver\", alpha: 0.05)",
        "(metal: \"cu\", roughness: 0.9)",
        "()",
        "(metal: \"aluminium\", alpha: 0.01)",
        "(n: [(400, 0.2), (550, 0.4), (700, 0.15)], k: [(400, 2.5), (550, 3.0), (700, 4.0)], \
         alpha: 0.2)",
        "(metal: \"gold\", alpha: 0.0)",
    ];
    let (mut diffs, mut mismatched, mut draws, mut scattered) = (Vec::new(), 0, 0, 0);
    let mut sample_diffs = Vec::new();
    for text in cases {
        // α = 0.01: near the macro normal D is ill-conditioned in f32 (see above).
        let narrow = text.contains("alpha: 0.01");
        let params: ron::Value = ron::from_str(text).unwrap();
        let a = builtin
            .material("conductor", &params, &ctx(&builtin))
            .unwrap();
        let b = lib.material("api_conductor", &params, &ctx(&lib)).unwrap();
        assert_eq!(a.flags(), b.flags(), "{params:?} flags");
        for _ in 0..2000 {
            let sc = ShadingContext::default();
            let wo = Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.1).normalize();
            let wi = Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.1).normalize();
            let lambda = SampledWavelengths::sample_uniform(rnd(), 360.0, 830.0);
            let (ul, u) = (rnd(), Vec2::new(rnd(), rnd()));
            let mode = TransportMode::Radiance;
            draws += 1;
            match (
                a.sample(wo, &sc, &lambda, ul, u, mode),
                b.sample(wo, &sc, &lambda, ul, u, mode),
            ) {
                (Some(x), Some(y)) => {
                    scattered += 1;
                    assert_eq!(x.flags, y.flags, "{params:?}");
                    assert_eq!(x.eta, y.eta);
                    let d = sample_diff(&x, &y);
                    assert!(
                        d < 5e-3,
                        "{params:?} sample {wo} {u}: {x:?} vs {y:?}: {d:.2e}"
                    );
                    if !narrow {
                        sample_diffs.push(d);
                    }
                }
                (None, None) => {}
                (x, y) => {
                    let w = x.or(y).unwrap().wi;
                    assert!(
                        w.z.abs() < 1e-6,
                        "{params:?} sample {wo} {u}: {x:?} vs {y:?}"
                    );
                    mismatched += 1;
                }
            }
            let (fa, fb) = (
                a.eval(wo, wi, &sc, &lambda, mode),
                b.eval(wo, wi, &sc, &lambda, mode),
            );
            let scale = fa.max_value().max(fb.max_value());
            for k in 0..4 {
                let d = rel(fa.0[k], fb.0[k], scale);
                assert!(d < 5e-3, "{params:?} eval {wo} {wi}: {fa:?} vs {fb:?}");
                diffs.push(d);
            }
            let (pa, pb) = (
                a.pdf(wo, wi, &sc, &lambda, mode),
                b.pdf(wo, wi, &sc, &lambda, mode),
            );
            let d = rel(pa, pb, pa.max(pb));
            assert!(d < 5e-3, "{params:?} pdf {wo} {wi}: {pa} vs {pb}");
            diffs.push(d);
        }
    }
    let (p99, worst) = spread(&mut diffs);
    let (s99, s_worst) = spread(&mut sample_diffs);
    let s50 = sample_diffs[sample_diffs.len() / 2];
    eprintln!(
        "conductor: {draws} draws, {scattered} scattered by both, {mismatched} decided by \
         rounding; eval and pdf: 99th percentile {p99:.2e}, largest {worst:.2e}; sample (α ≥ \
         0.05 and smooth): median {s50:.2e}, 99th percentile {s99:.2e}, largest {s_worst:.2e}"
    );
    assert!(p99 < 1e-5, "eval/pdf 99th percentile {p99:.2e}");
    assert!(s50 < 1e-5, "sample median {s50:.2e}");
    assert!(s99 < 1e-4, "sample 99th percentile {s99:.2e}");
    assert!(scattered > draws / 3, "{scattered} of {draws}");
    assert!(mismatched * 1000 <= draws, "{mismatched} of {draws}");
}

/// Quantity: the plugin's `api_spot` against the built-in `spot` with the same parameters (power
/// in W, lm and cd; spectra tabulated by the plugin (blackbody, D65) and one with a spectral line
/// read from the host per value): flags, power, spectrum, and over 2,000 random receivers,
/// wavelengths and random numbers each `sample_li` (radiance per lane, direction, density,
/// point), `sample_le` (origin, direction, intensity per lane, densities) and the direction
/// density of `pdf_le`.
///
/// Tolerance: power 1e-6 relative (the luminous efficacy is summed in the same order from the
/// same V(λ) and the same SPD values; an f32 in the end); every other value as for the conductor,
/// relative to the light's peak (its intensity along the axis, I₀·S(λ), over d² for `sample_li`),
/// 1e-5 for 99% and 1e-4 for all: f32 arithmetic in another order moves a direction by an ulp,
/// and the smoothstep's slope near the outer cone, 6x(1−x)/(cos θi − cos θo), turns that into
/// up to a few 1e-5 of the peak near the edge (and far more of the value itself, which tends to
/// 0 there: hence the peak as the scale); the plugin's 0.25 nm table of the SPD is
/// checked against the host's SPD to 1e-6 of its peak when built.
#[test]
fn the_spot_answers_as_the_builtin() {
    let builtin = factory(spectrace::plugin::builtin_registry());
    let lib = factory(registry());
    let mut rnd = rng(0x2545_f491_4f6c_dd1d);
    let bounds = Aabb {
        min: Vec3A::splat(-3.0),
        max: Vec3A::splat(3.0),
    };
    let cases = [
        "(position: (2, 3, 2), target: (0, 0, 0), inner_angle: 15, outer_angle: 25, \
         power: 1500, spd: \"blackbody:2856\")",
        "(position: (-1, 2, 0.5), target: (0.3, -1, 0), flux_lm: 800, spd: \"d65\")",
        "(position: (0, 0, 0), target: (0, 0, -1), inner_angle: 0, outer_angle: 120, \
         intensity_cd: 300, spd: \"0.8*blackbody:3000 + 0.2*line:589\")",
        "(position: (0.5, 0.5, 0.5), target: (0.5, 2, 0.5), inner_angle: 30, outer_angle: 30, \
         power: 10)",
    ];
    let mut diffs = Vec::new();
    let mut lit = 0;
    for params in cases {
        let params: ron::Value = ron::from_str(params).unwrap();
        let a = builtin.light("spot", &params, &ctx(&builtin)).unwrap();
        let b = lib.light("api_spot", &params, &ctx(&lib)).unwrap();
        for l in [&a, &b] {
            l.preprocess(&bounds);
            l.preprocess_view(&bounds);
        }
        assert_eq!(a.flags(), b.flags(), "{params:?} flags");
        assert!(
            (a.power() / b.power() - 1.0).abs() < 1e-6,
            "{params:?} power {} vs {}",
            a.power(),
            b.power()
        );
        let (sa, sb) = (a.spd(), b.spd());
        assert_eq!(sa.range(), sb.range());
        assert_eq!(sa.delta_lines(), sb.delta_lines());
        // The built-in's intensity along its axis (falloff 1), I₀·S(λ) per lane at its largest.
        let peak = |lambda: &SampledWavelengths, u1: Vec2| -> f32 {
            a.sample_le(u1, Vec2::new(0.0, 0.5), lambda)
                .map_or(0.0, |s| s.radiance.max_value())
        };
        for _ in 0..2000 {
            let lambda = SampledWavelengths::sample_uniform(rnd(), 360.0, 830.0);
            let lc = LightSampleContext {
                p: Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 5.0,
                p_error: Vec3A::ZERO,
                n: Vec3A::ZERO,
            };
            let (u1, u2) = (Vec2::new(rnd(), rnd()), Vec2::new(rnd(), rnd()));
            match (a.sample_li(&lc, u1, &lambda), b.sample_li(&lc, u1, &lambda)) {
                (Some(x), Some(y)) => {
                    lit += 1;
                    // Relative to the light's peak intensity there (I₀·S(λ)/d², falloff 1).
                    let d2 = (x.p_light - lc.p).length_squared();
                    let scale = peak(&lambda, u1) / d2;
                    let mut d = (x.wi - y.wi).abs().max_element() as f64;
                    for k in 0..4 {
                        d = d.max(rel(x.radiance.0[k], y.radiance.0[k], scale));
                    }
                    assert!(d < 1e-4, "{params:?} sample_li: {x:?} vs {y:?}");
                    assert_eq!((x.pdf, x.p_light, x.n_light), (y.pdf, y.p_light, y.n_light));
                    diffs.push(d);
                }
                (None, None) => {}
                (x, y) => panic!("{params:?} sample_li at {}: {x:?} vs {y:?}", lc.p),
            }
            let (x, y) = (
                a.sample_le(u1, u2, &lambda).unwrap(),
                b.sample_le(u1, u2, &lambda).unwrap(),
            );
            let scale = peak(&lambda, u1);
            let mut d = (x.ray.dir - y.ray.dir).abs().max_element() as f64;
            for k in 0..4 {
                d = d.max(rel(x.radiance.0[k], y.radiance.0[k], scale));
            }
            d = d.max(rel(x.pdf_dir, y.pdf_dir, x.pdf_dir));
            assert!(d < 1e-4, "{params:?} sample_le: {x:?} vs {y:?}");
            assert_eq!((x.ray.origin, x.pdf_pos), (y.ray.origin, y.pdf_pos));
            diffs.push(d);
            // A direction anywhere: inside or outside the cone.
            let dir = Vec3A::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5);
            let ray = Ray::new(x.ray.origin, dir);
            assert_eq!(
                a.pdf_le(&ray, Vec3A::ZERO).1,
                b.pdf_le(&ray, Vec3A::ZERO).1,
                "{params:?} pdf_le {dir}"
            );
        }
    }
    let (p99, worst) = spread(&mut diffs);
    eprintln!(
        "spot: {lit} lit receivers; relative differences: 99th percentile {p99:.2e}, largest \
         {worst:.2e}"
    );
    assert!(p99 < 1e-5, "99th percentile {p99:.2e}");
    assert!(lit > 1000, "{lit}");
}

/// The mean Y of each block of a `w`×`h` image cut into `bx`×`by` blocks, and of the whole.
fn block_means(xyz: &[[f64; 3]], w: usize, h: usize, bx: usize, by: usize) -> Vec<f64> {
    let mut out = vec![xyz.iter().map(|p| p[1]).sum::<f64>() / xyz.len() as f64];
    for j in 0..by {
        for i in 0..bx {
            let (x0, x1, y0, y1) = (i * w / bx, (i + 1) * w / bx, j * h / by, (j + 1) * h / by);
            let mut s = 0.0;
            for y in y0..y1 {
                for x in x0..x1 {
                    s += xyz[y * w + x][1];
                }
            }
            out.push(s / ((x1 - x0) * (y1 - y0)) as f64);
        }
    }
    out
}

/// `text` as a scene with the first camera at `w`×`h`.
fn scene(text: &str, name: &str, w: u32, h: u32) -> spectrace::scene::SceneDescription {
    let mut desc = spectrace::scene::parse_scene_str(text, std::path::Path::new(name)).unwrap();
    if let ron::Value::Map(m) = &mut desc.cameras[0].params {
        m.insert(
            ron::Value::String("resolution".into()),
            ron::from_str(&format!("({w}, {h})")).unwrap(),
        );
    }
    desc
}

/// Render `desc` (XYZ per pixel) with the built-ins and the API-only library's types.
fn render(
    desc: &spectrace::scene::SceneDescription,
    kind: IntegratorKind,
    spp: u32,
    seed: u64,
) -> Vec<[f64; 3]> {
    let f = factory(registry());
    let factories: [&dyn ObjectFactory; 1] = [&f];
    let scene = spectrace::scene::build_scene(
        desc,
        std::path::Path::new("."),
        std::path::Path::new("scene"),
        &factories,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    render_auto_xyz(&scene, &f, kind, spp, seed)
}

/// Per block: the z statistic of the difference of the two sets' mean block values, over the
/// standard error of that difference from the renders' scatter.
fn z_scores(a: &[Vec<f64>], b: &[Vec<f64>]) -> Vec<(f64, f64, f64)> {
    (0..a[0].len())
        .map(|k| {
            let (ma, sa) = mean_and_se(&a.iter().map(|r| r[k]).collect::<Vec<_>>());
            let (mb, sb) = mean_and_se(&b.iter().map(|r| r[k]).collect::<Vec<_>>());
            ((ma - mb) / (sa * sa + sb * sb).sqrt(), ma, mb)
        })
        .collect()
}

/// Quantity: the mean Y of the whole image and of each of 4×4 blocks, over eight independent
/// renders with the built-ins (seeds 1–8) and eight with the API-only plugin's conductor and spot
/// light (seeds 101–108), BDPT, 16 spp: the Cornell box variant with a rough aluminium block and
/// a spot light (32×32) and `scenes/materials.ron` with its rough gold ball and spot light
/// (48×30); every other object is the same built-in in both.
///
/// Tolerance: |z| < 4.5 per block, z the difference of the two means over its standard error
/// (from the scatter between renders, seven degrees of freedom per side). 34 blocks are tested;
/// for unbiased estimators the chance that any exceeds 4.5σ is about 34 × 7e-6 (normal), more
/// with so few renders per side (Student's t with ~14 d.o.f. puts 4.5 near 5e-4 per block), so
/// 4.5 keeps a false failure rare while a 10% change of the spot's power in `materials.ron`
/// (eight more renders, seeds 201–208) must be caught, or the test could not fail. The same seed gives the same image to f32 rounding (not tested here:
/// that is the point-wise tests' job); the seeds differ so that the comparison is statistical.
#[test]
fn scenes_render_within_noise_of_the_builtins() {
    let cornell = include_str!("../../scenes/api_only/cornell_box.ron");
    let cornell_plugin = include_str!("../../scenes/api_only/cornell_box_plugin.ron");
    let materials = include_str!("../../scenes/materials.ron");
    let materials_plugin = include_str!("../../scenes/api_only/materials_plugin.ron");
    let brighter = materials_plugin.replace("power: 1500", "power: 1650");
    assert_ne!(brighter, materials_plugin);
    let cases = [
        ("cornell", cornell, cornell_plugin, "", 32, 32),
        (
            "materials",
            materials,
            materials_plugin,
            brighter.as_str(),
            48,
            30,
        ),
    ];
    for (name, a, b, control, w, h) in cases {
        let set = |text: &str, seeds: std::ops::Range<u64>| -> Vec<Vec<f64>> {
            let desc = scene(text, name, w, h);
            seeds
                .map(|s| {
                    let img = render(&desc, IntegratorKind::Bdpt, 16, s);
                    block_means(&img, w as usize, h as usize, 4, 4)
                })
                .collect()
        };
        let builtin = set(a, 1..9);
        let plugin = set(b, 101..109);
        let z = z_scores(&builtin, &plugin);
        let worst = z.iter().map(|t| t.0.abs()).fold(0.0, f64::max);
        eprintln!(
            "{name}: whole image built in {:.5} plugin {:.5} (z {:.2}); largest |z| over the \
             blocks {worst:.2}",
            z[0].1, z[0].2, z[0].0
        );
        for (k, &(zk, ma, mb)) in z.iter().enumerate() {
            assert!(
                zk.abs() < 4.5,
                "{name} block {k}: built in {ma}, plugin {mb}, z {zk:.2}"
            );
        }
        if !control.is_empty() {
            // The control: the spot 10% brighter must be seen.
            let brighter = set(control, 201..209);
            let zc = z_scores(&builtin, &brighter);
            let caught = zc.iter().map(|t| t.0.abs()).fold(0.0, f64::max);
            eprintln!("{name}: spot +10%: largest |z| {caught:.2}");
            assert!(
                caught > 4.5,
                "a 10% brighter spot was not told apart: {caught:.2}"
            );
        }
    }
}
