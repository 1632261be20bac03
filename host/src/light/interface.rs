//! What a light is to the integrators: the [`Light`] trait, its sampling records, and the helpers point-like lights share.

use super::flags::LightFlags;
use crate::geometry::{Aabb, Ray};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::fmt::Debug;
use std::sync::Arc;

/// The receiving point of a light sample. `#[repr(C)]` in the plugin interface's `ReceiverF32`
/// layout: extension v6 passes it to plugin lights by reference (`plugin::layout`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct LightSampleContext {
    /// Point being lit (world).
    pub p: Vec3A,
    /// Its error bound (for the shadow ray).
    pub p_error: Vec3A,
    /// Its geometric normal (zero for points in media).
    pub n: Vec3A,
}

/// Light arriving at a point from a sampled light position. `#[repr(C)]` in the plugin
/// interface's `IncidentF32` layout: a plugin light writes it in place (extension v6).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct LightLiSample {
    /// Incident radiance carried along `wi` (W/(m²·sr·nm)); for delta lights the equivalent
    /// `I/d²` or `E` so that the estimator is `f·L·|cos|/pdf` in every case.
    pub radiance: SampledSpectrum,
    /// Unit direction from the receiver towards the light.
    pub wi: Vec3A,
    /// Solid-angle density of the sample (1/sr); 1 for delta lights (see [`LightFlags::is_delta`]).
    pub pdf: f32,
    /// The point on the light (for the visibility test).
    pub p_light: Vec3A,
    /// Its error bound.
    pub p_light_error: Vec3A,
    /// Light surface normal there (zero for point-like and directional lights).
    pub n_light: Vec3A,
}

/// A ray leaving a light (light tracing and BDPT light subpaths).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightLeSample {
    /// Origin on the light and unit direction.
    pub ray: Ray,
    /// Emitted radiance along the ray (W/(m²·sr·nm)); intensity W/(sr·nm) for point and spot
    /// lights; irradiance W/(m²·nm) for directional lights.
    pub radiance: SampledSpectrum,
    /// Density of the origin (1/m²; 1 for delta positions).
    pub pdf_pos: f32,
    /// Density of the direction (1/sr; 1 for delta directions).
    pub pdf_dir: f32,
    /// Light surface normal at the origin (zero when there is none).
    pub normal: Vec3A,
}

/// A light source. Object safe: the built-ins and the plugin adapters implement it alike.
pub trait Light: Send + Sync + Debug {
    /// What kind of light this is (delta position/direction, area, beams only).
    fn flags(&self) -> LightFlags;

    /// Total emitted power in W (∫ over wavelength and all directions), used to choose lights in
    /// proportion to their contribution.
    fn power(&self) -> f64;

    /// The normalised emission SPD (1/nm).
    fn spd(&self) -> Arc<dyn Spd>;

    /// Sample a point on the light as seen from `ctx` (next-event estimation).
    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample>;

    /// [`sample_li`](Self::sample_li) written into `out` (`true`) instead of returned; `out` is
    /// left as it was when there is no sample (`false`). For a caller that hands over a record
    /// of its own: the standard plugin library writes the host's sample straight into the
    /// record the host lent it, with no returned `Option` copied on the way. The default
    /// copies `sample_li`'s answer; point-like lights write in place.
    fn sample_li_into(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        lambda: &SampledWavelengths,
        out: &mut LightLiSample,
    ) -> bool {
        match self.sample_li(ctx, u, lambda) {
            Some(s) => {
                *out = s;
                true
            }
            None => false,
        }
    }

    /// Solid-angle density (1/sr) with which `sample_li` from `ctx` would produce the light point
    /// `p_light` with normal `n_light`. Zero for delta lights.
    fn pdf_li(&self, ctx: &LightSampleContext, p_light: Vec3A, n_light: Vec3A) -> f32;

    /// True when [`sample_li`](Self::sample_li) draws the light's points, from every receiver,
    /// with the area density [`sample_le`](Self::sample_le) gives its rays' origins (the
    /// positional density of [`pdf_le`](Self::pdf_le)): both uniform by area, as area lights
    /// on flat shapes are. BDPT's MIS then takes a next-event light vertex's density (its
    /// s = 1 strategy) to be the light subpath's start density. Otherwise (the default, always
    /// right, at the cost of one [`pdf_li`](Self::pdf_li) per MIS weight) it asks `pdf_li`
    /// for the density next-event estimation really had: an environment drawn by its map, a
    /// sphere by its cone, a luminaire's faces by their area.
    fn li_points_as_le(&self) -> bool {
        false
    }

    /// The numbers `u ∈ [0, 1]²` that [`sample_li`](Self::sample_li) from a receiver at
    /// `receiver` turns into the light point `p_light`, for a light whose map from `u` to its
    /// points is one-to-one from every receiver and the same kind of map from all (the same
    /// chart of the light's surface, or the same directions), with [`pdf_li`](Self::pdf_li)
    /// the density of `u` drawn uniformly: then a caller may draw `u` with any density `q(u)`
    /// on [0, 1]² and the point's density is `pdf_li · q(u)` (what the path tracer's
    /// visibility guide does, `integrator::nee_guide`). `None` (the default) for every other
    /// light. Answering: an area light on a quad (its chart `(s, t)`, whatever the receiver)
    /// or on a mesh of at most [`COORDS_MAX_TRIANGLES`](crate::geometry::COORDS_MAX_TRIANGLES)
    /// triangles; an environment whose source draws directions by a fixed map (the constant
    /// sky, image maps), from the direction `p_light − receiver`.
    fn sample_coords(&self, _receiver: Vec3A, _p_light: Vec3A) -> Option<Vec2> {
        None
    }

    /// Radiance leaving the light's surface at `p` (normal `n`, texture coordinate `uv`) in
    /// direction `w` (away from the light). Zero except for area lights.
    fn radiance(
        &self,
        p: Vec3A,
        n: Vec3A,
        uv: Vec2,
        w: Vec3A,
        lambda: &SampledWavelengths,
    ) -> SampledSpectrum;

    /// Sample an emitted ray: `u1` picks the origin, `u2` the direction.
    fn sample_le(&self, u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample>;

    /// Densities `(pdf_pos, pdf_dir)` of `sample_le` producing `ray` (leaving a point with normal
    /// `n`, zero when none).
    fn pdf_le(&self, ray: &Ray, n: Vec3A) -> (f32, f32);

    /// The seed's `next_beam`: one beam (origin, direction, wavelength, power in W as the flux
    /// estimate of one sample; see [`spectrace_plugin_api::Beam`]) from the host's random
    /// numbers. Lights flagged [`LightFlags::BEAMS_ONLY`] offer nothing else, so light tracing
    /// is the only way to render them. `None` for lights that do not hand out beams.
    fn next_beam(
        &self,
        _u: &spectrace_plugin_api::RandomSample,
    ) -> Option<spectrace_plugin_api::Beam> {
        None
    }

    /// The seed's `number_of_beams`: beams handed out by [`Light::next_beam`] so far.
    fn number_of_beams(&self) -> f64 {
        0.0
    }

    /// For environment lights: where a ray leaving the scene meets the light (the point and the
    /// light's normal there), so that the radiance it sees can be looked up with
    /// [`radiance`](Self::radiance) and weighted like an area light's. `None` for other lights.
    fn escape_point(&self, _ray: &Ray) -> Option<(Vec3A, Vec3A)> {
        None
    }

    /// The scene object whose surface this light is, for area lights.
    fn object(&self) -> Option<u32> {
        None
    }

    /// Called once the scene bounds are known (directional lights need them for `sample_le`).
    fn preprocess(&self, _scene_bounds: &Aabb) {}

    /// Called after [`preprocess`](Self::preprocess) with the bounds of the scene and every
    /// camera position (environment lights must enclose the cameras as well).
    fn preprocess_view(&self, _view_bounds: &Aabb) {}

    /// True when the emitted spectral radiance factors as `g(p, ω) · spd(λ)` with the shape
    /// [`spd`](Self::spd) the same at every point and in every direction (only the magnitude
    /// varies): then a spectrally flat path's colour can be integrated exactly over `spd`
    /// (`integrator::wavelengths::flat_colour`). The default is `false`, which is always safe.
    fn uniform_spectral_shape(&self) -> bool {
        false
    }

    /// A warning for the render summary about this light as built (e.g. a sun below the
    /// horizon, which gives no direct light). `None` by default.
    fn build_warning(&self) -> Option<String> {
        None
    }
}

/// Uniform direction on the unit sphere.
pub fn sample_uniform_sphere(u: Vec2) -> Vec3A {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * std::f32::consts::PI * u.y;
    Vec3A::new(r * phi.cos(), r * phi.sin(), z)
}

/// The numbers `u` with which [`sample_uniform_sphere`] gives the unit direction `d`
/// (`z = 1 − 2u.x`, `φ = 2π u.y`), in [0, 1)².
pub fn uniform_sphere_coords(d: Vec3A) -> Vec2 {
    let x = ((1.0 - d.z) * 0.5).clamp(0.0, 1.0 - f32::EPSILON / 2.0);
    let mut y = d.y.atan2(d.x) / (2.0 * std::f32::consts::PI);
    if y < 0.0 {
        y += 1.0;
    }
    if y >= 1.0 {
        y = 0.0;
    }
    Vec2::new(x, y)
}

/// Incident radiance at `ctx` from a point emitter at `position` whose intensity (W/(sr·nm) per
/// lane) towards the unit emission direction `w` is `intensity(w)`: the inverse-square law
/// `I(w)/d²`, as a delta sample (pdf 1). `None` when `ctx` sits on the emitter or nothing is
/// emitted towards it. Shared by every point-like light so the geometry lives in one place.
pub(crate) fn incident_from_point(
    position: Vec3A,
    ctx: &LightSampleContext,
    intensity: impl FnOnce(Vec3A) -> SampledSpectrum,
) -> Option<LightLiSample> {
    let (radiance, wi) = point_incidence(position, ctx, intensity)?;
    Some(point_sample(position, radiance, wi))
}

/// [`incident_from_point`] written into `out` (`true`), `out` untouched without a sample
/// (`false`): what point-like lights' [`Light::sample_li_into`] answers.
pub(crate) fn incident_from_point_into(
    position: Vec3A,
    ctx: &LightSampleContext,
    intensity: impl FnOnce(Vec3A) -> SampledSpectrum,
    out: &mut LightLiSample,
) -> bool {
    match point_incidence(position, ctx, intensity) {
        Some((radiance, wi)) => {
            *out = point_sample(position, radiance, wi);
            true
        }
        None => false,
    }
}

/// The radiance arriving at `ctx` from the point emitter and the unit direction towards it
/// (see [`incident_from_point`]).
#[inline]
fn point_incidence(
    position: Vec3A,
    ctx: &LightSampleContext,
    intensity: impl FnOnce(Vec3A) -> SampledSpectrum,
) -> Option<(SampledSpectrum, Vec3A)> {
    let d = position - ctx.p;
    let dist2 = d.length_squared();
    if !(dist2 > 0.0) {
        return None;
    }
    let wi = d / dist2.sqrt();
    let radiance = intensity(-wi) / dist2;
    if radiance.is_black() {
        return None;
    }
    Some((radiance, wi))
}

/// The delta sample of a point emitter at `position` (pdf 1, no surface).
#[inline]
fn point_sample(position: Vec3A, radiance: SampledSpectrum, wi: Vec3A) -> LightLiSample {
    LightLiSample {
        radiance,
        wi,
        pdf: 1.0,
        p_light: position,
        p_light_error: Vec3A::ZERO,
        n_light: Vec3A::ZERO,
    }
}
