//! Wavelength shifting at fluorescent surfaces, shared by pt, lt and bdpt (after Mojzík, Fichet
//! and Wilkie 2018, who extend hero-wavelength sampling with a wavelength change at a
//! fluorescent vertex).
//!
//! A fluorescent surface (a material whose [`Material::reradiation`] is `Some`) scatters
//! diffusely in both its parts: light of power 1 arriving at λᵢ leaves as ρ(λᵢ) at λᵢ and as
//! r(λᵢ → λₒ) dλₒ at longer λₒ, both with a cosine lobe. So at such a vertex the direction and
//! the wavelength are sampled independently: the direction from the cosine lobe with f = 1/π
//! ([`UNIT_LOBE`]), the wavelength by the functions here, whose per-lane weight is carried in
//! the path throughput. The choice is made when the path arrives at the vertex, so next-event
//! estimation, connections and the continuation from that vertex all use the new wavelength.
//!
//! - Camera paths (radiance, the path arrives with the observed λₒ): keep λₒ (weight ρ) or
//!   draw an excitation λᵢ < λₒ with [`Reradiation::sample_excitation`] (weight r/pdf).
//! - Light paths (importance, the path arrives with λᵢ): keep λᵢ or draw λₒ > λᵢ with
//!   [`Reradiation::sample_emission`].
//!
//! pt and lt choose per lane with probability `P = ρ/(ρ + F)` of keeping (F the re-radiated
//! part in that direction), so with exact sampling every lane's weight is the same whatever
//! the choice: `ρ + ∫ r dλᵢ` on camera paths (may exceed 1: many excitation wavelengths feed
//! one emission wavelength) and the albedo `ρ + ∫ r dλₒ ≤ 1` on light paths (energy is never
//! created). Lanes are independent after a shift: each has its own wavelength, while the film
//! keeps weighing the wavelength the camera observed (pt) or the one that reaches the camera
//! (lt). bdpt needs one choice per vertex for its MIS weights: [`keep_probability`] over the
//! lanes, then [`shift_camera_group`] (see `bdpt.rs`).

use crate::material::{
    same_hemisphere, sample_cosine_hemisphere, BsdfSample, Material, MaterialFlags, ShadingContext,
    TransportMode,
};
use crate::spectrum::reradiation::Reradiation;
use crate::spectrum::wavelength_sampling::rotated;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};
use std::f32::consts::FRAC_1_PI;

/// Bounds of bdpt's keep probability where both choices are possible: a choice taken with
/// probability below 0.1 would multiply its weight by more than 10.
const KEEP_BOUNDS: (f32, f32) = (0.1, 0.9);

/// The direction part of a fluorescent surface once its spectral weight is in the throughput:
/// a two-sided Lambertian of albedo 1 (f = 1/π on the side of `wo`), cosine-sampled exactly
/// like [`crate::material::fluorescent::Fluorescent`].
#[derive(Debug, Clone, Copy)]
pub struct UnitLobe;

/// The one [`UnitLobe`].
pub static UNIT_LOBE: UnitLobe = UnitLobe;

impl Material for UnitLobe {
    fn flags(&self) -> MaterialFlags {
        MaterialFlags::DIFFUSE | MaterialFlags::REFLECTION
    }

    fn sample(
        &self,
        wo: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _u_lobe: f32,
        u: Vec2,
        _mode: TransportMode,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let mut wi = sample_cosine_hemisphere(u);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        let pdf = wi.z.abs() * FRAC_1_PI;
        if pdf == 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            f: SampledSpectrum::splat(FRAC_1_PI),
            pdf,
            flags: MaterialFlags::DIFFUSE | MaterialFlags::REFLECTION,
            eta: 1.0,
        })
    }

    fn eval(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> SampledSpectrum {
        if same_hemisphere(wo, wi) {
            SampledSpectrum::splat(FRAC_1_PI)
        } else {
            SampledSpectrum::zero()
        }
    }

    fn pdf(
        &self,
        wo: Vec3A,
        wi: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _mode: TransportMode,
    ) -> f32 {
        if same_hemisphere(wo, wi) {
            wi.z.abs() * FRAC_1_PI
        } else {
            0.0
        }
    }
}

/// Which way the path travels through the fluorescent vertex.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Camera path: arrives with the emission wavelength, may move to an excitation one.
    Camera,
    /// Light path: arrives with the excitation wavelength, may move to an emission one.
    Light,
}

/// (ρ, re-radiated part) at `lambda` for `dir` (see the module docs).
#[inline]
fn parts(rr: &dyn Reradiation, lambda: f64, dir: Direction) -> (f64, f64) {
    let f = match dir {
        Direction::Camera => rr.excitation_fraction(lambda),
        Direction::Light => rr.reradiated_fraction(lambda),
    };
    (rr.reflectance(lambda).max(0.0), f.max(0.0))
}

/// Draw the other wavelength of a shift at `lambda` with `u`: (new λ, r(λᵢ → λₒ), pdf).
#[inline]
fn draw(rr: &dyn Reradiation, lambda: f64, u: f64, dir: Direction) -> Option<(f64, f64, f64)> {
    let (l, pdf) = match dir {
        Direction::Camera => rr.sample_excitation(lambda, u)?,
        Direction::Light => rr.sample_emission(lambda, u)?,
    };
    if !(pdf > 0.0) {
        return None;
    }
    let r = match dir {
        Direction::Camera => rr.reradiation(l, lambda),
        Direction::Light => rr.reradiation(lambda, l),
    };
    Some((l, r, pdf))
}

/// pt and lt: every live lane of `lambda` chooses on its own (keep with `ρ/(ρ + F)`) with the
/// rotated uniform `frac(u + k/LANES)`, and shifted lanes get their new wavelength. Returns the
/// per-lane weight that multiplies the throughput (0 on lanes that carry nothing further).
/// The lanes' pdfs and mask are left alone: they belong to the wavelengths the film weighs.
pub fn shift_lanes(
    rr: &dyn Reradiation,
    lambda: &mut SampledWavelengths,
    u: f32,
    dir: Direction,
) -> SampledSpectrum {
    let mut w = SampledSpectrum::zero();
    for k in 0..LANES {
        if !lambda.lanes.contains(k) {
            continue;
        }
        let l = lambda.lambda[k] as f64;
        let (rho, f) = parts(rr, l, dir);
        let total = rho + f;
        if !(total > 0.0) {
            continue;
        }
        let keep = rho / total;
        let uk = rotated(u as f64, k, LANES);
        if uk < keep {
            w[k] = total as f32;
        } else {
            let u2 = ((uk - keep) / (1.0 - keep)).clamp(0.0, 1.0 - f64::EPSILON);
            if let Some((new, r, pdf)) = draw(rr, l, u2, dir) {
                lambda.lambda[k] = new as f32;
                w[k] = (r / (pdf * (1.0 - keep))) as f32;
            }
        }
    }
    w
}

/// bdpt: the probability with which a camera subpath keeps its wavelengths at a fluorescent
/// vertex reached with `lambda` — one choice for all lanes, so the MIS weights stay scalar:
/// `Σρ / Σ(ρ + F)` over the live lanes, held within [0.1, 0.9] when both choices can carry
/// light, 1 when nothing re-radiates into these wavelengths and 0 when nothing is reflected.
pub fn keep_probability(rr: &dyn Reradiation, lambda: &SampledWavelengths) -> f32 {
    let (mut rho, mut f) = (0.0, 0.0);
    for k in 0..LANES {
        if lambda.lanes.contains(k) {
            let (r, e) = parts(rr, lambda.lambda[k] as f64, Direction::Camera);
            rho += r;
            f += e;
        }
    }
    if !(f > 0.0) {
        return 1.0;
    }
    if !(rho > 0.0) {
        return 0.0;
    }
    ((rho / (rho + f)) as f32).clamp(KEEP_BOUNDS.0, KEEP_BOUNDS.1)
}

/// bdpt: apply the choice `keep` (taken with probability `p_keep` from [`keep_probability`])
/// to every live lane of a camera subpath: keep (weight ρ/P) or draw each lane's excitation
/// wavelength with the rotated uniform (weight r/(pdf·(1 − P))). Returns the per-lane weight.
pub fn shift_camera_group(
    rr: &dyn Reradiation,
    lambda: &mut SampledWavelengths,
    keep: bool,
    p_keep: f32,
    u: f32,
) -> SampledSpectrum {
    let mut w = SampledSpectrum::zero();
    for k in 0..LANES {
        if !lambda.lanes.contains(k) {
            continue;
        }
        let l = lambda.lambda[k] as f64;
        if keep {
            if p_keep > 0.0 {
                w[k] = (rr.reflectance(l).max(0.0) / p_keep as f64) as f32;
            }
        } else if p_keep < 1.0 {
            let uk = rotated(u as f64, k, LANES).clamp(0.0, 1.0 - f64::EPSILON);
            if let Some((new, r, pdf)) = draw(rr, l, uk, Direction::Camera) {
                lambda.lambda[k] = new as f32;
                w[k] = (r / (pdf * (1.0 - p_keep as f64))) as f32;
            }
        }
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::fluorescent::fluorescent_from_bfc_param;
    use crate::spectrum::LaneMask;

    const SAMPLES: [&str; 8] = [
        "CIBA12.BFC",
        "CIPLAW10.BFC",
        "HERPICER.BFC",
        "HERPIORA.BFC",
        "IXCRLALE.BFC",
        "PHP8HP1C.BFC",
        "POLGREE.BFC",
        "TEXTYELL.BFC",
    ];

    fn bundled(name: &str) -> crate::material::fluorescent::Fluorescent {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/fluorescence");
        fluorescent_from_bfc_param(name, &dir).unwrap()
    }

    fn at(l: f32) -> SampledWavelengths {
        SampledWavelengths {
            lambda: [l; LANES],
            pdf: [1.0; LANES],
            lanes: LaneMask::ALL,
        }
    }

    /// Energy, light direction, every sample: for each of the 8 bundled matrices and every
    /// excitation wavelength 300–780 nm (1 nm), the weight of every single light-path shift
    /// (64 stratified choices × 4 lanes) is at most 1 + 1e-6: with exact sampling it is the
    /// albedo ρ + ∫r dλₒ whatever is chosen, and the albedo is ≤ 1 (f32 rounding: 1e-6).
    /// The largest weight is printed (the data's maximum albedo is 0.9583, HERPICER 760 nm).
    #[test]
    fn light_path_weights_never_exceed_one() {
        let mut worst = 0.0f32;
        for f in SAMPLES {
            let m = bundled(f);
            let rr = m.reradiation().unwrap();
            for k in 0..481 {
                let li = 300.0 + k as f32;
                for j in 0..64 {
                    let mut lam = at(li);
                    let w = shift_lanes(rr, &mut lam, (j as f32 + 0.5) / 64.0, Direction::Light);
                    for lane in 0..LANES {
                        assert!(w[lane] <= 1.0 + 1e-6, "{f} at {li} nm: weight {}", w[lane]);
                        assert!(lam.lambda[lane] >= li, "{f}: anti-Stokes shift at {li} nm");
                        worst = worst.max(w[lane]);
                    }
                }
            }
        }
        println!("largest light-path shift weight {worst}");
        assert!((worst - 0.9583).abs() < 2e-3, "{worst}");
    }

    /// Camera direction, the estimator's mean: for IXCRLALE (highlighter yellow) at 550 nm
    /// observed and an illuminant E(λ) = λ/500 (any smooth test function), the mean over 20 000
    /// stratified choices of weight × E(new λ) equals ρ(550)E(550) + ∫ r(λᵢ → 550)E(λᵢ) dλᵢ
    /// summed independently on 0.05 nm cells, within 0.5% (stratified u: the error is the
    /// within-cell spread of E, far below 0.5%).
    #[test]
    fn camera_shift_estimates_the_reradiation_integral() {
        let m = bundled("IXCRLALE.BFC");
        let rr = m.reradiation().unwrap();
        let e = |l: f64| l / 500.0;
        let lo = 550.0;
        let want = rr.reflectance(lo) * e(lo)
            + (0..12_000)
                .map(|k| {
                    let li = 250.0 + (k as f64 + 0.5) * 0.05;
                    rr.reradiation(li, lo) * e(li)
                })
                .sum::<f64>()
                * 0.05;
        let n = 20_000;
        let mut sum = 0.0;
        let mut sum_bdpt = 0.0;
        let p = keep_probability(rr, &at(lo as f32));
        for j in 0..n {
            let u = (j as f32 + 0.5) / n as f32;
            let mut lam = at(lo as f32);
            let w = shift_lanes(rr, &mut lam, u, Direction::Camera);
            sum += (0..LANES)
                .map(|k| w[k] as f64 * e(lam.lambda[k] as f64))
                .sum::<f64>()
                / LANES as f64;
            let keep = u < p;
            let u2 = if keep { u / p } else { (u - p) / (1.0 - p) };
            let mut lam = at(lo as f32);
            let w = shift_camera_group(rr, &mut lam, keep, p, u2);
            sum_bdpt += (0..LANES)
                .map(|k| w[k] as f64 * e(lam.lambda[k] as f64))
                .sum::<f64>()
                / LANES as f64;
        }
        let (got, got_bdpt) = (sum / n as f64, sum_bdpt / n as f64);
        assert!(rr.excitation_fraction(lo) > 0.1, "550 nm must fluoresce");
        assert!((got / want - 1.0).abs() < 5e-3, "pt {got} vs {want}");
        assert!(
            (got_bdpt / want - 1.0).abs() < 5e-3,
            "bdpt {got_bdpt} vs {want}"
        );
    }
}
