//! How bdpt and light tracing draw the wavelengths of a camera/light path pair.
//!
//! Both subpaths of a pair carry the same four lanes, drawn once per pair, so the wavelength
//! density is a common factor of every (s, t) strategy and cancels in their MIS weights: any
//! density that is positive wherever light can arrive is unbiased, and the choice only moves
//! the colour noise. Two densities:
//!
//! - [`PairWavelengths::Product`] (`--wavelength-sampling product`, the default where it
//!   applies): the path tracer's observer × √emission table
//!   ([`product_table`](crate::integrator::wavelengths::mixture::product_table),
//!   `¾·V·√p_emit/∫V·√p_emit + ¼·V/∫V`). It applies without
//!   fluorescence (a fluorescent scene's light subpaths may start at their own light's
//!   wavelengths, and its per-lane MIS weights read the mixture's lane densities: see
//!   `integrator/fluorescence/join.rs`), where no light is narrowband or has lines (the scene
//!   analysis; there the plan's mixture draws from the lights' spectra) and where some light
//!   has an evaluable spectrum. These are the scene's properties, not the render plan's
//!   switches: under `--effects all` bdpt and lt render a scene without those effects as under
//!   `auto`.
//! - [`PairWavelengths::Uniform`] (`--wavelength-sampling uniform`, where the product would
//!   apply): uniform on 360–830 nm; the plain baseline the agreement
//!   tests compare against.
//! - [`PairWavelengths::Mixture`] (`--wavelength-sampling visible`, and everywhere the two
//!   above do not apply): the render plan's one-sample mixture `½ p_vis + ½ p_emit`
//!   ([`WavelengthMixture`]), as before the product existed (images
//!   bit for bit the same).
//!
//! The lanes' pdfs are what the film divides by; the flat-path colour
//! ([`FlatColour`](crate::integrator::wavelengths::flat_colour::FlatColour)) needs the same density for its usable
//! probability, so it is built from [`PairWavelengths::pdf`].

use crate::effects::Effect;
use crate::integrator::plan::RenderPlan;
use crate::integrator::wavelengths::mixture::WavelengthMixture;
use crate::integrator::{PixelSampler, WavelengthSampling};
use crate::scene::Scene;
use crate::spectrum::wavelength_sampling::VISIBLE_RANGE;
use crate::spectrum::wavelength_table::WavelengthTable;
use crate::spectrum::SampledWavelengths;

/// The wavelength density of a render's path pairs (see the module docs).
#[derive(Clone, Copy, Debug)]
pub enum PairWavelengths<'a> {
    /// The render plan's observer-plus-emission mixture.
    Mixture(&'a WavelengthMixture),
    /// The observer × √emission table (non-fluorescent scenes with broadband lights).
    Product(&'a WavelengthTable),
    /// Uniform over [`VISIBLE_RANGE`] (where the product would apply).
    Uniform,
}

impl<'a> PairWavelengths<'a> {
    /// The density for `scene` (as planned) under `plan`: [`Product`](Self::Product) or
    /// [`Uniform`](Self::Uniform) when `sampling` asks for it and it applies (see the module
    /// docs), else the plan's [`Mixture`](Self::Mixture) (`Visible` and `LightSpd` mean the
    /// mixture).
    pub fn new(plan: &'a RenderPlan, scene: &Scene, sampling: WavelengthSampling) -> Self {
        // The scene's own properties, not the plan's switches: `--effects all` switches
        // fluorescence and narrowband emission on in scenes without them, and bdpt and lt
        // then render as under `auto` (the planned scene's objects say whether anything
        // shifts wavelengths; the analysis whether some light is narrowband or has lines).
        let effects = plan.effects();
        let applies = !scene.objects.fluorescence()
            && !effects.contains(Effect::NarrowbandEmission)
            && !effects.contains(Effect::LineEmission)
            && plan.mixture().emission_weight() < 1.0
            && plan.mixture().has_emission();
        let table = || applies.then(|| plan.product_table()).flatten();
        match sampling {
            WavelengthSampling::Product => {
                table().map_or(Self::Mixture(plan.mixture()), Self::Product)
            }
            WavelengthSampling::Uniform if applies => Self::Uniform,
            _ => Self::Mixture(plan.mixture()),
        }
    }

    /// Draw a pair's four lanes from the first three dimensions of `ld`: the mixture's
    /// component, light SPD and hero; the table and the uniform density use the third alone
    /// and skip the other two, so that every later dimension of the sample (film, lens, light
    /// subpath start) is the one it is under the mixture and only the wavelength density
    /// differs. Measured (docs/performance.md, "BDPT per sample"): drawing one dimension
    /// instead moved the caustic region's error at equal spp by 1.09–1.12× (caustic bdpt, 64
    /// and 512 spp, 8 seeds each; within the seeds' spread, not shown to be noise), skipping
    /// two keeps it within 1% of the mixture's per seed, for two 1D requests (≈ 160
    /// instructions) per pair.
    #[inline]
    pub fn sample(&self, ld: &mut PixelSampler) -> SampledWavelengths {
        // The hero's number; the two before it, which only the mixture reads, are skipped
        // rather than computed (`skip_1d` leaves the sampler where drawing them would).
        let hero = |ld: &mut PixelSampler| {
            ld.skip_1d();
            ld.skip_1d();
            ld.next_1d()
        };
        match self {
            Self::Product(t) => t.sample_lanes(hero(ld) as f64),
            Self::Uniform => SampledWavelengths::sample_uniform(
                hero(ld),
                VISIBLE_RANGE.0 as f32,
                VISIBLE_RANGE.1 as f32,
            ),
            Self::Mixture(m) => {
                let (u_comp, u_spd, u) = (ld.next_1d(), ld.next_1d(), ld.next_1d());
                m.sample_with(u_comp, u_spd as f64, u as f64)
            }
        }
    }

    /// Density (1/nm) of a continuous lane at `lambda_nm`.
    pub fn pdf(&self, lambda_nm: f64) -> f64 {
        match self {
            Self::Product(t) => t.pdf(lambda_nm),
            Self::Uniform => {
                let (lo, hi) = VISIBLE_RANGE;
                if (lo..=hi).contains(&lambda_nm) {
                    1.0 / (hi - lo)
                } else {
                    0.0
                }
            }
            Self::Mixture(m) => m.pdf(lambda_nm),
        }
    }

    /// A short name of the density, for the settings fingerprint of state files: a render
    /// resumed or merged from parts drawn from another density would not be the
    /// uninterrupted render.
    pub fn key(&self) -> &'static str {
        match self {
            Self::Product(_) => "product",
            Self::Uniform => "uniform",
            Self::Mixture(_) => "mixture",
        }
    }

    /// One phrase for the render summary.
    pub fn describe(&self) -> &'static str {
        match self {
            Self::Product(_) => "observer × √emission importance (¾) with visible importance (¼)",
            Self::Uniform => "uniform sampling",
            Self::Mixture(m) if !m.has_emission() => "visible-importance sampling",
            Self::Mixture(m) if m.emission_weight() >= 1.0 => {
                "all from the lights' spectra (render plan: all emission is narrowband)"
            }
            Self::Mixture(_) => "half visible-importance, half from the lights' spectra",
        }
    }
}
