//! Spectrum → CIE XYZ, the way CIE 15 prescribes for tabulated data (and issue 3 fixes): the
//! spectrum (and illuminant) are linearly interpolated onto the observer's 1 nm grid, taken as 0
//! outside their own range, multiplied and summed (Δλ = 1 nm).

use super::observer::{integration_grid, Observer};
use crate::spectrum::Spd;

/// Chromaticity `(x, y) = (X, Y)/(X+Y+Z)`; `(0, 0)` for black.
pub fn chromaticity(xyz: [f64; 3]) -> (f64, f64) {
    let s = xyz[0] + xyz[1] + xyz[2];
    if s == 0.0 || !s.is_finite() {
        return (0.0, 0.0);
    }
    (xyz[0] / s, xyz[1] / s)
}

/// XYZ from chromaticity `(x, y)` at luminance `Y`.
pub fn xyz_from_xy(x: f64, y: f64, luminance: f64) -> [f64; 3] {
    if y == 0.0 {
        return [0.0; 3];
    }
    [x * luminance / y, luminance, (1.0 - x - y) * luminance / y]
}

/// `Σ f(λ)·[x̄,ȳ,z̄](λ)` over the observer grid.
fn sum_weighted(obs: &dyn Observer, f: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut acc = [0.0; 3];
    for l in integration_grid(obs) {
        let w = f(l);
        if w != 0.0 {
            let c = obs.xyz_bar(l);
            for k in 0..3 {
                acc[k] += w * c[k];
            }
        }
    }
    acc
}

/// Unnormalized tristimulus integral of an emission SPD: the continuous part summed on the grid
/// plus each delta line's weight times the CMFs at its wavelength.
pub fn spd_tristimulus(spd: &dyn Spd, obs: &dyn Observer) -> [f64; 3] {
    let mut acc = sum_weighted(obs, |l| spd.value(l));
    for line in spd.delta_lines() {
        let c = obs.xyz_bar(line.lambda);
        for k in 0..3 {
            acc[k] += line.weight * c[k];
        }
    }
    acc
}

/// XYZ of an emitter, scaled so that Y = 100. All zeros if the SPD is invisible to `obs`.
pub fn emitter_xyz(spd: &dyn Spd, obs: &dyn Observer) -> [f64; 3] {
    let t = spd_tristimulus(spd, obs);
    if t[1].is_nan() || t[1] <= 0.0 {
        return [0.0; 3];
    }
    t.map(|v| 100.0 * v / t[1])
}

/// XYZ of a reflectance (any function of nm, usually in [0,1]) under an illuminant, with the
/// CIE factor `k = 100 / Σ S ȳ` so the perfect white has Y = 100. Delta lines of the illuminant
/// count as in [`spd_tristimulus`]. All zeros if the illuminant is invisible to `obs`.
pub fn reflectance_xyz(
    reflectance: impl Fn(f64) -> f64,
    illuminant: &dyn Spd,
    obs: &dyn Observer,
) -> [f64; 3] {
    let white = spd_tristimulus(illuminant, obs);
    if white[1].is_nan() || white[1] <= 0.0 {
        return [0.0; 3];
    }
    let k = 100.0 / white[1];
    let mut acc = sum_weighted(obs, |l| reflectance(l) * illuminant.value(l));
    for line in illuminant.delta_lines() {
        let c = obs.xyz_bar(line.lambda);
        for i in 0..3 {
            acc[i] += reflectance(line.lambda) * line.weight * c[i];
        }
    }
    acc.map(|v| k * v)
}
