//! The 24 ColorChecker patches under D65 (CIE 1931 2°) against XYZ computed independently here.
//!
//! Independent method: read the CSV files with a separate minimal reader, then integrate with
//! the trapezoid rule on the 5 nm grid: D65 and the CMFs taken at their own table entries on
//! that grid, the 10 nm reflectance linearly interpolated to the 5 nm midpoints; k = 100 / the
//! same trapezoid of S·ȳ over 360–780 nm (D65's table ends at 780). The library instead
//! interpolates everything onto the 1 nm grid and sums (CIE 15 practice). The two quadratures
//! differ by the CMF curvature inside 5 nm steps, measured at ≤ 0.04 here, so the tolerance
//! 0.05 (Y = 100 units) asked for by issue 3 is met with a little room.

use spectrace::color::{reflectance_xyz, CieObserverKind};
use spectrace::spectrum::{parse_spd_spec, SpectralCurve};

/// Rows of numbers from a CSV text: skip `#` lines and any row whose first field is not a number.
fn rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let f: Result<Vec<f64>, _> = l.split(',').map(|v| v.trim().parse::<f64>()).collect();
            f.ok()
        })
        .collect()
}

fn lookup(table: &[Vec<f64>], lambda: f64, col: usize) -> f64 {
    table
        .iter()
        .find(|r| r[0] == lambda)
        .map(|r| r[col])
        .unwrap_or_else(|| panic!("no row at {lambda}"))
}

#[test]
fn colorchecker_under_d65_matches_trapezoid() {
    let cmf = rows(include_str!("../data/cie/cie1931_2deg.csv"));
    let d65 = rows(include_str!("../data/illuminants/d65.csv"));
    let cc = rows(include_str!(
        "../data/reflectance/colorchecker_babelcolor_average.csv"
    ));
    assert_eq!(cc.len(), 36);
    let trapezoid = |lo: i32, hi: i32, f: &dyn Fn(f64) -> f64| -> f64 {
        (lo..=hi)
            .step_by(5)
            .map(|l| {
                let w = if l == lo || l == hi { 2.5 } else { 5.0 };
                w * f(l as f64)
            })
            .sum()
    };
    let k = 100.0 / trapezoid(360, 780, &|l| lookup(&d65, l, 1) * lookup(&cmf, l, 2));
    let refl = |patch: usize, l: f64| -> f64 {
        let i = ((l - 380.0) / 10.0).floor() as usize;
        if l == 730.0 {
            return cc[35][patch];
        }
        let s = (l - cc[i][0]) / 10.0;
        (1.0 - s) * cc[i][patch] + s * cc[i + 1][patch]
    };

    let d65_spd = parse_spd_spec("d65").unwrap();
    let obs = CieObserverKind::Cie1931_2.get();
    let mut worst: f64 = 0.0;
    for patch in 1..=24 {
        let expected: Vec<f64> = (0..3)
            .map(|c| {
                k * trapezoid(380, 730, &|l| {
                    refl(patch, l) * lookup(&d65, l, 1) * lookup(&cmf, l, c + 1)
                })
            })
            .collect();
        let curve = SpectralCurve::colorchecker(&patch.to_string()).unwrap();
        let got = reflectance_xyz(|l| curve.value(l), &d65_spd, obs);
        for c in 0..3 {
            let d = (got[c] - expected[c]).abs();
            worst = worst.max(d);
            assert!(
                d < 0.05,
                "patch {patch} channel {c}: library {} vs trapezoid {}",
                got[c],
                expected[c]
            );
        }
    }
    eprintln!("worst |ΔXYZ| over 24 patches: {worst:.4}");
}
