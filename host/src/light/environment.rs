//! Environment lights: light arriving from outside the scene in every direction (a sky), seen by
//! every ray that leaves the scene. The built-in scene type `environment` (parameters in
//! `builtin/light/environment.rs`) is a [`ConstantEnvironment`], radiance `scale · S(λ)`
//! W/(m²·sr·nm) from every direction; plugin lights with the ENVIRONMENT capability give their
//! own radiance through the same [`EnvironmentRadiance`] trait.
//!
//! # How integrators see it
//! An environment is modelled as a sphere around the scene and every camera (centre and radius
//! from the bounds given to [`Light::preprocess_view`], 1% larger) that emits the environment's
//! radiance inwards: a ray leaving the scene in direction `d` meets the sphere and sees `L(d)`
//! whatever the sphere's size, so the picture is exact, and BDPT's area-measure MIS treats the
//! sphere like any area light (no vertex at infinity). Next-event estimation draws the incident
//! direction from the [`EnvironmentRadiance`] (uniform over the sphere of directions unless the
//! source importance-samples) and reports that solid-angle density, which the BSDF-hit side of
//! MIS asks again through [`Light::pdf_li`]. A source whose map from sample numbers to directions
//! is one-to-one gives the numbers of a direction back ([`EnvironmentRadiance::direction_coords`]:
//! the constant sky, image maps and the CIE skies do), so the path tracer's visibility guide
//! (`integrator::nee_guide`) can draw them from a density learned per region, as for a sky
//! seen through a window. Light subpaths (light tracing, BDPT, the
//! illuminance sensors) of a source that asks for it
//! ([`EnvironmentRadiance::samples_emission`]: image maps and the CIE skies do, so bright
//! skies and suns start as many paths as they deserve) draw their direction from the same
//! distribution, then a point uniform on the disc of radius `R` through the centre across that
//! direction, moved along it onto the sphere (pbrt's construction, kept on the sphere so that the
//! start is an ordinary area-light vertex). Densities: position `1/(4πR²)`, direction
//! `4 · cos θ · p(ω)` (`θ` from the inward normal, `p` the source's density of `ω`), whose
//! product is the joint density `p(ω) · cos θ/(πR²)`; for a uniform source this is exactly an
//! area light's uniform position and `cos θ/π` lobe, so no special case is needed in the
//! connections. Other sources (the constant sky, plugin environments that do not declare
//! `SPHERE_EMISSION`) start uniformly on the sphere with cosine-distributed inward directions:
//! those same densities, drawn directly. A plugin environment that declares it starts its
//! subpaths from its own `sample_emission` on this sphere (`plugin::adapter`).
//!
//! BDPT weighs next-event estimation (its s = 1 strategy) with the density next-event
//! estimation has, `p(ω)` converted to area on the sphere, not with the subpaths' start
//! density (`integrator::bdpt::mis::nee_correction`): this light says so by leaving
//! [`Light::li_points_as_le`] false.
//!
//! Power for light selection: `π R² · 4π · L̄`, the flux through the scene's bounding disc (as
//! pbrt does), `L̄` the direction-averaged radiance integrated over wavelength.

use super::LightSampleContext;
use super::{
    sample_uniform_sphere, uniform_sphere_coords, Light, LightFlags, LightLeSample, LightLiSample,
};
use crate::geometry::{Aabb, Ray};
use crate::material::{sample_concentric_disk, sample_cosine_hemisphere, Frame};
use crate::spectrum::dense::DenseSpectrum;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;
use std::fmt::Debug;
use std::sync::{Arc, OnceLock};

/// Where an environment's radiance comes from (the built-in constant sky, or a plugin light
/// with the `ENVIRONMENT` capability).
pub trait EnvironmentRadiance: Send + Sync + Debug {
    /// Radiance W/(m²·sr·nm) per lane arriving along a ray that leaves the scene in unit
    /// direction `dir`.
    fn radiance(&self, dir: Vec3A, lambda: &SampledWavelengths) -> SampledSpectrum;

    /// The normalised spectrum light subpaths draw wavelengths from (1/nm).
    fn spd(&self) -> Arc<dyn Spd>;

    /// Radiance integrated over wavelength and averaged over all directions, W/(m²·sr).
    fn mean_radiance(&self) -> f64;

    /// A direction towards the environment as seen from `p` with its solid-angle density
    /// (1/sr), for next-event estimation. Default: uniform over the sphere.
    fn sample_direction(&self, _p: Vec3A, u: Vec2) -> Option<(Vec3A, f32)> {
        Some((sample_uniform_sphere(u), 1.0 / (4.0 * PI)))
    }

    /// The density (1/sr) with which [`sample_direction`](Self::sample_direction) from `p`
    /// returns the unit direction `dir`.
    fn direction_pdf(&self, _p: Vec3A, _dir: Vec3A) -> f32 {
        1.0 / (4.0 * PI)
    }

    /// The numbers `u` with which [`sample_direction`](Self::sample_direction) from `p`
    /// returns the unit direction `dir`, for a source whose map from `u` to directions is
    /// one-to-one (what lets the path tracer's visibility guide draw `u` with a density of
    /// its own, see [`Light::sample_coords`]). `None` (the default: a source that overrides
    /// `sample_direction` must override this too to answer).
    fn direction_coords(&self, _p: Vec3A, _dir: Vec3A) -> Option<Vec2> {
        None
    }

    /// True when light subpaths should also draw their direction from
    /// [`sample_direction`](Self::sample_direction) (asked from the sphere's centre; see the
    /// module docs). `false` (the default) keeps the uniform start: uniform on the sphere,
    /// cosine-distributed inwards.
    fn samples_emission(&self) -> bool {
        false
    }
}

/// The built-in environment: the same radiance `scale · S(λ)` from every direction.
#[derive(Debug)]
pub struct ConstantEnvironment {
    spd: Arc<dyn Spd>,
    scale: f32,
    radiance: DenseSpectrum,
}

impl ConstantEnvironment {
    /// Radiance `scale · spd(λ)` (`scale` in W/(m²·sr), `spd` normalised).
    pub fn new(spd: Arc<dyn Spd>, scale: f32) -> Result<Self, String> {
        if !(scale.is_finite() && scale > 0.0) {
            return Err(format!("`scale` must be a finite number > 0, got {scale}"));
        }
        Ok(Self {
            radiance: DenseSpectrum::from_spd(spd.clone(), scale),
            spd,
            scale,
        })
    }
}

impl EnvironmentRadiance for ConstantEnvironment {
    fn radiance(&self, _dir: Vec3A, lambda: &SampledWavelengths) -> SampledSpectrum {
        self.radiance.eval(lambda)
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.spd.clone()
    }

    fn mean_radiance(&self) -> f64 {
        self.scale as f64
    }

    // The default `sample_direction`: uniform over the sphere.
    fn direction_coords(&self, _p: Vec3A, dir: Vec3A) -> Option<Vec2> {
        Some(uniform_sphere_coords(dir))
    }
}

/// An environment light (see the module docs).
#[derive(Debug)]
pub struct EnvironmentLight {
    source: Arc<dyn EnvironmentRadiance>,
    /// Enclosing sphere (centre, radius), set by `preprocess_view`.
    sphere: OnceLock<(Vec3A, f32)>,
}

impl EnvironmentLight {
    /// An environment seeing `source`.
    pub fn new(source: Arc<dyn EnvironmentRadiance>) -> Self {
        Self {
            source,
            sphere: OnceLock::new(),
        }
    }

    /// The emitting sphere (centre, radius): the view bounds' centre and 1.01 × half their
    /// diagonal, once [`Light::preprocess_view`] has set it (the unit sphere before).
    pub fn sphere(&self) -> (Vec3A, f32) {
        *self.sphere.get().unwrap_or(&(Vec3A::ZERO, 1.0))
    }

    /// Where a ray from `p` (inside the sphere) along unit `d` leaves the sphere.
    fn exit(&self, p: Vec3A, d: Vec3A) -> Option<Vec3A> {
        let (c, r) = self.sphere();
        let o = p - c;
        let b = o.dot(d);
        let disc = b * b - (o.length_squared() - r * r);
        if !(disc >= 0.0) {
            return None;
        }
        let t = -b + disc.sqrt();
        (t > 0.0).then(|| p + d * t)
    }

    /// Inward unit normal of the sphere at `x`.
    fn inward(&self, x: Vec3A) -> Vec3A {
        let (c, _) = self.sphere();
        (c - x).normalize_or_zero()
    }
}

impl Light for EnvironmentLight {
    fn flags(&self) -> LightFlags {
        LightFlags::ENVIRONMENT
    }

    fn power(&self) -> f64 {
        let (_, r) = self.sphere();
        let r = r as f64;
        std::f64::consts::PI * r * r * 4.0 * std::f64::consts::PI * self.source.mean_radiance()
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.source.spd()
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        let (wi, pdf) = self.source.sample_direction(ctx.p, u)?;
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        let p_light = self.exit(ctx.p, wi)?;
        let radiance = self.source.radiance(wi, lambda);
        if radiance.is_black() {
            return None;
        }
        Some(LightLiSample {
            radiance,
            wi,
            pdf,
            p_light,
            p_light_error: Vec3A::ZERO,
            n_light: self.inward(p_light),
        })
    }

    fn pdf_li(&self, ctx: &LightSampleContext, p_light: Vec3A, _n_light: Vec3A) -> f32 {
        let d = (p_light - ctx.p).normalize_or_zero();
        if d == Vec3A::ZERO {
            return 0.0;
        }
        self.source.direction_pdf(ctx.p, d)
    }

    // The direction from the receiver to the point on the sphere, back to the source's numbers.
    fn sample_coords(&self, receiver: Vec3A, p_light: Vec3A) -> Option<Vec2> {
        let d = (p_light - receiver).normalize_or_zero();
        if d == Vec3A::ZERO {
            return None;
        }
        self.source.direction_coords(receiver, d)
    }

    fn radiance(
        &self,
        _p: Vec3A,
        n: Vec3A,
        _uv: Vec2,
        w: Vec3A,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum {
        // `w` travels into the scene: the ray that sees this point leaves along `−w`.
        if n.dot(w) <= 0.0 {
            return SampledSpectrum::zero();
        }
        self.source.radiance(-w, lambda)
    }

    fn sample_le(&self, u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        let (c, r) = self.sphere();
        if !self.source.samples_emission() {
            let origin = c + sample_uniform_sphere(u1) * r;
            let n = self.inward(origin);
            let local = sample_cosine_hemisphere(u2);
            if !(local.z > 0.0) {
                return None;
            }
            let dir = Frame::from_normal(n).to_world(local);
            return Some(LightLeSample {
                ray: Ray::new(origin, dir),
                radiance: self.source.radiance(-dir, lambda),
                pdf_pos: 1.0 / (4.0 * PI * r * r),
                pdf_dir: local.z / PI,
                normal: n,
            });
        }
        // The direction first, from the source's own distribution (the map's luminance for an
        // image, uniform for the constant sky), asked from the sphere's centre.
        let (w, pdf_w) = self.source.sample_direction(c, u2)?;
        if !(pdf_w > 0.0 && pdf_w.is_finite()) {
            return None;
        }
        let w = w.normalize_or_zero();
        if w == Vec3A::ZERO {
            return None;
        }
        // Then a point uniform on the disc of radius R through the centre across `w`, moved
        // along `w` onto the sphere: the ray travels along −w through the disc point.
        let d = sample_concentric_disk(u1);
        let frame = Frame::from_normal(w);
        let h2 = 1.0 - d.length_squared();
        if !(h2 > 0.0) {
            return None;
        }
        let cos = h2.sqrt();
        let origin = c + frame.to_world(Vec3A::new(d.x, d.y, cos)) * r;
        let dir = -w;
        let (pdf_pos, pdf_dir) = split_density(r, cos, pdf_w);
        let radiance = self.source.radiance(w, lambda);
        Some(LightLeSample {
            ray: Ray::new(origin, dir),
            radiance,
            pdf_pos,
            pdf_dir,
            normal: self.inward(origin),
        })
    }

    fn pdf_le(&self, ray: &Ray, _n: Vec3A) -> (f32, f32) {
        let (c, r) = self.sphere();
        let dir = ray.dir.normalize_or_zero();
        let cos = self.inward(ray.origin).dot(dir);
        if !(cos > 0.0) {
            return (1.0 / (4.0 * PI * r * r), 0.0);
        }
        if !self.source.samples_emission() {
            return (1.0 / (4.0 * PI * r * r), cos / PI);
        }
        split_density(r, cos, self.source.direction_pdf(c, -dir))
    }

    fn escape_point(&self, ray: &Ray) -> Option<(Vec3A, Vec3A)> {
        let d = ray.dir.normalize_or_zero();
        let x = self.exit(ray.origin, d)?;
        Some((x, self.inward(x)))
    }

    fn preprocess_view(&self, view_bounds: &Aabb) {
        let c = (view_bounds.min + view_bounds.max) * 0.5;
        let r = (view_bounds.max - view_bounds.min).length() * 0.5;
        let _ = self.sphere.set((c, 1.01 * r.max(1e-3)));
    }
}

/// `sample_le`'s densities for an inward ray meeting the sphere (radius `r`) at an angle of
/// cosine `cos` to its inward normal and travelling along `−w`, `w` drawn with density `pdf_w`
/// (1/sr): the joint density in area × solid angle is `pdf_w · cos/(πR²)` (a uniform disc point
/// of density `1/(πR²)` in the plane across `w`, projected onto the sphere: `dA⊥ = cos · dA`).
/// It is reported as the uniform positional density `1/(4πR²)` (the marginal over positions
/// when the directions are uniform) times the directional density `4 · cos · pdf_w`, which for
/// a uniform source is `cos/π`, the cosine lobe of an area light. Only the product enters the
/// light subpath's throughput; BDPT's MIS asks [`Light::pdf_le`] for the same split.
fn split_density(r: f32, cos: f32, pdf_w: f32) -> (f32, f32) {
    (1.0 / (4.0 * PI * r * r), 4.0 * cos.max(0.0) * pdf_w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::BuiltinSpd;

    fn light() -> EnvironmentLight {
        let spd: Arc<dyn Spd> = Arc::new(BuiltinSpd::blackbody(5000.0).unwrap());
        let l = EnvironmentLight::new(Arc::new(ConstantEnvironment::new(spd, 2.0).unwrap()));
        l.preprocess_view(&Aabb::from_point(Vec3A::splat(-1.0)).grow(Vec3A::splat(1.0)));
        l
    }

    /// `sample_le`'s densities are the ones `pdf_le` reports, its origins lie on the sphere and
    /// its directions point inwards; `sample_li` from inside reports the density `pdf_li` gives
    /// for the same point, and the point is on the sphere. Exact up to f32 rounding (1e-4
    /// relative).
    #[test]
    fn sampling_densities_agree() {
        let l = light();
        let lambda = SampledWavelengths::sample_visible(0.3);
        let (c, r) = l.sphere();
        for k in 0..200 {
            // (Off the unit square's edge, which maps to the disc's rim: a ray grazing the
            // sphere, of density zero, for which `sample_le` gives nothing.)
            let u1 = Vec2::new(
                (k as f32 * 0.618 + 0.013).fract(),
                (k as f32 * 0.414 + 0.1).fract(),
            );
            let u2 = Vec2::new(
                (k as f32 * 0.732 + 0.05).fract(),
                (k as f32 * 0.236 + 0.3).fract(),
            );
            let s = l.sample_le(u1, u2, &lambda).unwrap();
            assert!(((s.ray.origin - c).length() / r - 1.0).abs() < 1e-4);
            assert!(s.normal.dot(s.ray.dir) > 0.0);
            let (pp, pd) = l.pdf_le(&s.ray, s.normal);
            assert!((pp / s.pdf_pos - 1.0).abs() < 1e-4 && (pd / s.pdf_dir - 1.0).abs() < 1e-3);
            let ctx = LightSampleContext {
                p: Vec3A::new(0.3, -0.2, 0.5),
                p_error: Vec3A::ZERO,
                n: Vec3A::Z,
            };
            let li = l.sample_li(&ctx, u1, &lambda).unwrap();
            assert!(((li.p_light - c).length() / r - 1.0).abs() < 1e-4);
            assert!((l.pdf_li(&ctx, li.p_light, li.n_light) / li.pdf - 1.0).abs() < 1e-4);
            let seen = l.radiance(li.p_light, li.n_light, Vec2::ZERO, -li.wi, &lambda);
            assert_eq!(seen, li.radiance);
        }
    }
}
