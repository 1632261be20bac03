//! Mitsuba 3 spectra as spectrace values, in Mitsuba's spectral-mode units.
//!
//! - Reflectances (unitless): a number stays a number, `rgb` becomes `(rgb: (r, g, b))` (the
//!   same Jakob–Hanika sigmoid uplift Mitsuba uses; spectrace clamps to [0, 1]), a `spectrum`
//!   becomes its `(nm, value)` list.
//! - Emission (radiance W/(m²·sr·nm), intensity W/(sr·nm), irradiance W/(m²·nm)): always an
//!   absolute `(nm, value)` table on [`GRID`]. Mitsuba's spectral variants read an `rgb` or a
//!   plain `float` emission with the illuminant method: `rgb` → `2m · S(rgb / 2m)(λ) · D65'(λ)`,
//!   m the largest component, S the sigmoid uplift; `float v` → `v · D65'(λ)`; D65' is CIE D65
//!   scaled so that its film luminance `∫D65'ȳ / ∫ȳ` is 1 (checked against Mitsuba 3.9's
//!   `d65` values in the tests). Both renderers' films use `XYZ = ∫L x̄ȳz̄ dλ / ∫ȳ dλ`, so a
//!   table carried over unchanged gives the same pixel values.
//! - A `spectrum` given as `λ:v` pairs is zero outside its wavelengths (as in Mitsuba).

use crate::color::{uplift_srgb, CieObserverKind};
use crate::spectrum::Spd;

/// Wavelength grid of emission tables: Mitsuba's spectral range 360–830 nm, every 5 nm.
pub const GRID: (f64, f64, f64) = (360.0, 830.0, 5.0);

/// The grid's wavelengths.
pub fn grid() -> impl Iterator<Item = f64> {
    let (a, b, s) = GRID;
    let n = ((b - a) / s).round() as usize;
    (0..=n).map(move |i| a + s * i as f64)
}

/// D65 scaled to unit film luminance (Mitsuba's `d65` spectrum in its spectral variants).
pub fn d65_unit(lambda_nm: f64) -> f64 {
    static K: std::sync::OnceLock<(crate::spectrum::TabulatedSpd, f64)> =
        std::sync::OnceLock::new();
    let (d65, k) = K.get_or_init(|| {
        let d65 = crate::spectrum::bundled::bundled_spd("d65")
            .expect("d65 is bundled")
            .expect("the bundled d65 table parses");
        let (start, cmf) = CieObserverKind::Cie1931_2.get().grid();
        let (mut yd, mut y) = (0.0, 0.0);
        for (i, c) in cmf.iter().enumerate() {
            let l = start + i as f64;
            yd += d65.value(l) * c[1];
            y += c[1];
        }
        (d65, y / yd)
    });
    d65.value(lambda_nm) * k
}

/// Mitsuba's spectral-mode reading of an `rgb` emission, as a table on [`GRID`].
pub fn rgb_emission_table(rgb: [f64; 3]) -> Vec<(f64, f64)> {
    let m = rgb[0].max(rgb[1]).max(rgb[2]);
    if !(m > 0.0) {
        return grid().map(|l| (l, 0.0)).collect();
    }
    let s = 2.0 * m;
    let curve = uplift_srgb(rgb.map(|c| c.max(0.0) / s));
    grid()
        .map(|l| (l, s * curve.value(l) * d65_unit(l)))
        .collect()
}

/// [`rgb_emission_table`] at one wavelength.
pub fn rgb_emission(rgb: [f64; 3], lambda_nm: f64) -> f64 {
    let m = rgb[0].max(rgb[1]).max(rgb[2]);
    if !(m > 0.0) {
        return 0.0;
    }
    let s = 2.0 * m;
    s * uplift_srgb(rgb.map(|c| c.max(0.0) / s)).value(lambda_nm) * d65_unit(lambda_nm)
}

/// Linear interpolation in sorted `(nm, value)` pairs; zero outside them.
pub fn interpolate(pairs: &[(f64, f64)], lambda_nm: f64) -> f64 {
    if pairs.is_empty() || lambda_nm < pairs[0].0 || lambda_nm > pairs[pairs.len() - 1].0 {
        return 0.0;
    }
    let i = pairs.partition_point(|p| p.0 <= lambda_nm);
    if i == 0 {
        return pairs[0].1;
    }
    if i >= pairs.len() {
        return pairs[pairs.len() - 1].1;
    }
    let (a, b) = (pairs[i - 1], pairs[i]);
    let t = (lambda_nm - a.0) / (b.0 - a.0);
    a.1 + t * (b.1 - a.1)
}

/// Planck's spectral radiance of a black body, W/(m²·sr·nm).
pub fn planck(kelvin: f64, lambda_nm: f64) -> f64 {
    const H: f64 = 6.626_070_15e-34;
    const C: f64 = 299_792_458.0;
    const KB: f64 = 1.380_649e-23;
    let l = lambda_nm * 1e-9;
    2.0 * H * C * C / l.powi(5) / ((H * C / (l * KB * kelvin)).exp() - 1.0) * 1e-9
}

/// ∫ table dλ (trapezoids), table units × nm.
pub fn integral(table: &[(f64, f64)]) -> f64 {
    table
        .windows(2)
        .map(|w| 0.5 * (w[0].1 + w[1].1) * (w[1].0 - w[0].0))
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    // Mitsuba 3.9.1 (scalar_spectral) evaluated a `constant` emitter with these radiances at
    // these wavelengths (probe run once, numbers copied here): `float 2.0`, `rgb (1,1,1)` and
    // `rgb (0.8, 0.3, 0.1)`. D65' agrees to 0.3% (the D65 table and CMF sampling differ
    // slightly); the coloured rgb to 2% (the uplift's own fit against Mitsuba's tabulated one).
    #[test]
    fn matches_mitsuba_spectral_emission() {
        let nm = [400.0, 450.0, 500.0, 560.0, 600.0, 650.0, 700.0];
        let white = [
            0.83593, 1.18193, 1.10461, 1.01013, 0.90918, 0.80837, 0.72334,
        ];
        let orange = [
            0.07122, 0.14692, 0.21492, 0.37066, 0.52158, 0.74142, 0.87596,
        ];
        for i in 0..nm.len() {
            let d = d65_unit(nm[i]);
            assert!(
                (d / white[i] - 1.0).abs() < 3e-3,
                "D65' at {}: {d} vs {}",
                nm[i],
                white[i]
            );
            let w = rgb_emission([1.0, 1.0, 1.0], nm[i]);
            assert!((w / white[i] - 1.0).abs() < 3e-3, "white at {}: {w}", nm[i]);
            let o = rgb_emission([0.8, 0.3, 0.1], nm[i]);
            assert!(
                (o / orange[i] - 1.0).abs() < 0.02,
                "orange at {}: {o} vs {}",
                nm[i],
                orange[i]
            );
        }
    }

    // Planck at 5000 K, 500 nm: 1.2098e13 W/(m²·sr·m) = 12098 W/(m²·sr·nm) (textbook value).
    #[test]
    fn planck_value() {
        let v = planck(5000.0, 500.0);
        assert!((v / 12_098.0 - 1.0).abs() < 1e-3, "{v}");
    }
}
