//! What a render samples: which integrator (`--integrator bdpt|pt|lt`), which wavelengths a
//! camera/light path pair carries, and which light is handled by which strategies (for the
//! render summary).
//!
//! # Wavelengths of a path pair (BDPT and light tracing)
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
//! Lanes that land on a delta spectral line are dropped (pdf 0): lights evaluate only the
//! continuous part of their SPD.

use super::{RenderError, RenderResult, RenderSettings, SampleRng};
use crate::light::LightFlags;
use crate::scene::Scene;
use crate::spectrum::wavelength_sampling::{rotated, visible_pdf, visible_sample};
use crate::spectrum::{SampledWavelengths, Spd, LANES};
use std::sync::Arc;

/// The light transport algorithm of a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum IntegratorKind {
    /// Bidirectional path tracing with power-heuristic MIS over all (s, t) strategies.
    #[default]
    Bdpt,
    /// Unidirectional path tracing with next-event estimation.
    Pt,
    /// Light tracing: light paths connected to the camera (t = 1) only.
    Lt,
}

impl std::str::FromStr for IntegratorKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "bdpt" => Ok(Self::Bdpt),
            "pt" | "path" => Ok(Self::Pt),
            "lt" | "light" => Ok(Self::Lt),
            other => Err(format!(
                "unknown integrator {other:?}: expected bdpt, pt or lt"
            )),
        }
    }
}

impl std::fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Bdpt => "bdpt",
            Self::Pt => "pt",
            Self::Lt => "lt",
        })
    }
}

/// The one-sample mixture `½ p_vis + ½ p_emit` over wavelengths (see the module docs).
#[derive(Clone, Debug)]
pub struct WavelengthMixture {
    /// Distinct SPDs of evaluable lights with their summed light-pmf weights (Σ = 1).
    spds: Vec<(Arc<dyn Spd>, f64)>,
    cdf: Vec<f64>,
}

impl WavelengthMixture {
    /// The mixture for `scene`'s evaluable lights (beams-only lights bring their own
    /// wavelengths and are left out). Without such lights it is `p_vis` alone.
    pub fn new(scene: &Scene) -> Self {
        let mut spds: Vec<(Arc<dyn Spd>, f64)> = Vec::new();
        for (i, l) in scene.lights.lights().iter().enumerate() {
            let pmf = scene.lights.pmf(i) as f64;
            if l.flags().contains(LightFlags::BEAMS_ONLY) || !(pmf > 0.0) {
                continue;
            }
            let spd = l.spd();
            match spds.iter_mut().find(|(s, _)| Arc::ptr_eq(s, &spd)) {
                Some(e) => e.1 += pmf,
                None => spds.push((spd, pmf)),
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
        Self { spds, cdf }
    }

    /// Mixture density (1/nm) at `lambda_nm` (continuous parts only).
    pub fn pdf(&self, lambda_nm: f64) -> f64 {
        let vis = visible_pdf(lambda_nm);
        if self.spds.is_empty() {
            return vis;
        }
        0.5 * vis + 0.5 * self.emission_pdf(lambda_nm)
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

    /// Lane `i` at `frac(u + i/LANES)`, drawn from `spd` (visible importance without one) and
    /// carrying `density` at its wavelength; a lane on a delta line gets pdf 0.
    fn lanes(u: f64, spd: Option<&dyn Spd>, density: impl Fn(f64) -> f64) -> SampledWavelengths {
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
            lambda[i] = l;
            pdf[i] = if on_line {
                0.0
            } else {
                density(l as f64) as f32
            };
        }
        SampledWavelengths { lambda, pdf }
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
        Some(Self::lanes(u, Some(spd), |l| self.emission_pdf(l)))
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
        let emission = !self.spds.is_empty() && u_comp >= 0.5;
        let spd = emission.then(|| self.pick_spd(u_spd));
        Self::lanes(u, spd, |l| self.pdf(l))
    }
}

/// One line per light of the scene saying which strategies of `kind` render it.
pub fn strategy_summary(scene: &Scene, kind: IntegratorKind) -> Vec<String> {
    scene
        .lights
        .lights()
        .iter()
        .enumerate()
        .map(|(i, l)| {
            let f = l.flags();
            let what = if f.contains(LightFlags::BEAMS_ONLY) {
                "beams-only light"
            } else if f.contains(LightFlags::DELTA_DIRECTION) {
                "directional light"
            } else if f.contains(LightFlags::DELTA_POSITION) {
                "point-like light"
            } else {
                "area light"
            };
            let how = match (kind, f.contains(LightFlags::BEAMS_ONLY), f.is_delta()) {
                (_, true, _) if kind == IntegratorKind::Pt => {
                    "NOT rendered by pt (beams can only be light traced; use bdpt or lt)"
                }
                (_, true, _) => "light tracing of its beams (t = 1 splats, unweighted)",
                (IntegratorKind::Pt, _, true) => "pt: next-event estimation only",
                (IntegratorKind::Pt, _, false) => "pt: next-event estimation + BSDF hits (MIS)",
                (IntegratorKind::Lt, _, _) => "lt: light paths connected to the camera (t = 1)",
                (IntegratorKind::Bdpt, _, true) => {
                    "bdpt: all strategies with s ≥ 1 (never hit by camera paths), power-heuristic MIS"
                }
                (IntegratorKind::Bdpt, _, false) => {
                    "bdpt: all (s, t) strategies incl. s = 0 and t = 1, power-heuristic MIS"
                }
            };
            format!(
                "light {i} ({what}, {:.4} W, chosen with p = {:.4}): {how}",
                l.power(),
                scene.lights.pmf(i)
            )
        })
        .collect()
}

/// A finished render with the integrator's extras.
#[derive(Clone, Debug)]
pub struct IntegratorOutput {
    /// The image and the summary numbers.
    pub result: RenderResult,
    /// BDPT only, when asked for: each strategy's weighted contribution, labelled `(s, t)`;
    /// the label `(u32::MAX, u32::MAX)` holds all longer paths together.
    pub strategy_images: Vec<((u32, u32), crate::film::XyzImage)>,
    /// Contributions refused by the film's guard (NaN, infinite or negative); details in
    /// `film.rejected`.
    pub non_finite: u64,
    /// Per pixel (row-major), the largest luminance Y of one sample's contribution to that
    /// pixel's sum (before the 1/spp scaling), for firefly checks; empty for `pt`.
    pub max_sample_y: Vec<f64>,
    /// The exact film the image was made from (whole passes only), for slices and checkpoints.
    pub film: crate::film::FilmState,
}

/// Render `scene` with the integrator `kind`. `strategy_images` asks BDPT for one image per
/// (s, t) strategy (ignored by the other integrators).
pub fn render_with(
    scene: &Scene,
    settings: &RenderSettings,
    kind: IntegratorKind,
    strategy_images: bool,
    progress: &super::render::ProgressFn<'_>,
    cancel: Option<&std::sync::atomic::AtomicBool>,
) -> Result<IntegratorOutput, RenderError> {
    match kind {
        IntegratorKind::Pt => {
            let (result, film) = super::render::render_pt(scene, settings, progress, cancel)?;
            Ok(IntegratorOutput {
                result,
                strategy_images: Vec::new(),
                non_finite: film.rejected.total(),
                max_sample_y: Vec::new(),
                film,
            })
        }
        IntegratorKind::Bdpt => {
            super::bdpt::render_bdpt(scene, settings, strategy_images, progress, cancel)
        }
        IntegratorKind::Lt => {
            super::light_tracer::render_light_tracing(scene, settings, progress, cancel)
        }
    }
}

/// Write BDPT's strategy images as `DIR/strategy_s{s}_t{t}.exr` (and `strategy_longer.exr`),
/// creating `DIR`; returns the files written.
pub fn write_strategy_images(
    dir: &std::path::Path,
    output: &IntegratorOutput,
    scene: &Scene,
) -> Result<Vec<std::path::PathBuf>, String> {
    if output.strategy_images.is_empty() {
        return Ok(Vec::new());
    }
    std::fs::create_dir_all(dir).map_err(|e| {
        format!(
            "cannot create strategy image directory {}: {e}",
            dir.display()
        )
    })?;
    let mut written = Vec::new();
    for ((s, t), image) in &output.strategy_images {
        if (*s, *t) == (0, 1) {
            continue; // not a strategy (the lens is not in the scene); always black
        }
        let name = if *s == u32::MAX {
            "strategy_longer.exr".to_string()
        } else {
            format!("strategy_s{s}_t{t}.exr")
        };
        let path = dir.join(name);
        crate::film::write_exr(&path, image, &scene.options.rgb_space)
            .map_err(|e| e.to_string())?;
        written.push(path);
    }
    Ok(written)
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
