//! Exact colour of spectrally flat paths: where every scattering vertex of a path answers the
//! same at every wavelength (grey reflectance, constant IOR, no fluorescence, no dispersion),
//! the path's contribution at the sampled wavelengths is `L(λᵢ) = T · S(λᵢ)`, with `T` one
//! number and `S` its emitter's spectral shape. The ordinary estimator turns the lanes into
//! XYZ by `Σᵢ L(λᵢ)·x̄ȳz̄(λᵢ)/(pdf(λᵢ)·LANES·∫ȳ)`, whose expectation over the wavelengths is
//! `T · ∫ S x̄ȳz̄ dλ / ∫ȳ`; this file replaces it by that expectation itself,
//! `T̂ · K_S` with `T̂ = Σᵢ L(λᵢ) / Σᵢ S(λᵢ)` and `K_S = ∫ S x̄ȳz̄ dλ / ∫ȳ` computed once per
//! emitter (a Rao–Blackwellisation over the wavelength choice: no bias, and the colour noise
//! of the wavelength choice is gone; RGB renderers have none).
//!
//! Lanes where the emitter's shape is zero (D65 is tabulated to 780 nm only) or that sit on a
//! delta line (pdf 0) tell nothing about `T`; with `n` of the `LANES` lanes usable and
//! `P = ∫_{S>0} p(λ) dλ` the chance that a lane drawn from the wavelength mixture's density
//! `p` is usable, the estimate is `T̂ · K_S · n / (LANES · P)`.
//!
//! Why it is unbiased: for any fixed wavelengths, each usable lane's `L(λᵢ)/S(λᵢ)` is the
//! path's ordinary estimate of the flat transport `T` (all of the path's factors are the same
//! in every lane), whatever the sampling decisions were based on; every lane is marginally
//! drawn with density `p`, so `E[Σ_usable L(λᵢ)/S(λᵢ)] = LANES · P · E[T]`, and the estimate's
//! expectation is `E[T] · K_S`, the true colour.
//!
//! When it applies (everything else keeps the ordinary per-lane estimate):
//! - every vertex of the path is flat: a surface whose material says
//!   [`Material::spectrally_flat`](crate::material::Material::spectrally_flat) (emitters count
//!   as flat), not fluorescent or shifted, every lane still live; camera and light end points;
//! - the emitter's spectral radiance has one shape everywhere
//!   ([`Light::uniform_spectral_shape`](crate::light::Light::uniform_spectral_shape)), without
//!   delta lines.
//!
//! Spectral output: the spectral film keeps receiving the ordinary per-lane energies (an
//! unbiased estimate of the same spectrum); only the XYZ film gets the exact colour.
//!
//! | quantity | unit | meaning |
//! |---|---|---|
//! | `K_S` | (XYZ per unit `T`) | `∫ S(λ) x̄ȳz̄(λ) dλ / Σ ȳ` over the observer's range, midpoint rule at 0.1 nm |
//! | `S` | the light's SPD resampled at 1 nm (as the light itself evaluates it) | emitter shape |
//! | `P` | probability | `∫_{S>0} p(λ) dλ` over 300–1100 nm, midpoint rule at 0.1 nm (lines excluded: lanes on them have pdf 0) |

use crate::color::observer::Observer;
use crate::integrator::subpath::vertex::{Vertex, VertexKind};
use crate::scene::Scene;
use crate::spectrum::dense::DenseSpectrum;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};

/// Sub-steps per nm of the `K_S` and `P` integrals (midpoint rule).
const STEPS_PER_NM: usize = 10;
/// Range (nm) over which `P` integrates the wavelength density (beyond the observers' range,
/// in case an emission spectrum is drawn there).
const P_RANGE_NM: (f64, f64) = (300.0, 1100.0);

/// One emitter whose shape is uniform: the shape as the light evaluates it and its exact XYZ.
#[derive(Clone, Debug)]
struct FlatEmitter {
    shape: DenseSpectrum,
    xyz: [f64; 3],
    /// `K_S / (LANES · P)`: the factor per usable lane.
    xyz_per_lane: [f64; 3],
}

/// Which objects scatter flatly and which lights have a uniform shape, with each such light's
/// exact XYZ per unit transport (see the module docs).
#[derive(Clone, Debug)]
pub struct FlatColour {
    objects: Vec<bool>,
    emitters: Vec<Option<FlatEmitter>>,
}

impl FlatColour {
    /// The flat objects and emitters of `scene` under `observer`, for lanes drawn with the
    /// wavelength density `density` (1/nm; e.g. [`WavelengthMixture::pdf`](crate::integrator::wavelengths::mixture::WavelengthMixture::pdf)); `None` when no
    /// light qualifies (nothing to gain).
    pub fn new(
        scene: &Scene,
        observer: &dyn Observer,
        density: &dyn Fn(f64) -> f64,
    ) -> Option<Self> {
        let objects = scene
            .objects
            .objects()
            .iter()
            .map(|o| o.material.spectrally_flat())
            .collect();
        let iy = observer.integral_y();
        let emitters: Vec<Option<FlatEmitter>> = scene
            .lights
            .lights()
            .iter()
            .map(|l| {
                if !l.uniform_spectral_shape() || !(iy > 0.0) {
                    return None;
                }
                let spd = l.spd();
                if !spd.delta_lines().is_empty() {
                    return None;
                }
                let shape = DenseSpectrum::from_spd(spd, 1.0);
                let p = usable_probability(&shape, density);
                if !(p > 0.0) {
                    return None;
                }
                let xyz = integrate(&shape, observer).map(|v| v / iy);
                let xyz_per_lane = xyz.map(|k| k / (LANES as f64 * p));
                Some(FlatEmitter {
                    shape,
                    xyz,
                    xyz_per_lane,
                })
            })
            .collect();
        emitters
            .iter()
            .any(Option::is_some)
            .then_some(Self { objects, emitters })
    }

    /// True when light `light` has a uniform shape (its flat paths get the exact colour).
    pub fn emitter_is_flat(&self, light: u32) -> bool {
        matches!(self.emitters.get(light as usize), Some(Some(_)))
    }

    /// True when object `object` scatters the same at every wavelength (the path tracer's
    /// test of a vertex; fluorescence and dead lanes it tests itself).
    #[inline]
    pub fn object_is_flat(&self, object: u32) -> bool {
        self.objects.get(object as usize).copied().unwrap_or(false)
    }

    /// True when `v` scatters the same at every wavelength (end points count as flat; their
    /// emission or importance is handled by the emitter's shape and the camera, which is grey).
    pub fn vertex_is_flat(&self, v: &Vertex) -> bool {
        let own = match v.kind {
            VertexKind::Camera | VertexKind::Light { .. } => true,
            VertexKind::Surface { object } => self.object_is_flat(object),
        };
        own && v.lanes.is_all() && v.shifted.is_none() && !v.unit_lobe && v.moved == LaneMask::NONE
    }

    /// `out[i]`: vertices `0..=i` of `path` are all flat.
    pub fn prefix(&self, path: &[Vertex], out: &mut Vec<bool>) {
        out.clear();
        let mut all = true;
        for v in path {
            all = all && self.vertex_is_flat(v);
            out.push(all);
        }
    }

    /// The exact XYZ of a flat path's contribution `l` (per lane, weight applied) at
    /// wavelengths `lambda`, emitted by light `light`; `None` when that light has no uniform
    /// shape (use the ordinary estimate then).
    #[inline]
    pub fn xyz(
        &self,
        light: u32,
        l: &SampledSpectrum,
        lambda: &SampledWavelengths,
    ) -> Option<[f64; 3]> {
        let e = self.emitters.get(light as usize)?.as_ref()?;
        let mut sum_s = 0.0f64;
        let mut sum_l = 0.0f64;
        let mut usable = 0u32;
        for i in 0..LANES {
            let s = e.shape.value(lambda.lambda[i]) as f64;
            if s > 0.0 && lambda.pdf[i] > 0.0 {
                sum_s += s;
                sum_l += l.0[i] as f64;
                usable += 1;
            }
        }
        if usable == 0 {
            return Some([0.0; 3]);
        }
        let t = sum_l / sum_s * usable as f64;
        Some(e.xyz_per_lane.map(|k| k * t))
    }

    /// `K_S` of light `light` (XYZ per unit transport), when it has a uniform shape.
    pub fn emitter_xyz(&self, light: u32) -> Option<[f64; 3]> {
        Some(self.emitters.get(light as usize)?.as_ref()?.xyz)
    }
}

/// `P = ∫_{S>0} p(λ) dλ`: the chance that a lane drawn with density `density` sees `shape`
/// non-zero.
fn usable_probability(shape: &DenseSpectrum, density: &dyn Fn(f64) -> f64) -> f64 {
    let (lo, hi) = P_RANGE_NM;
    let n = ((hi - lo) * STEPS_PER_NM as f64) as usize;
    let h = (hi - lo) / n as f64;
    let mut p = 0.0;
    for k in 0..n {
        let nm = lo + (k as f64 + 0.5) * h;
        if shape.value(nm as f32) > 0.0 {
            p += density(nm) * h;
        }
    }
    p.min(1.0)
}

/// `∫ S(λ) x̄ȳz̄(λ) dλ` over the observer's range (midpoint rule, [`STEPS_PER_NM`] per nm).
fn integrate(shape: &DenseSpectrum, observer: &dyn Observer) -> [f64; 3] {
    let (lo, hi) = observer.range();
    let n = ((hi - lo) * STEPS_PER_NM as f64).round().max(0.0) as usize;
    let h = (hi - lo) / n.max(1) as f64;
    let mut out = [0.0f64; 3];
    for k in 0..n {
        let nm = lo + (k as f64 + 0.5) * h;
        let s = shape.value(nm as f32) as f64;
        let bar = observer.xyz_bar(nm);
        for c in 0..3 {
            out[c] += s * bar[c] * h;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::Sensor;
    use crate::integrator::wavelengths::mixture::WavelengthMixture;
    use crate::integrator::wavelengths::xyz_weights::XyzWeights;
    use crate::integrator::SampleRng;
    use crate::scene::{build_scene, parse_scene_str, BuiltinFactory};
    use std::path::Path;

    fn scene(text: &str) -> Scene {
        let file = Path::new("caustic.ron");
        let desc = parse_scene_str(text, file).unwrap();
        build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap()
    }

    /// `K_S` is the expectation of the ordinary estimate. Quantity: the mean over 400 000
    /// wavelength draws (the caustic scene's mixture) of the four-lane XYZ of a flat path of
    /// unit transport under the D65 lamp (`L(λ) = S(λ)`), per channel, against `K_S`; tolerance
    /// 4 standard errors of that mean (from the draws' own spread). And for every draw whose
    /// lanes all lie where D65 is tabulated (≤ 780 nm) the exact estimate is `K_S / P`, the
    /// same number whatever the wavelengths, up to float rounding (1e-5 relative).
    #[test]
    fn exact_colour_is_the_mean_of_the_lane_estimate() {
        let s = scene(include_str!("../../../../scenes/caustic.ron"));
        let mixture = WavelengthMixture::new(&s);
        let fc = FlatColour::new(&s, s.observer.as_ref(), &|l| mixture.pdf(l))
            .expect("D65 lamp qualifies");
        let light = 0u32;
        let k = fc.emitter_xyz(light).unwrap();
        let e = fc.emitters[0].as_ref().unwrap();
        let (shape, full) = (e.shape.clone(), e.xyz_per_lane.map(|v| v * LANES as f64));
        let sensor = Sensor::new(s.observer.clone());
        let n = 400_000u64;
        let (mut sum, mut sum2) = ([0.0f64; 3], [0.0f64; 3]);
        let mut worst = 0.0f64;
        for i in 0..n {
            let mut rng = SampleRng::for_sample(11, i, 0);
            let lambda = mixture.sample(&mut rng);
            let l = SampledSpectrum(lambda.lambda.map(|nm| shape.value(nm)));
            let xyz = XyzWeights::new(&sensor, &lambda).xyz(&l, crate::spectrum::LaneMask::ALL);
            for c in 0..3 {
                sum[c] += xyz[c];
                sum2[c] += xyz[c] * xyz[c];
            }
            if lambda.lambda.iter().all(|&nm| nm <= 780.0) {
                let exact = fc.xyz(light, &l, &lambda).unwrap();
                for c in 0..3 {
                    worst = worst.max((exact[c] / full[c] - 1.0).abs());
                }
            }
        }
        for c in 0..3 {
            let m = sum[c] / n as f64;
            let se = ((sum2[c] / n as f64 - m * m) / n as f64).sqrt();
            assert!(
                (m - k[c]).abs() < 4.0 * se,
                "channel {c}: lane mean {m} vs exact {} (se {se})",
                k[c]
            );
        }
        // With all four lanes usable the exact estimate is K_S / P whatever the wavelengths.
        assert!(worst < 1e-5, "exact estimate varies by {worst}");
    }

    /// Which surfaces count as flat. Quantity: the per-object flag for the caustic scene's
    /// grey floor (flat), coloured wall (not), constant-IOR glass (flat), lamp (flat: scatters
    /// nothing), and a dispersive glass (not). Exact booleans.
    #[test]
    fn flat_surfaces() {
        let text = include_str!("../../../../scenes/caustic.ron");
        let s = scene(text);
        let m = WavelengthMixture::new(&s);
        let fc = FlatColour::new(&s, s.observer.as_ref(), &|l| m.pdf(l)).unwrap();
        assert_eq!(fc.objects, vec![true, false, true, true]);
        let s = scene(&text.replace("(ior: 1.5)", "(ior: \"N-BK7\")"));
        let m = WavelengthMixture::new(&s);
        let fc = FlatColour::new(&s, s.observer.as_ref(), &|l| m.pdf(l)).unwrap();
        assert_eq!(fc.objects, vec![true, false, false, true]);
    }
}
