//! The t = 1 connection: a light-subpath vertex joined to a freshly sampled lens point, the
//! contribution landing on whatever pixel that point projects to (BDPT and light tracing).

use crate::camera::Camera;
use crate::integrator::subpath::vertex::{unoccluded, Vertex};
use crate::integrator::PathStats;
use crate::material::TransportMode;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec2;

/// Where a t = 1 contribution goes: (raster position, XYZ, its lanes for the spectral film,
/// computed only when asked for).
pub type SplatFn<'a> =
    dyn FnMut(Vec2, [f64; 3], &dyn Fn() -> crate::film::spectral_film::LaneEnergies) + 'a;

/// The t = 1 connection of light vertex `s − 1` (s ≥ 1) to a lens point sampled with `u`:
/// the unweighted contribution, the raster position and the lens vertex. For s = 1 it is the
/// light's own emission seen by the camera (area lights only).
#[inline(always)]
pub fn connect_to_camera(
    scene: &Scene,
    camera: &dyn Camera,
    light_path: &[Vertex],
    s: usize,
    lambda: &SampledWavelengths,
    u: Vec2,
    stats: &mut PathStats,
) -> Option<(SampledSpectrum, Vec2, Vertex)> {
    let qs = &light_path[s - 1];
    if !qs.connectible(scene) {
        return None;
    }
    let cs = camera.sample_wi(qs.p, u)?;
    if !(cs.pdf > 0.0 && cs.importance > 0.0) {
        return None;
    }
    let cam_v = Vertex::camera(
        cs.p_lens,
        cs.n_lens,
        SampledSpectrum::splat(cs.importance / cs.pdf),
    );
    // The wavelengths the subpath carries here (shifted by a fluorescent event, if any).
    let lambda = &qs.wavelengths(lambda);
    let c = if s == 1 {
        let li = qs.light_index(scene)? as usize;
        let light = &scene.lights.lights()[li];
        let w = cs.wi;
        let mut le = light.radiance(qs.p, qs.ng, qs.uv, w, lambda);
        scene.lights.keep_line_power_only(li, lambda, &mut le);
        let origin = qs.pdf_light_origin(scene, &cam_v);
        if le.is_black() || !(origin > 0.0) {
            return None;
        }
        le * (qs.ng.dot(w).abs() / origin) * cam_v.beta
    } else {
        let mut c = qs.beta * qs.f(scene, &cam_v, lambda, TransportMode::Importance) * cam_v.beta;
        if qs.on_surface() {
            c *= cs.wi.dot(qs.ns).abs();
        }
        c
    };
    if c.is_black() {
        return None;
    }
    stats.shadow_rays += 1;
    if !unoccluded(scene, qs, &cam_v) {
        return None;
    }
    Some((c, cs.p_raster, cam_v))
}
