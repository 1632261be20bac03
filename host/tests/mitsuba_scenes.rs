//! A public Mitsuba 3 scene with an image texture and an environment map, imported and rendered
//! by spectrace, against Mitsuba 3's own render of the same files.
//!
//! Scene: `scenes/mitsuba/mitsuba-data/docs/scenes/bsdf_diffuse_textured-flatplane.xml`, Mitsuba
//! 3's material-preview object with the `wood.jpg` bitmap texture, lit only by the `museum.exr`
//! environment map (rotated by its `to_world`, `scale` 3), the plane's checkerboard replaced by
//! its mean 0.3 in the file (spectrace's importer makes a checkerboard its mean; the flat plane
//! keeps that approximation out of this check; sources and licence in `scenes/mitsuba/README.md`).
//!
//! Reference: `scenes/mitsuba/mitsuba-data/reference/textured_flatplane_80x60_mitsuba.exr`,
//! Mitsuba 3.9.1 `llvm_ad_spectral`, 4096 spp, 80 × 60, made with
//! `python scripts/mitsuba_import/compare.py render bsdf_diffuse_textured-flatplane.xml
//! OUT.exr --spp 4096 --seed 7 --size 80 60 --threads 2` in that folder.

mod common_render;
use spectrace::color::SRGB;
use spectrace::integrator::{render, PathTracer, RenderSettings, SampleBudget};
use spectrace::scene::{build_scene, BuiltinFactory};
use spectrace::texture::image_file::{decode, LoadedImage};
use std::path::Path;

fn scene_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/mitsuba/mitsuba-data/docs/scenes")
}

/// The linear sRGB pixels of an EXR, row by row from the top.
fn exr_pixels(path: &Path) -> Vec<[f64; 3]> {
    let bytes = std::fs::read(path).unwrap();
    let (img, _) = decode(&bytes, None, 1 << 28).unwrap();
    let LoadedImage::Rgb(img) = img else {
        panic!("{}: not an RGB image", path.display())
    };
    img.pixels
        .iter()
        .map(|p| [p[0] as f64, p[1] as f64, p[2] as f64])
        .collect()
}

/// Per-channel mean of `pixels` where `keep` holds.
fn mean_where(pixels: &[[f64; 3]], keep: impl Fn(usize) -> bool) -> [f64; 3] {
    let mut m = [0.0f64; 3];
    let mut n = 0usize;
    for (i, p) in pixels.iter().enumerate().filter(|(i, _)| keep(*i)) {
        let _ = i;
        for c in 0..3 {
            m[c] += p[c];
        }
        n += 1;
    }
    m.map(|v| v / n.max(1) as f64)
}

/// Per-channel mean linear sRGB of an EXR.
fn exr_mean(path: &Path) -> [f64; 3] {
    mean_where(&exr_pixels(path), |_| true)
}

/// Quantity: the image's per-channel mean linear sRGB (80 × 60, path tracer, 256 spp, seed 1)
/// against Mitsuba 3's 4096-spp render of the same file. Tolerance: 1.5% per channel. Why: the
/// known difference is the environment light's colour, R −0.9%, G 0.0%, B +0.9% on long
/// renders of this scene at 160 × 120 (the two renderers' RGB → spectrum uplifts of the map's
/// saturated texels; docs/mitsuba-import.md, "Compared against Mitsuba 3"); noise adds little:
/// Mitsuba's own 256-spp means at this size (seeds 1 and 2) lie within 0.13% of its 4096-spp
/// mean, and ours, with as many samples, scatter alike, so 0.5% on top of the 1% is over 3σ
/// of both. What it catches: an sRGB texture read as linear (mid-tone texels twice too
/// bright), a missing `scale` (÷3), a lost texture (a constant 0.5 in place of the darker
/// wood); a mirrored or unrotated map changes which windows light the scene (its effect on the
/// mean is not measured here).
/// A texture upside down on this object hardly moves the mean: that is checked per pixel by
/// `mesh_uvs_follow_mitsubas_image_orientation` and in the docs' region RMSE.
/// spectrace's render of the Mitsuba file `name` (in [`scene_dir`]) at 80 × 60, path tracer,
/// `spp` samples, seed 1, 2 threads: the image's mean linear sRGB.
fn render_mean(name: &str, spp: u32) -> [f64; 3] {
    SRGB.xyz_to_rgb(render_image(name, spp).mean_xyz())
}

/// [`render_mean`]'s image.
fn render_image(name: &str, spp: u32) -> spectrace::film::XyzImage {
    render_image_with(name, spp, spectrace::integrator::select::IntegratorKind::Pt)
}

/// [`render_image`] with the integrator `kind`.
fn render_image_with(
    name: &str,
    spp: u32,
    kind: spectrace::integrator::select::IntegratorKind,
) -> spectrace::film::XyzImage {
    let file = scene_dir().join(name);
    let conv = spectrace::scene::mitsuba::convert_file(&file, &[]).unwrap();
    let mut desc = conv.desc;
    if let ron::Value::Map(m) = &mut desc.cameras[0].params {
        m.insert(
            ron::Value::String("resolution".into()),
            ron::Value::Seq(vec![
                ron::Value::Number(ron::Number::from(80i64)),
                ron::Value::Number(ron::Number::from(60i64)),
            ]),
        );
    }
    let scene = build_scene(&desc, &scene_dir(), Path::new(name), &[&BuiltinFactory]).unwrap();
    let settings = RenderSettings {
        budget: SampleBudget::Spp(spp),
        seed: 1,
        threads: Some(2),
        tracer: PathTracer {
            max_depth: scene.options.max_depth,
            ..PathTracer::default()
        },
        ..RenderSettings::default()
    };
    let plan = spectrace::integrator::RenderPlan::new(
        &scene,
        &spectrace::integrator::EffectsRequest {
            mode: spectrace::integrator::EffectsMode::Auto,
            forced: vec![],
            ..common_render::every_light_subpath()
        },
    );
    let image = if kind == spectrace::integrator::select::IntegratorKind::Pt {
        render(&scene, &settings, &|_, _| {}, None).unwrap().image
    } else {
        spectrace::integrator::select::render_planned(
            &scene,
            &plan,
            &settings,
            kind,
            false,
            &|_, _| {},
            None,
        )
        .unwrap()
        .result
        .image
    };
    assert_eq!(image.non_finite_count(), 0);
    image
}

#[test]
fn textured_env_lit_scene_matches_mitsuba_3() {
    let ours = render_mean("bsdf_diffuse_textured-flatplane.xml", 256);
    let want = exr_mean(&scene_dir().join("../../reference/textured_flatplane_80x60_mitsuba.exr"));
    for c in 0..3 {
        let ratio = ours[c] / want[c];
        assert!(
            (ratio - 1.0).abs() < 0.015,
            "channel {c}: spectrace {:?} vs Mitsuba {:?} (ratio {ratio:.4})",
            ours,
            want
        );
    }
}

/// Quantity: per-channel mean linear sRGB of `bsdf_plastic-flatplane.xml` (derived here: the
/// material-preview object in Mitsuba's `roughplastic`, GGX α 0.2, η 1.5, the wood bitmap as its
/// base; its interior in a smooth yellow `plastic`, η 1.9; flat 0.3 plane; the museum map)
/// rendered by spectrace (80 × 60, path tracer, 256 spp, seed 1) against Mitsuba 3.9.1's
/// 4096-spp render (`reference/plastic_flatplane_80x60_mitsuba.exr`, made with
/// `compare.py render bsdf_plastic-flatplane.xml OUT.exr --spp 4096 --seed 7 --size 80 60
/// --threads 2`), over the whole image and over each plastic (regions from Mitsuba's
/// `shape_index` AOV, `reference/plastic_flatplane_80x60_mask.exr` from `compare.py mask`,
/// edge pixels left out: 433 interior pixels, 1092 object pixels).
/// Tolerances and why (docs/mitsuba-import.md, "plastic"): the environment light's colour
/// differs by R −1%, B +1% everywhere (the two RGB → spectrum uplifts of the map); the rough
/// plastic is +1.7% brighter in spectrace in its diffuse part (Mitsuba's internal reflectance
/// quadrature, 63/64 of the integral, see tests/material_plastic.rs); noise of a region's mean
/// at 256 spp: ≤ 0.5% (object), ≤ 1% (interior, 433 pixels of a sharp reflection). So: whole
/// image within 2%; the smooth interior within 2.5%; the rough object between −0.5% and +4%.
/// Measured: whole 0.997, 1.005, 1.013; interior 0.997, 1.005, 1.019; object 1.014, 1.019, 1.026.
/// What it catches: the plastic imported as a lambertian, as before spectrace had plastic
/// (measured with the two materials made lambertians of their `diffuse_reflectance`: whole
/// 1.022, 1.019, 1.013; interior 0.947, 0.961, 0.708; object 1.144, 1.113, 1.106: all three
/// fail), a wrong index, a lost texture.
#[test]
fn plastic_scene_matches_mitsuba_3() {
    let image = render_image("bsdf_plastic-flatplane.xml", 256);
    let ours = image.to_rgb(&SRGB);
    let reference = scene_dir().join("../../reference");
    let want = exr_pixels(&reference.join("plastic_flatplane_80x60_mitsuba.exr"));
    let mask = exr_pixels(&reference.join("plastic_flatplane_80x60_mask.exr"));
    assert_eq!((ours.len(), want.len(), mask.len()), (4800, 4800, 4800));
    let mask = &mask;
    let region = |k: f64| move |i: usize| mask[i][0] == k;
    type Region<'a> = Box<dyn Fn(usize) -> bool + 'a>;
    let checks: [(&str, Region, f64, f64); 3] = [
        ("whole image", Box::new(|_| true), -0.02, 0.02),
        (
            "smooth plastic interior",
            Box::new(region(2.0)),
            -0.025,
            0.025,
        ),
        ("rough plastic object", Box::new(region(3.0)), -0.005, 0.04),
    ];
    let mut bad = Vec::new();
    for (name, keep, lo, hi) in &checks {
        let a = mean_where(&ours, keep);
        let b = mean_where(&want, keep);
        let r: Vec<f64> = (0..3).map(|c| a[c] / b[c]).collect();
        println!("{name}: spectrace {a:?}, Mitsuba {b:?}, ratio {r:.4?}");
        if r.iter().any(|x| !(x - 1.0 >= *lo && x - 1.0 <= *hi)) {
            bad.push(format!("{name}: ratio {r:.4?}"));
        }
    }
    assert!(bad.is_empty(), "{bad:?}");
}

/// BDPT on the smooth plastic: light subpaths that reach the plastic and continue by its
/// specular coating must still be joined to the camera (and to camera prefixes) through its
/// diffuse base, as the other strategies' MIS weights assume. Quantity: BDPT's mean linear sRGB
/// over the smooth plastic's interior (the mask of `plastic_scene_matches_mitsuba_3`) against
/// the path tracer's, both 256 spp, seed 1, 80 × 60. Tolerance 1.5% per channel: measured
/// 0.999, 1.004, 1.010 at seed 1 and within 0.998–1.002 at seeds 5 and 6 (the environment's
/// sun makes the blue channel the noisiest); when such vertices refused every connection
/// BDPT was 0.894, 0.867, 0.896 here (seed 1), 3.7–4.9% dark at seeds 5 and 6.
#[test]
fn bdpt_joins_through_the_diffuse_base_of_a_smooth_plastic() {
    use spectrace::integrator::select::IntegratorKind;
    let name = "bsdf_plastic-flatplane.xml";
    let bdpt = render_image_with(name, 256, IntegratorKind::Bdpt).to_rgb(&SRGB);
    let pt = render_image_with(name, 256, IntegratorKind::Pt).to_rgb(&SRGB);
    let mask = exr_pixels(&scene_dir().join("../../reference/plastic_flatplane_80x60_mask.exr"));
    let keep = |i: usize| mask[i][0] == 2.0;
    let (a, b) = (mean_where(&bdpt, keep), mean_where(&pt, keep));
    let r: Vec<f64> = (0..3).map(|c| a[c] / b[c]).collect();
    println!("smooth plastic interior: BDPT / PT {r:.4?}");
    assert!(
        r.iter().all(|x| (x - 1.0).abs() < 0.015),
        "BDPT / PT {r:.4?}"
    );
}
