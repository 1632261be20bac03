//! Measuring any light as a goniophotometer measures a luminaire: its intensity distribution on
//! a regular type C grid, its emission spectrum and the size of what emits, so that it can be
//! baked into a [`CandelaTable`] (a `luminaire` light in a blob) or exported as IES/EULUMDAT.
//!
//! - **Lights that can be evaluated** (point, spot, area, connectable plugin lights): at each
//!   grid direction ω a detector facing the light at distance R from its centre (far field:
//!   R = 100 × the emitter's largest extent, 1 for a point) takes `samples` next-event samples;
//!   I(ω) = E·R² (E = mean of L·cos/pdf). A point sample of the distribution at the grid node,
//!   like a goniophotometer's reading.
//! - **Lights that only hand out beams** (`next_beam`): `samples` beams are binned by direction
//!   into cells centred on the grid nodes; I = Σ power / (N · cell solid angle), the cell mean.
//!   Power per beam is its flux estimate (the seed's contract), so Σ power / N is the flux, and
//!   the table is scaled so that its integral (trapezoid, like a file's) is exactly that flux.
//!
//! Intensities are per unit of the normalised emission spectrum: the spectrum is the light's own
//! SPD tabulated at 1 nm (delta lines put into their 1 nm bin), or for beam-only lights the
//! beams' power histogram at 1 nm. Candela = W/sr × the spectrum's luminous efficacy (683·∫Sȳ).
//! The grid: `v` (γ) 0..180° and `h` (C) 0..360° in steps of `step_deg`, the luminaire frame
//! equal to the world frame (γ = 0 straight down, C0 along +x, C90 along −z).

use crate::light::{Light, LightFlags, LightSampleContext};
use crate::photometry::candela_table::CandelaTable;
use crate::photometry::efficacy::luminous_efficacy_lm_per_w;
use crate::photometry::luminaire::{Luminaire, PhotometricType, SourceFormat, Symmetry};
use crate::sampler::SampleRng;
use crate::spectrum::spd::spd_at;
use crate::spectrum::{Interpolation, SampledWavelengths, Spd, TabulatedSpd, LANES};
use glam::{Vec2, Vec3A};
use spectrace_plugin_api::RandomSample;

/// How to measure.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GoniometerSettings {
    /// Angular step of the grid, degrees (divides 180 and 360 evenly).
    pub step_deg: f64,
    /// Next-event samples per direction (evaluated lights; 1 suffices for point-like lights) or
    /// beams in all (beam-only lights).
    pub samples: u64,
    /// Seed of the random numbers.
    pub seed: u64,
}

impl Default for GoniometerSettings {
    fn default() -> Self {
        Self {
            step_deg: 2.5,
            samples: 64,
            seed: 1,
        }
    }
}

/// What the measurement gave.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// The intensity distribution in cd (type C, no symmetry, `h` 0..=360).
    pub luminaire: Luminaire,
    /// Emission spectrum as `(nm, value)` pairs, normalised to integrate to 1 (1/nm).
    pub spectrum: Vec<(f64, f64)>,
    /// Centre of the emitter (where the baked light sits), m (the renderer works in metres).
    pub centre: [f64; 3],
    /// Extent of the emitter along x, z, y (IES width, length, height), m.
    pub size: [f64; 3],
    /// Radiant flux of the measured table, W.
    pub flux_w: f64,
    /// Luminous flux of the measured table, lm.
    pub flux_lm: f64,
    /// The light's own stated power, W (for comparison).
    pub stated_power_w: f64,
}

impl Measurement {
    /// The measured table as data (for a `luminaire` light's `table`).
    pub fn table(&self, source: &str) -> CandelaTable {
        CandelaTable::from_luminaire(&self.luminaire, source)
    }
}

/// Measure `light` (see the module docs). Errors for lights a goniophotometer cannot measure
/// (directional, environment) and for lights that emit nothing visible.
pub fn measure(light: &dyn Light, settings: &GoniometerSettings) -> Result<Measurement, String> {
    let flags = light.flags();
    if flags.contains(LightFlags::DELTA_DIRECTION) || flags.contains(LightFlags::ENVIRONMENT) {
        return Err(
            "a directional or environment light has no position to measure around; only lights \
             that emit from a point or a bounded surface can be baked"
                .into(),
        );
    }
    let step = settings.step_deg;
    let nv = (180.0 / step).round() as usize;
    if !(step > 0.0 && step <= 90.0 && (nv as f64 * step - 180.0).abs() < 1e-9) {
        return Err(format!(
            "angular step {step}°: must be in (0, 90] and divide 180° evenly"
        ));
    }
    let nh = 2 * nv;
    let v_deg: Vec<f64> = (0..=nv).map(|j| j as f64 * step).collect();
    let h_deg: Vec<f64> = (0..=nh).map(|i| i as f64 * step).collect();
    let beams_only = flags.contains(LightFlags::BEAMS_ONLY);
    let ((intensity_w, spectrum, centre, size), beam_flux_w) = if beams_only {
        measure_beams(light, settings, &h_deg, &v_deg)?
    } else {
        (measure_evaluated(light, settings, &h_deg, &v_deg)?, None)
    };
    let nm: Vec<f64> = spectrum.iter().map(|p| p.0).collect();
    let values: Vec<f64> = spectrum.iter().map(|p| p.1).collect();
    let spd = TabulatedSpd::new("measured spectrum", &nm, &values, Interpolation::Linear)
        .map_err(|e| format!("the measured spectrum is not an SPD: {e}"))?;
    let k = luminous_efficacy_lm_per_w(&spd);
    if !(k > 0.0) {
        return Err("the light emits no visible light (luminous efficacy 0 lm/W)".into());
    }
    let spectrum: Vec<(f64, f64)> = spectrum.iter().map(|&(l, _)| (l, spd.value(l))).collect();
    let luminaire = Luminaire {
        format: SourceFormat::Table,
        photometric_type: PhotometricType::C,
        symmetry: Symmetry::None,
        h_deg,
        v_deg,
        candela: intensity_w.iter().map(|i| i * k).collect(),
        lamps: Vec::new(),
        multipliers: Vec::new(),
        absolute: true,
        rated_lamp_lumens: None,
        size_m: size,
        tilt: None,
        header: vec![format!(
            "goniometric measurement, {step} deg grid, {} {}",
            settings.samples,
            if beams_only {
                "beams"
            } else {
                "samples per direction"
            }
        )],
        warnings: Vec::new(),
    };
    let mut luminaire = luminaire;
    let mut flux_lm = luminaire.flux_lm();
    if let Some(beam_flux_w) = beam_flux_w {
        // Cell means sampled at the nodes integrate (trapezoid, as files are integrated) to
        // the beams' flux only up to the grid's resolution; the beams' flux is the measurement,
        // so the table is scaled to it.
        if !(flux_lm > 0.0) {
            return Err(format!(
                "the beams all leave within {:.3}° of straight up or down, where a table sampled \
                 every {step}° integrates to 0; use a smaller --step or measure the light aimed \
                 sideways",
                step / 2.0
            ));
        }
        luminaire = luminaire.scaled(beam_flux_w * k / flux_lm);
        flux_lm = luminaire.flux_lm();
    }
    Ok(Measurement {
        flux_w: flux_lm / k,
        flux_lm,
        luminaire,
        spectrum,
        centre,
        size,
        stated_power_w: light.power(),
    })
}

type Measured = (Vec<f64>, Vec<(f64, f64)>, [f64; 3], [f64; 3]);

/// Emitted rays whose origins give an evaluated light's emitting box.
const ORIGIN_SAMPLES: usize = 1 << 16;

/// Unit direction of type C angles (degrees) in the world frame.
fn direction(h: f64, v: f64) -> Vec3A {
    let (h, v) = (h.to_radians(), v.to_radians());
    Vec3A::new(
        (v.sin() * h.cos()) as f32,
        (-v.cos()) as f32,
        (-v.sin() * h.sin()) as f32,
    )
}

/// Bounding box of points: (centre, extent along x, z, y).
fn bounds_of(points: &[Vec3A]) -> Option<([f64; 3], [f64; 3])> {
    let first = *points.first()?;
    let (lo, hi) = points
        .iter()
        .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let c = (lo + hi) * 0.5;
    let e = hi - lo;
    Some((
        [c.x as f64, c.y as f64, c.z as f64],
        [e.x as f64, e.z as f64, e.y as f64],
    ))
}

/// Four wavelengths drawn from `spd` at stratified positions (shifted by `u`).
fn lanes_from(spd: &dyn Spd, u: f64) -> SampledWavelengths {
    let lambda: [f32; LANES] =
        std::array::from_fn(|i| spd.sample((i as f64 + u) / LANES as f64).lambda as f32);
    SampledWavelengths {
        lambda,
        pdf: [1.0; LANES],
        lanes: crate::spectrum::LaneMask::ALL,
    }
}

/// The light's SPD at 1 nm over its range, delta lines in their bin.
fn tabulate(spd: &dyn Spd) -> Vec<(f64, f64)> {
    let (lo, hi) = spd.range();
    let (lo, hi) = (lo.floor().max(200.0), hi.ceil().min(2000.0));
    let mut out: Vec<(f64, f64)> = (lo as i64..=hi as i64)
        .map(|l| (l as f64, spd.value(l as f64)))
        .collect();
    for line in spd.delta_lines() {
        if let Some(p) = out.iter_mut().min_by(|a, b| {
            (a.0 - line.lambda)
                .abs()
                .total_cmp(&(b.0 - line.lambda).abs())
        }) {
            p.1 += line.weight;
        }
    }
    out
}

fn measure_evaluated(
    light: &dyn Light,
    settings: &GoniometerSettings,
    h_deg: &[f64],
    v_deg: &[f64],
) -> Result<Measured, String> {
    let spd = light.spd();
    let mut rng = SampleRng::for_sample(settings.seed, 0, 0);
    // Where the light emits from: the box of the origins of emitted rays (a point light gives
    // one point). The box of n uniform points falls short of a panel's edges by ~1/(n+1) of its
    // size on each side; 65 536 points make that 3e-5 (1 024 made it 2e-3), below the table's
    // own discretisation, so a baked panel's near-field opening is the panel.
    let origins: Vec<Vec3A> = (0..ORIGIN_SAMPLES)
        .filter_map(|_| {
            let lambda = lanes_from(spd.as_ref(), rng.next_1d() as f64);
            light
                .sample_le(rng.next_2d(), rng.next_2d(), &lambda)
                .map(|s| s.ray.origin)
        })
        .collect();
    let (centre, size) = bounds_of(&origins).ok_or(
        "the light emits no rays (sample_le gave nothing), so there is nothing to measure",
    )?;
    let extent = size.iter().copied().fold(0.0, f64::max);
    let r = if extent > 0.0 { 100.0 * extent } else { 1.0 };
    let c = Vec3A::new(centre[0] as f32, centre[1] as f32, centre[2] as f32);
    let m = settings.samples.max(1);
    let side = (m as f64).sqrt().ceil() as u64;
    let mut intensity = Vec::with_capacity(h_deg.len() * v_deg.len());
    for (ih, &h) in h_deg.iter().enumerate() {
        for (iv, &v) in v_deg.iter().enumerate() {
            let w = direction(h, v);
            let p = c + w * r as f32;
            let ctx = LightSampleContext {
                p,
                p_error: Vec3A::ZERO,
                n: -w,
            };
            let mut rng = SampleRng::for_sample(settings.seed, (ih * v_deg.len() + iv) as u64, 1);
            let mut e = 0.0f64;
            for k in 0..m {
                // Stratified over the light (a point light ignores it).
                let u = Vec2::new(
                    (((k % side) as f32) + rng.next_1d()) / side as f32,
                    (((k / side % side) as f32) + rng.next_1d()) / side as f32,
                );
                let lambda = lanes_from(spd.as_ref(), rng.next_1d() as f64);
                let Some(s) = light.sample_li(&ctx, u, &lambda) else {
                    continue;
                };
                if !(s.pdf > 0.0) {
                    continue;
                }
                // Radiance per unit of the normalised SPD, averaged over the lanes.
                let norm = spd_at(spd.as_ref(), &lambda);
                let (mut num, mut den) = (0.0f64, 0.0f64);
                for i in 0..LANES {
                    num += s.radiance[i] as f64;
                    den += norm[i] as f64;
                }
                if !(den > 0.0) {
                    continue;
                }
                let cos = s.wi.dot(ctx.n).max(0.0) as f64;
                let cos = if light.flags().is_delta() { 1.0 } else { cos };
                e += num / den * cos / s.pdf as f64;
            }
            let d2 = if light.flags().is_delta() {
                // Delta lights report I/d² from their own position.
                let light_p = light
                    .sample_li(&ctx, Vec2::ZERO, &lanes_from(spd.as_ref(), 0.5))
                    .map_or(p, |s| s.p_light);
                (p - light_p).length_squared() as f64
            } else {
                r * r
            };
            intensity.push(e / m as f64 * d2);
        }
    }
    Ok((intensity, tabulate(spd.as_ref()), centre, size))
}

/// The beams' table and their flux (W, Σ power / N).
fn measure_beams(
    light: &dyn Light,
    settings: &GoniometerSettings,
    h_deg: &[f64],
    v_deg: &[f64],
) -> Result<(Measured, Option<f64>), String> {
    let step = h_deg[1] - h_deg[0];
    let (nh, nv) = (h_deg.len() - 1, v_deg.len());
    // Power per (h node 0..nh, v node), cells centred on the nodes; h = 360 copies h = 0.
    let mut power = vec![0.0f64; nh * nv];
    let mut spectrum = vec![0.0f64; 2000];
    let mut origins = Vec::new();
    let n = settings.samples.max(1);
    let mut rng = SampleRng::for_sample(settings.seed, 0, 2);
    for k in 0..n {
        let u = RandomSample {
            u: std::array::from_fn(|_| rng.next_1d() as f64),
        };
        let Some(b) = light.next_beam(&u) else {
            continue;
        };
        let d = Vec3A::new(
            b.direction.x as f32,
            b.direction.y as f32,
            b.direction.z as f32,
        );
        if !(b.power_w.is_finite() && b.power_w >= 0.0 && d.length() > 0.0) {
            continue;
        }
        let d = d.normalize();
        if k < 4096 {
            origins.push(Vec3A::new(
                b.origin.x as f32,
                b.origin.y as f32,
                b.origin.z as f32,
            ));
        }
        let gamma = (-(d.y as f64)).clamp(-1.0, 1.0).acos().to_degrees();
        let c = (-(d.z as f64))
            .atan2(d.x as f64)
            .to_degrees()
            .rem_euclid(360.0);
        let iv = ((gamma / step).round() as usize).min(nv - 1);
        let ih = ((c / step).round() as usize) % nh;
        power[ih * nv + iv] += b.power_w;
        let bin = b.wavelength_nm.floor();
        if (0.0..2000.0).contains(&bin) {
            spectrum[bin as usize] += b.power_w;
        }
    }
    let total: f64 = spectrum.iter().sum();
    if !(total > 0.0) {
        return Err(format!(
            "{n} beams carried no power in 0..2000 nm, so there is nothing to measure"
        ));
    }
    let (centre, size) = bounds_of(&origins).ok_or("the light handed out no beams")?;
    let half = step.to_radians() * 0.5;
    let dh = step.to_radians();
    let mut intensity = Vec::with_capacity((nh + 1) * nv);
    for ih in 0..=nh {
        for iv in 0..nv {
            let v = v_deg[iv].to_radians();
            let (v0, v1) = ((v - half).max(0.0), (v + half).min(std::f64::consts::PI));
            let omega = dh * (v0.cos() - v1.cos());
            intensity.push(power[(ih % nh) * nv + iv] / (n as f64 * omega));
        }
    }
    // Power histogram at 1 nm → (bin centre, W/nm), trimmed to where there is power.
    let first = spectrum.iter().position(|p| *p > 0.0).unwrap_or(0);
    let last = spectrum.iter().rposition(|p| *p > 0.0).unwrap_or(0);
    let lo = first.saturating_sub(1);
    let hi = (last + 1).min(spectrum.len() - 1);
    let table = (lo..=hi)
        .map(|i| (i as f64 + 0.5, spectrum[i] / total))
        .collect();
    Ok(((intensity, table, centre, size), Some(total / n as f64)))
}
