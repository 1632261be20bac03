//! Any light as a ray file: `n` rays drawn from the light as light tracing draws them, written
//! as TM-25-13 in the world frame (file x, y, z = world x, y, z, start points in mm).
//!
//! - Lights that can be evaluated (point, spot, area, luminaire, connectable plugin lights):
//!   each ray is the beam [`beam_from_emission`] makes (what such a light answers to
//!   `next_beam`): `sample_le` gives an origin and a direction, the wavelength is drawn from the
//!   light's normalised SPD with density `p(λ)`, and the ray's radiant flux is the one-sample
//!   flux estimate divided by `n`, `L(λ) · |cos θ| / (pdf_pos · pdf_dir · p(λ)) / n` W
//!   (|cos θ| = 1 without a surface), so the rays sum to the light's power up to Monte Carlo
//!   noise and their directions and origins follow its emission. The spectrum is written as one
//!   table (the SPD at 1 nm, identifier 3) when the SPD has no delta lines, else as a wavelength
//!   per ray (identifier 2).
//! - Lights that only hand out beams: each beam is one ray (its power / `n`), a wavelength per
//!   ray (identifier 2).
//!
//! Random numbers: eight per ray from the renderer's own generator
//! ([`SampleRng::for_sample`]), as a [`RandomSample`] (`u[0..4]` origin and direction, `u[4]`
//! wavelength), so the same seed gives the same file. A ray the light has nothing for (no
//! sample, or one that carries nothing) is written with flux 0 and counted as empty.

use crate::light::emission_beam::beam_from_emission;
use crate::light::{Light, LightFlags};
use crate::photometry::efficacy::luminous_efficacy_lm_per_w;
use crate::photometry::tm25::writer::{write_tm25, Tm25Spectrum, WriteHeader, WriteRay};
use crate::sampler::SampleRng;
use spectrace_plugin_api::RandomSample;
use std::io::Write;

/// What an export wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportSummary {
    /// Rays written.
    pub rays: u64,
    /// Rays the light had nothing for (no sample, or one that carries nothing): written with
    /// flux 0 so the count holds.
    pub empty: u64,
    /// Their radiant flux, W.
    pub flux_w: f64,
    /// The light's own stated power, W.
    pub stated_w: f64,
    /// Luminous flux, lm (from the light's SPD; NaN for beams-only lights).
    pub flux_lm: f64,
    /// Spectral data identifier written.
    pub spectral_id: i32,
}

/// Ray `i` of `n`: a beam of the light from the renderer's own random numbers for that ray
/// (the light's own beams, or [`beam_from_emission`]), its power divided by `n`. `None` when the
/// light has nothing for these numbers (no beam, or one that carries nothing).
fn ray_from(light: &dyn Light, seed: u64, i: u64, n: u64) -> Option<WriteRay> {
    let mut rng = SampleRng::for_sample(seed, i, 11);
    let u = RandomSample {
        u: std::array::from_fn(|_| rng.next_1d() as f64),
    };
    let b = if light.flags().contains(LightFlags::BEAMS_ONLY) {
        light.next_beam(&u)?
    } else {
        beam_from_emission(light, &u)
            .ok()
            .filter(|b| b.power_w > 0.0)?
    };
    let f = |v: f64| v as f32;
    Some(WriteRay {
        position_mm: [
            f(b.origin.x * 1e3),
            f(b.origin.y * 1e3),
            f(b.origin.z * 1e3),
        ],
        direction: [f(b.direction.x), f(b.direction.y), f(b.direction.z)],
        flux_w: (b.power_w * (1.0 / n as f64)) as f32,
        wavelength_nm: b.wavelength_nm as f32,
    })
}

/// Write `n` rays of `light` to `out` (see the module docs); `texts` fill the nine text
/// fields. Two passes over the same random numbers: the first sums the flux for the header.
pub fn export_light(
    light: &dyn Light,
    n: u64,
    seed: u64,
    texts: [String; 9],
    out: &mut impl Write,
) -> Result<ExportSummary, String> {
    if n == 0 {
        return Err("the number of rays must be ≥ 1".into());
    }
    let beams = light.flags().contains(LightFlags::BEAMS_ONLY);
    if light.flags().contains(LightFlags::DELTA_DIRECTION)
        || light.flags().contains(LightFlags::ENVIRONMENT)
    {
        return Err("a directional or environment light has no start points to write".into());
    }
    let spd = light.spd();
    let per_ray = beams || !spd.delta_lines().is_empty();
    let spectrum = if per_ray {
        Tm25Spectrum::PerRay
    } else {
        let (lo, hi) = spd.range();
        let (lo, hi) = (lo.ceil().max(200.0) as i64, hi.floor().min(2000.0) as i64);
        let t: Vec<(f32, f32)> = (lo..=hi)
            .map(|l| (l as f32, spd.value(l as f64) as f32))
            .collect();
        if !t.iter().any(|p| p.1 > 0.0) {
            return Err("the light's spectrum is zero on 200..2000 nm".into());
        }
        Tm25Spectrum::Table(t)
    };
    let mut flux = 0.0f64;
    let mut empty = 0u64;
    for i in 0..n {
        match ray_from(light, seed, i, n) {
            Some(r) => flux += r.flux_w as f64,
            None => empty += 1,
        }
    }
    let flux_lm = if beams {
        f64::NAN
    } else {
        flux * luminous_efficacy_lm_per_w(spd.as_ref())
    };
    let header = WriteHeader {
        luminous_flux_lm: flux_lm as f32,
        radiant_flux_w: flux as f32,
        date: String::new(),
        texts,
        spectrum: spectrum.clone(),
    };
    let rays = (0..n).map(|i| {
        ray_from(light, seed, i, n).unwrap_or(WriteRay {
            position_mm: [0.0; 3],
            direction: [0.0, 0.0, 1.0],
            flux_w: 0.0,
            wavelength_nm: 555.0,
        })
    });
    write_tm25(out, &header, n, rays).map_err(|e| e.to_string())?;
    Ok(ExportSummary {
        rays: n,
        empty,
        flux_w: flux,
        stated_w: light.power(),
        flux_lm,
        spectral_id: match spectrum {
            Tm25Spectrum::PerRay => 2,
            _ => 3,
        },
    })
}
