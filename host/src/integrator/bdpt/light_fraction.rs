//! The fraction `q` of BDPT's camera samples that trace light subpaths and the number `L` each
//! traces, and the pilot that chooses them per scene (after Grittmann, Yazici, Georgiev,
//! Slusallek 2022, "Efficiency-aware multiple importance sampling for bidirectional rendering
//! algorithms", ACM TOG 41(4) 80: choose the sample counts of the techniques, the number of
//! light paths among them, by a variance-times-cost estimate from a short pilot, and weigh the
//! techniques by those counts). Their candidates include no light paths at all: their renderer
//! starts with unidirectional path tracing and enables bidirectional techniques where the
//! estimate says they pay, computing the efficiency of other combinations from one
//! combination's samples. Here the limit `q = 0` is that candidate (`super::path_traced`: the
//! path tracer renders the image), where path tracing samples every path BDPT does.
//!
//! **The mechanism** (`bdpt.rs`): each camera sample traces its `L` light subpaths with
//! probability `q`, decided by a stratified dimension of the pixel's sampler
//! ([`super::dimensions::LIGHT_FRACTION`]): a pixel's samples trace about `q` of them. The
//! first is joined to every camera vertex, the others to the camera only (t = 1). When traced,
//! every strategy that uses a light subpath is divided by its expected count (`q` for s ≥ 2
//! with t ≥ 2, `q·L` for t = 1); s = 0 and s = 1 (next-event estimation) run in every camera
//! sample. The power heuristic weighs each strategy by its expected count ([`SampleCounts`]),
//! so the estimate stays unbiased (Wald's identity). The specular-chain and camera-chain
//! connections compete with s = 0 only (no other strategy makes their paths), so their weights
//! do not involve `q` or `L`.
//!
//! **The choice** ([`LightSubpaths::Auto`] and [`LightSubpathCount::Auto`], the defaults): a
//! deterministic pilot of [`PILOT_PIXELS`] pixels on a regular grid × [`PILOT_SPP`] samples
//! (its own seed derived from the render's, fixed chunks reduced in order: the same choice at
//! any thread count) renders with `q = 1` and the largest candidate count `L_p`
//! ([`Candidates`]: `q` in [`CANDIDATES`] × `L` in [`COUNTS`] where the scene has delta
//! surfaces, else `L = 1`; a forced fraction or count leaves the other to choose). Per camera
//! sample and candidate it splits the sample's weighted luminance `Y` under that candidate's
//! weights (all from one evaluation of the weight's parts, [`super::mis::PilotTerms`]) into
//! `A` (s = 0, s = 1 and the chain connections: count 1) and `C` (the light-subpath
//! strategies: the first subpath's joins `J`, and light tracing `T`, booked at the pixel each
//! splat lands in). The candidate's estimator is `A + (B/q)·C`, `B ~ Bernoulli(q)`, so per
//! pixel `E[X²] = E[A²] + 2E[A·C] + E[C²]/q`; its variance is that minus the square of the
//! pixel's own-part mean `E[A + C]` (the candidates move weight between the pixel's own
//! strategies and the t = 1 splats it receives; the splats' mean per camera sample is
//! negligible), summed over the pilot's pixels, leaving out the paths whose first camera-side
//! vertex is an emitter (as the bench leaves those pixels out: s = 0 makes them without
//! noise, while the power heuristic gives light tracing a share there). `T = (1/L)·Σ_{j<L} t_j`
//! over single-subpath values `t_j`, which are exchangeable, so every candidate `L` reads all
//! `L_p` of the pilot's subpaths ([`PilotSample::finish_sample`]). The cost per camera sample
//! is `cost_A + q·(cost_first + (L − 1)·cost_further)` from deterministic counts
//! ([`CostWeights`]), never a clock. The pilot picks the candidate maximising
//! `1/(variance·cost)` in two steps ([`Choice::from_sums`]): the fraction at `L = 4`, leaving
//! `q = 1` only where another is estimated at least [`MIN_GAIN`] better, then another count
//! only where it is estimated [`MIN_GAIN_COUNT`] better than that. The render says what it
//! chose and each candidate's estimate.
//!
//! **`q = 0`** (no light subpaths; the camera samples are path traced, `super::path_traced`):
//! offered where path tracing samples every path BDPT does (`path_traced::refusal`), chosen
//! where its estimate beats every `q > 0` by [`MIN_GAIN`]. Its variance, in the same definition,
//! is the larger of two estimates ([`PtPilotSums::estimate`]): the path tracer's own samples on
//! the same pilot pixels, samples and seed, and its second moment estimated from BDPT's pilot
//! samples, each weighed by the path tracer's densities of its path relative to the sampling
//! strategy's ([`PilotSample::book_pt`]), minus the pixels' squared means per path length.
//! The second sees the paths the path tracer finds rarely and light tracing finds (a caustic
//! core): on the spectral caustic at 64×48 the first gives 4.4 and the second 641 (BDPT at
//! q = 1: 25). Where both see everything they agree: 3.50 and 3.55 on the Cornell box, 5.2e-4
//! and 5.3e-4 in the window room (full size, seed 3). Its cost is [`PT_COST_WEIGHTS`] of the
//! path tracer's counted rays and shadow rays.
//!
//! | constant        | value                   | meaning                                        |
//! |-----------------|-------------------------|------------------------------------------------|
//! | `CANDIDATES`    | 1, ½, ¼, ⅛, 1/16        | BDPT's fractions the pilot compares            |
//! | `COUNTS`        | 1, 2, 4, 8              | light subpaths per camera sample it compares (scenes with delta surfaces; else 1) |
//! | `MIN_EXPECTED_SUBPATHS` | ¼               | fewest `q·L` of a candidate where counts are compared |
//! | (q = 0)         | path traced             | compared where eligible (`path_traced`)        |
//! | `PILOT_PIXELS`  | 1024                    | pixels of the pilot (a grid over the image)    |
//! | `PILOT_SPP`     | 8                       | camera samples per pilot pixel                 |
//! | `MIN_GAIN`      | 1.05                    | estimated efficiency gain needed to leave q = 1, and for q = 0 over every q > 0 |
//! | `MIN_GAIN_COUNT`| 1.15                    | estimated gain over the best fraction at L = 4 needed to take another L |
//!
//! The pilot costs 1024 × 8 BDPT camera samples at `L_p = 8` (and as many path-traced ones
//! where `q = 0` is offered): 0.02–0.10 s on the bench scenes at 160 × 120 on a loaded 2-core
//! machine (the run-time note prints it).
//!
//! Measured (docs/performance.md, "BDPT and its own strategies": instructions per camera
//! sample from callgrind, per-pixel variance from six seeds; efficiency 1/(MSE·instructions)
//! over the pixels that do not see an emitter, relative to `q = 1`, at `L = 4` where the scene
//! has delta surfaces):
//!
//! | scene                     | auto's `q` | q = ¼ | q = 1/16 | `pt` = q = 0 |
//! |---------------------------|------------|-------|----------|-------|
//! | `cornell_box.ron` (128²)  | 0 (predicted 1.44–1.76) | 0.84  | 0.80     | 1.29  |
//! | `bench/window_room.ron`   | 0 (predicted 1.8–2.5) | 1.28 | 1.33 (guided: 2.5) | 4.25 (guided BDPT at 1/16: 1.69× it) |
//! | `bench/glossy_metals.ron` | 1          | 0.71  | 0.39     | 0.28  |
//! | `bench/glass_sphere_mesh.ron` | 1      | 0.67  | 0.19     | 0.13  |
//! | `bench/spectral_caustic.ron` | ½ (most seeds; predicted 1.2) | 1.66 | – (½: 1.40) | – |
//!
//! The pilot picks the best candidate on all five: where `pt` is ahead (the Cornell box, the
//! window room) BDPT's camera part costs more per sample than `pt`'s whole sample, so no
//! `q > 0` reaches it, and `q = 0` renders `pt`'s image. The pilot's predicted variance ratio
//! of `q = 0` to `q = 1` against renders: 2.03 predicted, 1.92 measured on the Cornell box
//! (64×48), 0.79 and 0.87 in the window room (80×60; `integrators_bdpt_light_fraction`).
//!
//! The count `L`: measured against `L = 4` in [`super::LIGHT_PATHS`]'s table (the prism takes
//! `L = 8`, 1.29× measured for 1.24× predicted; the pilot's Var(L = 1)/Var(L = 4) and
//! Var(L = 8)/Var(L = 4) against renders: 1.86 and 0.80 predicted, 1.70 and 0.83 measured
//! on the spectral caustic, 3.05 and 0.64 against 2.88 and 0.67 on the glass sphere, 80 × 60,
//! `integrators_bdpt_light_fraction`; the cost model's ratio of `L = 8` to `L = 4` per camera
//! sample: 1.58, 1.58 and 1.62 against callgrind's 1.46, 1.52 and 1.62 on the glass sphere,
//! the spectral caustic and `caustic.ron`).
//!
//! Kept at `q = 1` with `L` = [`super::LIGHT_PATHS`] where the scene has delta surfaces (said
//! at run time; `--effect light-subpath-count` still sets `L`): scenes with beams-only lights
//! (their subpaths are light tracing alone) and scenes that render fluorescence (its two
//! light-subpath modes are not covered by the pilot and untested with `q < 1`).

use super::mis::{PilotTerms, SampleCounts};
use glam::Vec2;
use rayon::prelude::*;

pub use crate::integrator::plan::{LightSubpathCount, LightSubpaths};

/// The fractions the pilot compares, `q = 1` first.
pub const CANDIDATES: [f32; 5] = [1.0, 0.5, 0.25, 0.125, 0.0625];

/// The numbers of light subpaths per camera sample the pilot compares in scenes with delta
/// surfaces (`super::light_paths_for`; elsewhere 1).
pub const COUNTS: [u32; 4] = [1, 2, 4, 8];

/// Fewest light subpaths per camera sample (`q·L`) of a candidate where the pilot compares
/// counts: today's smallest without the count (q = 1/16 with 4 subpaths). Why: the pilot sees
/// the variance of the paths its own samples make. A candidate with few light subpaths hands
/// a caustic to the camera paths that hit the lamp through glass (s = 0), which the pilot's
/// few thousand camera samples rarely make: its estimate of those candidates falls where
/// their variance rises (the glass sphere: variance estimated 5× lower at q = 1/16, L = 1
/// than at q = 1, L = 1, so that candidate looked 4× as efficient as the base).
pub const MIN_EXPECTED_SUBPATHS: f32 = 0.25;

/// Most candidates (q, L) a pilot compares.
pub const MAX_CANDIDATES: usize = CANDIDATES.len() * COUNTS.len();

/// The candidates (q, L) of one pilot: fraction `q` of camera samples tracing light
/// subpaths, `L` light subpaths each; the pilot renders at `q = 1` with the largest `L`
/// ([`pilot_paths`](Self::pilot_paths)), and `base` is the one kept unless another is
/// estimated [`MIN_GAIN`] better.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Candidates {
    list: [(f32, u32); MAX_CANDIDATES],
    len: usize,
    base: usize,
}

impl Default for Candidates {
    fn default() -> Self {
        Self::new(&CANDIDATES, &[1], 1)
    }
}

impl Candidates {
    /// The pairs of `fractions` × `counts` (each non-empty, at most [`CANDIDATES`] and
    /// [`COUNTS`] long), the base being the first fraction with `base_count` (or the count
    /// nearest to it). Where the counts are compared (more than one), the pairs with fewer
    /// than [`MIN_EXPECTED_SUBPATHS`] light subpaths per camera sample (`q·L`) are left out,
    /// except the first fraction's.
    pub fn new(fractions: &[f32], counts: &[u32], base_count: u32) -> Self {
        assert!(!fractions.is_empty() && !counts.is_empty());
        assert!(fractions.len() * counts.len() <= MAX_CANDIDATES);
        let mut list = [(1.0, 1); MAX_CANDIDATES];
        let mut len = 0;
        for &l in counts {
            for (i, &q) in fractions.iter().enumerate() {
                let few = counts.len() > 1 && q * (l as f32) < MIN_EXPECTED_SUBPATHS;
                if i == 0 || !few {
                    list[len] = (q, l.max(1));
                    len += 1;
                }
            }
        }
        let l0 = *counts
            .iter()
            .min_by_key(|&&l| (l as i64 - base_count as i64).abs())
            .unwrap_or(&1);
        let base = list[..len]
            .iter()
            .position(|&(q, l)| q == fractions[0] && l == l0)
            .unwrap_or(0);
        Self { list, len, base }
    }

    /// The candidates, (q, L).
    pub fn list(&self) -> &[(f32, u32)] {
        &self.list[..self.len]
    }

    /// The candidate kept unless another is estimated [`MIN_GAIN`] better.
    pub fn base(&self) -> (f32, u32) {
        self.list[self.base]
    }

    /// Light subpaths per camera sample of the pilot: the largest candidate `L`.
    pub fn pilot_paths(&self) -> u32 {
        self.list().iter().map(|c| c.1).max().unwrap_or(1)
    }

    /// The factors by which each candidate multiplies a pilot connection's weighted
    /// contribution: strategy (s, t) with weight `w_pilot` under the pilot's counts and `terms`
    /// its weight's parts. The candidate's weight over the pilot's, and for t = 1 times the
    /// pilot's count `L_p`: light tracing is booked per subpath, undivided (`l·w`), and
    /// [`PilotSample::finish_sample`] forms each candidate's mean over its `L` subpaths. The
    /// fraction's `1/q` is the estimator's (`PilotSums::estimates`), not the booking's.
    pub fn ratios(
        &self,
        terms: &PilotTerms,
        (s, t): (usize, usize),
        w_pilot: f32,
    ) -> [f64; MAX_CANDIDATES] {
        let mut out = [0.0; MAX_CANDIDATES];
        if !(w_pilot > 0.0) {
            return out;
        }
        let lp = self.pilot_paths() as f64;
        for (o, &(q, l)) in out.iter_mut().zip(self.list()) {
            let w = terms.weight(s, t, counts(l, q));
            *o = (w / w_pilot) as f64;
            if t == 1 {
                *o *= lp;
            }
        }
        out
    }
}

/// What the pilot learns of one connection besides its weight: the parts of its weight
/// ([`PilotTerms`]), from which its weight under each candidate follows, and the path
/// tracer's squared densities for its path.
#[derive(Clone, Copy, Debug, Default)]
pub struct AltWeights {
    /// The weight's parts and `(p₀/p)²`, `(p₁/p)²`.
    pub terms: PilotTerms,
}

/// Pilot pixels (a regular grid over the image; fewer when the image is smaller).
pub const PILOT_PIXELS: u32 = 1024;

/// Camera samples per pilot pixel (its within-pixel variance needs several).
pub const PILOT_SPP: u32 = 8;

/// Pilot pixels per work unit (fixed, so the reduction order never depends on threads).
const CHUNK: usize = 32;

/// Estimated efficiency gain over `q = 1` below which `q = 1` stays (the pilot's estimate
/// scatters by a few percent between seeds).
pub const MIN_GAIN: f64 = 1.05;

/// Estimated efficiency gain over the best fraction at the base count needed to take another
/// count `L`. Why more than [`MIN_GAIN`]: the pilot's estimates of other counts scatter by
/// ~5% between seeds and err by up to ~1.2× where rare bright paths carry much of the
/// variance, which the pilot's few thousand camera samples rarely see (`scenes/materials.ron`,
/// a spot light's caustics through glass: `L = 1` estimated 1.18× the best fraction at
/// `L = 4`, measured 0.97×). With [`MIN_GAIN`] the glass spheres' tie between `L = 4` and
/// `L = 8` (estimated 1.00–1.06× at 80 × 60, measured 0.98×) went to whichever a seed
/// favoured; a count that pays clearly is estimated well above 1.15 (the prism: 1.24×,
/// measured 1.29×).
pub const MIN_GAIN_COUNT: f64 = 1.15;

/// Salt of the pilot's seed, so its numbers are not the render's.
const PILOT_SALT: u64 = 0x6C62_272E_07BB_0142;

/// Deterministic work counts of one part of a camera sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PartCost {
    /// Closest-hit rays (random-walk steps).
    pub rays: u64,
    /// Shadow rays (connections tested for visibility).
    pub shadow_rays: u64,
    /// Connections that reached their MIS weight (BSDF evaluations and the weight's chain).
    pub connections: u64,
}

impl PartCost {
    fn add(&mut self, o: &PartCost) {
        self.rays += o.rays;
        self.shadow_rays += o.shadow_rays;
        self.connections += o.connections;
    }
}

/// Relative costs of the counted events, in instructions (callgrind, see [`COST_WEIGHTS`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CostWeights {
    /// Per closest-hit ray and its vertex (BSDF sampling, densities).
    pub ray: f64,
    /// Per shadow ray.
    pub shadow_ray: f64,
    /// Per connection that reached its weight.
    pub connection: f64,
    /// Per camera sample, whatever it traces (wavelengths, camera ray, sampler).
    pub sample: f64,
}

/// The cost model's weights (instructions), fitted (least squares on relative error) to
/// callgrind instruction counts of BDPT per camera sample at `q = 1` and `q = 1/16` (each the
/// difference of a 3-spp and a 1-spp render at 64×48, `--threads 1`, seed 3), split into the
/// camera part `I_A` and the light part `I_C` (`I(q) = I_A + q·I_C`), against the pilot's
/// counts per camera sample of the same scenes:
///
/// | scene                     | `I_A` | `I_C` | camera rays, shadow rays, connections | light rays, shadow rays, connections | model `I_A`, `I_C` |
/// |---------------------------|-------|-------|------|------|------|
/// | `cornell_box.ron`         | 14.8 k | 25.3 k | 3.10, 1.94, 1.74 | 2.93, 7.19, 5.95 | 1.17×, 0.98× |
/// | `bench/window_room.ron`   | 14.9 k | 6.9 k  | 3.26, 2.92, 0.69 | 1.68, 0.91, 0.91 | 1.04×, 0.93× |
/// | `bench/glass_sphere_mesh.ron` | 18.0 k | 17.9 k | 2.77, 1.17, 0.57 | 7.68, 1.02, 0.40 | 0.74×, 1.03× |
///
/// The glass sphere's camera part is underestimated by a quarter: its specular-chain solves
/// are not counted (they add to the camera part, so the model errs towards q = 1 there).
pub const COST_WEIGHTS: CostWeights = CostWeights {
    ray: 2200.0,
    shadow_ray: 430.0,
    connection: 2500.0,
    sample: 5200.0,
};

/// The path tracer's cost model (the candidate `q = 0`, [`PtPilotSums`]): instructions per
/// camera sample of `--integrator pt` (the difference of a 3-spp and a 1-spp render at 64×48,
/// `--threads 1`, seed 3, over 2·64·48 samples), fitted by non-negative least squares on
/// relative error to the path-tracing pilot's counts per camera sample of the same scenes at
/// 64×48 (seed 3). The free fit (sample −4100, ray 4200, shadow ray −600) is within 2.5% but
/// not physical; the non-negative one puts the sample's own work into its camera ray:
///
/// | scene                         | instructions | rays, shadow rays | model |
/// |-------------------------------|--------------|-------------------|-------|
/// | `cornell_box.ron`             | 10.89 k      | 3.92, 2.43        | 0.98× |
/// | `bench/window_room.ron`       | 14.51 k      | 4.98, 4.46        | 1.00× |
/// | `bench/glass_sphere_mesh.ron` | 7.40 k       | 2.83, 0.86        | 0.96× |
/// | `bench/glossy_metals.ron`     | 12.90 k      | 4.51, 3.12        | 0.97× |
/// | `bench/spectral_caustic.ron`  | 6.96 k       | 2.84, 1.39        | 1.07× |
pub const PT_COST_WEIGHTS: CostWeights = CostWeights {
    ray: 2300.0,
    shadow_ray: 680.0,
    connection: 0.0,
    sample: 0.0,
};

impl CostWeights {
    /// The instructions `part` stands for.
    pub fn of(&self, part: &PartCost) -> f64 {
        self.ray * part.rays as f64
            + self.shadow_ray * part.shadow_rays as f64
            + self.connection * part.connections as f64
    }
}

/// The part of a camera sample's estimate a pilot connection belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Counted once per camera sample: s = 0, s = 1 with t ≥ 2, the chain connections.
    Camera,
    /// The first light subpath's joins (s ≥ 2, t ≥ 2).
    Join,
    /// Light tracing (t = 1) from light subpath `j` (0: the first).
    LightTracing(u32),
}

/// One pixel's bookings within the current camera sample, per candidate: the camera part, the
/// joins, and light tracing's single-subpath values (`l · w`, not divided by a count): the
/// first subpath's, the current further subpath's, and the further subpaths' sum and sum of
/// squares.
#[derive(Clone, Copy, Debug)]
struct Entry {
    pixel: u64,
    a: [f64; MAX_CANDIDATES],
    join: [f64; MAX_CANDIDATES],
    t0: [f64; MAX_CANDIDATES],
    current: [f64; MAX_CANDIDATES],
    sum: [f64; MAX_CANDIDATES],
    sum_sq: [f64; MAX_CANDIDATES],
}

impl Entry {
    fn new(pixel: u64) -> Self {
        let z = [0.0; MAX_CANDIDATES];
        Self {
            pixel,
            a: z,
            join: z,
            t0: z,
            current: z,
            sum: z,
            sum_sq: z,
        }
    }
}

/// The pilot's sums (additive over camera samples, reduced in a fixed order).
#[derive(Clone, Debug, Default)]
pub struct PilotSums {
    /// The candidates these sums are booked for.
    candidates: Candidates,
    /// Per candidate: Σ A², Σ A·C, Σ C² over the camera samples' own pixels.
    own: [[f64; 3]; MAX_CANDIDATES],
    /// The same for the pixels other than the sample's own (t = 1 and camera-chain splats).
    splat: [[f64; 3]; MAX_CANDIDATES],
    /// Per candidate: Σ over pilot pixels of the squared mean of their own-pixel estimate
    /// (`A + C`: the candidates move weight between the pixel's own strategies and the
    /// t = 1 splats, so its own part's mean depends on the candidate).
    mean_sq: [f64; MAX_CANDIDATES],
    /// Camera samples and pixels.
    samples: u64,
    pixels: u64,
    /// Work counts of the camera part, of the first light subpath (with its joins and its
    /// t = 1 connections) and of the further light subpaths (t = 1 only, all of them).
    camera: PartCost,
    light: PartCost,
    further: PartCost,
    /// The path tracer's second moment of `Y` per camera sample, summed over the pilot's
    /// pixels, estimated from these BDPT samples ([`PilotSample::book_pt`]).
    pt_m2: f64,
    /// Connections whose path neither s = 0 nor s = 1 makes (the path tracer would miss it).
    pt_missed: u64,
    /// Σ over pilot pixels and path lengths of the squared mean of the pixel's own-pixel `Y`
    /// of that length (the splats' means left out).
    pt_mean_sq: f64,
}

impl PilotSums {
    fn add(&mut self, o: &PilotSums) {
        if self.samples == 0 {
            self.candidates = o.candidates;
        }
        for k in 0..MAX_CANDIDATES {
            for m in 0..3 {
                self.own[k][m] += o.own[k][m];
                self.splat[k][m] += o.splat[k][m];
            }
        }
        for (m, o) in self.mean_sq.iter_mut().zip(&o.mean_sq) {
            *m += o;
        }
        self.samples += o.samples;
        self.pixels += o.pixels;
        self.camera.add(&o.camera);
        self.light.add(&o.light);
        self.further.add(&o.further);
        self.pt_m2 += o.pt_m2;
        self.pt_missed += o.pt_missed;
        self.pt_mean_sq += o.pt_mean_sq;
    }

    /// The candidates of these sums.
    pub fn candidates(&self) -> &Candidates {
        &self.candidates
    }

    /// Per candidate: (q, L, variance, cost per camera sample, efficiency 1/(variance·cost)).
    /// The variance is the sum over the pilot's pixels of one camera sample's variance of
    /// the pixel's `Y` (within-pixel sample variance for the own-pixel part, with `n − 1`;
    /// the splats' second moment, whose mean per camera sample is negligible, over `n`). The
    /// cost is `cost_A + q·(cost_first + (L − 1)·cost_further)`: the camera part, the first
    /// light subpath with all its connections, and each further light subpath (the pilot's
    /// `L_p − 1` of them averaged).
    pub fn estimates(&self, weights: &CostWeights) -> Vec<Estimate> {
        let n = (self.samples as f64 / self.pixels.max(1) as f64).max(2.0);
        let per_sample = 1.0 / self.samples.max(1) as f64;
        let cost_a = weights.sample + weights.of(&self.camera) * per_sample;
        let cost_first = weights.of(&self.light) * per_sample;
        let further_paths = self.candidates.pilot_paths().saturating_sub(1).max(1) as f64;
        let cost_further = weights.of(&self.further) * per_sample / further_paths;
        self.candidates
            .list()
            .iter()
            .enumerate()
            .map(|(k, &(q, l))| {
                let q64 = q as f64;
                let m2 = |s: &[f64; 3]| s[0] + 2.0 * s[1] + s[2] / q64;
                let variance =
                    (m2(&self.own[k]) - n * self.mean_sq[k]) / (n - 1.0) + m2(&self.splat[k]) / n;
                let cost = cost_a + q64 * (cost_first + (l as f64 - 1.0) * cost_further);
                let efficiency = 1.0 / (variance * cost);
                Estimate {
                    q,
                    light_paths: l,
                    variance,
                    cost,
                    efficiency,
                }
            })
            .collect()
    }
}

/// The pilot's estimate for one candidate (q, L).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// The fraction.
    pub q: f32,
    /// Light subpaths per camera sample that traces them (0 for the path tracer, `q = 0`).
    pub light_paths: u32,
    /// Summed per-pixel variance of one camera sample's luminance (the pilot's pixels).
    pub variance: f64,
    /// Cost per camera sample (instructions, [`COST_WEIGHTS`]).
    pub cost: f64,
    /// `1 / (variance · cost)`.
    pub efficiency: f64,
}

/// The pilot's recorder inside a BDPT worker: the current camera sample's bookings and the
/// sums so far.
#[derive(Clone, Debug)]
pub struct PilotSample {
    width: u32,
    height: u32,
    entries: Vec<Entry>,
    /// Σ of the current pixel's own-pixel estimates per candidate, and its sample count.
    pixel_sum: [f64; MAX_CANDIDATES],
    pixel_samples: u64,
    /// Σ of the current pixel's own-pixel `Y` per path length (bounces; the last entry: longer).
    depth_sum: [f64; DEPTHS],
    sums: PilotSums,
}

/// Path lengths the pilot's per-length means tell apart ([`PilotSample::book_pt`]).
const DEPTHS: usize = 24;

impl PilotSample {
    /// An empty recorder for an image of `width × height` pixels and `candidates`.
    pub fn new(width: u32, height: u32, candidates: Candidates) -> Self {
        Self {
            width,
            height,
            entries: Vec::with_capacity(16),
            pixel_sum: [0.0; MAX_CANDIDATES],
            pixel_samples: 0,
            depth_sum: [0.0; DEPTHS],
            sums: PilotSums {
                candidates,
                ..PilotSums::default()
            },
        }
    }

    /// The candidates booked.
    pub fn candidates(&self) -> &Candidates {
        &self.sums.candidates
    }

    fn pixel(&self, at: Vec2) -> u64 {
        let x = (at.x.max(0.0) as u32).min(self.width - 1);
        let y = (at.y.max(0.0) as u32).min(self.height - 1);
        y as u64 * self.width as u64 + x as u64
    }

    /// Books weighted luminance `y` (under the pilot's counts) of a connection landing at
    /// raster position `at`, of part `part`, with each candidate's factor
    /// ([`Candidates::ratios`]; 1 for the strategies no candidate changes).
    pub fn book(&mut self, at: Vec2, part: Part, y: f64, ratios: &[f64; MAX_CANDIDATES]) {
        let pixel = self.pixel(at);
        let i = match self.entries.iter().position(|e| e.pixel == pixel) {
            Some(i) => i,
            None => {
                self.entries.push(Entry::new(pixel));
                self.entries.len() - 1
            }
        };
        let e = &mut self.entries[i];
        let to = match part {
            Part::Camera => &mut e.a,
            Part::Join => &mut e.join,
            Part::LightTracing(0) => &mut e.t0,
            Part::LightTracing(_) => &mut e.current,
        };
        for (p, r) in to.iter_mut().zip(ratios) {
            *p += y * r;
        }
    }

    /// Ends a further light subpath (`j ≥ 1`) of the current camera sample: its per-pixel
    /// values join the sum and the sum of squares.
    pub fn end_subpath(&mut self) {
        for e in &mut self.entries {
            for k in 0..MAX_CANDIDATES {
                let c = e.current[k];
                e.sum[k] += c;
                e.sum_sq[k] += c * c;
                e.current[k] = 0.0;
            }
        }
    }

    /// Books one connection's share of the path tracer's second moment (the candidate
    /// `q = 0`): the connection of weighted luminance `y`, weight `w`, `n` expected samples of
    /// its strategy per camera sample and the path tracer's relative squared densities
    /// `ratios` = `(p₀/p)², (p₁/p)²` ([`PilotTerms::pt_ratios`]). Its path, `x`, made with
    /// density `p` by this strategy, is one sample of BDPT's combination estimating
    /// `∫ f²·(w₀²/p₀ + w₁²/p₁)` (the path tracer's second moment, its power-heuristic weights
    /// `wᵢ = pᵢ²/(p₀² + p₁²)`): `w·h(x)/(n·p)` with `f/p = y·n/w` is
    /// `y²·n/w · (r₀³ + r₁³)/(r₀² + r₁²)²`, `rᵢ = pᵢ/p`. So the path tracer's variance where it
    /// samples a path rarely (a caustic: light tracing finds it) is seen although no path
    /// tracer sample of the pilot found it.
    pub fn book_pt(&mut self, y: f64, w: f32, n: f32, ratios: &[f32; 2], own_depth: Option<usize>) {
        if !(w > 0.0) || y == 0.0 {
            return;
        }
        if let Some(d) = own_depth {
            self.depth_sum[d.min(DEPTHS - 1)] += y;
        }
        let (big0, big1) = (ratios[0] as f64, ratios[1] as f64);
        let sum = big0 + big1;
        if !(sum > 0.0) {
            self.sums.pt_missed += 1;
            return;
        }
        let g = (big0 * big0.sqrt() + big1 * big1.sqrt()) / (sum * sum);
        let term = y * y * n as f64 / w as f64 * g;
        if term.is_finite() {
            self.sums.pt_m2 += term;
        } else {
            self.sums.pt_missed += 1;
        }
    }

    /// Ends a camera sample of the pixel whose centre is `center`, with its work counts: the
    /// camera part, the first light subpath's and the further light subpaths'.
    pub fn finish_sample(
        &mut self,
        center: Vec2,
        camera: PartCost,
        light: PartCost,
        further: PartCost,
    ) {
        let own = self.pixel(center);
        let candidates = self.sums.candidates;
        let lp = candidates.pilot_paths() as f64;
        for e in &self.entries {
            let is_own = e.pixel == own;
            for (k, &(_, l)) in candidates.list().iter().enumerate() {
                // Light tracing over `L` subpaths, `T = (1/L)·Σ_{j<L} t_j`, from all `L_p` of
                // the pilot: the t_j are exchangeable (the same distribution, independent
                // given the camera sample's wavelengths), so E[T] = E[t],
                // E[T²] = E[t²]/L + (1 − 1/L)·E[t_i·t_j], E[A·T] = E[A·t], and the joins,
                // which share the first subpath, E[J·T] = (E[J·t₀] + (L − 1)·E[J·t_j])/L,
                // j ≥ 1. Every candidate L reads every subpath (its first L alone gave the
                // small L estimates of few samples, which rare bright splats decided).
                let l = l as f64;
                let total = e.t0[k] + e.sum[k];
                let squares = e.t0[k] * e.t0[k] + e.sum_sq[k];
                let mean = total / lp;
                let (pairs, join_further) = if lp > 1.0 {
                    (
                        (total * total - squares) / (lp * (lp - 1.0)),
                        e.join[k] * e.sum[k] / (lp - 1.0),
                    )
                } else {
                    (0.0, 0.0)
                };
                let t2 = squares / lp / l + (1.0 - 1.0 / l) * pairs;
                let jt = (e.join[k] * e.t0[k] + (l - 1.0) * join_further) / l;
                let c = e.join[k] + mean;
                let c2 = e.join[k] * e.join[k] + 2.0 * jt + t2;
                let sk = if is_own {
                    self.pixel_sum[k] += e.a[k] + c;
                    &mut self.sums.own[k]
                } else {
                    &mut self.sums.splat[k]
                };
                sk[0] += e.a[k] * e.a[k];
                sk[1] += e.a[k] * c;
                sk[2] += c2;
            }
        }
        self.entries.clear();
        self.pixel_samples += 1;
        self.sums.samples += 1;
        self.sums.camera.add(&camera);
        self.sums.light.add(&light);
        self.sums.further.add(&further);
    }

    /// Ends a pilot pixel (all its samples done).
    pub fn finish_pixel(&mut self) {
        if self.pixel_samples > 0 {
            for (acc, sum) in self.sums.mean_sq.iter_mut().zip(&self.pixel_sum) {
                let m = sum / self.pixel_samples as f64;
                *acc += m * m;
            }
            for sum in &self.depth_sum {
                let m = sum / self.pixel_samples as f64;
                self.sums.pt_mean_sq += m * m;
            }
            self.sums.pixels += 1;
        }
        self.depth_sum = [0.0; DEPTHS];
        self.pixel_sum = [0.0; MAX_CANDIDATES];
        self.pixel_samples = 0;
    }

    /// The sums recorded.
    pub fn sums(&self) -> &PilotSums {
        &self.sums
    }
}

/// The pilot's pixels: a regular grid of at most about [`PILOT_PIXELS`] over the image.
pub fn pilot_pixels(width: u32, height: u32) -> Vec<(u32, u32)> {
    let area = width as f64 * height as f64;
    let stride = ((area / PILOT_PIXELS as f64).sqrt().ceil() as u32).max(1);
    let mut out = Vec::new();
    let mut y = stride / 2;
    while y < height {
        let mut x = stride / 2;
        while x < width {
            out.push((x, y));
            x += stride;
        }
        y += stride;
    }
    out
}

/// The pilot's seed for render seed `seed`.
pub fn pilot_seed(seed: u64) -> u64 {
    seed ^ PILOT_SALT
}

/// Sums a pilot reduces over its chunks (in chunk order).
pub trait Sums: Default + Send {
    /// Adds `o` to these sums.
    fn add_sums(&mut self, o: &Self);
}

impl Sums for PilotSums {
    fn add_sums(&mut self, o: &Self) {
        self.add(o);
    }
}

/// Runs `chunk` (which renders its pilot pixels, BDPT with `q = 1` or the path tracer, and
/// returns its sums) over fixed chunks of [`pilot_pixels`] on `pool`, and reduces the sums in
/// chunk order.
pub fn run_pilot<T, F>(pool: &rayon::ThreadPool, width: u32, height: u32, chunk: F) -> T
where
    T: Sums,
    F: Fn(&[(u32, u32)]) -> T + Sync,
{
    let pixels = pilot_pixels(width, height);
    let parts: Vec<T> = pool.install(|| pixels.par_chunks(CHUNK).map(&chunk).collect());
    let mut sums = T::default();
    for p in &parts {
        sums.add_sums(p);
    }
    sums
}

/// The path tracer's pilot sums (the candidate `q = 0`): one camera sample's luminance `Y`
/// per pilot pixel and sample, under the same pixels, samples and seed as BDPT's pilot, with
/// the camera samples whose first hit is an emitter booked as 0 (as BDPT's pilot leaves out
/// the paths whose first camera-side vertex is one), and the work counts.
#[derive(Clone, Debug, Default)]
pub struct PtPilotSums {
    /// Σ Y² over the camera samples.
    y2: f64,
    /// Σ over pilot pixels of the squared mean of their `Y`.
    mean_sq: f64,
    samples: u64,
    pixels: u64,
    /// The current pixel's Σ Y and sample count.
    pixel_sum: f64,
    pixel_samples: u64,
    /// Rays and shadow rays (no connections: the path tracer weighs inline).
    cost: PartCost,
}

impl Sums for PtPilotSums {
    fn add_sums(&mut self, o: &Self) {
        self.y2 += o.y2;
        self.mean_sq += o.mean_sq;
        self.samples += o.samples;
        self.pixels += o.pixels;
        self.cost.add(&o.cost);
    }
}

impl PtPilotSums {
    /// Books one camera sample of the current pixel: its luminance `y` (0 where left out)
    /// and its work counts.
    pub fn add_sample(&mut self, y: f64, cost: PartCost) {
        let y = if y.is_finite() { y } else { 0.0 };
        self.y2 += y * y;
        self.pixel_sum += y;
        self.pixel_samples += 1;
        self.samples += 1;
        self.cost.add(&cost);
    }

    /// Ends a pilot pixel (all its samples done).
    pub fn finish_pixel(&mut self) {
        if self.pixel_samples > 0 {
            let m = self.pixel_sum / self.pixel_samples as f64;
            self.mean_sq += m * m;
            self.pixels += 1;
        }
        self.pixel_sum = 0.0;
        self.pixel_samples = 0;
    }

    /// The estimate of `q = 0` in the definition of [`PilotSums::estimates`]: the sum over the
    /// pilot's pixels of one camera sample's variance of `Y`, and the cost per camera sample
    /// from `weights` ([`PT_COST_WEIGHTS`]). The variance is the larger of two estimates, each
    /// blind to a part: these path-traced samples' own (within-pixel, `n − 1`), which misses
    /// the paths the path tracer finds rarely (a caustic core: a few hits of great value
    /// carry its variance), and the second moment from BDPT's pilot samples (`bdpt`,
    /// [`PilotSample::book_pt`]: light tracing finds those paths) minus these samples' squared
    /// pixel means, which misses the correlation between a camera sample's path lengths.
    /// Infinite where BDPT's pilot made a path neither s = 0 nor s = 1 makes.
    pub fn estimate(&self, weights: &CostWeights, bdpt: &PilotSums) -> Estimate {
        let n = (self.samples as f64 / self.pixels.max(1) as f64).max(2.0);
        let direct = (self.y2 - n * self.mean_sq) / (n - 1.0);
        let n_bdpt = (bdpt.samples as f64 / bdpt.pixels.max(1) as f64).max(1.0);
        let reweighted = bdpt.pt_m2 / n_bdpt - bdpt.pt_mean_sq;
        let variance = if bdpt.pt_missed > 0 {
            f64::INFINITY
        } else {
            direct.max(reweighted)
        };
        let cost = weights.sample + weights.of(&self.cost) / self.samples.max(1) as f64;
        Estimate {
            q: 0.0,
            light_paths: 0,
            variance,
            cost,
            efficiency: 1.0 / (variance * cost),
        }
    }

    /// The two variance estimates of [`estimate`](Self::estimate) (direct, from BDPT's samples).
    pub fn variances(&self, bdpt: &PilotSums) -> (f64, f64) {
        let n = (self.samples as f64 / self.pixels.max(1) as f64).max(2.0);
        let direct = (self.y2 - n * self.mean_sq) / (n - 1.0);
        let n_bdpt = (bdpt.samples as f64 / bdpt.pixels.max(1) as f64).max(1.0);
        (direct, bdpt.pt_m2 / n_bdpt - bdpt.pt_mean_sq)
    }

    /// Rays and shadow rays per camera sample (for the cost fit's table).
    pub fn counts_per_sample(&self) -> (f64, f64) {
        let n = self.samples.max(1) as f64;
        (self.cost.rays as f64 / n, self.cost.shadow_rays as f64 / n)
    }
}

/// The pilot's decision: the chosen fraction and count and every candidate's estimate.
#[derive(Clone, Debug)]
pub struct Choice {
    /// The chosen fraction; 0: no light subpaths, the camera samples are path traced.
    pub q: f32,
    /// The chosen number of light subpaths per camera sample that traces them.
    pub light_paths: u32,
    /// The candidates' estimates, [`Candidates::list`] order.
    pub estimates: Vec<Estimate>,
    /// The candidate kept unless another is estimated [`MIN_GAIN`] better.
    pub base: (f32, u32),
    /// The path tracer's estimate (`q = 0`), where the scene lets it stand for BDPT.
    pub path_traced: Option<Estimate>,
    /// Why `q = 0` was not offered, where it was not.
    pub path_traced_refused: Option<&'static str>,
    /// The path tracer's rays and shadow rays per camera sample in its pilot (the inputs of
    /// [`PT_COST_WEIGHTS`]), where it ran.
    pub path_traced_work: Option<(f64, f64)>,
}

impl Choice {
    /// The pilot's choice in two steps, each keeping what it has unless another candidate is
    /// estimated [`MIN_GAIN`] better: among the fractions at the base count (the base
    /// candidate, [`Candidates::base`]: `q = 1` with [`super::LIGHT_PATHS`] light subpaths
    /// where the scene has delta surfaces), then among all candidates (another count L). So a
    /// count other than the base's is taken only where it beats the best fraction at the
    /// base's count, not where it ties with it: a fraction and a count often trade for the
    /// same expected number of light subpaths per camera sample (`q·L`), and with 20
    /// candidates the largest of several near-equal noisy estimates would decide. The base
    /// stays where the estimates are degenerate (no light, no variance). `q = 0`
    /// (`path_traced`, its estimate) only where it beats every `q > 0` by [`MIN_GAIN`].
    pub fn from_sums(sums: &PilotSums, path_traced: Option<Estimate>) -> Self {
        let estimates = sums.estimates(&COST_WEIGHTS);
        let base = sums.candidates().base();
        let usable =
            |e: &&Estimate| e.efficiency.is_finite() && e.efficiency > 0.0 && e.variance > 0.0;
        let best_of = |l: Option<u32>| {
            estimates
                .iter()
                .filter(usable)
                .filter(|e| l.is_none_or(|l| e.light_paths == l))
                .max_by(|a, b| a.efficiency.total_cmp(&b.efficiency))
        };
        let mut kept = estimates
            .iter()
            .filter(usable)
            .find(|e| (e.q, e.light_paths) == base);
        if let (Some(k), Some(b)) = (kept, best_of(Some(base.1))) {
            if b.efficiency >= MIN_GAIN * k.efficiency {
                kept = Some(b);
            }
        }
        let best = best_of(None);
        if let (Some(k), Some(b)) = (kept, best) {
            if b.efficiency >= MIN_GAIN_COUNT * k.efficiency {
                kept = Some(b);
            }
        }
        let (mut q, light_paths) = kept.map_or(base, |k| (k.q, k.light_paths));
        if let (Some(p), Some(b)) = (&path_traced, best) {
            let usable = p.efficiency.is_finite() && p.variance > 0.0 && p.cost > 0.0;
            if usable && p.efficiency >= MIN_GAIN * b.efficiency {
                q = 0.0;
            }
        }
        Self {
            q,
            light_paths,
            estimates,
            base,
            path_traced,
            path_traced_refused: None,
            path_traced_work: None,
        }
    }

    /// The estimate of fraction `q` with `light_paths` subpaths, if it is a candidate (q = 0:
    /// the path tracer's, whatever `light_paths`).
    pub fn estimate(&self, q: f32, light_paths: u32) -> Option<&Estimate> {
        if q == 0.0 {
            return self.path_traced.as_ref();
        }
        self.estimates
            .iter()
            .find(|e| e.q == q && e.light_paths == light_paths)
    }

    /// The estimate of the chosen candidate.
    pub fn chosen(&self) -> Option<&Estimate> {
        self.estimate(self.q, self.light_paths)
    }

    /// The estimated efficiency of the chosen candidate over the base's.
    pub fn gain(&self) -> f64 {
        let base = self.estimate(self.base.0, self.base.1);
        match (self.chosen(), base) {
            (Some(c), Some(b)) if (c.efficiency / b.efficiency).is_finite() => {
                c.efficiency / b.efficiency
            }
            _ => 1.0,
        }
    }

    /// The run-time line: what was chosen and why (every candidate's estimated efficiency
    /// relative to the base's, grouped by L).
    pub fn note(&self, seconds: f64) -> String {
        let base_eff = self
            .estimate(self.base.0, self.base.1)
            .map_or(f64::NAN, |e| e.efficiency);
        let mut groups: Vec<String> = Vec::new();
        if let Some(p) = &self.path_traced {
            groups.push(format!("q = 0: {:.2}", p.efficiency / base_eff));
        }
        let mut counts: Vec<u32> = self.estimates.iter().map(|e| e.light_paths).collect();
        counts.dedup();
        for l in counts {
            let row: Vec<String> = self
                .estimates
                .iter()
                .filter(|e| e.light_paths == l)
                .map(|e| format!("{} {:.2}", fraction_text(e.q), e.efficiency / base_eff))
                .collect();
            groups.push(format!("L = {l}: {}", row.join(", ")));
        }
        let chosen = if self.q == 0.0 {
            "q = 0, the camera samples are path traced".to_string()
        } else {
            format!("q = {}, L = {}", fraction_text(self.q), self.light_paths)
        };
        let refused = self
            .path_traced_refused
            .map_or_else(String::new, |why| format!("; q = 0 not offered: {why}"));
        format!(
            "bdpt light subpaths: {chosen} (estimated efficiency {:.2}x q = {}, L = {}; \
             candidates {}{refused}), pilot {seconds:.2} s",
            self.gain(),
            fraction_text(self.base.0),
            self.base.1,
            groups.join("; ")
        )
    }
}

/// `q` as text: `1`, `1/2`, … for the reciprocals of integers, else the decimal.
pub fn fraction_text(q: f32) -> String {
    let r = 1.0 / q;
    if q <= 0.0 {
        "0".into()
    } else if q >= 1.0 {
        "1".into()
    } else if (r - r.round()).abs() < 1e-4 {
        format!("1/{}", r.round() as u32)
    } else {
        format!("{q}")
    }
}

/// The counts of a render at fraction `q` with `light_paths` light subpaths.
pub fn counts(light_paths: u32, q: f32) -> SampleCounts {
    SampleCounts {
        light_paths,
        fraction: q,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Quantity: the pilot's variance estimate from sums built by hand for one pixel whose
    /// camera samples give A = 1 always and C = 2 or 0 (mean 1): under q, E[X²] = 1 + 2·1 +
    /// E[C²]/q = 3 + 2/q, mean 2, so the variance is E[X²] − 4 = 2/q − 1 (exact; tolerance
    /// rounding). Checks the assembly of `A² + 2AC + C²/q` and the `n − 1` of the own part.
    #[test]
    fn variance_of_a_bernoulli_split_is_exact() {
        let mut p = PilotSample::new(4, 4, Candidates::default());
        let c = Vec2::new(1.5, 1.5);
        let ones = [1.0; MAX_CANDIDATES];
        for i in 0..4 {
            p.book(c, Part::Camera, 1.0, &ones);
            p.book(c, Part::Join, if i % 2 == 0 { 2.0 } else { 0.0 }, &ones);
            p.finish_sample(
                c,
                PartCost::default(),
                PartCost::default(),
                PartCost::default(),
            );
        }
        p.finish_pixel();
        let est = p.sums().estimates(&COST_WEIGHTS);
        for e in est {
            let q = e.q as f64;
            // Sample variance with n − 1 of four samples {3, 1, 3, 1} at q = 1 is 4/3, and the
            // formula's second moment (3 + 2/q) with the same n − 1 correction.
            let expect = (4.0 * (3.0 + 2.0 / q) - 4.0 * 4.0) / 3.0;
            assert!((e.variance - expect).abs() < 1e-9, "{e:?} vs {expect}");
        }
    }

    /// Quantity: the path tracer's second moment reweighted from BDPT's samples
    /// (`book_pt`), against values worked by hand. A path made by s = 0 alone (`(p₀/p)² = 1`,
    /// p₁ = 0, weight 1, one sample a camera sample) adds `y²`: the path tracer samples it as
    /// BDPT did. A light-tracing path (weight ½ of its luminance 2, so `y = 1`; one of 4 light
    /// subpaths, `n = 4`) that s = 0 makes with a tenth of its density (`(p₀/p)² = 0.01`) and
    /// s = 1 not at all adds `y²·n/w·(r₀³/r₀⁴) = 1·4/0.5·10 = 80`: its unweighted value
    /// `f/p = y·n/w = 8`, `∫ f²/p₀` per sample of it `8²·(p/p₀)/n·w`. Where both make it equally
    /// (`(p₀/p)² = (p₁/p)² = 1`), each path-tracer sample weighs ½: `2·(½)²/1 = ½`, so `y²/2`.
    /// A path neither makes is counted as missed. Tolerance: rounding.
    #[test]
    fn path_tracer_second_moment_by_reweighting() {
        let mut p = PilotSample::new(4, 4, Candidates::default());
        p.book_pt(2.0, 1.0, 1.0, &[1.0, 0.0], Some(1));
        assert!((p.sums().pt_m2 - 4.0).abs() < 1e-9);
        let mut p = PilotSample::new(4, 4, Candidates::default());
        p.book_pt(1.0, 0.5, 4.0, &[0.01, 0.0], None);
        assert!((p.sums().pt_m2 - 80.0).abs() < 1e-4, "{}", p.sums().pt_m2);
        let mut p = PilotSample::new(4, 4, Candidates::default());
        p.book_pt(3.0, 1.0, 1.0, &[1.0, 1.0], Some(1));
        assert!((p.sums().pt_m2 - 4.5).abs() < 1e-9);
        p.book_pt(3.0, 1.0, 1.0, &[0.0, 0.0], Some(1));
        assert_eq!(p.sums().pt_missed, 1);
    }

    /// Quantity: the pilot grid. At most about `PILOT_PIXELS` pixels, all inside the image,
    /// none repeated (tolerance: none).
    #[test]
    fn pilot_grid_covers_the_image() {
        for (w, h) in [(1, 1), (64, 64), (160, 120), (1920, 1080)] {
            let p = pilot_pixels(w, h);
            assert!(!p.is_empty());
            assert!(p.len() <= PILOT_PIXELS as usize + (w + h) as usize);
            assert!(p.iter().all(|&(x, y)| x < w && y < h));
            let mut q = p.clone();
            q.sort_unstable();
            q.dedup();
            assert_eq!(q.len(), p.len());
        }
    }
}
