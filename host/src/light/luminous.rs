//! Radiometric ↔ photometric values of a light: a photometric parameter (lm, cd, lx, cd/m²)
//! as its radiometric equivalent, and the render summary's statement of a light's flux (W and
//! lm), both with the luminous efficacy of the light's spectrum,
//! K = Km · ∫ S(λ) V(λ) dλ in lm/W ([`crate::photometry::efficacy`]: Km = 683.002 lm/W, V = ȳ of
//! the CIE 1931 2° observer, the 1 nm table in `host/data/cie/`).

use crate::color::{CieObserverKind, Observer};
pub use crate::photometry::efficacy::{luminous_efficacy_lm_per_w, KM_LM_PER_W};
use crate::spectrum::Spd;

/// V(λ), the CIE 1931 2° ȳ (dimensionless, 0 outside 360–830 nm).
pub fn photopic_v(lambda_nm: f64) -> f64 {
    CieObserverKind::Cie1931_2.get().xyz_bar(lambda_nm)[1]
}

/// A photometric value given for a light, converted to its radiometric equivalent with the
/// light's spectrum: `value / K` (e.g. lm → W, cd → W/sr, lx → W/m², cd/m² → W/(m²·sr)). An
/// error when the spectrum has no visible part (K = 0), which no photometric value can
/// describe.
pub fn radiometric_from_photometric(param: &str, value: f64, spd: &dyn Spd) -> Result<f64, String> {
    if !(value.is_finite() && value >= 0.0) {
        return Err(format!(
            "parameter `{param}`: must be finite and ≥ 0, got {value}"
        ));
    }
    let k = luminous_efficacy_lm_per_w(spd);
    if !(k > 0.0) {
        return Err(format!(
            "parameter `{param}`: the light's spectrum has no visible part (luminous efficacy \
             0 lm/W), so a photometric value cannot set its power; give the radiometric value"
        ));
    }
    Ok(value / k)
}

/// `x` with 4 significant digits, in exponent form below 1e-3 and from 1e6.
fn sig4(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let mag = x.abs().log10().floor();
    if !(-3.0..6.0).contains(&mag) {
        return format!("{x:.3e}");
    }
    let decimals = (3.0 - mag).max(0.0) as usize;
    format!("{x:.decimals$}")
}

/// How the render summary states a light's emission: `123.4 W, 1.573e4 lm` (its luminous
/// flux from its spectrum), or, when the scene's emission is in relative units, its share of
/// the scene's power (`relative emission: 42.0% of the scene's power`), never watts.
/// `spd` is `None` for a beams-only light, whose spectrum is not probed (its beams carry their
/// own wavelengths, and a plugin built against API 0.1.0 may not offer wavelength calls).
pub fn flux_text(power_w: f64, spd: Option<&dyn Spd>, relative: bool, total_w: f64) -> String {
    if relative {
        let share = if total_w > 0.0 {
            power_w / total_w
        } else {
            0.0
        };
        return format!(
            "relative emission: {:.1}% of the scene's power",
            100.0 * share
        );
    }
    match spd {
        Some(spd) => format!(
            "{} W, {} lm",
            sig4(power_w),
            sig4(power_w * luminous_efficacy_lm_per_w(spd))
        ),
        None => format!(
            "{} W (beams carry their own wavelengths: no lm without probing them)",
            sig4(power_w)
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::parse_spd_spec;

    // A 555 nm line: V(555) = 1.0000 in the CIE 1931 table, so K = Km within the table's
    // 4-digit rounding (1e-4); a 1000 lm line is 1000/683.002 W.
    // The summary's numbers: 4 significant digits, exponent form outside 1e-3..1e6; relative
    // emission never prints watts.
    #[test]
    fn flux_text_forms() {
        let s = parse_spd_spec("line:555").unwrap();
        let t = flux_text(1.0, Some(&s), false, 1.0);
        assert!(t.starts_with("1.000 W, 683.0 lm"), "{t}");
        assert_eq!(sig4(140655392.0), "1.407e8");
        let r = flux_text(3.0, Some(&s), true, 4.0);
        assert_eq!(r, "relative emission: 75.0% of the scene's power");
        let b = flux_text(2.0, None, false, 2.0);
        assert!(
            b.starts_with("2.000 W (beams") && !b.contains(" lm,"),
            "{b}"
        );
    }

    #[test]
    fn line_at_555_nm_has_the_maximum_efficacy() {
        let s = parse_spd_spec("line:555").unwrap();
        let k = luminous_efficacy_lm_per_w(&s);
        assert!((k / KM_LM_PER_W - 1.0).abs() < 1e-4, "{k}");
        let w = radiometric_from_photometric("flux_lm", 1000.0, &s).unwrap();
        assert!((w - 1000.0 / k).abs() < 1e-12);
    }

    // A 2700 K blackbody (`blackbody:T` is tabulated on 360–830 nm and normalised there):
    // its efficacy equals Km · ∫B·V / ∫B over 360–830 nm computed here straight from Planck's
    // law with a 0.1 nm trapezoid (independent of the SPD code; same V table). 1e-4 covers the
    // SPD's own tabulation and the 1 nm sum (measured 2e-6). A spectrum with no visible part is refused.
    #[test]
    fn blackbody_matches_planck() {
        for t in [2700.0, 6500.0] {
            let k = luminous_efficacy_lm_per_w(&parse_spd_spec(&format!("blackbody:{t}")).unwrap());
            let planck = |nm: f64| {
                let l = nm * 1e-9;
                l.powi(-5) / ((1.438_776_877e-2 / (l * t)).exp() - 1.0)
            };
            let (mut num, mut den) = (0.0, 0.0);
            let n = 4700;
            for i in 0..=n {
                let nm = 360.0 + 470.0 * i as f64 / n as f64;
                let w = if i == 0 || i == n { 0.5 } else { 1.0 };
                num += w * planck(nm) * photopic_v(nm);
                den += w * planck(nm);
            }
            let expect = KM_LM_PER_W * num / den;
            println!("{t} K: {k} lm/W, Planck {expect} lm/W");
            assert!(
                (k / expect - 1.0).abs() < 1e-4,
                "{t} K: {k} vs {expect} lm/W"
            );
        }
        let uv = parse_spd_spec("line:300").unwrap();
        let e = radiometric_from_photometric("flux_lm", 1.0, &uv).unwrap_err();
        assert!(e.contains("no visible part"), "{e}");
    }
}
