//! The light subpath: a light chosen by power, an emitted ray, then the random walk in
//! importance mode (BDPT and light tracing).

use crate::integrator::subpath::random_walk::{random_walk, WalkShift};
use crate::integrator::subpath::vertex::Vertex;
use crate::integrator::wavelengths::mixture::WavelengthMixture;
use crate::integrator::{PathStats, UniformSource};
use crate::light::LightFlags;
use crate::material::TransportMode;
use crate::scene::Scene;
use crate::spectrum::{LaneMask, SampledWavelengths};
use glam::Vec2;

/// How a light subpath started.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightStart {
    /// No light could be sampled (no lights, or a zero-density sample).
    None,
    /// A subpath from an evaluable light is in the path buffer.
    Path,
    /// The chosen light is beams-only: light `index` chosen with probability `pmf`; the caller
    /// traces one of its beams instead.
    Beams {
        /// Light index.
        index: usize,
        /// Its selection probability.
        pmf: f32,
    },
}

/// The light subpath: a light chosen by power, an emitted ray from `sample_le`, then a random
/// walk in importance mode, up to `max_vertices` vertices; `shift` says what the walk does at
/// fluorescent surfaces.
#[allow(clippy::too_many_arguments)]
pub fn generate_light_subpath<S: UniformSource>(
    scene: &Scene,
    lambda: &SampledWavelengths,
    rng: &mut S,
    max_vertices: usize,
    rr_depth: u32,
    path: &mut Vec<Vertex>,
    stats: &mut PathStats,
    shift: WalkShift,
) -> LightStart {
    let u_light = rng.next_1d();
    let u1 = rng.next_2d();
    let u2 = rng.next_2d();
    generate_light_subpath_with(
        scene,
        lambda,
        (u_light, u1, u2),
        rng,
        max_vertices,
        rr_depth,
        path,
        stats,
        shift,
    )
}

/// [`generate_light_subpath`] with the start given: `u_light` picks the light, `u1` and `u2`
/// go to its `sample_le` (for callers with stratified samples); `rng` drives the walk.
#[allow(clippy::too_many_arguments)]
pub fn generate_light_subpath_with<S: UniformSource>(
    scene: &Scene,
    lambda: &SampledWavelengths,
    (u_light, u1, u2): (f32, Vec2, Vec2),
    rng: &mut S,
    max_vertices: usize,
    rr_depth: u32,
    path: &mut Vec<Vertex>,
    stats: &mut PathStats,
    shift: WalkShift,
) -> LightStart {
    path.clear();
    if max_vertices == 0 {
        return LightStart::None;
    }
    let Some((li, pmf)) = scene.lights.sample(u_light) else {
        return LightStart::None;
    };
    if scene.lights.lights()[li]
        .flags()
        .contains(LightFlags::BEAMS_ONLY)
    {
        return LightStart::Beams { index: li, pmf };
    }
    start_at_light(
        scene,
        (li, pmf),
        lambda,
        (u1, u2),
        rng,
        max_vertices,
        rr_depth,
        path,
        stats,
        shift,
    )
}

/// bdpt in a fluorescent scene, when the pair's mode says the light subpath draws its own
/// wavelengths: as [`generate_light_subpath_with`], with the lanes drawn after the light is
/// chosen, from that light's spectrum with `u_lambda`
/// ([`WavelengthMixture::sample_light`]), and written to `own` (their pdfs are the draw's
/// densities). The subpath's vertices carry wavelengths relative to `own`.
#[allow(clippy::too_many_arguments)]
pub fn generate_light_subpath_own<S: UniformSource>(
    scene: &Scene,
    mixture: &WavelengthMixture,
    u_lambda: f64,
    (u_light, u1, u2): (f32, Vec2, Vec2),
    rng: &mut S,
    max_vertices: usize,
    rr_depth: u32,
    path: &mut Vec<Vertex>,
    stats: &mut PathStats,
    own: &mut SampledWavelengths,
) -> LightStart {
    path.clear();
    own.lanes = LaneMask::NONE;
    if max_vertices == 0 {
        return LightStart::None;
    }
    let Some((li, pmf)) = scene.lights.sample(u_light) else {
        return LightStart::None;
    };
    if scene.lights.lights()[li]
        .flags()
        .contains(LightFlags::BEAMS_ONLY)
    {
        return LightStart::Beams { index: li, pmf };
    }
    let Some(lambda) = mixture.sample_light(li, u_lambda) else {
        return LightStart::None;
    };
    *own = lambda;
    start_at_light(
        scene,
        (li, pmf),
        own,
        (u1, u2),
        rng,
        max_vertices,
        rr_depth,
        path,
        stats,
        WalkShift::LightLanesRecorded,
    )
}

/// The rest of a light subpath once light `li` (chosen with `pmf`) and the wavelengths are
/// known: the emitted ray from `sample_le` and the walk.
#[allow(clippy::too_many_arguments)]
#[inline]
fn start_at_light<S: UniformSource>(
    scene: &Scene,
    (li, pmf): (usize, f32),
    lambda: &SampledWavelengths,
    (u1, u2): (Vec2, Vec2),
    rng: &mut S,
    max_vertices: usize,
    rr_depth: u32,
    path: &mut Vec<Vertex>,
    stats: &mut PathStats,
    shift: WalkShift,
) -> LightStart {
    let light = &scene.lights.lights()[li];
    let flags = light.flags();
    let Some(mut les) = light.sample_le(u1, u2, lambda) else {
        return LightStart::None;
    };
    scene
        .lights
        .keep_line_power_only(li, lambda, &mut les.radiance);
    if !(les.pdf_pos > 0.0 && les.pdf_dir > 0.0) || les.radiance.is_black() {
        return LightStart::None;
    }
    let cos = if les.normal != glam::Vec3A::ZERO {
        les.normal.dot(les.ray.dir).abs()
    } else {
        1.0
    };
    let beta = les.radiance * (cos / (pmf * les.pdf_pos * les.pdf_dir));
    let mut v0 = Vertex::light(
        li as u32,
        les.ray.origin,
        glam::Vec3A::ZERO,
        les.normal,
        beta,
    );
    v0.pdf_fwd = pmf * les.pdf_pos;
    path.push(v0);
    random_walk(
        scene,
        les.ray,
        lambda,
        rng,
        beta,
        les.pdf_dir,
        max_vertices - 1,
        TransportMode::Importance,
        rr_depth,
        path,
        stats,
        shift,
    );
    // Parallel rays of a directional light: the density at the first hit is positional.
    if flags.contains(LightFlags::DELTA_DIRECTION) && path.len() > 1 {
        let cos1 = if path[1].on_surface() {
            path[1].ng.dot(les.ray.dir).abs()
        } else {
            1.0
        };
        path[1].pdf_fwd = les.pdf_pos * cos1;
    }
    LightStart::Path
}
