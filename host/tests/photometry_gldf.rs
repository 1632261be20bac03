//! GLDF containers: the example in `scenes/gldf/` read, its spectrum carried into a render, and
//! hostile containers refused with the fault named.

use spectrace::color::cct::{cct_duv, uv_1960};
use spectrace::color::cri::color_rendering;
use spectrace::integrator::{
    render_with, IntegratorKind, PathTracer, RenderSettings, SampleBudget,
};
use spectrace::photometry::gldf::Gldf;
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory};
use spectrace::spectrum::{Interpolation, TabulatedSpd};
use std::io::Write;
use std::path::{Path, PathBuf};

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/gldf/example_downlight.gldf")
}

/// The example container: two variants with one emitter each, both on one light source whose
/// spectrum (a `spectrum/text` file) is CIE LED-B1, 380–780 nm at 5 nm (81 values).
#[test]
fn the_example_container_reads() {
    let mut g = Gldf::open(&example()).unwrap();
    assert_eq!(g.variants.len(), 2);
    let (v, e) = g.choose(Some("spot"), None).unwrap();
    assert_eq!((v.id.as_str(), e.id.as_str()), ("spot", "emitterSpot"));
    let s = g.spectrum_of(&e).unwrap().clone();
    assert_eq!(s.len(), 81);
    assert_eq!((s[0].0, s[80].0), (380.0, 780.0));
    let lum = g.luminaire_of(&e).unwrap();
    assert!(lum.flux_lm() > 0.0);
    assert!(g
        .choose(Some("nope"), None)
        .unwrap_err()
        .contains("variants: downlight, spot"));
}

/// The container's spectrum reaches the render: a white (ρ = 0.8) floor lit by the `gldf`
/// light, rendered with path tracing; the CCT of the image's mean XYZ is within 50 K of the CCT
/// of the container's spectrum (both by Ohno's method, CIE 1931 2°). A white Lambertian floor
/// reflects the spectrum unchanged, so only noise and the film's wavelength sampling separate
/// them (measured: a few K); an illuminant-A default (2856 K) or an equal-energy one (5455 K)
/// would be hundreds of K away from LED-B1's.
#[test]
fn the_containers_spectrum_sets_the_rendered_cct() {
    let g = Gldf::open(&example()).unwrap();
    let (_, e) = g.choose(None, None).unwrap();
    let s = g.spectrum_of(&e).unwrap().clone();
    let nm: Vec<f64> = s.iter().map(|p| p.0).collect();
    let v: Vec<f64> = s.iter().map(|p| p.1).collect();
    let spd = TabulatedSpd::new("b1", &nm, &v, Interpolation::Linear).unwrap();
    let want = color_rendering(&spd).unwrap().cct_k;
    let text = format!(
        r#"(observer: "cie1931-2",
            materials: [(name: "white", type: "lambertian", params: (reflectance: 0.8))],
            objects: [(name: "floor", type: "quad", material: "white",
                       params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4)))],
            lights: [(name: "lum", type: "gldf", params: (file: "{}", position: (0, 1.5, 0)))],
            cameras: [(name: "c", type: "perspective",
                       params: (position: (0, 2, 2), look_at: (0, 0, 0), fov: 40, resolution: (24, 24)))])"#,
        example().display()
    );
    let desc = parse_scene_str(&text, Path::new("gldf.ron")).unwrap();
    let scene = build_scene(
        &desc,
        Path::new("."),
        Path::new("gldf.ron"),
        &[&BuiltinFactory],
    )
    .unwrap();
    let settings = RenderSettings {
        sampler: Default::default(),
        budget: SampleBudget::Spp(16),
        seed: 3,
        threads: None,
        camera: None,
        tile_size: 16,
        tracer: PathTracer {
            max_depth: 1,
            ..PathTracer::default()
        },
    };
    let out = render_with(
        &scene,
        &settings,
        IntegratorKind::Pt,
        false,
        &|_, _| {},
        None,
    )
    .unwrap();
    let xyz = out.result.image.mean_xyz();
    let (u, v) = uv_1960(xyz);
    let (cct, duv) = cct_duv(u, v).unwrap();
    println!("rendered floor CCT {cct:.1} K (Duv {duv:.4}), container spectrum {want:.1} K");
    assert!((cct - want).abs() < 50.0, "{cct} K vs {want} K");
}

fn zip_of(entries: &[(&str, &[u8])]) -> Vec<u8> {
    let mut buf = std::io::Cursor::new(Vec::new());
    {
        let mut z = zip::ZipWriter::new(&mut buf);
        let opts = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated);
        for (name, data) in entries {
            z.start_file(*name, opts).unwrap();
            z.write_all(data).unwrap();
        }
        z.finish().unwrap();
    }
    buf.into_inner()
}

fn refused(bytes: Vec<u8>) -> String {
    Gldf::from_bytes(bytes, Path::new("bad.gldf"))
        .unwrap_err()
        .to_string()
}

const MINIMAL: &str = r#"<Root><Header/><GeneralDefinitions/><ProductDefinitions/></Root>"#;

/// Hostile or broken containers: each refused with the file and the fault named, nothing read
/// outside the container, memory bounded (the bomb stops at the limit + 1 byte).
#[test]
fn bad_containers_are_refused() {
    assert!(Gldf::from_bytes(
        zip_of(&[("product.xml", MINIMAL.as_bytes())]),
        Path::new("ok.gldf")
    )
    .is_ok());
    let e = refused(zip_of(&[
        ("product.xml", MINIMAL.as_bytes()),
        ("ldc/../../etc/passwd", b"x"),
    ]));
    assert!(
        e.contains("bad.gldf") && e.contains("outside the container"),
        "{e}"
    );
    let e = refused(zip_of(&[
        ("product.xml", MINIMAL.as_bytes()),
        ("/etc/passwd", b"x"),
    ]));
    assert!(e.contains("outside the container"), "{e}");
    let e = refused(b"PK\x03\x04 not really a zip".to_vec());
    assert!(e.contains("not a readable zip"), "{e}");
    let e = refused(zip_of(&[("other.xml", b"<Root/>")]));
    assert!(
        e.contains("product.xml") && e.contains("not in the container"),
        "{e}"
    );
    // Entity expansion ("billion laughs"): the DTD is refused before anything expands.
    let lol = r#"<?xml version="1.0"?><!DOCTYPE Root [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">]><Root>&c;</Root>"#;
    let e = refused(zip_of(&[("product.xml", lol.as_bytes())]));
    assert!(e.contains("product.xml") && e.contains("DTD"), "{e}");
    // A file name in product.xml that leaves its folder.
    let sneaky = r#"<Root><GeneralDefinitions><Files><File id="f" contentType="ldc/ies" type="localFileName">../../x.ies</File></Files></GeneralDefinitions></Root>"#;
    let e = refused(zip_of(&[("product.xml", sneaky.as_bytes())]));
    assert!(e.contains("leaves its folder"), "{e}");
    // A zip bomb: 65 MiB of zeros (64 KiB compressed) as product.xml, above the 64 MiB limit.
    let zeros = vec![0u8; (65 << 20) as usize];
    let e = refused(zip_of(&[("product.xml", &zeros)]));
    assert!(e.contains("zip bomb"), "{e}");
}

/// Bounded randomised inputs (the quick companion of the `gldf` fuzz target): 3 000 damaged
/// copies of the example container (flipped bytes, cuts) and 1 000 containers whose
/// `product.xml` had a byte changed or cut: every one read or refused, never a panic, and every
/// accepted container's variants, emitters, photometry and spectra used.
#[test]
fn the_reader_survives_damaged_containers() {
    let seed = std::fs::read(example()).unwrap();
    let xml = {
        let mut g = Gldf::open(&example()).unwrap();
        String::from_utf8(g.entry("product.xml").unwrap()).unwrap()
    };
    let mut rng = 0x2545F4914F6CDD1Du64;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    let mut ok = 0;
    for case in 0..4_000 {
        let bytes = if case < 3_000 {
            let mut b = seed.clone();
            for _ in 0..1 + next() % 3 {
                if next() % 4 == 0 {
                    let at = next() as usize % (b.len() + 1);
                    b.truncate(at);
                } else if !b.is_empty() {
                    let at = next() as usize % b.len();
                    b[at] ^= 1 << (next() % 8);
                }
            }
            b
        } else {
            let mut x = xml.clone().into_bytes();
            let at = next() as usize % x.len();
            if next() % 2 == 0 {
                x.truncate(at);
            } else {
                x[at] = b"<>/\"= a0&;"[next() as usize % 10];
            }
            zip_of(&[("product.xml", &x)])
        };
        if let Ok(mut g) = Gldf::from_bytes(bytes, Path::new("damaged.gldf")) {
            ok += 1;
            for v in g.variants.clone() {
                if let Ok((_, e)) = g.choose(Some(&v.id), None) {
                    let _ = g.spectrum_of(&e);
                    let _ = g.luminaire_of(&e);
                }
            }
        }
    }
    println!("{ok} of 4000 accepted");
}
