//! A TM-25 ray file as a light: the file's rays handed out as beams (the seed's `next_beam`),
//! each drawn with replacement in proportion to its flux, carrying the whole flux as its
//! estimate (power = Φ, since the draw has probability φ_i / Φ), at a wavelength from the
//! ray's own column, the file's single wavelength or its spectral table (the ray's, by its
//! index), or the light's `spd` when the file has no spectral data.
//!
//! The rays are read from the mapped file when drawn: what is kept in memory is one cumulative
//! flux per ray (8 bytes, against the file's 28 or more), or, for a file of more than
//! `max_rays` rays, `max_rays` indices chosen by systematic resampling in proportion to flux
//! (each then equally likely, the draw still unbiased). Beams only: a ray set is a sample of
//! the source, not a function one can evaluate, so light tracing and BDPT's light paths use
//! it and nothing else sees it (the `near_field` model of the `ray_file` type builds an
//! evaluable light from the rays instead).

use super::{Light, LightFlags, LightLeSample, LightLiSample, LightSampleContext};
use crate::geometry::Ray;
use crate::photometry::tm25::RayFile;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd, TabulatedSpd};
use glam::{Vec2, Vec3A};
use spectrace_plugin_api::{Beam, RandomSample, Vec3};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

/// How rays are drawn.
#[derive(Debug)]
enum Picks {
    /// Cumulative flux per ray (draw by binary search).
    Cdf(Vec<f64>),
    /// Ray indices chosen in proportion to flux (draw uniformly).
    Subset(Vec<u64>),
}

/// Where a ray's wavelength comes from.
#[derive(Debug)]
pub enum RaySpectrum {
    /// The wavelength column.
    PerRay,
    /// One wavelength, nm.
    Single(f64),
    /// One table for every ray (identifier 3) or the light's spd (identifier 0).
    Shared(Arc<dyn Spd>),
    /// A table per ray by its 1-based index column.
    Indexed(Vec<Arc<dyn Spd>>),
}

/// A ray-file light (module docs).
#[derive(Debug)]
pub struct RayFileLight {
    file: Arc<RayFile>,
    picks: Picks,
    /// World position of the file's origin.
    origin: Vec3A,
    /// World directions of the file's x, y, z axes.
    axes: [Vec3A; 3],
    /// Metres per file length unit.
    metres_per_unit: f64,
    power_w: f64,
    spectrum: RaySpectrum,
    spd: Arc<dyn Spd>,
    beams: AtomicU64,
}

/// The spectral tables of a file as SPDs (normalised by the SPD type).
pub fn file_spectra(file: &RayFile) -> Result<Vec<Arc<dyn Spd>>, String> {
    file.header
        .spectra
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let nm: Vec<f64> = t.iter().map(|p| p.0 as f64).collect();
            let v: Vec<f64> = t.iter().map(|p| p.1 as f64).collect();
            TabulatedSpd::new(
                &format!("spectral table {} of {}", i + 1, file.path.display()),
                &nm,
                &v,
                crate::spectrum::Interpolation::Linear,
            )
            .map(|s| Arc::new(s) as Arc<dyn Spd>)
            .map_err(|e| format!("spectral table {}: {e}", i + 1))
        })
        .collect()
}

impl RayFileLight {
    /// A light of `file`'s rays. `flux_of(ray)` is a ray's radiant flux in W (the caller
    /// converts luminous flux with the spectrum); `scale` multiplies every flux (a flux
    /// override); the file's point (0,0,0) sits at `origin`, its axes along `axes`, its lengths
    /// in units of `metres_per_unit` m. Every ray is checked; the error names the bad one.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        file: Arc<RayFile>,
        origin: Vec3A,
        axes: [Vec3A; 3],
        metres_per_unit: f64,
        flux_of: impl Fn(&crate::photometry::tm25::RawRay) -> f64,
        scale: f64,
        spectrum: RaySpectrum,
        spd: Arc<dyn Spd>,
        max_rays: u64,
    ) -> Result<Self, String> {
        let n = file.n_rays();
        let n_spectra = file.header.spectra.len();
        let mut total = 0.0f64;
        let keep_cdf = n <= max_rays;
        let mut cdf = Vec::new();
        if keep_cdf {
            cdf.try_reserve_exact(n as usize)
                .map_err(|_| format!("{n} rays: no memory for their cumulative flux"))?;
        }
        for i in 0..n {
            let r = file.ray(i);
            crate::photometry::tm25::reader::check_ray(&r, n_spectra)
                .map_err(|m| format!("{}: ray {}: {m}", file.path.display(), i + 1))?;
            total += flux_of(&r);
            if keep_cdf {
                cdf.push(total);
            }
        }
        if !(total > 0.0 && total.is_finite()) {
            return Err(format!(
                "{}: the rays carry no flux (sum {total} W)",
                file.path.display()
            ));
        }
        let picks = if keep_cdf {
            Picks::Cdf(cdf)
        } else {
            // Systematic resampling: thresholds (k + ½)·Φ/M, one pass.
            let m = max_rays.max(1);
            let mut out = Vec::new();
            out.try_reserve_exact(m as usize)
                .map_err(|_| format!("max_rays {m}: no memory for the indices"))?;
            let step = total / m as f64;
            let mut next = 0.5 * step;
            let mut acc = 0.0;
            for i in 0..n {
                acc += flux_of(&file.ray(i));
                while acc > next && (out.len() as u64) < m {
                    out.push(i);
                    next += step;
                }
            }
            while (out.len() as u64) < m {
                out.push(n - 1);
            }
            Picks::Subset(out)
        };
        Ok(Self {
            file,
            picks,
            origin,
            axes,
            metres_per_unit,
            power_w: total * scale,
            spectrum,
            spd,
            beams: AtomicU64::new(0),
        })
    }

    /// Rays drawn from: all, or the resampled subset's size.
    pub fn rays_used(&self) -> u64 {
        match &self.picks {
            Picks::Cdf(c) => c.len() as u64,
            Picks::Subset(s) => s.len() as u64,
        }
    }

    /// The ray file.
    pub fn file(&self) -> &RayFile {
        &self.file
    }

    /// Index of the ray drawn by `u` ∈ [0,1).
    fn pick(&self, u: f64) -> u64 {
        match &self.picks {
            Picks::Cdf(c) => {
                let x = u * c[c.len() - 1];
                (c.partition_point(|&v| v <= x) as u64).min(c.len() as u64 - 1)
            }
            Picks::Subset(s) => s[((u * s.len() as f64) as usize).min(s.len() - 1)],
        }
    }

    /// World origin and unit direction of ray `i`.
    pub fn world_ray(&self, i: u64) -> (Vec3A, Vec3A, crate::photometry::tm25::RawRay) {
        let r = self.file.ray(i);
        let [x, y, z] = self.axes;
        let m = self.metres_per_unit as f32;
        let p =
            self.origin + (x * r.position_mm[0] + y * r.position_mm[1] + z * r.position_mm[2]) * m;
        let d = (x * r.direction[0] + y * r.direction[1] + z * r.direction[2]).normalize();
        (p, d, r)
    }
}

impl Light for RayFileLight {
    fn flags(&self) -> LightFlags {
        LightFlags::BEAMS_ONLY
    }

    fn power(&self) -> f64 {
        self.power_w
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.spd.clone()
    }

    fn sample_li(
        &self,
        _ctx: &LightSampleContext,
        _u: Vec2,
        _lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        None
    }

    fn pdf_li(&self, _ctx: &LightSampleContext, _p: Vec3A, _n: Vec3A) -> f32 {
        0.0
    }

    fn radiance(
        &self,
        _p: Vec3A,
        _n: Vec3A,
        _uv: Vec2,
        _w: Vec3A,
        _l: &SampledWavelengths,
    ) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    fn sample_le(&self, _u1: Vec2, _u2: Vec2, _l: &SampledWavelengths) -> Option<LightLeSample> {
        None
    }

    fn pdf_le(&self, _ray: &Ray, _n: Vec3A) -> (f32, f32) {
        (0.0, 0.0)
    }

    fn next_beam(&self, u: &RandomSample) -> Option<Beam> {
        self.beams.fetch_add(1, Ordering::Relaxed);
        let i = self.pick(u.u[0]);
        let (p, d, r) = self.world_ray(i);
        let nm = match &self.spectrum {
            RaySpectrum::PerRay => r.wavelength_nm.unwrap_or(f32::NAN) as f64,
            RaySpectrum::Single(l) => *l,
            RaySpectrum::Shared(s) => s.sample(u.u[1]).lambda,
            RaySpectrum::Indexed(t) => {
                let k = r.spectrum_index.unwrap_or(1.0) as usize;
                t.get(k.saturating_sub(1))?.sample(u.u[1]).lambda
            }
        };
        Some(Beam {
            origin: Vec3::new(p.x as f64, p.y as f64, p.z as f64),
            direction: Vec3::new(d.x as f64, d.y as f64, d.z as f64),
            wavelength_nm: nm,
            power_w: self.power_w,
            source_id: 0,
        })
    }

    fn number_of_beams(&self) -> f64 {
        self.beams.load(Ordering::Relaxed) as f64
    }
}
