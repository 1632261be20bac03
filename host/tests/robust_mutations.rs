//! Property-based mutation tests of the file readers, the quick companion of the coverage-guided
//! fuzz targets in `fuzz/`: a valid file of each format is damaged by a random list of edits
//! (flipped bytes, inserted or deleted runs, a cut, a duplicated slice, a number swapped for an
//! extreme one) and the reader must answer with a value or an error — never a panic, and a mesh
//! it accepts must be valid, and a luminaire (IES, EULUMDAT) it accepts must survive being used
//! and written back out. 1024 cases per reader, well under a second each.

use proptest::prelude::*;
use spectrace::geometry::{parse_obj, parse_ply};
use spectrace::photometry::{eulumdat::parse_eulumdat, ies::parse_ies, Luminaire};
use spectrace::plugin::blob::Blob;
use spectrace::scene::{build_scene, parse_scene_str, BuiltinFactory, ObjectFactory};
use spectrace::spectrum::csv_table::parse_csv_table;
use std::path::Path;

/// One edit of a byte string.
#[derive(Clone, Debug)]
enum Edit {
    Flip(usize, u8),
    Insert(usize, Vec<u8>),
    Delete(usize, usize),
    Cut(usize),
    Duplicate(usize, usize, usize),
    /// Replace the run of digits at the position by an extreme literal.
    Number(usize, &'static str),
}

const EXTREMES: [&str; 10] = [
    "0",
    "-0",
    "1e308",
    "-1e400",
    "nan",
    "inf",
    "4294967295",
    "18446744073709551616",
    "-1",
    "0.0000000000000000000000000000000000000000000001",
];

fn edit() -> impl Strategy<Value = Edit> {
    let pos = any::<prop::sample::Index>().prop_map(|i| i.index(usize::MAX / 2));
    prop_oneof![
        (pos.clone(), any::<u8>()).prop_map(|(p, b)| Edit::Flip(p, b)),
        (pos.clone(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(p, b)| Edit::Insert(p, b)),
        (pos.clone(), 1usize..32).prop_map(|(p, n)| Edit::Delete(p, n)),
        pos.clone().prop_map(Edit::Cut),
        (pos.clone(), 1usize..64, pos.clone()).prop_map(|(a, n, b)| Edit::Duplicate(a, n, b)),
        (pos, prop::sample::select(EXTREMES.to_vec())).prop_map(|(p, s)| Edit::Number(p, s)),
    ]
}

fn apply(bytes: &[u8], edits: &[Edit]) -> Vec<u8> {
    let mut b = bytes.to_vec();
    for e in edits {
        let at = |p: usize, b: &Vec<u8>| if b.is_empty() { 0 } else { p % (b.len() + 1) };
        match e {
            Edit::Flip(p, x) if !b.is_empty() => {
                let i = p % b.len();
                b[i] ^= x;
            }
            Edit::Flip(..) => {}
            Edit::Insert(p, run) => {
                let i = at(*p, &b);
                b.splice(i..i, run.iter().copied());
            }
            Edit::Delete(p, n) => {
                let i = at(*p, &b);
                let j = (i + n).min(b.len());
                b.drain(i..j);
            }
            Edit::Cut(p) => {
                let i = at(*p, &b);
                b.truncate(i);
            }
            Edit::Duplicate(p, n, q) => {
                let i = at(*p, &b);
                let j = (i + n).min(b.len());
                let run: Vec<u8> = b[i..j].to_vec();
                let k = at(*q, &b);
                b.splice(k..k, run);
            }
            Edit::Number(p, lit) => {
                let i = at(*p, &b);
                let j = i + b[i..].iter().take_while(|c| c.is_ascii_digit()).count();
                b.splice(i..j, lit.bytes());
            }
        }
    }
    b
}

fn edits() -> impl Strategy<Value = Vec<Edit>> {
    prop::collection::vec(edit(), 1..6)
}

const OBJ: &str = "# a quad and a triangle\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\n\
vt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf -1 -2 -3\n";

const PLY_ASCII: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n\
property float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
element face 1\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n4 0 1 2 3\n";

fn ply_binary() -> Vec<u8> {
    let mut b = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
property float y\nproperty float z\nelement face 1\nproperty list uchar uint vertex_indices\n\
end_header\n"
        .to_vec();
    for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        for x in p {
            b.extend_from_slice(&x.to_le_bytes());
        }
    }
    b.push(3);
    for i in [0u32, 1, 2] {
        b.extend_from_slice(&i.to_le_bytes());
    }
    b
}

const CSV: &str = "# a lamp\nwavelength_nm,relative_power,second\n380,0.5,1\n400,1.0,2\n\
500,2.5,3\n600,\"3\",4\n780,0.25,5\n";

const SCENE: &str = r#"(
    observer: "cie1931-2",
    output: (spp: 4, max_depth: 4, rgb_space: "srgb"),
    materials: [
        (name: "floor", type: "lambertian", params: (reflectance: 0.7)),
        (name: "glass", type: "dielectric", params: (ior: 1.5)),
        (name: "metal", type: "conductor", params: (metal: "au", roughness: 0.2)),
        (name: "lamp", type: "emissive", params: (radiance: "d65", scale: 40.0)),
    ],
    objects: [
        (name: "floor", type: "quad", material: "floor",
         params: (corner: (-2, 0, 2), edge0: (4, 0, 0), edge1: (0, 0, -4))),
        (name: "ball", type: "sphere", material: "glass", params: (center: (0, 0.8, 0), radius: 0.5)),
        (name: "lamp", type: "quad", material: "lamp",
         params: (corner: (-0.1, 2.6, -0.1), edge0: (0.2, 0, 0), edge1: (0, 0, 0.2))),
    ],
    lights: [(name: "spot", type: "spot", params: (position: (0, 3, 0), target: (0, 0, 0), inner_angle: 20, outer_angle: 30, power: 10, spd: "blackbody:3000"))],
    cameras: [(name: "front", type: "perspective",
         params: (position: (0, 1.6, 4.5), look_at: (0, 0.5, 0), fov: 45, resolution: (16, 12)))],
)"#;

/// A type B IES file with absolute photometry (LM-63-2002).
const IES: &[u8] = include_bytes!("data/photometry/type_b_absolute_lm63_2002.ies");
/// An IES file with the tilt data included (LM-63-1995).
const IES_TILT: &[u8] = include_bytes!("data/photometry/tilt_include_lm63_1995.ies");
/// A EULUMDAT file with two lamp sets and symmetry 3.
const LDT: &[u8] = include_bytes!("data/photometry/isym3_two_lamp_sets.ldt");
/// A EULUMDAT file without symmetry and with decimal commas.
const LDT_COMMA: &[u8] = include_bytes!("data/photometry/isym0_decimal_comma.ldt");

/// Everything the renderer and the exporters do with a luminaire (flux, intensities, direction
/// sampling, both writers): none of it may panic on a luminaire the reader accepted.
fn use_luminaire(lum: Result<Luminaire, spectrace::photometry::PhotometryError>) {
    let Ok(lum) = lum else { return };
    let _ = lum.flux_lm();
    let _ = lum.max_cd();
    for d in [
        [0.0, 0.0, -1.0],
        [0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0],
        [0.6, -0.48, 0.64],
    ] {
        let _ = lum.intensity_cd(d);
    }
    if let Some(s) = spectrace::photometry::DirectionSampler::new(&lum) {
        for (u1, u2) in [(0.0, 0.0), (0.5, 0.25), (0.999999, 0.999999)] {
            let (d, _) = s.sample(&lum, u1, u2);
            let _ = s.pdf(&lum, d);
        }
    }
    let _ = spectrace::photometry::ies_writer::write_ies_2019(&lum, "mutated");
    let _ = spectrace::photometry::eulumdat_writer::write_eulumdat(&lum, "mutated");
}

/// Where luminaire files "live": `TILT=<file>` resolves in a folder that does not exist.
const LUMINAIRE_DIR: &str = "/nonexistent-spectrace-test";

fn check_mesh(m: Result<spectrace::geometry::TriangleMesh, spectrace::geometry::GeometryError>) {
    if let Ok(mesh) = m {
        mesh.validate().expect("a mesh the reader accepts is valid");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1024, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn obj_reader_survives_mutations(e in edits()) {
        let bytes = apply(OBJ.as_bytes(), &e);
        check_mesh(parse_obj(&String::from_utf8_lossy(&bytes), Path::new("m.obj")));
    }

    #[test]
    fn ply_ascii_reader_survives_mutations(e in edits()) {
        check_mesh(parse_ply(&apply(PLY_ASCII.as_bytes(), &e), Path::new("m.ply")));
    }

    #[test]
    fn ply_binary_reader_survives_mutations(e in edits()) {
        check_mesh(parse_ply(&apply(&ply_binary(), &e), Path::new("m.ply")));
    }

    #[test]
    fn csv_reader_survives_mutations(e in edits()) {
        let bytes = apply(CSV.as_bytes(), &e);
        let _ = parse_csv_table(&String::from_utf8_lossy(&bytes), "m.csv");
    }

    #[test]
    fn blob_reader_survives_mutations(e in edits()) {
        let params: ron::Value =
            ron::from_str("(position: (0, 2, 0), power: 60, spd: \"d65\")").unwrap();
        let good = Blob::pack_builtin_light("point", &params).unwrap().encode().unwrap();
        if let Ok(blob) = Blob::decode(&apply(&good, &e)) {
            let factory = spectrace::plugin::factory::RegistryFactory::new(
                std::sync::Arc::new(spectrace::plugin::builtin_registry()),
                spectrace::plugin::adapter::PluginFaults::new(),
            );
            let _ = blob.instantiate(&factory);
        }
    }

    #[test]
    fn ies_reader_survives_mutations(e in edits(), tilt in any::<bool>()) {
        let seed = if tilt { IES_TILT } else { IES };
        let path = Path::new(LUMINAIRE_DIR).join("m.ies");
        use_luminaire(parse_ies(&apply(seed, &e), &path));
    }

    #[test]
    fn eulumdat_reader_survives_mutations(e in edits(), comma in any::<bool>()) {
        let seed = if comma { LDT_COMMA } else { LDT };
        let path = Path::new(LUMINAIRE_DIR).join("m.ldt");
        use_luminaire(parse_eulumdat(&apply(seed, &e), &path));
    }

    #[test]
    fn scene_parser_survives_mutations(e in edits()) {
        let bytes = apply(SCENE.as_bytes(), &e);
        let text = String::from_utf8_lossy(&bytes);
        let file = Path::new("m.ron");
        if let Ok(desc) = parse_scene_str(&text, file) {
            let factories: [&dyn ObjectFactory; 1] = [&BuiltinFactory];
            let _ = build_scene(&desc, Path::new("/nonexistent-spectrace-test"), file, &factories);
        }
    }
}

/// The unmutated inputs are valid, so the mutations start from files the readers accept (a
/// broken seed would test only the first error path).
#[test]
fn the_seeds_are_valid() {
    check_mesh(parse_obj(OBJ, Path::new("m.obj")));
    assert!(parse_obj(OBJ, Path::new("m.obj")).is_ok());
    assert!(parse_ply(PLY_ASCII.as_bytes(), Path::new("m.ply")).is_ok());
    assert!(parse_ply(&ply_binary(), Path::new("m.ply")).is_ok());
    parse_csv_table(CSV, "m.csv").unwrap();
    for (seed, name) in [(IES, "m.ies"), (IES_TILT, "m.ies")] {
        parse_ies(seed, &Path::new(LUMINAIRE_DIR).join(name)).unwrap();
    }
    for seed in [LDT, LDT_COMMA] {
        parse_eulumdat(seed, &Path::new(LUMINAIRE_DIR).join("m.ldt")).unwrap();
    }
    let desc = parse_scene_str(SCENE, Path::new("m.ron")).unwrap();
    let factories: [&dyn ObjectFactory; 1] = [&BuiltinFactory];
    build_scene(&desc, Path::new("."), Path::new("m.ron"), &factories).unwrap();
}
