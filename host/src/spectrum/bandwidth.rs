//! How narrow an SPD is: its *equivalent width* W = (∫S dλ)² / ∫S² dλ (nm), the width of the
//! box with the same peak-weighted power. For a normalised SPD W = 1/E_S[S(λ)], the inverse
//! of the SPD's mean value at its own draws, which [`equivalent_width_nm`] estimates from
//! equally spaced quantiles of the SPD's inverse CDF (exact sampling; no grid to miss a spike).
//!
//! Why it matters: a wavelength sampler that ignores the SPD (visible importance, at most
//! 0.0036/nm) lands in a band of width W with probability ≈ 0.0036·W per lane, so an SPD much
//! narrower than [`NARROWBAND_WIDTH_NM`] is found by a camera path only rarely and then as a
//! firefly: such lights need their wavelengths drawn from their own spectrum.

use super::spd::Spd;

/// Below this equivalent width (nm) an SPD counts as narrowband: a visible-importance lane
/// hits it with probability under 0.0036 × 10 ≈ 4% per lane.
pub const NARROWBAND_WIDTH_NM: f64 = 10.0;

/// Quantiles used by [`equivalent_width_nm`].
const PROBES: usize = 4096;

/// Equivalent width (nm) of the continuous part of `spd`; 0 for an SPD made only of delta
/// lines, `f64::INFINITY` when the continuous part evaluates to 0 at all of its draws.
pub fn equivalent_width_nm(spd: &dyn Spd) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    for k in 0..PROBES {
        let s = spd.sample((k as f64 + 0.5) / PROBES as f64);
        if s.is_delta {
            continue;
        }
        sum += spd.value(s.lambda);
        n += 1;
    }
    if n == 0 {
        return 0.0;
    }
    let mean = sum / n as f64;
    if mean > 0.0 {
        1.0 / mean
    } else {
        f64::INFINITY
    }
}

/// True when `spd` has delta lines or a continuous part narrower than
/// [`NARROWBAND_WIDTH_NM`]: visible-importance wavelength sampling would (almost) miss it.
pub fn is_narrowband(spd: &dyn Spd) -> bool {
    spd.is_delta() || equivalent_width_nm(spd) < NARROWBAND_WIDTH_NM
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::parse_spd_spec;

    // Equivalent width of a box of width w is w exactly, of a Gaussian of standard deviation σ
    // it is 2σ√π. Tolerance 1% (quantile-probe estimate with 4096 probes on a smooth or flat
    // density; the tabulated Gaussian's own discretisation is far finer).
    #[test]
    fn widths_of_known_shapes() {
        let boxy = crate::spectrum::TabulatedSpd::new(
            "box",
            &[500.0, 520.0],
            &[1.0, 1.0],
            crate::spectrum::Interpolation::Linear,
        )
        .unwrap();
        let w = equivalent_width_nm(&boxy);
        assert!((w / 20.0 - 1.0).abs() < 0.01, "{w}");
        let sigma = 2.0;
        let gauss = crate::spectrum::TabulatedSpd::from_fn("g", 560.0, 620.0, 0.05, |l| {
            (-0.5 * ((l - 590.0) / sigma).powi(2)).exp()
        })
        .unwrap();
        let w = equivalent_width_nm(&gauss);
        let want = 2.0 * sigma * std::f64::consts::PI.sqrt();
        assert!((w / want - 1.0).abs() < 0.01, "{w} vs {want}");
        assert!(is_narrowband(&gauss));
        assert!(is_narrowband(&parse_spd_spec("line:589").unwrap()));
        assert!(!is_narrowband(&parse_spd_spec("d65").unwrap()));
    }
}
