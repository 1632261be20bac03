//! XYZ of a fluorescent sample under an illuminant, split into the reflected and the
//! fluoresced (re-radiated) light, with the same normalisation as for a reflectance: the
//! perfect white diffuser under the illuminant has Y = 100 (CIE factor k = 100/Σ S ȳ).
//!
//! Reflected: `k Σ ρ(λ) S(λ) c̄(λ)` on the observer's 1 nm grid (as [`reflectance_xyz`]).
//! Fluoresced: `k Σ_λₒ c̄(λₒ) ∫ S(λᵢ) r(λᵢ → λₒ) dλᵢ`, the inner integral by the midpoint
//! rule on 1 nm cells over the sample's excitation range (plus each delta line of the
//! illuminant times r at its wavelength).

use super::observer::{integration_grid, Observer};
use super::xyz::{reflectance_xyz, spd_tristimulus};
use crate::spectrum::reradiation::Reradiation;
use crate::spectrum::Spd;

/// Cell width (nm) of the excitation integral.
const EXCITATION_STEP_NM: f64 = 1.0;

/// The colour of a fluorescent sample (tristimulus values, perfect white Y = 100).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FluorescentXyz {
    /// Reflected + fluoresced.
    pub total: [f64; 3],
    /// Light leaving at the wavelength it arrived with.
    pub reflected: [f64; 3],
    /// Light re-radiated at longer wavelengths.
    pub fluoresced: [f64; 3],
}

/// XYZ of `sample` under `illuminant` for `obs` (see the module docs); all zeros when the
/// illuminant is invisible to `obs`.
pub fn fluorescent_xyz(
    sample: &dyn Reradiation,
    illuminant: &dyn Spd,
    obs: &dyn Observer,
) -> FluorescentXyz {
    let white = spd_tristimulus(illuminant, obs);
    if !(white[1] > 0.0) {
        return FluorescentXyz {
            total: [0.0; 3],
            reflected: [0.0; 3],
            fluoresced: [0.0; 3],
        };
    }
    let k = 100.0 / white[1];
    let reflected = reflectance_xyz(|l| sample.reflectance(l), illuminant, obs);
    let (lo, _) = sample.range();
    let lines = illuminant.delta_lines();
    let mut fluoresced = [0.0; 3];
    for lambda_o in integration_grid(obs) {
        let mut s = 0.0;
        let mut li = lo + 0.5 * EXCITATION_STEP_NM;
        while li < lambda_o {
            s += illuminant.value(li) * sample.reradiation(li, lambda_o) * EXCITATION_STEP_NM;
            li += EXCITATION_STEP_NM;
        }
        for line in &lines {
            s += line.weight * sample.reradiation(line.lambda, lambda_o);
        }
        if s != 0.0 {
            let c = obs.xyz_bar(lambda_o);
            for (f, ci) in fluoresced.iter_mut().zip(c) {
                *f += k * s * ci;
            }
        }
    }
    FluorescentXyz {
        total: std::array::from_fn(|i| reflected[i] + fluoresced[i]),
        reflected,
        fluoresced,
    }
}
