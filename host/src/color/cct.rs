//! Correlated colour temperature (CCT) and distance from the Planckian locus (Duv) by Ohno's
//! method (Y. Ohno, "Practical use and calculation of CCT and Duv", LEUKOS 10(1), 2014, the
//! method of his 2013 papers): the chromaticity in CIE 1960 (u, v) is compared with a table
//! of Planckian (u, v), refined as a cascade around the nearest entry, and the last table is
//! solved by the triangular solution when |Duv| < 0.002 and by the parabolic one otherwise.
//!
//! The Planckian locus uses the CIE 1931 2° observer on its 1 nm grid and Planck's law with
//! the SI 2019 constants (c₂ = 1.438777 × 10⁻² m·K).

use super::observer::{integration_grid, Observer};
use super::CieObserverKind;
use crate::spectrum::blackbody::planck;

/// Temperatures the search covers, K: the range Ohno's tables cover.
pub const CCT_RANGE_K: (f64, f64) = (1000.0, 100_000.0);

/// Largest |Duv| for which a CCT means anything (CIE 15:2004 section 9.5 and ANSI C78.377
/// use 0.05 as the limit of "white" light).
pub const MAX_ABS_DUV: f64 = 0.05;

/// CIE 1960 UCS (u, v) of XYZ; `(0, 0)` for black.
pub fn uv_1960(xyz: [f64; 3]) -> (f64, f64) {
    let d = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];
    if !(d > 0.0) {
        return (0.0, 0.0);
    }
    (4.0 * xyz[0] / d, 6.0 * xyz[1] / d)
}

/// CIE 1960 (u, v) of a blackbody at `kelvin` for the CIE 1931 2° observer.
pub fn planck_uv(kelvin: f64) -> (f64, f64) {
    let obs = CieObserverKind::Cie1931_2.get();
    let mut xyz = [0.0; 3];
    for l in integration_grid(obs) {
        let p = planck(l, kelvin);
        let c = obs.xyz_bar(l);
        for k in 0..3 {
            xyz[k] += p * c[k];
        }
    }
    uv_1960(xyz)
}

/// CCT (K) and Duv of a chromaticity in CIE 1960 (u, v); Duv is positive above the locus
/// (greener), negative below (pinker). `None` when the nearest Planckian point lies at an end
/// of [`CCT_RANGE_K`] or |Duv| > [`MAX_ABS_DUV`]: the light is too far from white for a CCT.
pub fn cct_duv(u: f64, v: f64) -> Option<(f64, f64)> {
    let (t, duv) = cct_duv_unchecked(u, v)?;
    (duv.abs() <= MAX_ABS_DUV).then_some((t, duv))
}

/// [`cct_duv`] without the |Duv| limit.
fn cct_duv_unchecked(u: f64, v: f64) -> Option<(f64, f64)> {
    let dist = |t: f64| {
        let (pu, pv) = planck_uv(t);
        ((u - pu).powi(2) + (v - pv).powi(2)).sqrt()
    };
    // Coarse table: 1 % steps over the range.
    let (lo, hi) = CCT_RANGE_K;
    let n = ((hi / lo).ln() / 1.01f64.ln()).ceil() as usize;
    let mut ts: Vec<f64> = (0..=n)
        .map(|i| lo * (hi / lo).powf(i as f64 / n as f64))
        .collect();
    let mut ds: Vec<f64> = ts.iter().map(|&t| dist(t)).collect();
    let mut m = argmin(&ds);
    if m == 0 || m == ts.len() - 1 {
        return None;
    }
    // Cascade: 10 geometric steps between the neighbours of the nearest entry, 4 times
    // (each narrows the step 5×, ending at about 1.6e-5 relative).
    for _ in 0..4 {
        let (a, b) = (ts[m - 1], ts[m + 1]);
        ts = (0..=10)
            .map(|i| a * (b / a).powf(i as f64 / 10.0))
            .collect();
        ds = ts.iter().map(|&t| dist(t)).collect();
        m = argmin(&ds).clamp(1, 9);
    }
    let (t0, t1, t2) = (ts[m - 1], ts[m], ts[m + 1]);
    let (d0, d1, d2) = (ds[m - 1], ds[m], ds[m + 1]);
    // Triangular solution on the chord between the neighbours.
    let (u0, v0) = planck_uv(t0);
    let (u2, v2) = planck_uv(t2);
    let l = ((u2 - u0).powi(2) + (v2 - v0).powi(2)).sqrt();
    let x = (d0 * d0 - d2 * d2 + l * l) / (2.0 * l);
    let t_tri = t0 + (t2 - t0) * x / l;
    let v_chord = v0 + (v2 - v0) * x / l;
    let sign = if v - v_chord >= 0.0 { 1.0 } else { -1.0 };
    let duv_tri = sign * (d0 * d0 - x * x).max(0.0).sqrt();
    if duv_tri.abs() < 0.002 {
        return Some((t_tri, duv_tri));
    }
    // Parabolic solution through the three nearest entries.
    let xx = (t2 - t1) * (t0 - t2) * (t1 - t0);
    let a = (t0 * (d2 - d1) + t1 * (d0 - d2) + t2 * (d1 - d0)) / xx;
    let b = -(t0 * t0 * (d2 - d1) + t1 * t1 * (d0 - d2) + t2 * t2 * (d1 - d0)) / xx;
    let c = -(d0 * (t2 - t1) * t1 * t2 + d1 * (t0 - t2) * t0 * t2 + d2 * (t1 - t0) * t0 * t1) / xx;
    let t = -b / (2.0 * a);
    let duv = sign * (a * t * t + b * t + c);
    Some((t, duv))
}

fn argmin(xs: &[f64]) -> usize {
    let mut best = 0;
    for (i, &x) in xs.iter().enumerate() {
        if x < xs[best] {
            best = i;
        }
    }
    best
}
