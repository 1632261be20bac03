//! ANSI/IES TM-30-18/20 colour fidelity Rf and gamut Rg (Rf is the CIE 224:2017 index): the 99
//! colour evaluation samples (`host/data/cie/ces99_cie224_1nm.csv`) under the source and under
//! its reference, compared in CAM02-UCS.
//!
//! Steps: CCT by Ohno's method (CIE 1931 2°, 380–780 nm); reference a blackbody up to 4000 K,
//! CIE daylight from 5000 K, and between the two a mix of both, each normalized to Y = 1,
//! weighted (CCT − 4000)/1000 towards daylight; sample XYZ with the CIE 1964 10° observer on
//! 380–780 nm (1 nm, the CIE 224 table at 1 nm), white Y = 100; CIECAM02 with
//! L_A = 100 cd/m², Y_b = 20, average surround, complete adaptation (D = 1); CAM02-UCS (J′,
//! a′, b′). Rf = 10 ln(exp((100 − 6.73 ΔĒ)/10) + 1) of the mean ΔE′; Rg = 100 × area of the
//! polygon of the 16 hue-bin mean (a′, b′) under the source / under the reference, the samples
//! binned by their hue under the reference.

use super::cct::{cct_duv, uv_1960};
use super::cri::interp;
use super::daylight::daylight_spd;
use super::observer::Observer;
use super::CieObserverKind;
use crate::spectrum::blackbody::planck;
use crate::spectrum::Spd;

/// TM-30's wavelength range, nm.
const RANGE_NM: (f64, f64) = (380.0, 780.0);
/// CIE 224:2017 scale factor of Rf.
const RF_SCALE: f64 = 6.73;

/// TM-30 figures of a source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tm30 {
    /// CCT (K) used for the reference (380–780 nm).
    pub cct_k: f64,
    /// Fidelity index Rf (0–100).
    pub rf: f64,
    /// Gamut index Rg (100 = as saturated as the reference).
    pub rg: f64,
}

fn samples() -> &'static (Vec<f64>, Vec<Vec<f64>>) {
    static TABLE: std::sync::OnceLock<(Vec<f64>, Vec<Vec<f64>>)> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let t = crate::spectrum::csv_table::parse_csv_table(
            include_str!("../../data/cie/ces99_cie224_1nm.csv"),
            "data/cie/ces99_cie224_1nm.csv",
        )
        .expect("the bundled CES table is valid");
        (t.wavelengths, t.columns)
    })
}

/// Σ S(λ)·ρ(λ)·cmf(λ) on 380–780 nm at 1 nm, with the delta lines of `source` in that range.
fn tristimulus(
    source: &dyn Fn(f64) -> f64,
    lines: &[(f64, f64)],
    rho: &dyn Fn(f64) -> f64,
    obs: &dyn Observer,
) -> [f64; 3] {
    let mut acc = [0.0; 3];
    let mut add = |l: f64, w: f64| {
        let c = obs.xyz_bar(l);
        for k in 0..3 {
            acc[k] += w * c[k];
        }
    };
    let n = (RANGE_NM.1 - RANGE_NM.0) as usize;
    for i in 0..=n {
        let l = RANGE_NM.0 + i as f64;
        add(l, source(l) * rho(l));
    }
    for &(l, w) in lines {
        if (RANGE_NM.0..=RANGE_NM.1).contains(&l) {
            add(l, w * rho(l));
        }
    }
    acc
}

/// CIECAM02 (J, M, h in degrees) of `xyz` under white `xyz_w` (both with Y_w = 100), L_A = 100,
/// Y_b = 20, average surround (F = 1, c = 0.69, N_c = 1), D = 1; then CAM02-UCS (J′, a′, b′).
fn cam02_ucs(xyz: [f64; 3], xyz_w: [f64; 3]) -> [f64; 4] {
    const CAT02: [[f64; 3]; 3] = [
        [0.7328, 0.4296, -0.1624],
        [-0.7036, 1.6975, 0.0061],
        [0.0030, 0.0136, 0.9834],
    ];
    const HPE: [[f64; 3]; 3] = [
        [0.38971, 0.68898, -0.07868],
        [-0.22981, 1.18340, 0.04641],
        [0.0, 0.0, 1.0],
    ];
    let (la, yb, c, nc) = (100.0f64, 20.0f64, 0.69f64, 1.0f64);
    let mul = |m: &[[f64; 3]; 3], v: [f64; 3]| {
        [0, 1, 2].map(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
    };
    let cat_inv = super::matrix3::inverse(&CAT02).expect("CAT02 is invertible");
    let k = 1.0 / (5.0 * la + 1.0);
    let k4 = k.powi(4);
    let fl = 0.2 * k4 * (5.0 * la) + 0.1 * (1.0 - k4).powi(2) * (5.0 * la).cbrt();
    let n = yb / xyz_w[1];
    let nbb = 0.725 * (1.0 / n).powf(0.2);
    let z = 1.48 + n.sqrt();
    let rgb_w = mul(&CAT02, xyz_w);
    let post = |xyz: [f64; 3]| {
        let rgb = mul(&CAT02, xyz);
        let rgb_c = [0, 1, 2].map(|i| xyz_w[1] / rgb_w[i] * rgb[i]);
        let rgb_p = mul(&HPE, mul(&cat_inv, rgb_c));
        rgb_p.map(|x| {
            let f = (fl * x.abs() / 100.0).powf(0.42);
            x.signum() * 400.0 * f / (f + 27.13) + 0.1
        })
    };
    let aw = post(xyz_w);
    let a_w = (2.0 * aw[0] + aw[1] + aw[2] / 20.0 - 0.305) * nbb;
    let p = post(xyz);
    let a = p[0] - 12.0 * p[1] / 11.0 + p[2] / 11.0;
    let b = (p[0] + p[1] - 2.0 * p[2]) / 9.0;
    let h = b.atan2(a).to_degrees().rem_euclid(360.0);
    let et = 0.25 * ((h.to_radians() + 2.0).cos() + 3.8);
    let achromatic = (2.0 * p[0] + p[1] + p[2] / 20.0 - 0.305) * nbb;
    let j = 100.0 * (achromatic / a_w).max(0.0).powf(c * z);
    let t = (50000.0 / 13.0 * nc * nbb * et * (a * a + b * b).sqrt())
        / (p[0] + p[1] + 21.0 / 20.0 * p[2]);
    let chroma = t.powf(0.9) * (j / 100.0).sqrt() * (1.64 - 0.29f64.powf(n)).powf(0.73);
    let m = chroma * fl.powf(0.25);
    let jp = 1.7 * j / (1.0 + 0.007 * j);
    let mp = (1.0 + 0.0228 * m).ln() / 0.0228;
    [jp, mp * h.to_radians().cos(), mp * h.to_radians().sin(), h]
}

/// TM-30 Rf and Rg of `source`; `None` without a CCT in 1000–25000 K.
pub fn tm30(source: &dyn Spd) -> Option<Tm30> {
    let lines: Vec<(f64, f64)> = source
        .delta_lines()
        .iter()
        .map(|d| (d.lambda, d.weight))
        .collect();
    let test = |l: f64| source.value(l);
    let obs2 = CieObserverKind::Cie1931_2.get();
    let obs10 = CieObserverKind::Cie1964_10.get();
    let one = |_: f64| 1.0;
    let (u, v) = uv_1960(tristimulus(&test, &lines, &one, obs2));
    let (cct, _) = cct_duv(u, v)?;
    if !(1000.0..=25_000.0).contains(&cct) {
        return None;
    }
    // Reference, each part normalized to Y = 1 (CIE 1931 2°) before mixing.
    let bb = move |l: f64| planck(l, cct);
    let dl = daylight_spd(cct);
    let y_of = |f: &dyn Fn(f64) -> f64| tristimulus(f, &[], &one, obs2)[1];
    let (ybb, ydl) = (y_of(&bb), y_of(&dl));
    let m = ((cct - 4000.0) / 1000.0).clamp(0.0, 1.0);
    let reference = move |l: f64| (1.0 - m) * bb(l) / ybb + m * dl(l) / ydl;
    let white_t = tristimulus(&test, &lines, &one, obs10);
    let white_r = tristimulus(&reference, &[], &one, obs10);
    let (kt, kr) = (100.0 / white_t[1], 100.0 / white_r[1]);
    let (ws, cols) = samples();
    let mut de_sum = 0.0;
    let mut bins_t = [[0.0f64; 2]; 16];
    let mut bins_r = [[0.0f64; 2]; 16];
    let mut counts = [0usize; 16];
    for col in cols {
        let rho = |l: f64| interp(ws, col, l);
        let xt = tristimulus(&test, &lines, &rho, obs10).map(|x| x * kt);
        let xr = tristimulus(&reference, &[], &rho, obs10).map(|x| x * kr);
        let ct = cam02_ucs(xt, white_t.map(|x| x * kt));
        let cr = cam02_ucs(xr, white_r.map(|x| x * kr));
        de_sum +=
            ((ct[0] - cr[0]).powi(2) + (ct[1] - cr[1]).powi(2) + (ct[2] - cr[2]).powi(2)).sqrt();
        let bin = ((cr[3] / 22.5).floor() as usize).min(15);
        bins_t[bin][0] += ct[1];
        bins_t[bin][1] += ct[2];
        bins_r[bin][0] += cr[1];
        bins_r[bin][1] += cr[2];
        counts[bin] += 1;
    }
    let de = de_sum / cols.len() as f64;
    let rf = 10.0 * ((100.0 - RF_SCALE * de) / 10.0).exp().ln_1p();
    let area = |bins: &[[f64; 2]; 16]| {
        let pts: Vec<[f64; 2]> = (0..16)
            .filter(|&i| counts[i] > 0)
            .map(|i| [bins[i][0] / counts[i] as f64, bins[i][1] / counts[i] as f64])
            .collect();
        (0..pts.len())
            .map(|i| {
                let (p, q) = (pts[i], pts[(i + 1) % pts.len()]);
                0.5 * (p[0] * q[1] - p[1] * q[0])
            })
            .sum::<f64>()
    };
    let rg = 100.0 * area(&bins_t) / area(&bins_r);
    Some(Tm30 { cct_k: cct, rf, rg })
}
