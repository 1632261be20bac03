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
//! (lt). bdpt makes the same per-lane choices on both its subpaths and records, per lane, the
//! probability of each event for its own side and for the other side
//! ([`shift_lanes_recorded`], [`event_probability`]): its MIS weights are per lane.

use crate::material::{
    same_hemisphere, sample_cosine_lobe, BsdfSample, Material, MaterialFlags, ShadingContext,
    TransportMode,
};
use crate::spectrum::reradiation::Reradiation;
use crate::spectrum::spd::{is_line_lane, off_lines};
use crate::spectrum::wavelength_sampling::rotated;
use crate::spectrum::DeltaLine;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};
use std::f32::consts::FRAC_1_PI;

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

    fn sample_into<'a>(
        &self,
        wo: Vec3A,
        _ctx: &ShadingContext,
        _lambda: &SampledWavelengths,
        _u_lobe: f32,
        u: Vec2,
        _mode: TransportMode,
        out: &'a mut BsdfSample,
    ) -> Option<&'a BsdfSample> {
        let (wi, pdf) = sample_cosine_lobe(wo, u)?;
        Some(out.write(BsdfSample {
            wi,
            f: SampledSpectrum::splat(FRAC_1_PI),
            pdf,
            flags: MaterialFlags::DIFFUSE | MaterialFlags::REFLECTION,
            eta: 1.0,
        }))
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

/// (ρ, re-radiated part) at `lambda` (nm, as the lane stores it) for `dir` (see the module
/// docs). A camera lane sitting exactly on one of the lights' `lines` is a discrete draw of
/// that line: only light that is itself a line at that wavelength (reflected, never
/// re-radiated, which is continuous in the emission wavelength) belongs to it, so its
/// re-radiated part is 0 and it always keeps its wavelength.
#[inline]
fn parts(rr: &dyn Reradiation, lambda: f32, dir: Direction, lines: &[DeltaLine]) -> (f64, f64) {
    let l = lambda as f64;
    let f = match dir {
        Direction::Camera if is_line_lane(lines, lambda) => 0.0,
        Direction::Camera => rr.excitation_fraction(l),
        Direction::Light => rr.reradiated_fraction(l),
    };
    (rr.reflectance(l).max(0.0), f.max(0.0))
}

/// Camera paths: the share of excitation draws that go to the lights' delta lines when some
/// line can excite the emission wavelength. A continuous draw never lands on a line, so
/// without these a line lamp (a 365 nm mercury line, a UV laser) would never be found to
/// excite anything; the continuous part stays (the other half) for continuous light,
/// including light another fluorescent surface re-radiates at any wavelength.
const LINE_SHARE: f64 = 0.5;

/// How strongly the camera-side excitation draw picks the light `line` for the emission
/// wavelength `lambda_o` (nm): the line's weight × r(λ_line → λₒ), 0 for lines at or above
/// λₒ. One definition for the draw ([`draw_excitation`]) and its density
/// ([`excitation_density`]), which must agree exactly.
#[inline]
fn line_score(rr: &dyn Reradiation, line: &DeltaLine, lambda_o: f64) -> f64 {
    if line.lambda < lambda_o {
        (line.weight * rr.reradiation(line.lambda, lambda_o)).max(0.0)
    } else {
        0.0
    }
}

/// Camera paths: an excitation wavelength for the emission wavelength `lambda_o` (nm) drawn
/// with `u` from the one-sample mixture of the lights' `lines` (probability [`LINE_SHARE`],
/// a line picked ∝ its weight × r(λ_line → λₒ)) and the material's continuous excitation
/// density (the rest). Returns the new lane wavelength (exactly the line's f32 for a line, so
/// lights give it the line's discrete power; moved off any line otherwise) and the weight
/// r/probability: r(λᵢ → λₒ)/(q·P(line)) for a line — the lane then carries the line's
/// power, a discrete measure — and r/((1 − q)·pdf(λᵢ)) for a continuous draw (per nm),
/// returned as (λ, r, probability). The two parts are disjoint measures, so the mixture is
/// unbiased without MIS. Without lines (q = 0) it is the continuous draw alone, bit for bit.
fn draw_excitation(
    rr: &dyn Reradiation,
    lambda_o: f64,
    u: f64,
    lines: &[DeltaLine],
) -> Option<(f32, f64, f64)> {
    let score = |l: &DeltaLine| line_score(rr, l, lambda_o);
    let total: f64 = lines.iter().map(score).sum();
    let q = if total > 0.0 { LINE_SHARE } else { 0.0 };
    if u < q {
        let target = u / q * total;
        let mut acc = 0.0;
        let mut chosen = None;
        for l in lines {
            let c = score(l);
            if c > 0.0 {
                acc += c;
                chosen = Some((l.lambda, c));
                if acc > target {
                    break;
                }
            }
        }
        let (l, c) = chosen?;
        return Some((l as f32, rr.reradiation(l, lambda_o), q * c / total));
    }
    let u2 = ((u - q) / (1.0 - q)).clamp(0.0, 1.0 - f64::EPSILON);
    let (l, r, pdf) = draw(rr, lambda_o, u2, Direction::Camera)?;
    Some((off_lines(l as f32, lines), r, pdf * (1.0 - q)))
}

/// Draw the new wavelength of a shift at `lambda` for `dir`: (new λ, r, probability)
/// (camera: [`draw_excitation`]; light: the material's emission density).
#[inline]
fn draw_shift(
    rr: &dyn Reradiation,
    lambda: f64,
    u: f64,
    dir: Direction,
    lines: &[DeltaLine],
) -> Option<(f32, f64, f64)> {
    match dir {
        Direction::Camera => draw_excitation(rr, lambda, u, lines),
        Direction::Light => {
            draw(rr, lambda, u, dir).map(|(l, r, pdf)| (off_lines(l as f32, lines), r, pdf))
        }
    }
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
    lines: &[DeltaLine],
) -> SampledSpectrum {
    shift_lanes_with(rr, lambda, u, dir, lines, false).weight
}

/// One per-lane shift step with what bdpt's MIS needs about it ([`shift_lanes_recorded`]).
#[derive(Clone, Copy, Debug)]
pub struct LaneShift {
    /// Per-lane weight that multiplies the throughput.
    pub weight: SampledSpectrum,
    /// Per lane, the probability with which this subpath made its choice: `ρ/(ρ + F)` for a
    /// keep, `F/(ρ + F)` × the density (1/nm, or the discrete probability of a delta line)
    /// of the new wavelength for a shift; 0 on dead lanes.
    pub own: [f32; LANES],
    /// Per lane, the same for a subpath coming from the other end that makes the same event
    /// at this vertex ([`event_probability`] with the wavelengths swapped).
    pub other: [f32; LANES],
    /// Lanes whose wavelength this step changed.
    pub moved: LaneMask,
}

/// bdpt: [`shift_lanes`] (the same choices, weights and new wavelengths, bit for bit) plus,
/// per lane, the probabilities of the event for this side and the other side (see
/// [`LaneShift`]), so that the MIS weights can compare strategies that make the same event on
/// either subpath.
pub fn shift_lanes_recorded(
    rr: &dyn Reradiation,
    lambda: &mut SampledWavelengths,
    u: f32,
    dir: Direction,
    lines: &[DeltaLine],
) -> LaneShift {
    shift_lanes_with(rr, lambda, u, dir, lines, true)
}

fn shift_lanes_with(
    rr: &dyn Reradiation,
    lambda: &mut SampledWavelengths,
    u: f32,
    dir: Direction,
    lines: &[DeltaLine],
    record: bool,
) -> LaneShift {
    let mut out = LaneShift {
        weight: SampledSpectrum::zero(),
        own: [0.0; LANES],
        other: [0.0; LANES],
        moved: LaneMask::NONE,
    };
    for k in 0..LANES {
        if !lambda.lanes.contains(k) {
            continue;
        }
        let arrive = lambda.lambda[k];
        let (rho, f) = parts(rr, arrive, dir, lines);
        let total = rho + f;
        if !(total > 0.0) {
            continue;
        }
        let keep = rho / total;
        let uk = rotated(u as f64, k, LANES);
        if uk < keep {
            out.weight[k] = total as f32;
            if record {
                out.own[k] = keep as f32;
                out.other[k] = event_probability(rr, arrive, arrive, dir.other(), lines) as f32;
            }
        } else {
            let u2 = ((uk - keep) / (1.0 - keep)).clamp(0.0, 1.0 - f64::EPSILON);
            let l = arrive as f64;
            if let Some((new, r, prob)) = draw_shift(rr, l, u2, dir, lines) {
                lambda.lambda[k] = new;
                out.weight[k] = (r / (prob * (1.0 - keep))) as f32;
                if record {
                    out.own[k] = (prob * (1.0 - keep)) as f32;
                    out.other[k] = event_probability(rr, new, arrive, dir.other(), lines) as f32;
                    if new != arrive {
                        out.moved = out.moved.with(k);
                    }
                }
            }
        }
    }
    out
}

impl Direction {
    /// The other end's direction.
    pub fn other(self) -> Self {
        match self {
            Self::Camera => Self::Light,
            Self::Light => Self::Camera,
        }
    }
}

/// The probability with which a `dir` path arriving at a fluorescent vertex with `arrive`
/// (nm) leaves it with `after`: `ρ/(ρ + F)` when `after == arrive` (a keep), else `F/(ρ + F)`
/// × the density of drawing `after` ([`excitation_density`] on camera paths, the material's
/// emission density on light paths); 0 where the event is impossible for `dir` (anti-Stokes,
/// or a camera lane on a delta line, which never shifts). The same formulas as the draws in
/// [`shift_lanes`], evaluated for any pair of wavelengths.
pub fn event_probability(
    rr: &dyn Reradiation,
    arrive: f32,
    after: f32,
    dir: Direction,
    lines: &[DeltaLine],
) -> f64 {
    let (rho, f) = parts(rr, arrive, dir, lines);
    let total = rho + f;
    if !(total > 0.0) {
        return 0.0;
    }
    if after == arrive {
        return rho / total;
    }
    if !(f > 0.0) {
        return 0.0;
    }
    let density = match dir {
        Direction::Camera if after < arrive => excitation_density(rr, arrive as f64, after, lines),
        Direction::Light if after > arrive => rr.emission_pdf(arrive as f64, after as f64),
        _ => 0.0,
    };
    f / total * density.max(0.0)
}

/// The probability with which [`draw_excitation`] produces the lane wavelength `lambda_i`
/// (nm, as a lane stores it) for the emission wavelength `lambda_o`: the line part's discrete
/// probability `q · Σ score/total` when `lambda_i` sits exactly on some of the lights'
/// `lines`, else the continuous part's density `(1 − q) · pdf(λᵢ)` (1/nm).
pub fn excitation_density(
    rr: &dyn Reradiation,
    lambda_o: f64,
    lambda_i: f32,
    lines: &[DeltaLine],
) -> f64 {
    let score = |l: &DeltaLine| line_score(rr, l, lambda_o);
    let total: f64 = lines.iter().map(score).sum();
    let q = if total > 0.0 { LINE_SHARE } else { 0.0 };
    if is_line_lane(lines, lambda_i) {
        let on: f64 = lines
            .iter()
            .filter(|l| l.lambda as f32 == lambda_i)
            .map(score)
            .sum();
        return if total > 0.0 { q * on / total } else { 0.0 };
    }
    (1.0 - q) * rr.excitation_pdf(lambda_o, lambda_i as f64)
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
                    let w =
                        shift_lanes(rr, &mut lam, (j as f32 + 0.5) / 64.0, Direction::Light, &[]);
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
        for j in 0..n {
            let u = (j as f32 + 0.5) / n as f32;
            let mut lam = at(lo as f32);
            let w = shift_lanes(rr, &mut lam, u, Direction::Camera, &[]);
            sum += (0..LANES)
                .map(|k| w[k] as f64 * e(lam.lambda[k] as f64))
                .sum::<f64>()
                / LANES as f64;
        }
        let got = sum / n as f64;
        assert!(rr.excitation_fraction(lo) > 0.1, "550 nm must fluoresce");
        assert!((got / want - 1.0).abs() < 5e-3, "{got} vs {want}");
    }

    /// Camera direction with a delta line among the lights: for IXCRLALE at 550 nm observed
    /// under E(λ) = λ/500 per nm plus a line of mass M = 200 at 436 nm (mercury's g line),
    /// the mean over 20 000 stratified choices of weight × E(new λ) — the line's mass when the
    /// lane sits exactly on the line (discrete measure), the continuous E otherwise — equals
    /// ρE(550) + ∫ r(λᵢ → 550)E(λᵢ) dλᵢ + r(436 → 550)·M (independent 0.05 nm sums; the
    /// line's term is over 10% of it), within 0.5% (pt, lt and bdpt make the same per-lane
    /// choice). A lane on the line itself keeps its wavelength with weight ρ (nothing
    /// re-radiated is a line).
    #[test]
    fn camera_shift_reaches_a_delta_line() {
        let m = bundled("IXCRLALE.BFC");
        let rr = m.reradiation().unwrap();
        let line = DeltaLine {
            lambda: 436.0,
            weight: 1.0,
        };
        let mass = 200.0;
        let e = |l: f32| -> f64 {
            if l == 436.0 {
                mass
            } else {
                l as f64 / 500.0
            }
        };
        let lo = 550.0;
        let want = rr.reflectance(lo) * lo / 500.0
            + (0..12_000)
                .map(|k| {
                    let li = 250.0 + (k as f64 + 0.5) * 0.05;
                    rr.reradiation(li, lo) * li / 500.0
                })
                .sum::<f64>()
                * 0.05
            + rr.reradiation(436.0, lo) * mass;
        assert!(
            rr.reradiation(436.0, lo) * mass > 0.1 * want,
            "436 nm must excite"
        );
        let n = 20_000;
        let (mut sum, mut on_line) = (0.0, 0usize);
        let lines = [line];
        for j in 0..n {
            let u = (j as f32 + 0.5) / n as f32;
            let mut lam = at(lo as f32);
            let w = shift_lanes(rr, &mut lam, u, Direction::Camera, &lines);
            on_line += (0..LANES).filter(|&k| lam.lambda[k] == 436.0).count();
            sum += (0..LANES)
                .map(|k| w[k] as f64 * e(lam.lambda[k]))
                .sum::<f64>()
                / 4.0;
        }
        let got = sum / n as f64;
        assert!(on_line > 0, "no draw landed on the line");
        assert!((got / want - 1.0).abs() < 5e-3, "{got} vs {want}");
        // A lane on the line: always kept, weight ρ(436).
        let mut lam = at(436.0);
        let w = shift_lanes(rr, &mut lam, 0.999, Direction::Camera, &lines);
        assert_eq!(lam.lambda, [436.0; LANES]);
        assert!((w[0] as f64 - rr.reflectance(436.0)).abs() < 1e-6);
    }
}
