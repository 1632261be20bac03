//! Fluorescence rendered by pt, lt and bdpt: the three agree on a small fluorescent scene, a
//! flat patch under a uniform illuminant shows the colour `spectrace color FILE.BFC
//! --illuminant …` computes, a near-UV-lit fluorescent patch shows visible light its
//! non-fluorescent twin does not, and switching fluorescence off gives the reflectance-only
//! image.

use spectrace::cli::color::{compute_bfc, ColorArgs};
use spectrace::color::xyz::chromaticity;
use spectrace::color::CieObserverKind;
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, Scene};
use std::path::{Path, PathBuf};

fn scene(text: &str) -> Scene {
    let file = Path::new("fluorescence-test.ron");
    let desc = parse_scene_str(text, file).unwrap();
    build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
}

/// Render `scene` with `kind` (all threads; images do not depend on the thread count).
fn render(
    scene: &Scene,
    kind: IntegratorKind,
    spp: u32,
    seed: u64,
    max_depth: u32,
) -> spectrace::integrator::IntegratorOutput {
    let settings = RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(spp),
        seed,
        threads: None,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth,
            ..PathTracer::default()
        },
    };
    let out = render_with(scene, &settings, kind, false, &|_, _| {}, None).unwrap();
    assert_eq!(out.result.image.non_finite_count(), 0, "{kind}: non-finite");
    out
}

/// Mean and standard error over runs.
fn mean_se(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// A highlighter-yellow card (IXCRLALE) beside a wall of the parametric model (ρ = 0.4, half of
/// 350–480 nm absorbed and re-emitted around 600 nm with yield 0.9), lit by a D65 panel the
/// camera does not see (under D65 41% of the card's Y is fluoresced, see `color_fluorescence`). Light
/// reaches the camera after 1 or 2 bounces through the fluorescent card, so shifts happen at
/// directly and indirectly lit vertices, and bdpt joins unshifted paths through it too.
const AGREEMENT: &str = r#"(
    materials: [
        (name: "card", type: "fluorescent", params: (bfc: "IXCRLALE")),
        (name: "wall", type: "fluorescent",
         params: (reflectance: 0.4, absorption: [(340, 0), (350, 0.5), (480, 0.5), (490, 0)],
                  emission: "gaussian:600:40", quantum_yield: 0.9)),
        (name: "lamp", type: "emissive", params: (radiance: "d65", scale: 50)),
    ],
    objects: [
        (name: "card", type: "quad", material: "card",
         params: (corner: (-1, -1, -2), edge0: (2, 0, 0), edge1: (0, 2, 0))),
        (name: "wall", type: "quad", material: "wall",
         params: (corner: (1, -1, -2), edge0: (0, 0, 2), edge1: (0, 2, 0))),
        (name: "lamp", type: "quad", material: "lamp",
         params: (corner: (-0.5, 1.2, -0.5), edge0: (0, 0, -1), edge1: (1, 0, 0))),
    ],
    cameras: [ (name: "c", type: "perspective",
         params: (position: (0, 0, 1), look_at: (0, 0, -2), fov: 50, resolution: (12, 12))) ],
)"#;

/// Quantity: the image mean of X, Y and Z of [`AGREEMENT`] (max depth 3) for pt, lt and bdpt,
/// each the mean of 10 independent renders (seeds; 12×12 pixels, 1024 spp for pt and bdpt,
/// 4096 for lt). Tolerance: each integrator's mean within
/// 0.5% of pt's, and the test itself must be able to see 0.5%: 3 combined standard errors
/// (from the seeds' spread) below 0.5%. Printed: means, differences and standard errors.
#[test]
fn pt_lt_and_bdpt_agree_with_fluorescence() {
    let s = scene(AGREEMENT);
    assert!(s.objects.fluorescence());
    let runs = |kind: IntegratorKind, spp: u32| -> Vec<[f64; 3]> {
        (0..10u64)
            .map(|seed| render(&s, kind, spp, 100 + seed, 3).result.image.mean_xyz())
            .collect()
    };
    let pt = runs(IntegratorKind::Pt, 1024);
    let others = [
        // Light tracing is the noisiest here (the camera sees the card from a small lens).
        (IntegratorKind::Lt, runs(IntegratorKind::Lt, 4096)),
        (IntegratorKind::Bdpt, runs(IntegratorKind::Bdpt, 1024)),
    ];
    for c in 0..3 {
        let (mp, sp) = mean_se(&pt.iter().map(|x| x[c]).collect::<Vec<_>>());
        for (kind, r) in &others {
            let (m, se) = mean_se(&r.iter().map(|x| x[c]).collect::<Vec<_>>());
            let diff = m / mp - 1.0;
            let sigma = (se * se / (mp * mp) + sp * sp * m * m / (mp * mp * mp * mp)).sqrt();
            println!(
                "{kind} channel {c}: {m:.6} vs pt {mp:.6}: {:+.3}% (σ {:.3}%)",
                100.0 * diff,
                100.0 * sigma
            );
            assert!(
                3.0 * sigma < 0.005,
                "{kind} channel {c}: 3σ = {}",
                3.0 * sigma
            );
            assert!(
                diff.abs() < 0.005,
                "{kind} channel {c}: {:+.3}%",
                100.0 * diff
            );
        }
    }
}

/// A 1 m square patch of `material` under a uniform sky of D65 (integrated radiance 10
/// W/(m²·sr)), seen from 0.5 m above by a 20° camera that sees nothing but the patch: every
/// point of it receives E = π·L from the whole hemisphere.
fn sky_patch(material: &str) -> String {
    format!(
        r#"(
    materials: [ (name: "m", {material}) ],
    objects: [ (name: "patch", type: "quad", material: "m",
         params: (corner: (-0.5, 0, 0.5), edge0: (1, 0, 0), edge1: (0, 0, -1))) ],
    lights: [ (name: "sky", type: "environment", params: (radiance: "d65", scale: 10)) ],
    cameras: [ (name: "c", type: "perspective",
         params: (position: (0, 0.5, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 20,
                  resolution: (4, 4))) ],
)"#
    )
}

fn bfc_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("data/fluorescence")
        .join(format!("{name}.BFC"))
}

/// Quantity: the colour of each of the 8 bundled samples as rendered by pt on a patch under a
/// uniform D65 sky, normalised by the render of a perfect white diffuser (ρ = 1) in the same
/// place: XYZ_patch / Y_white · 100 against `spectrace color FILE.BFC --illuminant d65`
/// (`compute_bfc`, whose numbers `color_fluorescence` checks against independent 10 nm sums).
/// Tolerances: 0.003 in x and y and 1% in Y. The render integrates the continuous model
/// (piecewise-constant r over the file's 10 nm cells, D65 at 1 nm) while `spectrace color`
/// sums it on 1 nm cells; Monte Carlo noise is small (2 seeds × 4096 spp on 4×4 pixels: the
/// seeds' spread is printed, at most 0.22%, IXCRLALE). Measured: largest differences 0.0011
/// in x and y, 0.64% in Y (the red HERPICER and HERPIORA, a systematic offset larger than
/// their 0.03% spread: the two integrations differ where the steep red reflectance meets the
/// matrix's band edges). Each rendered colour must
/// also differ from the render with fluorescence off by more than the tolerance, so the
/// comparison sees the re-radiation. IXCRLALE is also rendered by bdpt (2048 spp, same
/// tolerances): its shifted camera paths end on the sky (s = 0) or sample it (s = 1).
#[test]
fn a_sky_lit_patch_shows_the_colour_spectrace_color_computes() {
    let white = scene(&sky_patch(
        r#"type: "lambertian", params: (reflectance: 1)"#,
    ));
    let y_white: f64 = (0..2u64)
        .map(|seed| {
            render(&white, IntegratorKind::Pt, 4096, 11 + seed, 2)
                .result
                .image
                .mean_xyz()[1]
        })
        .sum::<f64>()
        / 2.0;
    for name in [
        "CIBA12", "CIPLAW10", "HERPICER", "HERPIORA", "IXCRLALE", "PHP8HP1C", "POLGREE", "TEXTYELL",
    ] {
        let mut s = scene(&sky_patch(&format!(
            r#"type: "fluorescent", params: (bfc: "{name}")"#
        )));
        let runs: Vec<[f64; 3]> = (0..2u64)
            .map(|seed| {
                render(&s, IntegratorKind::Pt, 4096, 21 + seed, 2)
                    .result
                    .image
                    .mean_xyz()
            })
            .collect();
        let got: [f64; 3] =
            std::array::from_fn(|c| (runs[0][c] + runs[1][c]) / 2.0 * 100.0 / y_white);
        let spread = (runs[0][1] / runs[1][1] - 1.0).abs();
        let (want, _) = compute_bfc(&ColorArgs {
            spd: bfc_path(name).display().to_string(),
            observer: CieObserverKind::Cie1931_2,
            illuminant: Some("d65".into()),
            json: false,
        })
        .unwrap();
        let (x, y) = chromaticity(got);
        let (xw, yw) = chromaticity(want.total);
        println!(
            "{name}: rendered x {x:.4} y {y:.4} Y {:.2}; spectrace color x {xw:.4} y {yw:.4} Y {:.2}; seed spread {:.2}%",
            got[1],
            want.total[1],
            100.0 * spread
        );
        assert!(
            (x - xw).abs() < 0.003 && (y - yw).abs() < 0.003,
            "{name}: xy"
        );
        assert!((got[1] / want.total[1] - 1.0).abs() < 0.01, "{name}: Y");
        if name == "IXCRLALE" {
            // bdpt too: its camera paths shift, then end on the sky (s = 0) or sample it (s = 1).
            let b = render(&s, IntegratorKind::Bdpt, 2048, 41, 2)
                .result
                .image
                .mean_xyz();
            let b: [f64; 3] = b.map(|v| v * 100.0 / y_white);
            let (xb, yb) = chromaticity(b);
            println!("{name}: bdpt x {xb:.4} y {yb:.4} Y {:.2}", b[1]);
            assert!(
                (xb - xw).abs() < 0.003 && (yb - yw).abs() < 0.003,
                "{name}: bdpt xy"
            );
            assert!((b[1] / want.total[1] - 1.0).abs() < 0.01, "{name}: bdpt Y");
        }
        s.objects.set_fluorescence(false);
        let off = render(&s, IntegratorKind::Pt, 1024, 31, 2)
            .result
            .image
            .mean_xyz();
        let off: [f64; 3] = off.map(|v| v * 100.0 / y_white);
        let (xo, yo) = chromaticity(off);
        assert!(
            (xo - x).hypot(yo - y) > 0.003 || (off[1] / got[1] - 1.0).abs() > 0.01,
            "{name}: fluorescence does not show (off: x {xo:.4} y {yo:.4} Y {:.2})",
            off[1]
        );
    }
}

/// Two 0.5 m patches side by side, highlighter yellow (IXCRLALE) on the left and its
/// non-fluorescent twin (the same reflectance) on the right, under a near-UV LED panel only
/// (Gaussian at 365 nm, FWHM 15 nm: below 1e-6 of its power above 410 nm).
const UV: &str = r#"(
    materials: [
        (name: "card", type: "fluorescent", params: (bfc: "IXCRLALE")),
        (name: "twin", type: "fluorescent", params: (bfc: "IXCRLALE", reradiate: false)),
        (name: "uv", type: "emissive", params: (radiance: "gaussian:365:15", scale: 100)),
    ],
    objects: [
        (name: "card", type: "quad", material: "card",
         params: (corner: (-0.5, 0, 0.25), edge0: (0.5, 0, 0), edge1: (0, 0, -0.5))),
        (name: "twin", type: "quad", material: "twin",
         params: (corner: (0, 0, 0.25), edge0: (0.5, 0, 0), edge1: (0, 0, -0.5))),
        (name: "uv", type: "quad", material: "uv",
         params: (corner: (-1, 1, 1), edge0: (0, 0, -2), edge1: (2, 0, 0))),
    ],
    cameras: [ (name: "c", type: "perspective",
         params: (position: (0, 0.9, 0), look_at: (0, 0, 0), up: (0, 0, -1), fov: 50,
                  resolution: (16, 8))) ],
)"#;

/// Mean Y of the left and right halves of an image.
fn halves(img: &spectrace::film::XyzImage) -> (f64, f64) {
    let (mut l, mut r) = (0.0, 0.0);
    for (i, p) in img.xyz.iter().enumerate() {
        if (i as u32 % img.width) < img.width / 2 {
            l += p[1];
        } else {
            r += p[1];
        }
    }
    let n = img.xyz.len() as f64 / 2.0;
    (l / n, r / n)
}

/// Quantities: mean Y of the fluorescent half and of the twin half of [`UV`], pt, lt and bdpt
/// at 64 spp. Under near-UV light the twin reflects almost nothing visible while the card
/// fluoresces: the card's half must be over 20× brighter in every integrator (measured ratio
/// printed; the twin's light is the LED's far tail only). With fluorescence switched off the
/// scene is the reflectance-only image: the card's half renders exactly like the twin's
/// material (the same reflectance, the same random numbers), so the image equals the render
/// in which the card is replaced by its twin, pixel for pixel, bit for bit.
#[test]
fn near_uv_light_shows_fluorescence_the_twin_does_not() {
    let s = scene(UV);
    for kind in [IntegratorKind::Pt, IntegratorKind::Lt, IntegratorKind::Bdpt] {
        let (card, twin) = halves(&render(&s, kind, 64, 5, 4).result.image);
        println!("{kind}: card half Y {card:.6}, twin half Y {twin:.6}");
        assert!(card > 0.0 && card > 20.0 * twin, "{kind}: {card} vs {twin}");
    }
    let mut off = scene(UV);
    off.objects.set_fluorescence(false);
    assert!(!off.objects.fluorescence());
    let twins = scene(&UV.replace(
        r#"(bfc: "IXCRLALE")"#,
        r#"(bfc: "IXCRLALE", reradiate: false)"#,
    ));
    assert!(!twins.objects.fluorescence());
    for kind in [IntegratorKind::Pt, IntegratorKind::Lt, IntegratorKind::Bdpt] {
        let a = render(&off, kind, 16, 5, 4).result.image;
        let b = render(&twins, kind, 16, 5, 4).result.image;
        assert_eq!(
            a, b,
            "{kind}: fluorescence off is not the reflectance-only image"
        );
    }
}

/// Bad parameters of the `fluorescent` type are errors naming the item, the parameter and
/// what is wrong (and a missing file by its path); nothing panics.
#[test]
fn bad_fluorescent_parameters_are_clear_errors() {
    let build = |params: &str| -> String {
        let text = format!(
            r#"(
    materials: [ (name: "f", type: "fluorescent", params: ({params})) ],
    objects: [ (name: "p", type: "quad", material: "f",
         params: (corner: (0, 0, 0), edge0: (1, 0, 0), edge1: (0, 1, 0))) ],
    cameras: [ (name: "c", type: "perspective",
         params: (position: (0.5, 0.5, 2), look_at: (0.5, 0.5, 0), fov: 40, resolution: (4, 4))) ],
)"#
        );
        let file = Path::new("bad.ron");
        let desc = parse_scene_str(&text, file).unwrap();
        match build_scene(
            &desc,
            Path::new("/nonexistent-dir"),
            file,
            &[&BuiltinFactory],
        ) {
            Ok(_) => panic!("accepted: {params}"),
            Err(e) => e.to_string(),
        }
    };
    let e = build(r#"bfc: "missing.BFC""#);
    assert!(
        e.contains("bfc") && e.contains("missing.BFC") && e.contains("IXCRLALE"),
        "{e}"
    );
    let e = build(r#"bfc: "IXCRLALE", quantum_yield: 0.5"#);
    assert!(e.contains("not both"), "{e}");
    let e = build("");
    assert!(e.contains("absorption") && e.contains("bfc"), "{e}");
    let e = build(r#"absorption: 0.8, reflectance: 0.5, emission: "gaussian:520:40""#);
    assert!(e.contains("ρ + a ≤ 1"), "{e}");
    let e = build(r#"absorption: 1.5, emission: "gaussian:520:40""#);
    assert!(e.contains("absorption"), "{e}");
    let e = build(r#"absorption: 0.5, emission: "gaussian:520:40", quantum_yield: 2"#);
    assert!(e.contains("quantum_yield"), "{e}");
    let e = build(r#"bfc: "IXCRLALE", colour: 1"#);
    assert!(e.contains("colour"), "{e}");
    for e in [build(r#"bfc: "missing.BFC""#), build("")] {
        assert!(e.contains("material \"f\""), "{e}");
    }
    // A file that is not a matrix: its path and line.
    let readme = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/fluorescence/README.md");
    let e = build(&format!("bfc: {:?}", readme.display().to_string()));
    assert!(e.contains("README.md:1") && e.contains("BFC-450"), "{e}");
}

/// [`UV`] with the LED replaced by a line lamp: all of its power in the 365 nm mercury line
/// (`line:365`, a delta in wavelength).
fn uv_line() -> String {
    UV.replace(
        r#""gaussian:365:15", scale: 100"#,
        r#""line:365", scale: 100"#,
    )
}

/// Quantities: mean Y of the fluorescent card's half of [`uv_line`] for pt, lt and bdpt over 8
/// seeds each (16×8 pixels; pt and bdpt 1024 spp, lt 4096), and of the twin's half. A line
/// lamp excites the card only at exactly 365 nm: a camera path's excitation wavelength drawn
/// from a continuous density never lands there, so before the excitation draw included the
/// lights' lines path tracing (and bdpt's camera-side shifts) rendered the card as dark as
/// the twin while light tracing saw it. Tolerance: pt, lt and bdpt agree within 4 combined
/// standard errors (seeds' spread; printed, about 0.2–0.6%) and within 2%; the card's half is
/// over 1000× the twin's (the twin reflects only the line itself, where ȳ(365 nm) = 3.9e-6).
#[test]
fn a_uv_line_lamp_excites_fluorescence_in_every_integrator() {
    let s = scene(&uv_line());
    assert!(s.objects.fluorescence());
    assert_eq!(s.lights.delta_lines().len(), 1, "the lamp is one line");
    let runs = |kind: IntegratorKind, spp: u32| -> (Vec<f64>, Vec<f64>) {
        (0..8u64)
            .map(|seed| halves(&render(&s, kind, spp, 200 + seed, 4).result.image))
            .unzip()
    };
    let (pt_card, pt_twin) = runs(IntegratorKind::Pt, 1024);
    let (mp, sp) = mean_se(&pt_card);
    let (mt, _) = mean_se(&pt_twin);
    println!(
        "pt: card half Y {mp:.6} (se {:.3}%), twin half {mt:.3e}",
        100.0 * sp / mp
    );
    assert!(mp > 1000.0 * mt.max(0.0) && mp > 0.0, "pt: {mp} vs {mt}");
    for (kind, spp) in [(IntegratorKind::Lt, 4096), (IntegratorKind::Bdpt, 1024)] {
        let (card, twin) = runs(kind, spp);
        let (m, se) = mean_se(&card);
        let (t, _) = mean_se(&twin);
        let diff = m / mp - 1.0;
        let sigma = (se / m).hypot(sp / mp);
        println!(
            "{kind}: card half Y {m:.6} (se {:.3}%), twin half {t:.3e}; vs pt {:+.3}% (σ {:.3}%)",
            100.0 * se / m,
            100.0 * diff,
            100.0 * sigma
        );
        assert!(m > 1000.0 * t.max(0.0), "{kind}: {m} vs {t}");
        assert!(
            diff.abs() < 4.0 * sigma && diff.abs() < 0.05,
            "{kind}: {:+.3}% (σ {:.3}%)",
            100.0 * diff,
            100.0 * sigma
        );
    }
}

/// [`UV`] lit by two lamps side by side, each of integrated radiance 100: the 365 nm mercury
/// line (`line:365`) and a narrow continuous LED at the same wavelength (Gaussian, FWHM 4 nm),
/// or only one of them (`which`: "both", "line", "led").
fn line_and_led(which: &str) -> String {
    let line = r#"(name: "uv", type: "quad", material: "uv",
         params: (corner: (-1, 1, 1), edge0: (0, 0, -2), edge1: (1, 0, 0))),"#;
    let led = r#"(name: "led", type: "quad", material: "led",
         params: (corner: (0, 1, 1), edge0: (0, 0, -2), edge1: (1, 0, 0))),"#;
    let objects = match which {
        "line" => line.to_string(),
        "led" => led.to_string(),
        _ => format!("{line}\n        {led}"),
    };
    UV.replace(
        r#"(name: "uv", type: "emissive", params: (radiance: "gaussian:365:15", scale: 100)),"#,
        r#"(name: "uv", type: "emissive", params: (radiance: "line:365", scale: 100)),
        (name: "led", type: "emissive", params: (radiance: "gaussian:365:4", scale: 100)),"#,
    )
    .replace(
        r#"(name: "uv", type: "quad", material: "uv",
         params: (corner: (-1, 1, 1), edge0: (0, 0, -2), edge1: (2, 0, 0))),"#,
        &objects,
    )
}

/// Light adds up: with a `line:365` lamp and a continuous LED at 365 nm side by side, the
/// fluorescent card's half of the image (mean Y, 6 seeds) equals the sum of the renders with
/// each lamp alone, in pt, bdpt and lt (512 spp, lt 2048). A lane drawn exactly on the line
/// (a camera path's excitation draw onto the lamp's line, or the pair's wavelengths from the
/// lights' spectra) carries a discrete probability; if the LED's continuous density at
/// 365 nm is counted on it too, the sum picks up an extra LED density × 1 nm — about 1/4.3 of
/// the LED's share for this 4 nm wide LED: measured before the fix +10.9% (pt), +9.6% (bdpt),
/// +10.1% (lt), σ ≈ 1%, at 4096/2048/4096 spp. Tolerance: within 4 combined standard errors
/// (seeds' spread, printed; 0.8–1.9% at these spp) and within 5%, which the +10% fails.
#[test]
fn a_line_lane_takes_only_the_line_power_beside_a_continuous_light_there() {
    let (both, line, led) = (
        scene(&line_and_led("both")),
        scene(&line_and_led("line")),
        scene(&line_and_led("led")),
    );
    assert_eq!(both.lights.delta_lines().len(), 1);
    assert_eq!(both.lights.lights().len(), 2);
    for (kind, spp) in [
        (IntegratorKind::Pt, 2048),
        (IntegratorKind::Bdpt, 512),
        (IntegratorKind::Lt, 1024),
    ] {
        let card = |s: &Scene| -> Vec<f64> {
            (0..6u64)
                .map(|seed| halves(&render(s, kind, spp, 300 + seed, 4).result.image).0)
                .collect()
        };
        let (mb, sb) = mean_se(&card(&both));
        let (ml, sl) = mean_se(&card(&line));
        let (me, se) = mean_se(&card(&led));
        let sum = ml + me;
        let diff = mb / sum - 1.0;
        let sigma = (sb * sb + sl * sl + se * se).sqrt() / sum;
        println!(
            "{kind}: both {mb:.6}, line {ml:.6} + led {me:.6} = {sum:.6}: {:+.3}% (σ {:.3}%)",
            100.0 * diff,
            100.0 * sigma
        );
        assert!(
            ml > 0.0 && me > 0.0,
            "{kind}: each lamp must excite the card"
        );
        assert!(
            diff.abs() < 4.0 * sigma && diff.abs() < 0.05,
            "{kind}: {:+.3}% (σ {:.3}%)",
            100.0 * diff,
            100.0 * sigma
        );
    }
}

/// Y means of `img` over its `rows` (top row 0): the whole band and its 2 × 2 tiles.
fn band_tiles(img: &spectrace::film::XyzImage, rows: std::ops::Range<u32>) -> [f64; 5] {
    let (w, h0, h1) = (img.width, rows.start, rows.end);
    let mut sum = [0.0f64; 5];
    let mut n = [0usize; 5];
    for y in rows {
        for x in 0..w {
            let yv = img.xyz[(y * w + x) as usize][1];
            let tile = 1 + (2 * (y - h0) / (h1 - h0)) as usize * 2 + (2 * x / w) as usize;
            for i in [0, tile] {
                sum[i] += yv;
                n[i] += 1;
            }
        }
    }
    std::array::from_fn(|i| sum[i] / n[i] as f64)
}

/// Quantity: Y means (the whole image or band, and its 2 × 2 tiles) of bdpt against an
/// integrator that renders the same band independently, each the mean of 8 seeds, on the
/// bundled fluorescence scenes: `scenes/fluorescence.ron` (bdpt 128 spp against pt 512 and
/// lt 512), `fluorescent_caustic.ron` below row 70 of 120 (the floor; lt cannot see the lamp
/// through the ball above it; bdpt 128 against lt 512) and `fluorescent_indirect_uv.ron`
/// (bdpt 128 against pt 512; lt cannot see the card through the ball). bdpt's light
/// subpaths here start half the time at their own wavelengths, joined to camera subpaths
/// through fluorescent endpoints (`integrator/fluorescence/join.rs`). Tolerance: 4 combined
/// standard errors of the two means (from the seeds' spread; with 7 degrees of freedom a
/// true mean lies beyond that about 0.5% of the time), printed with the differences. Long
/// (about 3 minutes on two idle cores): `cargo test --release --test render_fluorescence --
/// --ignored`.
#[test]
#[ignore = "long: about 3 minutes on 2 idle cores"]
fn bdpt_agrees_on_the_bundled_fluorescence_scenes() {
    let data = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let load = |rel: &str| -> Scene {
        let path = data.join(rel);
        let text = std::fs::read_to_string(&path).unwrap();
        let desc = parse_scene_str(&text, &path).unwrap();
        build_scene(&desc, path.parent().unwrap(), &path, &[&BuiltinFactory]).unwrap()
    };
    let cases: [(&str, u32, IntegratorKind, std::ops::Range<u32>); 4] = [
        ("../scenes/fluorescence.ron", 8, IntegratorKind::Pt, 0..96),
        ("../scenes/fluorescence.ron", 8, IntegratorKind::Lt, 0..96),
        (
            "tests/data/fluorescent_caustic.ron",
            16,
            IntegratorKind::Lt,
            70..120,
        ),
        (
            "tests/data/fluorescent_indirect_uv.ron",
            10,
            IntegratorKind::Pt,
            0..96,
        ),
    ];
    let mut failures = Vec::new();
    for (file, depth, other, rows) in cases {
        let s = load(file);
        let runs = |kind: IntegratorKind, spp: u32| -> Vec<[f64; 5]> {
            (0..8u64)
                .map(|seed| {
                    band_tiles(
                        &render(&s, kind, spp, 500 + seed, depth).result.image,
                        rows.clone(),
                    )
                })
                .collect()
        };
        let b = runs(IntegratorKind::Bdpt, 128);
        let o = runs(other, 512);
        for i in 0..5 {
            let (mb, sb) = mean_se(&b.iter().map(|x| x[i]).collect::<Vec<_>>());
            let (mo, so) = mean_se(&o.iter().map(|x| x[i]).collect::<Vec<_>>());
            let sigma = (sb * sb + so * so).sqrt();
            let what = if i == 0 {
                "band".to_string()
            } else {
                format!("tile {i}")
            };
            println!(
                "{file} {what}: bdpt {mb:.6} vs {other} {mo:.6}: {:+.3}% (σ {:.3}%)",
                100.0 * (mb / mo - 1.0),
                100.0 * sigma / mo
            );
            if (mb - mo).abs() > 4.0 * sigma {
                failures.push(format!("{file} {what}: {mb} vs {other} {mo}, σ {sigma}"));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
