//! The wavelengths of a camera/light path pair (BDPT and light tracing) in fluorescent and
//! narrowband scenes and under `--wavelength-sampling visible`, drawn from
//! [`WavelengthMixture`] (elsewhere the pair draws from the observer × √emission table, see
//! [`crate::integrator::wavelengths::pairs`]); the path tracer's light-SPD sampling and the render plan's
//! narrowband mixture use it too.
//!
//!
//! A connection joins a camera subpath and a light subpath, so both must carry the same
//! wavelengths. Camera paths prefer the observer's sensitivity (the visible-importance density
//! `p_vis`), light paths prefer what the lights emit (`p_emit = Σ_L P(L)·S_L(λ)`, the SPDs of
//! the evaluable lights weighted by the power-proportional light pmf). One wavelength set per
//! pair is drawn from the one-sample mixture `p(λ) = ½ p_vis(λ) + ½ p_emit(λ)` (a fair coin picks
//! the component, then a light's SPD by power if it is the emission component; the hero and its
//! rotations `frac(u + i/LANES)` come from that component's inverse CDF). Each lane's marginal
//! density is exactly the mixture, which is stored as its pdf: this is the balance heuristic
//! between the two spectral strategies. Because the wavelengths are drawn independently of the
//! light chosen for the light subpath and shared by every (s, t) strategy of the pair, the
//! wavelength density is a common factor of all strategies and cancels in their MIS weights.
//! A lane that lands on a delta spectral line carries the line's discrete probability
//! (emission-component probability × the line's share of the emission). When the render plan
//! finds all emission narrowband (and no fluorescence), the emission component is drawn
//! with probability 1 instead of ½ ([`WavelengthMixture::emission_only`]).

use crate::integrator::SampleRng;
use crate::light::LightFlags;
use crate::scene::Scene;
use crate::spectrum::spd::{is_line_lane, line_mass_at_lane, off_lines};
use crate::spectrum::wavelength_sampling::{
    rotated, visible_pdf, visible_sample, VISIBLE_CENTRE, VISIBLE_RANGE, VISIBLE_SHARPNESS,
};
use crate::spectrum::wavelength_table::WavelengthTable;
use crate::spectrum::{DeltaLine, LaneMask, SampledWavelengths, Spd, LANES};
use std::sync::Arc;

/// The one-sample mixture `½ p_vis + ½ p_emit` over wavelengths (see the module docs).
#[derive(Clone, Debug)]
pub struct WavelengthMixture {
    /// Distinct SPDs of evaluable lights with their summed light-pmf weights (Σ = 1).
    spds: Vec<(Arc<dyn Spd>, f64)>,
    cdf: Vec<f64>,
    /// Every delta line of the emission component, weight = P(SPD) × line fraction.
    lines: Vec<DeltaLine>,
    /// Probability of the emission component (½; 1 when the render plan finds all emission
    /// narrowband, where observer draws almost never see a light).
    emission_weight: f64,
    /// Per scene light, its entry in `spds` (`None` for beams-only lights): bdpt's light
    /// subpaths draw their own wavelengths from their light's spectrum in a fluorescent scene.
    light_spd: Vec<Option<usize>>,
}

impl WavelengthMixture {
    /// The mixture for `scene`'s evaluable lights (beams-only lights bring their own
    /// wavelengths and are left out). Without such lights it is `p_vis` alone.
    pub fn new(scene: &Scene) -> Self {
        let mut spds: Vec<(Arc<dyn Spd>, f64)> = Vec::new();
        let mut light_spd = Vec::with_capacity(scene.lights.lights().len());
        for (i, l) in scene.lights.lights().iter().enumerate() {
            let pmf = scene.lights.pmf(i) as f64;
            if l.flags().contains(LightFlags::BEAMS_ONLY) || !(pmf > 0.0) {
                light_spd.push(None);
                continue;
            }
            let spd = l.spd();
            match spds.iter_mut().position(|(s, _)| Arc::ptr_eq(s, &spd)) {
                Some(e) => {
                    spds[e].1 += pmf;
                    light_spd.push(Some(e));
                }
                None => {
                    light_spd.push(Some(spds.len()));
                    spds.push((spd, pmf));
                }
            }
        }
        let total: f64 = spds.iter().map(|e| e.1).sum();
        let mut acc = 0.0;
        let mut cdf = Vec::with_capacity(spds.len());
        for e in &mut spds {
            e.1 /= total;
            acc += e.1;
            cdf.push(acc);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        let lines = spds
            .iter()
            .flat_map(|(s, w)| {
                s.delta_lines().into_iter().map(move |l| DeltaLine {
                    lambda: l.lambda,
                    weight: l.weight * w,
                })
            })
            .collect();
        Self {
            spds,
            cdf,
            lines,
            emission_weight: 0.5,
            light_spd,
        }
    }

    /// True when every emitting SPD is narrowband: delta lines only, or lines plus a continuous
    /// part whose equivalent width is below
    /// [`NARROWBAND_WIDTH_NM`](crate::spectrum::bandwidth::NARROWBAND_WIDTH_NM). Then almost
    /// every observer draw lands where no light emits.
    pub fn all_narrowband(&self) -> bool {
        use crate::spectrum::bandwidth::{equivalent_width_nm, NARROWBAND_WIDTH_NM};
        !self.spds.is_empty()
            && self
                .spds
                .iter()
                .all(|(s, _)| equivalent_width_nm(s.as_ref()) < NARROWBAND_WIDTH_NM)
    }

    /// The mixture drawing from the emission component alone (weight 1). Unbiased whenever
    /// nothing shifts wavelengths: a camera or light path carries light only at wavelengths
    /// some light emits, and there the emission density is positive. Worth it when all
    /// emission is narrowband ([`all_narrowband`](Self::all_narrowband)), where the observer
    /// component's draws almost always miss and only add variance. The render plan decides.
    pub fn emission_only(mut self) -> Self {
        if !self.spds.is_empty() {
            self.emission_weight = 1.0;
        }
        self
    }

    /// Probability of the emission component.
    pub fn emission_weight(&self) -> f64 {
        self.emission_weight
    }

    /// The observer's visible-importance density alone (no emission component): what the
    /// render plan uses when narrowband emission is switched off.
    pub fn visible_only() -> Self {
        Self {
            spds: Vec::new(),
            cdf: Vec::new(),
            lines: Vec::new(),
            emission_weight: 0.0,
            light_spd: Vec::new(),
        }
    }

    /// True when the emission component has delta lines.
    pub fn has_lines(&self) -> bool {
        !self.lines.is_empty()
    }

    /// Mixture density (1/nm) at `lambda_nm` (continuous parts only).
    pub fn pdf(&self, lambda_nm: f64) -> f64 {
        let vis = visible_pdf(lambda_nm);
        if self.spds.is_empty() {
            return vis;
        }
        let w = self.emission_weight;
        (1.0 - w) * vis + w * self.emission_pdf(lambda_nm)
    }

    /// What [`sample_with`](Self::sample_with) stores as the pdf of a lane at `lambda_nm` (as
    /// the lane holds it): the discrete probability of a delta line when the lane sits exactly
    /// on one, else the mixture density (1/nm). bdpt's MIS needs it where a fluorescent shift
    /// makes the other end of a path carry a wavelength the mixture did not draw.
    pub fn lane_density(&self, lambda_nm: f32) -> f64 {
        let mass = line_mass_at_lane(&self.lines, lambda_nm);
        if mass > 0.0 {
            self.emission_weight * mass
        } else {
            self.pdf(lambda_nm as f64)
        }
    }

    /// True when the scene has evaluable lights, i.e. the emission component exists.
    pub fn has_emission(&self) -> bool {
        !self.spds.is_empty()
    }

    /// The emission component alone, `p_emit(λ) = Σ_L P(L)·S_L(λ)` (1/nm, continuous parts);
    /// 0 everywhere without evaluable lights.
    pub fn emission_pdf(&self, lambda_nm: f64) -> f64 {
        self.spds.iter().map(|(s, w)| w * s.pdf(lambda_nm)).sum()
    }

    /// The light SPD `u_spd` picks by power (the scene must have evaluable lights).
    fn pick_spd(&self, u_spd: f64) -> &dyn Spd {
        let k = self
            .cdf
            .partition_point(|&c| c <= u_spd)
            .min(self.spds.len() - 1);
        self.spds[k].0.as_ref()
    }

    /// Lane `i` at `frac(u + i/LANES)`, drawn from `spd` (visible importance without one);
    /// a continuous lane carries `density` at its wavelength, a lane on a delta line the
    /// line's discrete probability `line_scale × P(line)`.
    fn lanes(
        &self,
        u: f64,
        spd: Option<&dyn Spd>,
        line_scale: f64,
        density: impl Fn(f64) -> f64,
    ) -> SampledWavelengths {
        let mut lambda = [0.0f32; LANES];
        let mut pdf = [0.0f32; LANES];
        for i in 0..LANES {
            let ui = rotated(u, i, LANES);
            let (l, on_line) = match spd {
                Some(s) => {
                    let d = s.sample(ui);
                    (d.lambda as f32, d.is_delta)
                }
                None => (visible_sample(ui) as f32, false),
            };
            if on_line {
                lambda[i] = l;
                pdf[i] = (line_scale * line_mass_at_lane(&self.lines, l)) as f32;
            } else {
                let l = off_lines(l, &self.lines);
                lambda[i] = l;
                pdf[i] = density(l as f64) as f32;
            }
        }
        SampledWavelengths {
            lambda,
            pdf,
            lanes: LaneMask::ALL,
        }
    }

    /// Wavelengths from the emission component alone (path tracing's light-SPD sampling):
    /// `u_spd` picks a light SPD by power, lane `i` is its inverse CDF at `frac(u + i/LANES)`
    /// and carries [`emission_pdf`](Self::emission_pdf), its marginal density; lanes on a delta
    /// line get pdf 0. `None` without evaluable lights.
    pub fn sample_emission(&self, u_spd: f64, u: f64) -> Option<SampledWavelengths> {
        if self.spds.is_empty() {
            return None;
        }
        let spd = self.pick_spd(u_spd);
        Some(self.lanes(u, Some(spd), 1.0, |l| self.emission_pdf(l)))
    }

    /// bdpt's own light wavelengths in a fluorescent scene: lane `i` drawn from light
    /// `light`'s spectrum at `frac(u + i/LANES)`, each lane carrying
    /// [`light_lane_density`](Self::light_lane_density) (a line's share of that spectrum on a
    /// line, the density elsewhere). `None` for a light without an evaluable spectrum here
    /// (beams-only, or a mixture built without lights).
    pub fn sample_light(&self, light: usize, u: f64) -> Option<SampledWavelengths> {
        let spd = self.spds[(*self.light_spd.get(light)?)?].0.as_ref();
        let mut out = SampledWavelengths {
            lambda: [0.0; LANES],
            pdf: [0.0; LANES],
            lanes: LaneMask::ALL,
        };
        for i in 0..LANES {
            let d = spd.sample(rotated(u, i, LANES));
            let l = if d.is_delta {
                d.lambda as f32
            } else {
                off_lines(d.lambda as f32, &self.lines)
            };
            out.lambda[i] = l;
            out.pdf[i] = self.light_lane_density(light, l) as f32;
        }
        Some(out)
    }

    /// The probability with which [`sample_light`](Self::sample_light) for light `light` gives
    /// a lane at `lambda_nm` (as the lane stores it): the share of the light's spectrum in a
    /// line there (discrete), 0 on another light's line (continuous draws are moved off every
    /// line), else the spectrum's density (1/nm).
    pub fn light_lane_density(&self, light: usize, lambda_nm: f32) -> f64 {
        let Some(Some(e)) = self.light_spd.get(light) else {
            return 0.0;
        };
        let spd = self.spds[*e].0.as_ref();
        if is_line_lane(&self.lines, lambda_nm) {
            return spd
                .delta_lines()
                .iter()
                .filter(|l| l.lambda as f32 == lambda_nm)
                .map(|l| l.weight)
                .sum();
        }
        spd.pdf(lambda_nm as f64)
    }

    /// Draw the pair's wavelengths: three uniforms from `rng` (component, SPD, hero).
    pub fn sample(&self, rng: &mut SampleRng) -> SampledWavelengths {
        let u_comp = rng.next_1d();
        let u_spd = rng.next_1d() as f64;
        let u = rng.next_1d() as f64;
        self.sample_with(u_comp, u_spd, u)
    }

    /// [`sample`](Self::sample) from given uniforms: `u_comp` picks the component, `u_spd` the
    /// light SPD, `u` the hero (for callers with stratified samples). Every lane carries the
    /// mixture density [`pdf`](Self::pdf).
    pub fn sample_with(&self, u_comp: f32, u_spd: f64, u: f64) -> SampledWavelengths {
        let w = self.emission_weight;
        let emission = !self.spds.is_empty() && u_comp as f64 >= 1.0 - w;
        let spd = emission.then(|| self.pick_spd(u_spd));
        self.lanes(u, spd, w, |l| self.pdf(l))
    }
}

/// Share of the visible-importance density in [`WavelengthSampling::Product`](crate::integrator::WavelengthSampling::Product)'s mixture (the
/// rest is visible importance × emission; see [`super::groups`] for how it was chosen).
pub const PRODUCT_VISIBLE_SHARE: f64 = 0.25;

/// The table of [`WavelengthSampling::Product`](crate::integrator::WavelengthSampling::Product) for the emission component of `mixture`
/// (which must have one): `(1 − s)·V·√p_emit/∫V·√p_emit + s·V/∫V` on [`VISIBLE_RANGE`],
/// with `s` = [`PRODUCT_VISIBLE_SHARE`] and `V` the smooth visible-importance shape. An error
/// when the lights emit nothing inside the visible range.
pub fn product_table(mixture: &WavelengthMixture) -> Result<WavelengthTable, String> {
    let visible = |l: f64| {
        let c = (VISIBLE_SHARPNESS * (l - VISIBLE_CENTRE)).cosh();
        1.0 / (c * c)
    };
    let product = |l: f64| visible(l) * mixture.emission_pdf(l).sqrt();
    WavelengthTable::from_mixture(
        VISIBLE_RANGE,
        &[
            (1.0 - PRODUCT_VISIBLE_SHARE, &product),
            (PRODUCT_VISIBLE_SHARE, &visible),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each lane's stored pdf is the density it was drawn with: the Monte Carlo estimate of
    /// ∫_{400}^{700} 1 dλ = 300 nm from 2·10⁵ pair draws (×4 lanes) on the Cornell box (its
    /// measured light SPD as the emission component) is within 1% (the estimator's relative
    /// standard error here is below 0.2%).
    #[test]
    fn mixture_pdf_matches_its_draws() {
        let scene = crate::scene::default_scene().unwrap();
        let m = WavelengthMixture::new(&scene);
        let n = 200_000;
        let mut sum = 0.0f64;
        for k in 0..n {
            let mut rng = SampleRng::for_sample(3, k, 0);
            let w = m.sample(&mut rng);
            for i in 0..LANES {
                let l = w.lambda[i] as f64;
                if (400.0..700.0).contains(&l) && w.pdf[i] > 0.0 {
                    sum += 1.0 / w.pdf[i] as f64;
                }
            }
        }
        let est = sum / (n as f64 * LANES as f64);
        assert!((est / 300.0 - 1.0).abs() < 0.01, "{est}");
    }
}
