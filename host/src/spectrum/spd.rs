//! The [`Spd`] trait: a spectral power distribution normalized so that its integral over its
//! range is 1 (seed §2). Absolute power belongs to the light that uses it.
//!
//! Every SPD can also *generate* wavelengths with a density proportional to itself, which is
//! how light subpaths pick their wavelength. Delta lines (lasers, idealized emission lines) carry
//! probability mass instead of density and are reported separately.

use super::{SampledSpectrum, SampledWavelengths, LANES};

/// One wavelength drawn from an SPD.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpdSample {
    /// Wavelength in nm.
    pub lambda: f64,
    /// Density in 1/nm for a continuous draw, or the discrete probability (unitless) when
    /// `is_delta` is true.
    pub pdf: f64,
    /// True when the draw picked a delta line.
    pub is_delta: bool,
}

/// A delta component of an SPD: all of `weight` (fraction of the total power) at `lambda`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DeltaLine {
    /// Wavelength in nm.
    pub lambda: f64,
    /// Fraction of the SPD's total power in this line (unitless, ≤ 1).
    pub weight: f64,
}

/// A normalized spectral power distribution. Implemented by the built-ins ([`super::BuiltinSpd`])
/// and by the plugin adapter for SPDs supplied by plugins.
pub trait Spd: Send + Sync + std::fmt::Debug {
    /// Continuous part of the normalized SPD at `lambda_nm`, in 1/nm; 0 outside the range.
    /// Delta lines contribute nothing here (see [`Spd::delta_lines`]).
    fn value(&self, lambda_nm: f64) -> f64;

    /// Draw a wavelength with `u ∈ [0,1)` with probability proportional to the SPD.
    fn sample(&self, u: f64) -> SpdSample;

    /// Density (1/nm) with which [`Spd::sample`] produces a continuous `lambda_nm`. For the
    /// built-ins this equals [`Spd::value`] because sampling is exact.
    fn pdf(&self, lambda_nm: f64) -> f64;

    /// `(min, max)` wavelengths in nm outside which the SPD is zero.
    fn range(&self) -> (f64, f64);

    /// Delta lines and their power fractions; empty for a purely continuous SPD.
    fn delta_lines(&self) -> Vec<DeltaLine> {
        Vec::new()
    }

    /// True when the SPD has any delta line, so estimators must treat matching draws as discrete.
    fn is_delta(&self) -> bool {
        !self.delta_lines().is_empty()
    }
}

/// The SPD at each lane (what a light multiplies by its power), in the lane's own measure:
/// a lane whose f32 wavelength is exactly that of one of `spd`'s delta lines is a *discrete*
/// draw of that line and gets the line's power fraction (unitless; its pdf is then the
/// line's discrete probability, see [`is_line_lane`]); every other lane gets the continuous
/// part (1/nm). Without the first case a laser or a `line:589` lamp would be black.
pub fn spd_at(spd: &dyn Spd, lambda: &SampledWavelengths) -> SampledSpectrum {
    let lines = spd.delta_lines();
    SampledSpectrum(std::array::from_fn(|i| {
        let l = lambda.lambda[i];
        let mass = line_mass_at_lane(&lines, l);
        if mass > 0.0 {
            mass as f32
        } else {
            spd.value(l as f64) as f32
        }
    }))
}

/// Sum of the power fractions of the `lines` whose wavelength rounds to exactly `lambda_nm`
/// (f32, as lanes store it); 0 when the lane is on no line.
pub fn line_mass_at_lane(lines: &[DeltaLine], lambda_nm: f32) -> f64 {
    lines
        .iter()
        .filter(|l| l.lambda as f32 == lambda_nm)
        .map(|l| l.weight)
        .sum()
}

/// True when a lane at `lambda_nm` counts as a discrete draw of one of `lines` (see
/// [`spd_at`]).
pub fn is_line_lane(lines: &[DeltaLine], lambda_nm: f32) -> bool {
    lines.iter().any(|l| l.lambda as f32 == lambda_nm)
}

/// A continuously drawn wavelength moved off the delta lines: if `lambda_nm` happens to round
/// to a line's f32 wavelength (probability about 10⁻⁷ per lane), it becomes the next f32 up,
/// so that only discrete draws land on a line and [`spd_at`] never mistakes a density draw for
/// a line (which would weight it by the line's mass over a density: a firefly). Moving the
/// draw by one ulp (6·10⁻⁵ nm at 589 nm) changes no continuous estimate measurably.
pub fn off_lines(lambda_nm: f32, lines: &[DeltaLine]) -> f32 {
    if is_line_lane(lines, lambda_nm) {
        lambda_nm.next_up()
    } else {
        lambda_nm
    }
}

/// Probability mass of the delta lines of `spd` at exactly `lambda_nm` (sum of their weights).
pub fn delta_mass_at(spd: &dyn Spd, lambda_nm: f64) -> f64 {
    spd.delta_lines()
        .iter()
        .filter(|l| l.lambda == lambda_nm)
        .map(|l| l.weight)
        .sum()
}

/// Compile-time check that the lane count used by `spd_at` matches the rest of the crate.
const _: () = assert!(LANES >= 1);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::parse_spd_spec;

    // A lane exactly on a line gets the line's power fraction (0.25 of this mix, exact in
    // binary), a lane elsewhere the continuous part (0.75 × D65's density, compared to 1e-6
    // relative for f32 rounding); `off_lines` moves a continuous draw off a line by one ulp.
    #[test]
    fn lanes_on_a_line_get_its_mass() {
        let s = parse_spd_spec("0.75*d65 + 0.25*line:589").unwrap();
        let w = SampledWavelengths {
            lambda: [589.0, 500.0, 589.0f32.next_up(), 600.0],
            pdf: [1.0; LANES],
            lanes: crate::spectrum::LaneMask::ALL,
        };
        let v = spd_at(&s, &w);
        assert_eq!(v[0], 0.25);
        for i in 1..LANES {
            let want = s.value(w.lambda[i] as f64) as f32;
            assert!(
                (v[i] - want).abs() <= 1e-6 * want,
                "lane {i}: {} vs {want}",
                v[i]
            );
            assert!(v[i] < 0.01, "lane {i} took the line's mass");
        }
        let lines = s.delta_lines();
        assert_eq!(off_lines(589.0, &lines), 589.0f32.next_up());
        assert_eq!(off_lines(500.0, &lines), 500.0);
    }
}
