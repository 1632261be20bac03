//! IES LM-63 and EULUMDAT readers: every real file in `host/data/photometry/` loads and matches
//! an independent reading; each synthetic file in `host/tests/data/photometry/` checks the case
//! it was written for; malformed files give errors naming the file, line and field; the
//! direction sampler's pdf is normalized and importance-samples the table.

use spectrace::photometry::{
    load_luminaire, DirectionSampler, IesVersion, Luminaire, PhotometricType, SourceFormat,
    Symmetry,
};
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

fn real(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/photometry")
        .join(name)
}

fn own(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/photometry")
        .join(name)
}

fn load(path: &Path) -> Luminaire {
    load_luminaire(path).unwrap_or_else(|e| panic!("{e}"))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-12)
}

/// Printed by `python3 scripts/photometry_check.py` (an independent plain-Python reading of the
/// files, sharing no code with the Rust readers): file, flux in lm, (C, γ, cd) samples.
type Expected = (&'static str, f64, &'static [(f64, f64, f64)]);
const INDEPENDENT: &[Expected] = &[
    (
        "anon_sample03_isym2.ldt",
        334.1449,
        &[
            (0.0, 0.0, 0.0000),
            (0.0, 30.0, 177.5956),
            (45.0, 30.0, 105.0265),
            (90.0, 60.0, 0.0733),
            (135.0, 45.0, 0.0000),
            (200.0, 20.0, 0.0000),
            (300.0, 75.0, 24.3523),
        ],
    ),
    (
        "anon_sample05_isym1.ldt",
        4824.0225,
        &[
            (0.0, 0.0, 1847.8204),
            (0.0, 30.0, 1684.7588),
            (45.0, 30.0, 1684.7588),
            (90.0, 60.0, 347.8916),
            (135.0, 45.0, 1041.5143),
            (200.0, 20.0, 1902.7470),
            (300.0, 75.0, 200.0462),
        ],
    ),
    (
        "anon_sample07_isym4.ldt",
        4988.0012,
        &[
            (0.0, 0.0, 2729.0616),
            (0.0, 30.0, 2423.7199),
            (45.0, 30.0, 2557.6395),
            (90.0, 60.0, 184.6392),
            (135.0, 45.0, 1454.9265),
            (200.0, 20.0, 2639.0281),
            (300.0, 75.0, 38.1271),
        ],
    ),
    (
        "erco_downlight_lm63-1986_onevalperline.ies",
        1294.0129,
        &[
            (0.0, 0.0, 1500.1344),
            (0.0, 30.0, 630.0777),
            (45.0, 30.0, 630.0777),
            (90.0, 60.0, 0.0149),
            (135.0, 45.0, 41.6667),
            (200.0, 20.0, 1500.5526),
            (300.0, 75.0, 0.0000),
        ],
    ),
    (
        "erco_par38_lm63-1986_quadrant.ies",
        4027.7648,
        &[
            (0.0, 0.0, 56580.0000),
            (0.0, 30.0, 574.0000),
            (45.0, 30.0, 574.0000),
            (90.0, 60.0, 79.9910),
            (135.0, 45.0, 512.0900),
            (200.0, 20.0, 865.1000),
            (300.0, 75.0, 61.9920),
        ],
    ),
    (
        "infinity_arealight_lm63-1995_bilateral.ies",
        6477.7158,
        &[
            (0.0, 0.0, 1789.0000),
            (0.0, 30.0, 1994.0000),
            (45.0, 30.0, 2020.0000),
            (90.0, 60.0, 1759.0000),
            (135.0, 45.0, 1230.0000),
            (200.0, 20.0, 1535.0000),
            (300.0, 75.0, 403.0000),
        ],
    ),
    (
        "infinity_minican_lm63-1995_leading_space.ies",
        2913.0985,
        &[
            (0.0, 0.0, 8183.0000),
            (0.0, 30.0, 992.0000),
            (45.0, 30.0, 992.0000),
            (90.0, 60.0, 8.0000),
            (135.0, 45.0, 119.0000),
            (200.0, 20.0, 2714.0000),
            (300.0, 75.0, 0.0000),
        ],
    ),
    (
        "ledalite_examp1_iesna95_nonstd.ies",
        5294.3455,
        &[
            (0.0, 0.0, 778.4000),
            (0.0, 30.0, 628.4000),
            (45.0, 30.0, 918.8000),
            (90.0, 60.0, 18.7000),
            (135.0, 45.0, 558.6000),
            (200.0, 20.0, 744.6667),
            (300.0, 75.0, 0.0000),
        ],
    ),
    (
        "lithonia_esg_iesna91_commas.ies",
        32.8235,
        &[
            (0.0, 0.0, 166.0000),
            (0.0, 30.0, 7.0000),
            (45.0, 30.0, 6.0000),
            (90.0, 60.0, 3.0000),
            (135.0, 45.0, 4.0000),
            (200.0, 20.0, 13.1111),
            (300.0, 75.0, 1.0000),
        ],
    ),
    (
        "unknown_iesna91_split_header.ies",
        13099.8415,
        &[
            (0.0, 0.0, 8379.0000),
            (0.0, 30.0, 6246.5700),
            (45.0, 30.0, 6246.5700),
            (90.0, 60.0, 244.0000),
            (135.0, 45.0, 3408.6881),
            (200.0, 20.0, 8177.2909),
            (300.0, 75.0, 0.0000),
        ],
    ),
];

// Every real file loads and agrees with the independent reading: candela within 0.5 % (or
// 0.01 cd where the value is near zero) and flux within 1 %, the agreement the issue asks for.
// Both read the same numbers with the same definitions, so any larger gap is a reading bug.
#[test]
fn real_files_match_an_independent_reading() {
    let files: Vec<_> = std::fs::read_dir(real(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".ies") || n.ends_with(".ldt"))
        .collect();
    assert_eq!(files.len(), 10, "{files:?}");
    for name in &files {
        let (_, flux, samples) = INDEPENDENT
            .iter()
            .find(|(n, _, _)| n == name)
            .unwrap_or_else(|| panic!("{name} has no independent reading"));
        let lum = load(&real(name));
        let f = lum.flux_lm();
        assert!(rel(f, *flux) < 0.01, "{name}: flux {f} lm vs {flux} lm");
        for &(h, v, cd) in *samples {
            let got = lum.candela_at(h, v);
            assert!(
                (got - cd).abs() <= 0.005 * cd + 0.01,
                "{name}: cd at ({h}, {v}) = {got} vs {cd}"
            );
        }
    }
}

// The relative files' integrated flux against what their makers state: the ERCO downlight's
// header says "light output ratio: 0.5912" of its 2200 lm; the EULUMDAT files state LORL = 100 %
// (samples 03, 05) and 100 % (07) of the lamp flux. Tolerance 1.5 %: the trapezoid rule on
// 5° (or 2.5°) grids and the makers' own rounding of the LOR.
#[test]
fn integrated_flux_matches_stated_light_output_ratio() {
    let erco = load(&real("erco_downlight_lm63-1986_onevalperline.ies"));
    assert!(
        rel(erco.flux_lm(), 0.5912 * 2200.0) < 0.015,
        "{}",
        erco.flux_lm()
    );
    for (name, lamp_lm) in [
        ("anon_sample03_isym2.ldt", 333.0),
        ("anon_sample05_isym1.ldt", 4828.0),
        ("anon_sample07_isym4.ldt", 4997.0),
    ] {
        let lum = load(&real(name));
        assert!(
            rel(lum.flux_lm(), lamp_lm) < 0.015,
            "{name}: {}",
            lum.flux_lm()
        );
    }
}

// Header facts of the real files (format, type, symmetry, multipliers as stated in them).
#[test]
fn real_file_headers() {
    let l = load(&real("erco_downlight_lm63-1986_onevalperline.ies"));
    assert_eq!(l.format, SourceFormat::Ies(IesVersion::Lm63_1986));
    assert_eq!(l.symmetry, Symmetry::Axial);
    assert_eq!(l.multipliers[0].value, 2.2);
    assert_eq!(l.rated_lamp_lumens, Some(2200.0));
    let l = load(&real("lithonia_esg_iesna91_commas.ies"));
    assert_eq!(l.format, SourceFormat::Ies(IesVersion::Lm63_1991));
    assert_eq!(
        (l.symmetry, l.h_deg.len(), l.v_deg.len()),
        (Symmetry::Quadrant, 5, 37)
    );
    let l = load(&real("infinity_minican_lm63-1995_leading_space.ies"));
    assert_eq!(l.format, SourceFormat::Ies(IesVersion::Lm63_1995));
    let l = load(&real("ledalite_examp1_iesna95_nonstd.ies"));
    assert_eq!(l.lamps[0].count, 2);
    assert!(l.warnings.iter().any(|w| w.contains("IESNA95")));
    let l = load(&real("infinity_arealight_lm63-1995_bilateral.ies"));
    assert_eq!(l.symmetry, Symmetry::BilateralC0C180);
    let l = load(&real("anon_sample07_isym4.ldt"));
    assert_eq!(
        (l.format, l.symmetry),
        (SourceFormat::Eulumdat, Symmetry::Quadrant)
    );
}

// For every file, `intensity_cd` of the direction of (h, v) equals `candela_at(h, v)`: the
// frame conversions of the module docs are inverse to each other (1e-9 relative: rounding).
#[test]
fn direction_and_angles_round_trip() {
    for name in [
        "erco_par38_lm63-1986_quadrant.ies",
        "infinity_arealight_lm63-1995_bilateral.ies",
        "anon_sample03_isym2.ldt",
    ] {
        let lum = load(&real(name));
        for h in [10.0, 100.0, 190.0, 280.0] {
            for v in [5.0, 40.0, 85.0] {
                let d = lum.direction_of(h, v);
                let (a, b) = (lum.intensity_cd(d), lum.candela_at(h, v));
                assert!(
                    (a - b).abs() <= 1e-9 * b.max(1.0),
                    "{name} {h} {v}: {a} {b}"
                );
            }
        }
    }
    // Type C frame: nadir is −y, C0 is +x, C90 is −z.
    let lum = load(&own("tilt_include_lm63_1995.ies"));
    let nadir = lum.direction_of(0.0, 0.0);
    assert!((nadir[1] + 1.0).abs() < 1e-12);
    let c90 = lum.direction_of(90.0, 90.0);
    assert!((c90[2] + 1.0).abs() < 1e-12, "{c90:?}");
}

// Type A with lateral symmetry: I = 100 (1 + sin v)(1 + cos h) stored for h 0..90. The value at
// h = −30 is the value at +30; the −z pole (v = +90, h = 0) is 400 cd, the +z pole 0 cd (the
// type A frame of the docs); flux = 200 (π + 2) = 1028.32 lm, within 0.2 % (5° trapezoid error
// of the cos v weight is 0.06 %, plus 3-decimal rounding).
#[test]
fn type_a_lateral() {
    let l = load(&own("type_a_lateral_lm63_2002.ies"));
    assert_eq!(l.photometric_type, PhotometricType::A);
    assert_eq!(l.symmetry, Symmetry::LateralH);
    let f = |h: f64, v: f64| 100.0 * (1.0 + v.to_radians().sin()) * (1.0 + h.to_radians().cos());
    assert!((l.candela_at(-30.0, 45.0) - f(30.0, 45.0)).abs() < 1e-3);
    assert!((l.intensity_cd([0.0, 0.0, -1.0]) - 400.0).abs() < 1e-3);
    assert!(l.intensity_cd([0.0, 0.0, 1.0]).abs() < 1e-3);
    assert!(
        rel(l.flux_lm(), 200.0 * (PI + 2.0)) < 0.002,
        "{}",
        l.flux_lm()
    );
}

// Type B, absolute photometry, candela multiplier 2: I = 100 (1 + 0.5 sin h)(1 + cos v) with
// the file storing I/2. +x (h = 90) is 300 cd and −x is 100 cd (the type B frame); no rated
// lumens; flux 200 (π + 2) lm within 0.2 % as for type A.
#[test]
fn type_b_absolute_photometry() {
    let l = load(&own("type_b_absolute_lm63_2002.ies"));
    assert_eq!(l.photometric_type, PhotometricType::B);
    assert_eq!(l.symmetry, Symmetry::None);
    assert!(l.absolute);
    assert_eq!(l.rated_lamp_lumens, None);
    assert_eq!(l.lamps[0].lumens, None);
    assert!((l.intensity_cd([1.0, 0.0, 0.0]) - 300.0).abs() < 1e-2);
    assert!((l.intensity_cd([-1.0, 0.0, 0.0]) - 100.0).abs() < 1e-2);
    assert!(
        rel(l.flux_lm(), 200.0 * (PI + 2.0)) < 0.002,
        "{}",
        l.flux_lm()
    );
}

// TILT=INCLUDE (CRLF, commas and blanks mixed, type C over 0..360): the tilt table is read and
// the header numbers after it land in the right fields (1500 lm, 13 planes); candela at stored
// angles is the analytic 100 cos γ (1 + 0.5 cos C) to the file's 3 decimals; C = 345 lies
// between the last plane (330) and 360, which is read from C = 360 itself.
#[test]
fn tilt_include() {
    let l = load(&own("tilt_include_lm63_1995.ies"));
    let t = l.tilt.as_ref().unwrap();
    assert_eq!((t.geometry, t.source.as_str()), (1, "INCLUDE"));
    assert_eq!(t.angles_deg, vec![0.0, 30.0, 60.0, 90.0]);
    assert_eq!(t.factors, vec![1.0, 0.95, 0.8, 0.6]);
    assert_eq!(l.rated_lamp_lumens, Some(1500.0));
    assert_eq!(l.symmetry, Symmetry::None);
    let f = |c: f64, g: f64| 100.0 * g.to_radians().cos() * (1.0 + 0.5 * c.to_radians().cos());
    assert!((l.candela_at(240.0, 40.0) - f(240.0, 40.0)).abs() < 1e-3);
    let mid = 0.5 * (f(330.0, 40.0) + f(360.0, 40.0));
    assert!((l.candela_at(345.0, 40.0) - mid).abs() < 1e-3);
    assert_eq!(l.candela_at(0.0, 120.0), 0.0);
}

// TILT=<file> next to the IES file (LM-63-1986): the tilt file is read; the 1986 ballast-lamp
// factor 0.5 is a multiplier, so 50 cd stored gives 25 cd.
#[test]
fn tilt_file_and_1986_ballast_lamp_factor() {
    let l = load(&own("tilt_file_lm63_1986.ies"));
    assert_eq!(l.format, SourceFormat::Ies(IesVersion::Lm63_1986));
    let t = l.tilt.as_ref().unwrap();
    assert_eq!((t.geometry, t.factors.len()), (2, 3));
    assert!(t.source.ends_with("tilt_file_lamp.tlt"));
    assert!((l.candela_at(123.0, 30.0) - 25.0).abs() < 1e-12);
}

// LM-63-2019, C90..C270: the ballast factor 0.9 scales the table, the file generation type
// 1.1 does not; the C90-C270 mirror gives I(C) = I(180 − C); flux 0.9 · 100 · 4π lm within
// 0.6 % (trapezoid of sin γ on 15° steps is 0.57 % low).
#[test]
fn lm63_2019_file_generation_type_is_not_a_multiplier() {
    let l = load(&own("bilateral_c90_lm63_2019.ies"));
    assert_eq!(l.format, SourceFormat::Ies(IesVersion::Lm63_2019));
    assert_eq!(l.symmetry, Symmetry::BilateralC90C270);
    let m = l
        .multipliers
        .iter()
        .find(|m| m.name == "file generation type")
        .unwrap();
    assert!(!m.applied && m.value == 1.1);
    let f = |c: f64| 0.9 * 100.0 * (1.0 + 0.5 * c.to_radians().sin());
    assert!((l.candela_at(90.0, 30.0) - f(90.0)).abs() < 1e-3);
    assert!((l.candela_at(30.0, 30.0) - f(150.0)).abs() < 1e-3);
    assert!((l.candela_at(300.0, 30.0) - f(240.0)).abs() < 1e-3);
    assert!(
        rel(l.flux_lm(), 0.9 * 100.0 * 4.0 * PI) < 0.006,
        "{}",
        l.flux_lm()
    );
}

// EULUMDAT Isym 0 with decimal commas everywhere: I = 100 cos γ (1 + 0.3 cos C + 0.2 sin C)
// cd/klm with a 1000 lm lamp; exact at stored angles (3 decimals); flux 100 π lm within 0.3 %
// (trapezoid of cos γ sin γ on 5° steps is 0.25 % low).
#[test]
fn eulumdat_isym0_decimal_commas() {
    let l = load(&own("isym0_decimal_comma.ldt"));
    assert_eq!(l.symmetry, Symmetry::None);
    assert_eq!(l.h_deg.len(), 8);
    assert_eq!(l.lamps[0].watts, Some(12.5));
    let f = |c: f64, g: f64| {
        let (c, g) = (c.to_radians(), g.to_radians());
        100.0 * g.cos() * (1.0 + 0.3 * c.cos() + 0.2 * c.sin())
    };
    for (c, g) in [(45.0, 30.0), (315.0, 60.0), (180.0, 0.0)] {
        assert!((l.candela_at(c, g) - f(c, g)).abs() < 1e-3, "{c} {g}");
    }
    assert!(rel(l.flux_lm(), 100.0 * PI) < 0.003, "{}", l.flux_lm());
}

// EULUMDAT Isym 3 (C90..C270 stored) with two lamp sets: the second set's 6 lines are skipped
// correctly (2000 lm of set 1 scales the cd/klm values; set 2 reads 3 lamps, 3000 lm); the
// C90-C270 mirror gives I(45) = I(135) and I(300) = I(240); flux 2π · 200 · ½ lm within 0.3 %.
#[test]
fn eulumdat_isym3_two_lamp_sets() {
    let l = load(&own("isym3_two_lamp_sets.ldt"));
    assert_eq!(l.symmetry, Symmetry::BilateralC90C270);
    assert_eq!(l.lamps.len(), 2);
    assert_eq!((l.lamps[1].count, l.lamps[1].lumens), (3, Some(3000.0)));
    assert_eq!(l.h_deg.first(), Some(&90.0));
    assert_eq!(l.h_deg.last(), Some(&270.0));
    let f = |c: f64, g: f64| 200.0 * g.to_radians().cos() * (1.0 + 0.5 * c.to_radians().sin());
    for (c, g) in [(45.0, 30.0), (135.0, 30.0), (300.0, 60.0), (0.0, 10.0)] {
        assert!((l.candela_at(c, g) - f(c, g)).abs() < 2e-3, "{c} {g}");
    }
    assert!(rel(l.flux_lm(), 200.0 * PI) < 0.003, "{}", l.flux_lm());
}

fn write_temp(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spectrace-photometry-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

// Malformed files: each error names the file, the line and the field.
#[test]
fn malformed_files_name_file_line_and_field() {
    let good_tail = "1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 45 90\n0\n10 5 0\n";
    let cases: &[(&str, String, &str, usize)] = &[
        (
            "no_tilt.ies",
            "IESNA:LM-63-2002\n[TEST] x\n".to_string(),
            "TILT=",
            0,
        ),
        (
            "bad_number.ies",
            "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 4x5 90\n0\n10 5 0\n"
                .to_string(),
            "vertical angle 2",
            5,
        ),
        (
            "bad_type.ies",
            "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 7 2 0 0 0\n1 1 10\n0 45 90\n0\n10 5 0\n"
                .to_string(),
            "photometric type",
            3,
        ),
        (
            "truncated.ies",
            "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 45 90\n0\n10 5\n"
                .to_string(),
            "candela (horizontal angle 1, vertical angle 3)",
            7,
        ),
        (
            "descending.ies",
            "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 90 45\n0\n10 5 0\n"
                .to_string(),
            "vertical angle 3",
            5,
        ),
        (
            "missing_tilt_file.ies",
            format!("IESNA:LM-63-2002\nTILT=nowhere.tlt\n{good_tail}"),
            "TILT=",
            2,
        ),
        (
            "bad_isym.ldt",
            "c\n1\n7\n24\n15\n37\n5\n".to_string(),
            "Isym",
            3,
        ),
    ];
    for (name, text, field, line) in cases {
        let p = write_temp(name, text);
        let e = load_luminaire(&p).expect_err(name);
        let msg = e.to_string();
        assert!(msg.contains(name), "{msg}");
        assert_eq!(e.field, *field, "{msg}");
        if *line > 0 {
            assert_eq!(e.line, Some(*line), "{msg}");
        }
    }
    let e = load_luminaire(Path::new("/nonexistent/x.ies")).unwrap_err();
    assert!(e.to_string().contains("/nonexistent/x.ies"));
}

// Direction sampler on a real quadrant file and the type A/B files: (1) the pdf integrates to 1
// over the sphere (midpoint rule on a 0.125° × 0.5° grid in polar angle and azimuth about −y,
// which the type C files' cell edges fall on; tolerance 0.5 % for the type A/B cells whose
// edges do not); (2) the pdf returned by `sample` equals `pdf` of the sampled direction; (3)
// the estimator I/pdf of the flux over 20000 samples lies within 4 standard errors of the
// table's trapezoid flux plus the gap between the sampler's piecewise-constant total and the
// trapezoid (at most 2 %: the ERCO PAR38 peaks at 56580 cd on 1.25° steps at the nadir, where
// cell means of corners and the trapezoid of I sin γ differ by 1 %).
#[test]
fn direction_sampler_is_normalized_and_unbiased() {
    for path in [
        real("erco_par38_lm63-1986_quadrant.ies"),
        real("anon_sample03_isym2.ldt"),
        own("type_a_lateral_lm63_2002.ies"),
        own("type_b_absolute_lm63_2002.ies"),
    ] {
        let lum = load(&path);
        let s = DirectionSampler::new(&lum).unwrap();
        // (1) ∫ pdf dω over a 1° grid in polar angle θ from −y and azimuth φ.
        let (nt, np) = (1440, 720);
        let (dt, dp) = (PI / nt as f64, 2.0 * PI / np as f64);
        let mut integral = 0.0;
        for i in 0..nt {
            let t = (i as f64 + 0.5) * dt;
            for j in 0..np {
                let p = (j as f64 + 0.5) * dp;
                let d = [t.sin() * p.cos(), -t.cos(), -t.sin() * p.sin()];
                integral += s.pdf(&lum, d) * t.sin() * dt * dp;
            }
        }
        assert!(
            (integral - 1.0).abs() < 0.005,
            "{}: ∫pdf = {integral}",
            path.display()
        );
        // (2) and (3).
        let m = 20_000;
        let (mut sum, mut sum2) = (0.0, 0.0);
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..m {
            let (d, pdf) = s.sample(&lum, rnd(), rnd());
            assert!(pdf > 0.0);
            let p2 = s.pdf(&lum, d);
            assert!(rel(p2, pdf) < 1e-6, "{}: {pdf} vs {p2}", path.display());
            let x = lum.intensity_cd(d) / pdf;
            sum += x;
            sum2 += x * x;
        }
        let mean = sum / m as f64;
        let se = ((sum2 / m as f64 - mean * mean) / m as f64).sqrt();
        let flux = lum.flux_lm();
        let gap = (s.total_lm() - flux).abs();
        assert!(
            gap < 0.02 * flux,
            "{}: {} vs {flux}",
            path.display(),
            s.total_lm()
        );
        assert!(
            (mean - flux).abs() < 4.0 * se + gap + 1e-9 * flux,
            "{}: MC {mean} ± {se} vs {flux}",
            path.display()
        );
    }
}

// `spectrace luminaire --json`: `flux_lm` is the table's flux and `samples` carry {h, v, cd};
// the command itself runs and exits 0 on a real file and 1 on a missing one.
#[test]
fn luminaire_command_json() {
    let path = real("lithonia_esg_iesna91_commas.ies");
    let lum = load(&path);
    let j = spectrace::cli::luminaire::report_json(&lum, "x.ies", &[(0.0, 0.0), (45.0, 30.0)]);
    assert_eq!(j["flux_lm"].as_f64().unwrap(), lum.flux_lm());
    assert_eq!(j["samples"][0]["cd"].as_f64().unwrap(), 166.0);
    assert_eq!(j["samples"][1]["h"].as_f64().unwrap(), 45.0);
    assert_eq!(j["format"], "IES LM-63-1991");
    let file = path.to_str().unwrap();
    let code =
        spectrace::cli::main_with_args(["spectrace", "luminaire", file, "--at", "0,0", "--json"]);
    assert_eq!(code, 0);
    let code = spectrace::cli::main_with_args(["spectrace", "luminaire", "/nonexistent.ies"]);
    assert_eq!(code, 1);
}

// Bad input of every kind gives an error, never a panic: each real file cut short at 40 places
// and with 200 single bytes overwritten (deterministic positions and values) either loads or
// returns an error that names the file.
#[test]
fn damaged_files_never_panic() {
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut rnd = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for e in std::fs::read_dir(real("")).unwrap() {
        let p = e.unwrap().path();
        let ext = p
            .extension()
            .and_then(|e| e.to_str())
            .unwrap_or("")
            .to_string();
        if ext != "ies" && ext != "ldt" {
            continue;
        }
        let bytes = std::fs::read(&p).unwrap();
        let mut variants = Vec::new();
        for k in 1..=40 {
            variants.push(bytes[..bytes.len() * k / 41].to_vec());
        }
        for _ in 0..200 {
            let mut b = bytes.clone();
            let i = (rnd() % b.len() as u64) as usize;
            let choices = b"0123456789 ,.-eE\nx\x00\xff";
            b[i] = choices[(rnd() % choices.len() as u64) as usize];
            variants.push(b);
        }
        for (k, v) in variants.iter().enumerate() {
            let name = format!("damaged_{k}.{ext}");
            let path = write_temp_bytes(&name, v);
            let result = std::panic::catch_unwind(|| {
                if let Ok(l) = load_luminaire(&path) {
                    let _ = l.flux_lm();
                    let _ = l.candela_at(33.0, 44.0);
                    let _ = DirectionSampler::new(&l).map(|s| s.sample(&l, 0.3, 0.7));
                }
                load_luminaire(&path).err().map(|e| e.to_string())
            });
            match result {
                Ok(Some(msg)) => assert!(msg.contains(&name), "{msg}"),
                Ok(None) => {}
                Err(_) => panic!("{} variant {k} panicked", p.display()),
            }
        }
    }
}

fn write_temp_bytes(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("spectrace-damaged-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}
