//! `spectrace luminaire export`: IES LM-63-2019 and EULUMDAT writers. Every real and synthetic
//! file read → written → read gives the same candela table.

use spectrace::photometry::eulumdat_writer::write_eulumdat;
use spectrace::photometry::ies_writer::write_ies_2019;
use spectrace::photometry::{load_luminaire, Luminaire, PhotometricType, SourceFormat};
use std::path::{Path, PathBuf};

fn all_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    for dir in ["data/photometry", "tests/data/photometry"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if matches!(p.extension().and_then(|e| e.to_str()), Some("ies" | "ldt")) {
                out.push(p);
            }
        }
    }
    out.sort();
    assert_eq!(out.len(), 17, "{out:?}");
    out
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spectrace-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn reread(text: &str, name: &str) -> Luminaire {
    let p = temp(name);
    std::fs::write(&p, text).unwrap();
    load_luminaire(&p).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

// IES → IES LM-63-2019 → read: the same angles and candela exactly (values are written in the
// shortest form that parses back to the same f64, and the multipliers are folded in as 1), the
// same symmetry, type and flux, absolute photometry kept.
#[test]
fn ies_export_reproduces_the_table() {
    for path in all_files() {
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        let a = load_luminaire(&path).unwrap();
        let b = reread(&write_ies_2019(&a, &name), &format!("{name}.ies"));
        assert_eq!(
            b.format,
            SourceFormat::Ies(spectrace::photometry::IesVersion::Lm63_2019)
        );
        assert_eq!(a.h_deg, b.h_deg, "{name}");
        assert_eq!(a.v_deg, b.v_deg, "{name}");
        assert_eq!(a.candela, b.candela, "{name}");
        assert_eq!(
            (a.symmetry, a.photometric_type),
            (b.symmetry, b.photometric_type)
        );
        assert_eq!(a.absolute, b.absolute, "{name}");
        assert_eq!(a.flux_lm(), b.flux_lm(), "{name}");
        assert_eq!(a.tilt.is_some(), b.tilt.is_some(), "{name}");
        if let Some(r) = a.rated_lamp_lumens {
            let rb = b.rated_lamp_lumens.unwrap();
            assert!((r - rb).abs() <= 1e-9 * r, "{name}: {r} vs {rb}");
        }
    }
}

// Type C → EULUMDAT → read: the same candela at every stored angle within 1e-9 relative (the
// cd/klm division and multiplication round), the same symmetry and flux within 1e-9; a C360
// plane, which EULUMDAT does not store, reads back from C0. Types A and B are refused.
#[test]
fn eulumdat_export_reproduces_the_table() {
    for path in all_files() {
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        let a = load_luminaire(&path).unwrap();
        let text = write_eulumdat(&a, &name);
        if a.photometric_type != PhotometricType::C {
            assert!(text.unwrap_err().contains("type C"), "{name}");
            continue;
        }
        let b = reread(&text.unwrap(), &format!("{name}.ldt"));
        assert_eq!(a.symmetry, b.symmetry, "{name}");
        for &h in &a.h_deg {
            for &v in &a.v_deg {
                let (x, y) = (a.candela_at(h, v), b.candela_at(h, v));
                assert!(
                    (x - y).abs() <= 1e-9 * x.max(1.0),
                    "{name} ({h}, {v}): {x} vs {y}"
                );
            }
        }
        let (fa, fb) = (a.flux_lm(), b.flux_lm());
        assert!((fa - fb).abs() <= 1e-9 * fa, "{name}: {fa} vs {fb}");
    }
}

// The command: export writes a file that `spectrace luminaire` reads (exit 0), and a type B
// file asked for as EULUMDAT fails with exit 1 and writes nothing.
#[test]
fn export_command() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/photometry/anon_sample07_isym4.ldt");
    let out = temp("cmd.ies");
    let code = spectrace::cli::main_with_args([
        "spectrace",
        "luminaire",
        "export",
        src.to_str().unwrap(),
        "--format",
        "ies",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0);
    assert!(load_luminaire(&out).is_ok());
    let b = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/photometry/type_b_absolute_lm63_2002.ies");
    let out2 = temp("cmd_b.ldt");
    let code = spectrace::cli::main_with_args([
        "spectrace",
        "luminaire",
        "export",
        b.to_str().unwrap(),
        "--format",
        "ldt",
        "-o",
        out2.to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(!out2.exists());
}
