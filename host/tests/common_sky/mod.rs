//! The CIE standard general sky formula (ISO 15469:2004 / CIE S 011/E:2003) written out for the
//! tests, independently of the renderer's code.
#![allow(dead_code)]

use std::f64::consts::{FRAC_PI_2, PI};

/// The standard's parameters (a, b, c, d, e) of types 1–15, typed in from ISO 15469 Table 2
/// (independently of the renderer's table).
pub const TYPES: [[f64; 5]; 15] = [
    [4.0, -0.70, 0.0, -1.0, 0.00],
    [4.0, -0.70, 2.0, -1.5, 0.15],
    [1.1, -0.80, 0.0, -1.0, 0.00],
    [1.1, -0.80, 2.0, -1.5, 0.15],
    [0.0, -1.00, 0.0, -1.0, 0.00],
    [0.0, -1.00, 2.0, -1.5, 0.15],
    [0.0, -1.00, 5.0, -2.5, 0.30],
    [0.0, -1.00, 10.0, -3.0, 0.45],
    [-1.0, -0.55, 2.0, -1.5, 0.15],
    [-1.0, -0.55, 5.0, -2.5, 0.30],
    [-1.0, -0.55, 10.0, -3.0, 0.45],
    [-1.0, -0.32, 10.0, -3.0, 0.45],
    [-1.0, -0.32, 16.0, -3.0, 0.30],
    [-1.0, -0.15, 16.0, -3.0, 0.30],
    [-1.0, -0.15, 24.0, -2.8, 0.15],
];

/// L/Lz by the standard's formula: element at zenith angle z, azimuth az; sun at zs, azs.
pub fn standard(t: &[f64; 5], z: f64, az: f64, zs: f64, azs: f64) -> f64 {
    let [a, b, c, d, e] = *t;
    let phi = |z: f64| 1.0 + a * (b / z.cos()).exp();
    let f = |chi: f64| 1.0 + c * ((d * chi).exp() - (d * FRAC_PI_2).exp()) + e * chi.cos().powi(2);
    let chi = (zs.cos() * z.cos() + zs.sin() * z.sin() * (az - azs).cos())
        .clamp(-1.0, 1.0)
        .acos();
    f(chi) * phi(z) / (f(zs) * phi(0.0))
}

/// ∫ L/Lz cos Z dω by a Gauss-free midpoint rule on 400 × 1600 cells (independent of the
/// renderer's quadrature; converged to 1e-6).
pub fn standard_horizontal(t: &[f64; 5], zs: f64) -> f64 {
    let (n, m) = (400, 1600);
    let mut s = 0.0;
    for i in 0..n {
        let z = (i as f64 + 0.5) / n as f64 * FRAC_PI_2;
        let mut row = 0.0;
        for j in 0..m {
            row += standard(t, z, 2.0 * PI * (j as f64 + 0.5) / m as f64, zs, 0.0);
        }
        s += row * z.cos() * z.sin();
    }
    s * (FRAC_PI_2 / n as f64) * (2.0 * PI / m as f64)
}

/// `K_m ∫ spd V dλ` of an SPD spec (lm/W), 1 nm sum over the CIE 1931 2° table.
pub fn efficacy(spec: &str) -> f64 {
    use spectrace::color::{CieObserverKind, Observer};
    use spectrace::spectrum::Spd;
    let spd = spectrace::spectrum::parse_spd_spec(spec).unwrap();
    let obs = CieObserverKind::Cie1931_2.get();
    let (lo, hi) = obs.range();
    let mut s = 0.0;
    let mut l = lo.ceil();
    while l <= hi {
        s += spd.value(l) * obs.xyz_bar(l)[1];
        l += 1.0;
    }
    spectrace::sensor::KM_LM_PER_W * s
}
