//! CIE 13.3-1995 colour rendering index: the general index Ra (mean of R1–R8) and the special
//! indices R1–R14, from the 14 test colour samples of CIE 13.3 (`host/data/cie/tcs_cie13_3.csv`).
//!
//! Steps as CIE 13.3 prescribes: CCT of the source (here by Ohno's method, [`super::cct`]);
//! reference illuminant a blackbody below 5000 K and CIE daylight at and above; each sample's
//! CIE 1960 (u, v) and Y under both (Y = 100 for the white); von Kries adaptation of the test
//! side in CIE 13.3's (c, d) form; U*V*W* (CIE 1964) differences; Rᵢ = 100 − 4.6 ΔEᵢ.
//! CIE 1931 2° observer, on its 1 nm grid.

use super::cct::{cct_duv, uv_1960};
use super::daylight::daylight_spd;
use super::xyz::{reflectance_xyz, spd_tristimulus};
use super::CieObserverKind;
use crate::spectrum::{Spd, TabulatedSpd};

/// CCT at and above which the reference illuminant is CIE daylight (CIE 13.3).
pub const DAYLIGHT_FROM_K: f64 = 5000.0;

/// The CIE 13.3 result for a source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColorRendering {
    /// CCT (K) used to pick the reference.
    pub cct_k: f64,
    /// General colour rendering index, the mean of R1–R8.
    pub ra: f64,
    /// Special indices R1–R14.
    pub r: [f64; 14],
}

/// The 14 test colour samples: wavelengths (nm) and 14 radiance-factor columns.
pub(crate) fn test_colour_samples() -> &'static (Vec<f64>, Vec<Vec<f64>>) {
    static TABLE: std::sync::OnceLock<(Vec<f64>, Vec<Vec<f64>>)> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let t = crate::spectrum::csv_table::parse_csv_table(
            include_str!("../../data/cie/tcs_cie13_3.csv"),
            "data/cie/tcs_cie13_3.csv",
        )
        .expect("the bundled CIE 13.3 sample table is valid");
        (t.wavelengths, t.columns)
    })
}

/// Linear interpolation in a tabulated function; 0 outside its range.
pub(crate) fn interp(ws: &[f64], vs: &[f64], l: f64) -> f64 {
    if l < ws[0] || l > ws[ws.len() - 1] {
        return 0.0;
    }
    let i = ws.partition_point(|&w| w <= l).clamp(1, ws.len() - 1);
    let t = (l - ws[i - 1]) / (ws[i] - ws[i - 1]);
    vs[i - 1] + (vs[i] - vs[i - 1]) * t
}

/// The CIE 13.3 reference illuminant for a CCT: a blackbody below 5000 K, CIE daylight above.
pub fn cri_reference(cct_k: f64) -> TabulatedSpd {
    let r = if cct_k < DAYLIGHT_FROM_K {
        TabulatedSpd::blackbody(cct_k, 300.0, 830.0)
    } else {
        TabulatedSpd::from_fn("daylight", 300.0, 830.0, 1.0, daylight_spd(cct_k))
    };
    r.expect("a reference for a CCT in range is valid")
}

/// CIE 13.3 colour rendering of `source`; `None` when it has no CCT (see [`cct_duv`]) or no
/// power visible to the CIE 1931 2° observer.
pub fn color_rendering(source: &dyn Spd) -> Option<ColorRendering> {
    let obs = CieObserverKind::Cie1931_2.get();
    let white_t = spd_tristimulus(source, obs);
    if !(white_t[1] > 0.0) {
        return None;
    }
    let (ut, vt) = uv_1960(white_t);
    let (cct, _) = cct_duv(ut, vt)?;
    let reference = cri_reference(cct);
    let (ur, vr) = uv_1960(spd_tristimulus(&reference, obs));
    let c = |u: f64, v: f64| (4.0 - u - 10.0 * v) / v;
    let d = |u: f64, v: f64| (1.708 * v + 0.404 - 1.481 * u) / v;
    let (cr, dr) = (c(ur, vr), d(ur, vr));
    let (ct, dt) = (c(ut, vt), d(ut, vt));
    let (ws, cols) = test_colour_samples();
    let mut r = [0.0; 14];
    for (i, col) in cols.iter().enumerate().take(14) {
        let rho = |l: f64| interp(ws, col, l);
        let xyz_t = reflectance_xyz(rho, source, obs);
        let xyz_r = reflectance_xyz(rho, &reference, obs);
        // Test side, adapted to the reference white.
        let (u, v) = uv_1960(xyz_t);
        let (ci, di) = (cr / ct * c(u, v), dr / dt * d(u, v));
        let den = 16.518 + 1.481 * ci - di;
        let (ua, va) = ((10.872 + 0.404 * ci - 4.0 * di) / den, 5.520 / den);
        let uvw = |y: f64, u: f64, v: f64| {
            let w = 25.0 * y.cbrt() - 17.0;
            [13.0 * w * (u - ur), 13.0 * w * (v - vr), w]
        };
        let a = uvw(xyz_t[1], ua, va);
        let (u2, v2) = uv_1960(xyz_r);
        let b = uvw(xyz_r[1], u2, v2);
        let de = ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
        r[i] = 100.0 - 4.6 * de;
    }
    let ra = r[..8].iter().sum::<f64>() / 8.0;
    Some(ColorRendering { cct_k: cct, ra, r })
}
