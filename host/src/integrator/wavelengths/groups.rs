//! Several groups of [`LANES`] wavelengths on one camera path ("wavelengths per path" N = 1, 4,
//! 8, 12, 16) and how the path tracer draws them (visible, uniform or light-SPD importance).
//!
//! # Layout
//! A path with N = 4G wavelengths carries G groups of `LANES = 4`. The k-th of the 4G lanes
//! uses the primary sample `frac(u + k/(4G))`, and group g holds lanes k = g, g+G, g+2G, g+3G,
//! so group g is itself an ordinary 4-lane rotation set drawn from `u_g = frac(u + g/(4G))`.
//! Every lane's primary sample is on its own uniform on [0, 1), so each lane's marginal density
//! is the sampling density, which is the pdf it stores; the 4G lanes stay stratified.
//!
//! # Film estimator
//! [`Sensor::to_xyz`](crate::film::Sensor::to_xyz) averages `L/pdf` over the 4 lanes of a group
//! and the render driver averages over the G groups, so each sample is
//! `1/(4G) Σ_k L(λ_k)/p(λ_k)`: a mean of 4G unbiased estimates. When a dispersive event keeps
//! only the hero (lane 0 of group 0), the sample must become `L(λ₀)/p(λ₀)`, so the hero's stored
//! pdf is divided by 4G ([`PathWavelengths::terminate_secondary`]) and every other lane's pdf
//! becomes 0.
//!
//! N = 1 is the 4-lane set with lanes 1..3 dropped from the start (hero pdf divided by 4, as
//! after a dispersive event). It still computes a 4-wide vector for every material and light
//! call, so it is not 4× cheaper than N = 4: only the colour noise per sample is worse.
//!
//! # Light-SPD importance ([`WavelengthSampling::LightSpd`])
//! Wavelengths are drawn from the scene's emission `p_emit(λ) = Σ_L P(L)·S_L(λ)` (the
//! power-proportional light pmf times each evaluable light's normalised SPD), reusing BDPT's
//! [`WavelengthMixture`]: one extra uniform picks a light SPD by power for all groups of the
//! path, the groups rotate through its inverse CDF, and every lane stores `p_emit(λ)`, its
//! marginal density (the one-sample balance heuristic over the lights' SPDs). A path tracer
//! without fluorescence sees emission only where some light emits, and there `p_emit > 0`, so
//! the estimator is unbiased even though `p_emit` is 0 where the observer is still sensitive.
//! A lane that lands on a delta spectral line carries the line's discrete probability
//! ([`WavelengthMixture`]), so line lights render.
//!
//! # Observer × emission importance ([`WavelengthSampling::Product`], the default)
//! What a camera path carries at λ is proportional to the emission there, and the film weighs
//! it by the observer's response, so wavelengths are drawn from
//! `p(λ) = ¾·V(λ)·√p_emit(λ)/∫V·√p_emit + ¼·V(λ)/∫V`, with `V` the visible-importance
//! shape (`sech²(0.0072 (λ − 538 nm))` on 360–830 nm) and `p_emit` the emission component
//! above, tabulated once per render as an equal-probability table ([`WavelengthTable`];
//! drawing costs what visible-importance sampling costs). The visible quarter keeps the
//! density positive wherever visible importance is, so the estimator stays unbiased whatever
//! the lights' SPDs say (a textured or plugin emitter whose `spd` is only indicative, emission
//! outside the SPD's range, light reflected at wavelengths a light emits little).
//!
//! The shape was chosen by measurement on the Cornell box (its light emits nothing at 400 nm
//! and most at 700 nm; path tracer, 32 spp, 4–8 seeds, against the Mitsuba reference):
//! MSE, relative MSE and mean ΔE of `V·p_emit^γ` mixed with a share `s` of `V`, relative to
//! visible importance alone: γ = 1, s = ¼: 0.874, 0.92, 1.02 (the blue channel, where the
//! light is weak, gets noisier than the others gain in ΔE); γ = ½, s = 0.1: 0.869, 0.89,
//! 0.957; γ = ½, s = ¼: 0.876, 0.90, 0.950; γ = ⅓, ⅔ and s = 0, 0.15 lie within 1% of these
//! in MSE. The light-SPD density alone gave 0.91 in MSE for 14% more instructions (its mixture
//! search per lane). The square root and the quarter temper the emission's weight: the film's
//! three channels want different wavelengths, and the blue one sees little of a reddish
//! light (on the Cornell box at 16 spp the blue channel's image mean still spreads about 1.3×
//! as much over 8 seeds as with visible importance, red and green 0.8–1.0×).
//!
//! It applies without fluorescence (visible importance is used there: fluorescent light
//! appears at wavelengths no light emits) and where the render plan does not draw from the
//! lights' spectra itself; a scene without evaluable lights uses visible importance.
//!
//! # Visible importance and the render plan
//! With [`WavelengthSampling::Visible`] (and the default where the render plan asks for it)
//! the lanes come from the observer's visible-importance density, unless the render plan
//! draws wavelengths from the lights' spectra ([`RenderPlan::emission_wavelengths`]:
//! narrowband or line emission found, or forced on); then they come from the plan's
//! one-sample mixture ½ p_vis + ½ p_emit, as in bdpt. Beams-only lights are left out (`pt`
//! cannot render them). A scene without evaluable lights has no emission to sample and falls
//! back to visible-importance sampling.

use crate::integrator::plan::RenderPlan;
use crate::integrator::wavelengths::mixture::WavelengthMixture;
use crate::integrator::{PixelSampler, WavelengthSampling};
use crate::spectrum::wavelength_sampling::{rotated, visible_pdf};
use crate::spectrum::wavelength_table::WavelengthTable;
use crate::spectrum::{LaneMask, SampledWavelengths, LANES};

/// Largest supported number of wavelengths per path.
pub const MAX_WAVELENGTHS_PER_PATH: u32 = 16;

/// Largest number of 4-lane groups on one path.
pub const MAX_GROUPS: usize = MAX_WAVELENGTHS_PER_PATH as usize / LANES;

/// Groups of a path with `n` wavelengths: 1 for n = 1, n/4 for multiples of 4 up to
/// [`MAX_WAVELENGTHS_PER_PATH`]; an error naming the value otherwise.
pub fn groups_for(n: u32) -> Result<usize, String> {
    if n == 1
        || (n.is_multiple_of(LANES as u32) && n >= LANES as u32 && n <= MAX_WAVELENGTHS_PER_PATH)
    {
        Ok((n as usize / LANES).max(1))
    } else {
        Err(format!(
            "wavelengths per path must be 1 or a multiple of {LANES} up to \
             {MAX_WAVELENGTHS_PER_PATH}, got {n}"
        ))
    }
}

/// The wavelength groups of one camera path (group 0 is the hero group; its lane 0 the hero).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathWavelengths {
    groups: [SampledWavelengths; MAX_GROUPS],
    count: usize,
}

impl Default for PathWavelengths {
    /// One group without live lanes (a buffer for [`PathWavelengthSampler::sample_into`]).
    fn default() -> Self {
        let empty = SampledWavelengths {
            lambda: [0.0; LANES],
            pdf: [0.0; LANES],
            lanes: LaneMask::NONE,
        };
        Self {
            groups: [empty; MAX_GROUPS],
            count: 1,
        }
    }
}

impl PathWavelengths {
    /// A path carrying `groups` (1 to [`MAX_GROUPS`] of them; extra ones are ignored). A single
    /// group whose lane mask holds only the hero counts as hero-only, as
    /// [`SampledWavelengths::terminate_secondary`] leaves it.
    pub fn from_groups(groups: &[SampledWavelengths]) -> Self {
        let count = groups.len().clamp(1, MAX_GROUPS);
        let empty = SampledWavelengths {
            lambda: [0.0; LANES],
            pdf: [0.0; LANES],
            lanes: LaneMask::NONE,
        };
        let mut g = [empty; MAX_GROUPS];
        g[..count].copy_from_slice(&groups[..count]);
        Self { groups: g, count }
    }

    /// Only the hero lane is left: the hero group's lane mask says so (lanes on delta lines
    /// also have pdf 0, so the pdfs cannot).
    fn hero_only(&self) -> bool {
        self.groups[0].lanes.count() <= 1
    }

    /// Number of groups the path started with.
    #[allow(clippy::len_without_is_empty)]
    pub fn len(&self) -> usize {
        self.count
    }

    /// Groups that still carry wavelengths: all of them, or 1 once only the hero is left.
    pub fn active_groups(&self) -> usize {
        if self.hero_only() {
            1
        } else {
            self.count
        }
    }

    /// The groups (terminated ones have pdf 0 in every lane).
    pub fn groups(&self) -> &[SampledWavelengths] {
        &self.groups[..self.count]
    }

    /// Keep only the hero wavelength, as a wavelength-dependent event demands: every other lane
    /// of every group gets pdf 0 and the hero's pdf is divided by the 4G lanes the film averages
    /// over (see the module docs), so the sample stays unbiased. Idempotent.
    pub fn terminate_secondary(&mut self) {
        if self.hero_only() {
            return;
        }
        let lanes = (LANES * self.count) as f32;
        let hero = &mut self.groups[0];
        for p in &mut hero.pdf[1..] {
            *p = 0.0;
        }
        hero.pdf[0] /= lanes;
        hero.lanes = hero.lanes.terminate_secondary();
        for g in &mut self.groups[1..self.count] {
            g.pdf = [0.0; LANES];
            g.lanes = LaneMask::NONE;
        }
    }
}

/// The range (nm) of [`WavelengthSampling::Uniform`]'s lanes.
const UNIFORM_RANGE_NM: (f64, f64) = (360.0, 830.0);

/// Draws a camera path's wavelength groups for one render.
#[derive(Clone, Debug)]
pub struct PathWavelengthSampler {
    sampling: WavelengthSampling,
    /// Light-SPD sampling was asked for in a scene with fluorescence: visible is used.
    fluorescence_refused_light_spd: bool,
    groups: usize,
    single_lane: bool,
    /// The render plan's emission mixture, for [`WavelengthSampling::LightSpd`] in scenes with
    /// evaluable lights, and for [`WavelengthSampling::Visible`] when the plan draws
    /// wavelengths from the lights' spectra.
    emission: Option<WavelengthMixture>,
    /// The observer × emission table of [`WavelengthSampling::Product`] (then `sampling` is
    /// `Product`; where it does not apply, `sampling` is `Visible`).
    product: Option<WavelengthTable>,
}

impl PathWavelengthSampler {
    /// The sampler for a scene under `plan` with `per_path` wavelengths per path (see
    /// [`groups_for`]). Whether the lights' spectra are sampled is the plan's decision
    /// ([`RenderPlan::emission_wavelengths`]), made once from the scene analysis.
    ///
    /// `scene_fluoresces` is whether the scene's objects shift wavelengths
    /// (`Objects::fluorescence`, which path tracing follows); observer × emission sampling
    /// falls back to visible importance only when both it and the plan say so.
    pub fn new(
        plan: &RenderPlan,
        sampling: WavelengthSampling,
        per_path: u32,
        scene_fluoresces: bool,
    ) -> Result<Self, String> {
        let groups = groups_for(per_path)?;
        let mixture = || Some(plan.mixture().clone()).filter(|m| m.has_emission());
        // Light-SPD sampling would never observe wavelengths that only fluorescence emits.
        let requested = sampling;
        let sampling = if sampling == WavelengthSampling::LightSpd && plan.fluorescence() {
            WavelengthSampling::Visible
        } else {
            sampling
        };
        // Observer × emission where it applies (see the module docs), else visible importance.
        let fluoresces = plan.fluorescence() && scene_fluoresces;
        let product = match sampling {
            WavelengthSampling::Product if !fluoresces && !plan.emission_wavelengths() => {
                plan.product_table().cloned()
            }
            _ => None,
        };
        let sampling = if sampling == WavelengthSampling::Product && product.is_none() {
            WavelengthSampling::Visible
        } else {
            sampling
        };
        let emission = match sampling {
            WavelengthSampling::LightSpd => mixture(),
            WavelengthSampling::Visible if plan.emission_wavelengths() => mixture(),
            _ => None,
        };
        Ok(Self {
            sampling,
            fluorescence_refused_light_spd: requested == WavelengthSampling::LightSpd
                && requested != sampling,
            groups,
            single_lane: per_path == 1,
            emission,
            product,
        })
    }

    /// How the lanes are drawn in this render: the requested sampling, or `Visible` where it
    /// fell back (light-SPD or product sampling that does not apply to the scene).
    pub fn sampling(&self) -> WavelengthSampling {
        self.sampling
    }

    /// True when light-SPD sampling was asked for but the scene has no evaluable light, so
    /// visible-importance sampling is used instead.
    pub fn light_spd_fell_back(&self) -> bool {
        self.sampling == WavelengthSampling::LightSpd && self.emission.is_none()
    }

    /// True when light-SPD sampling was asked for but the scene renders fluorescence, whose
    /// emission lies where no light emits: visible-importance sampling is used instead.
    pub fn light_spd_refused_for_fluorescence(&self) -> bool {
        self.fluorescence_refused_light_spd
    }

    /// The density (1/nm) with which each lane of each group is drawn, marginally (the
    /// rotations move a lane, not its distribution): what the flat-path colour's usable
    /// probability integrates (`wavelengths::flat_colour`).
    pub fn lane_density(&self, lambda_nm: f64) -> f64 {
        if let Some(t) = &self.product {
            return t.pdf(lambda_nm);
        }
        match (self.sampling, &self.emission) {
            (WavelengthSampling::Uniform, _) => {
                let (lo, hi) = UNIFORM_RANGE_NM;
                if (lo..=hi).contains(&lambda_nm) {
                    1.0 / (hi - lo)
                } else {
                    0.0
                }
            }
            (WavelengthSampling::LightSpd, Some(m)) => m.emission_pdf(lambda_nm),
            (WavelengthSampling::Visible, Some(m)) => m.pdf(lambda_nm),
            _ => visible_pdf(lambda_nm),
        }
    }

    /// Draw the path's wavelengths: one uniform from `rng` for the rotations, plus one to pick
    /// the light SPD for [`WavelengthSampling::LightSpd`] (Product, Visible and Uniform draw
    /// exactly one, so Visible and Uniform with N = 4 reproduce earlier images bit for bit).
    pub fn sample(&self, rng: &mut PixelSampler) -> PathWavelengths {
        let mut w = PathWavelengths::default();
        self.sample_into(rng, &mut w);
        w
    }

    /// [`sample`](Self::sample) into `w` (whatever it held): the render loop keeps one
    /// `PathWavelengths` per tile instead of building and moving a 152-byte value per sample
    /// (two `memcpy` calls, about 60 instructions).
    #[inline]
    pub fn sample_into(&self, rng: &mut PixelSampler, w: &mut PathWavelengths) {
        let u = rng.next_1d();
        let u_spd = match &self.emission {
            Some(_) => rng.next_1d(),
            None => 0.0,
        };
        let u_comp = match (&self.emission, self.sampling) {
            (Some(_), WavelengthSampling::Visible) => rng.next_1d(),
            _ => 0.0,
        };
        let n = LANES * self.groups;
        w.count = self.groups;
        for (g, group) in w.groups.iter_mut().enumerate().take(self.groups) {
            let ug = rotated(u as f64, g, n) as f32;
            if let Some(t) = &self.product {
                *group = t.sample_lanes(ug as f64);
                continue;
            }
            *group = match (self.sampling, &self.emission) {
                (WavelengthSampling::Uniform, _) => {
                    let (lo, hi) = UNIFORM_RANGE_NM;
                    SampledWavelengths::sample_uniform(ug, lo as f32, hi as f32)
                }
                (WavelengthSampling::LightSpd, Some(m)) => m
                    .sample_emission(u_spd as f64, ug as f64)
                    .unwrap_or_else(|| SampledWavelengths::sample_visible(ug)),
                (WavelengthSampling::Visible, Some(m)) => {
                    m.sample_with(u_comp, u_spd as f64, ug as f64)
                }
                _ => SampledWavelengths::sample_visible(ug),
            };
        }
        if self.single_lane {
            w.terminate_secondary();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    // Valid counts map to their group count; anything else is an error naming the value.
    #[test]
    fn group_counts() {
        assert_eq!(groups_for(1), Ok(1));
        assert_eq!(groups_for(4), Ok(1));
        assert_eq!(groups_for(8), Ok(2));
        assert_eq!(groups_for(16), Ok(4));
        for bad in [0, 2, 3, 6, 20, 32] {
            let e = groups_for(bad).unwrap_err();
            assert!(e.contains(&bad.to_string()), "{e}");
        }
    }

    // Group g of a G-group path is the 4-lane set drawn from frac(u + g/(4G)), so the 4G lanes
    // are the rotations frac(u + k/(4G)): uniform sampling makes them equally spaced by
    // 470/(4G) nm (checked to 1e-3 nm, f32 rounding of ~500 nm values is ~3e-5 nm).
    #[test]
    fn lanes_are_rotations_of_one_sample() {
        let scene = crate::scene::default_scene().unwrap();
        let s = PathWavelengthSampler::new(
            &RenderPlan::auto(&scene),
            WavelengthSampling::Uniform,
            16,
            false,
        )
        .unwrap();
        let mut rng = PixelSampler::new(1, 2, 3);
        let w = s.sample(&mut rng);
        let mut all: Vec<f32> = w.groups().iter().flat_map(|g| g.lambda).collect();
        all.sort_by(f32::total_cmp);
        for pair in all.windows(2) {
            assert!((pair[1] - pair[0] - 470.0 / 16.0).abs() < 1e-3, "{all:?}");
        }
    }

    // The film algebra: a constant radiance 1 gives Y = 1 whatever the hero-only state, since
    // the hero's pdf is divided by the 4G lanes the film averages over. Checked for G = 1..4
    // by a stratified 4·10⁴-sample estimate of E[Y] (MC error < 1e-3; tolerance 2e-3 as in the
    // sensor's own test).
    #[test]
    fn hero_only_paths_stay_unbiased() {
        let observer: std::sync::Arc<dyn crate::color::Observer> =
            std::sync::Arc::new(crate::color::CieObserverKind::Cie1931_2.get().clone());
        let sensor = crate::film::Sensor::new(observer);
        let one = crate::spectrum::SampledSpectrum::splat(1.0);
        for g in 1..=MAX_GROUPS {
            let n = 40_000;
            let mut y = 0.0;
            for i in 0..n {
                let u = (i as f32 + 0.5) / n as f32;
                let groups: Vec<SampledWavelengths> = (0..g)
                    .map(|k| SampledWavelengths::sample_visible(rotated(u as f64, k, 4 * g) as f32))
                    .collect();
                let mut w = PathWavelengths::from_groups(&groups);
                w.terminate_secondary();
                let sum: f64 = w.groups().iter().map(|l| sensor.to_xyz(&one, l)[1]).sum();
                y += sum / g as f64;
            }
            y /= n as f64;
            assert!((y - 1.0).abs() < 2e-3, "G = {g}: Y = {y}");
        }
    }

    // `lane_density` is the density each lane is drawn with, in every sampling mode: every
    // lane of 2000 draws × 4 groups stores that density as its pdf (relative 1e-5: f32
    // rounding of the stored pdf), and it integrates to 1 over 300–1100 nm (midpoint rule at
    // 0.01 nm; tolerance 2e-3 for the rule's error at the tables' steps). The flat-path
    // colour's usable probability integrates it, so a wrong density would bias that colour.
    #[test]
    fn lane_density_is_the_density_lanes_are_drawn_with() {
        let scene = crate::scene::default_scene().unwrap();
        let plan = RenderPlan::auto(&scene);
        for mode in [
            WavelengthSampling::Product,
            WavelengthSampling::Visible,
            WavelengthSampling::Uniform,
            WavelengthSampling::LightSpd,
        ] {
            let s = PathWavelengthSampler::new(&plan, mode, 16, false).unwrap();
            for k in 0..2000u64 {
                let mut rng = PixelSampler::new(5, k, 0);
                for g in s.sample(&mut rng).groups() {
                    for i in 0..LANES {
                        let (l, p) = (g.lambda[i] as f64, g.pdf[i] as f64);
                        let d = s.lane_density(l);
                        assert!(
                            (p - d).abs() <= 1e-5 * d,
                            "{mode:?} {l} nm: pdf {p}, density {d}"
                        );
                    }
                }
            }
            let h = 0.01;
            let total: f64 = (0..80_000)
                .map(|k| s.lane_density(300.0 + (k as f64 + 0.5) * h) * h)
                .sum();
            assert!(
                (total - 1.0).abs() < 2e-3,
                "{mode:?}: density integrates to {total}"
            );
        }
    }

    // Observer × emission sampling: every lane stores the product table's density at its
    // wavelength, and that density is positive over the whole visible range (the visible
    // quarter), so the MC estimate of ∫_{360}^{830} 1 dλ = 470 nm over all lanes is within 1%
    // (the estimator's relative standard error with 5·10⁴ paths × 16 lanes is below 0.3%; 1/p
    // is at most 4/V's density in the far tails). A fluorescent scene falls back
    // to visible importance.
    #[test]
    fn product_lanes_carry_their_density_over_the_visible_range() {
        let scene = crate::scene::default_scene().unwrap();
        let plan = RenderPlan::auto(&scene);
        let s = PathWavelengthSampler::new(&plan, WavelengthSampling::Product, 16, false).unwrap();
        assert_eq!(s.sampling(), WavelengthSampling::Product);
        let table = crate::integrator::wavelengths::mixture::product_table(plan.mixture()).unwrap();
        let n = 50_000u32;
        let mut sum = 0.0f64;
        for k in 0..n {
            let mut rng = PixelSampler::new(7, k as u64, 0);
            let w = s.sample(&mut rng);
            for g in w.groups() {
                for i in 0..LANES {
                    let l = g.lambda[i] as f64;
                    assert_eq!(g.pdf[i], table.pdf(l) as f32);
                    assert!(g.pdf[i] > 0.0, "{l} nm");
                    sum += 1.0 / g.pdf[i] as f64;
                }
            }
        }
        let est = sum / (n as f64 * 16.0);
        assert!((est / 470.0 - 1.0).abs() < 0.01, "{est}");
        // The Cornell light emits nothing at 400 nm and most at 700 nm: the table follows it,
        // below visible importance in the blue, above it in the red.
        let vis = crate::spectrum::wavelength_sampling::visible_pdf;
        assert!(table.pdf(420.0) < 0.8 * vis(420.0));
        assert!(table.pdf(650.0) > 1.2 * vis(650.0));
        // A fluorescent scene keeps visible importance: its light appears where no light emits.
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/fluorescence.ron");
        let fl = crate::scene::load_scene_file(&path, &[&crate::scene::BuiltinFactory]).unwrap();
        let plan = RenderPlan::auto(&fl);
        assert!(plan.fluorescence());
        let s = PathWavelengthSampler::new(
            &plan,
            WavelengthSampling::Product,
            4,
            fl.objects.fluorescence(),
        )
        .unwrap();
        assert_eq!(s.sampling(), WavelengthSampling::Visible);
    }

    // Light-SPD sampling: every lane's pdf is the emission density at its wavelength, and the
    // MC estimate of ∫_{400}^{700} 1 dλ = 300 nm over the Cornell light's support (its SPD
    // covers 400–700 nm) is within 1% (relative standard error < 0.2% with 5·10⁴ paths × 16
    // lanes).
    #[test]
    fn light_spd_lanes_carry_emission_density() {
        let scene = crate::scene::default_scene().unwrap();
        let s = PathWavelengthSampler::new(
            &RenderPlan::auto(&scene),
            WavelengthSampling::LightSpd,
            16,
            false,
        )
        .unwrap();
        assert!(!s.light_spd_fell_back());
        let m = WavelengthMixture::new(&scene);
        let n = 50_000u32;
        let mut sum = 0.0f64;
        for k in 0..n {
            let mut rng = PixelSampler::new(5, k as u64, 0);
            let w = s.sample(&mut rng);
            for g in w.groups() {
                for i in 0..LANES {
                    let l = g.lambda[i] as f64;
                    assert_eq!(g.pdf[i], m.emission_pdf(l) as f32);
                    if (400.0..700.0).contains(&l) && g.pdf[i] > 0.0 {
                        sum += 1.0 / g.pdf[i] as f64;
                    }
                }
            }
        }
        let est = sum / (n as f64 * 16.0);
        assert!((est / 300.0 - 1.0).abs() < 0.01, "{est}");
    }
}
