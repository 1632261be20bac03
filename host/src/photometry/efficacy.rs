//! Luminous efficacy of radiation: how many lumens one watt of a normalised SPD gives, so that a
//! photometric table (cd, lm) and a spectrum (1/nm) make a radiometric light (W/sr/nm, W).
//!
//! K = Km · ∫ S(λ) ȳ(λ) dλ with Km = 683 lm/W (CIE 15: the maximum luminous efficacy for
//! photopic vision at 555 nm / 540 THz) and ȳ of the CIE 1931 2° observer, summed on its 1 nm grid
//! like every other tristimulus integral of the host ([`crate::color::xyz::spd_tristimulus`]).

use crate::color::xyz::spd_tristimulus;
use crate::color::CieObserverKind;
use crate::spectrum::Spd;

/// Maximum luminous efficacy for photopic vision, lm/W.
pub const KM_LM_PER_W: f64 = 683.0;

/// Lumens per watt of radiant flux distributed as the normalised `spd` (lm/W); 0 when the
/// spectrum is invisible.
pub fn luminous_efficacy_lm_per_w(spd: &dyn Spd) -> f64 {
    let y = spd_tristimulus(spd, CieObserverKind::Cie1931_2.get())[1];
    if y.is_finite() && y > 0.0 {
        KM_LM_PER_W * y
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::parse_spd_spec;

    /// A 555 nm line gives Km·ȳ(555 nm) = 683 lm/W (ȳ(555) = 1.0000 in the CIE table, so
    /// 1e-4); the equal-energy SPD, 1/(hi − lo) per nm, gives 683·Σȳ/(hi − lo) (the same sum
    /// written out; 1% covers the grid's end points, which the two sums may count differently).
    #[test]
    fn efficacy_of_a_line_and_of_equal_energy() {
        let line = parse_spd_spec("line:555").unwrap();
        assert!((luminous_efficacy_lm_per_w(&line) / 683.0 - 1.0).abs() < 1e-4);
        let e = parse_spd_spec("e").unwrap();
        let k = luminous_efficacy_lm_per_w(&e);
        let (lo, hi) = e.range();
        let obs = CieObserverKind::Cie1931_2.get();
        use crate::color::Observer;
        let want = 683.0 * obs.integral_y() / (hi - lo);
        assert!((k / want - 1.0).abs() < 1e-2, "{k} vs {want}");
    }
}
