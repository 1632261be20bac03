//! A plugin material's re-radiation as the host's
//! [`Reradiation`]: what `integrator::fluorescence` shifts wavelengths with, so the integrators
//! treat a plugin's fluorescent material exactly as the built-in `fluorescent` one.
//!
//! Every call's result is checked before the renderer sees it ([`super::checked`]'s rules, and
//! the ones fluorescence adds: no reflectance above 1, no re-radiated fraction above 1, no
//! anti-Stokes emission, draws on the right side of the given wavelength with a density > 0). A
//! refused result or a failed call reads as "nothing" (0 or no draw) and is counted per object
//! and reason in the shared `PluginFaults`, which the render summary reports.
//!
//! When it is built, [`PluginReradiation::new`] also checks energy over the whole range the
//! material declares: at every excitation wavelength (1 nm steps) ρ(λᵢ) plus the re-radiated
//! fraction — the larger of what the plugin reports and ∫ r(λᵢ → λₒ) dλₒ summed by the host
//! (0.5 nm midpoints) — must not exceed 1 by more than [`ENERGY_TOLERANCE`]; a material that
//! would create energy, or answers NaN or negative values there, is refused with the
//! wavelength named.

use super::checked::{self, Reason};
use super::faults::Origin;
use crate::spectrum::reradiation::Reradiation;
use spectrace_plugin_api::abi::std_types::{ROption, RResult};
use spectrace_plugin_api::reradiation::ReradiationBox;
use spectrace_plugin_api::{PluginError, WavelengthDraw};
use std::fmt;

/// How far above 1 the albedo ρ + ∫ r dλₒ may be found at construction. The host's own sum is a
/// 0.5 nm midpoint rule: exact for data constant over cells whose edges fall on whole or half
/// nanometres (tabulated matrices), and within about 0.1% for smooth emission bands of 10 nm
/// or more; 1% leaves room for that and for a plugin's own rounding while refusing any real
/// energy gain.
pub const ENERGY_TOLERANCE: f64 = 0.01;

/// Excitation wavelengths outside this range (nm) are not scanned at construction: no
/// observer or bundled spectrum reaches beyond it.
const SCAN_NM: (f64, f64) = (200.0, 2000.0);

/// A plugin material's re-radiation face as host [`Reradiation`] data (see the module docs).
pub struct PluginReradiation {
    rr: ReradiationBox,
    range: (f64, f64),
    origin: Origin,
}

impl fmt::Debug for PluginReradiation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "PluginReradiation({})", self.origin.label)
    }
}

fn value(v: &f64) -> Result<(), Reason> {
    checked::scalar(*v)
}

fn at_most_one(v: &f64) -> Result<(), Reason> {
    checked::scalar(*v)?;
    if *v <= 1.0 + 1e-9 {
        Ok(())
    } else {
        Err("fraction above 1 (creates energy)")
    }
}

/// A draw: wavelength in range and on the right side of `other` (`above`: longer), density > 0.
fn draw(d: &ROption<WavelengthDraw>, other: f64, above: bool) -> Result<(), Reason> {
    let ROption::RSome(d) = d else {
        return Ok(());
    };
    checked::wavelength(d.lambda_nm)?;
    if above && !(d.lambda_nm > other) {
        return Err("emission drawn at or below the excitation wavelength (anti-Stokes)");
    }
    if !above && !(d.lambda_nm < other) {
        return Err("excitation drawn at or above the emission wavelength (anti-Stokes)");
    }
    if d.pdf.is_finite() && d.pdf > 0.0 {
        Ok(())
    } else {
        Err("wavelength density NaN, infinite or not > 0")
    }
}

impl PluginReradiation {
    /// Wrap `rr` and check it (its range, and energy over it); `origin` names the plugin object
    /// in every message. An error says what is wrong and where.
    pub fn new(rr: ReradiationBox, origin: Origin) -> Result<Self, String> {
        let who = &origin.label;
        let range = match rr.range_nm() {
            RResult::ROk([lo, hi]) if lo.is_finite() && hi.is_finite() && lo < hi && lo > 0.0 => {
                (lo, hi)
            }
            RResult::ROk([lo, hi]) => {
                return Err(format!(
                    "{who}: its re-radiation range [{lo}, {hi}] nm is not an interval of \
                     positive wavelengths"
                ))
            }
            RResult::RErr(e) => return Err(format!("{who}: range_nm: {e}")),
        };
        let made = Self { rr, range, origin };
        made.check_energy()?;
        Ok(made)
    }

    /// The energy check described in the module docs.
    fn check_energy(&self) -> Result<(), String> {
        let who = &self.origin.label;
        let call = |what: &str, li: f64, r: RResult<f64, PluginError>| -> Result<f64, String> {
            match r {
                RResult::ROk(v) if v.is_finite() && v >= 0.0 => Ok(v),
                RResult::ROk(v) => Err(format!(
                    "{who}: {what} at {li} nm is {v}: re-radiation values must be finite and ≥ 0"
                )),
                RResult::RErr(e) => Err(format!("{who}: {what} at {li} nm: {e}")),
            }
        };
        let (lo, hi) = (
            self.range.0.max(SCAN_NM.0).floor(),
            self.range.1.min(SCAN_NM.1),
        );
        let mut li = lo;
        while li <= hi {
            let rho = call("reflectance", li, self.rr.reflectance(li))?;
            let reported = call("reradiated_fraction", li, self.rr.reradiated_fraction(li))?;
            let mut summed = 0.0;
            let mut lo_nm = li + 0.25;
            while lo_nm < hi + 0.5 {
                summed += call("reradiation", li, self.rr.reradiation(li, lo_nm))? * 0.5;
                lo_nm += 0.5;
            }
            let albedo = rho + reported.max(summed);
            if albedo > 1.0 + ENERGY_TOLERANCE {
                return Err(format!(
                    "{who}: its re-radiation creates energy: at {li} nm excitation it returns \
                     {albedo:.4} of the incident power (reflectance {rho:.4}, re-radiated \
                     {:.4}: reported {reported:.4}, ∫ r dλₒ {summed:.4}); at most 1 is allowed",
                    reported.max(summed)
                ));
            }
            li += 1.0;
        }
        Ok(())
    }

    /// What [`WavelengthDraw`] the plugin gave, checked; `above`: an emission draw.
    fn drawn(
        &self,
        r: RResult<ROption<WavelengthDraw>, PluginError>,
        other: f64,
        above: bool,
    ) -> Option<(f64, f64)> {
        self.origin
            .checked(r, |d| draw(d, other, above))
            .and_then(|d| d.into_option())
            .map(|d| (d.lambda_nm, d.pdf))
    }
}

impl Reradiation for PluginReradiation {
    fn reflectance(&self, lambda_nm: f64) -> f64 {
        (self.origin)
            .checked(self.rr.reflectance(lambda_nm), at_most_one)
            .unwrap_or(0.0)
    }

    fn reradiation(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> f64 {
        let stokes = lambda_o_nm > lambda_i_nm;
        (self.origin)
            .checked(self.rr.reradiation(lambda_i_nm, lambda_o_nm), |v| {
                value(v)?;
                if !stokes && *v > 0.0 {
                    Err("re-radiation at or below the excitation wavelength (anti-Stokes)")
                } else {
                    Ok(())
                }
            })
            .unwrap_or(0.0)
    }

    fn reradiated_fraction(&self, lambda_i_nm: f64) -> f64 {
        (self.origin)
            .checked(self.rr.reradiated_fraction(lambda_i_nm), at_most_one)
            .unwrap_or(0.0)
    }

    fn sample_emission(&self, lambda_i_nm: f64, u: f64) -> Option<(f64, f64)> {
        self.drawn(self.rr.sample_emission(lambda_i_nm, u), lambda_i_nm, true)
    }

    fn emission_pdf(&self, lambda_i_nm: f64, lambda_o_nm: f64) -> f64 {
        (self.origin)
            .checked(self.rr.emission_pdf(lambda_i_nm, lambda_o_nm), |p| {
                checked::density(*p)
            })
            .unwrap_or(0.0)
    }

    fn excitation_fraction(&self, lambda_o_nm: f64) -> f64 {
        (self.origin)
            .checked(self.rr.excitation_fraction(lambda_o_nm), value)
            .unwrap_or(0.0)
    }

    fn sample_excitation(&self, lambda_o_nm: f64, u: f64) -> Option<(f64, f64)> {
        self.drawn(
            self.rr.sample_excitation(lambda_o_nm, u),
            lambda_o_nm,
            false,
        )
    }

    fn excitation_pdf(&self, lambda_o_nm: f64, lambda_i_nm: f64) -> f64 {
        (self.origin)
            .checked(self.rr.excitation_pdf(lambda_o_nm, lambda_i_nm), |p| {
                checked::density(*p)
            })
            .unwrap_or(0.0)
    }

    fn range(&self) -> (f64, f64) {
        self.range
    }
}
