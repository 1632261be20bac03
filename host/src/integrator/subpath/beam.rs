//! Beams of `BEAMS_ONLY` lights (only the seed's `next_beam`): a beam is one Monte Carlo
//! sample of its source's flux (`power_w` already divides by the densities of its origin,
//! direction and wavelength), carried at its single wavelength and light traced. BDPT and light
//! tracing both use it, with weight 1, since no other strategy can reach those lights.

use crate::camera::Camera;
use crate::film::spectral_film::LaneEnergies;
use crate::film::Sensor;
use crate::geometry::Ray;
use crate::integrator::subpath::camera_connection::{connect_to_camera, SplatFn};
use crate::integrator::subpath::random_walk::{random_walk, WalkShift};
use crate::integrator::subpath::vertex::Vertex;
use crate::integrator::{PathStats, UniformSource};
use crate::material::TransportMode;
use crate::scene::Scene;
use crate::spectrum::{LaneMask, SampledSpectrum, SampledWavelengths, LANES};
use glam::Vec3A;

/// Trace one beam of beams-only light `index` (chosen with probability `pmf`) and hand every
/// camera connection of its path to `splat` as (raster position, XYZ, its lane for the
/// spectral film on demand).
#[allow(clippy::too_many_arguments)]
pub fn trace_beam<S: UniformSource>(
    scene: &Scene,
    camera: &dyn Camera,
    sensor: &Sensor,
    index: usize,
    pmf: f32,
    max_depth: u32,
    rr_depth: u32,
    rng: &mut S,
    stats: &mut PathStats,
    splat: &mut SplatFn<'_>,
) {
    let u: [f64; 8] = std::array::from_fn(|_| rng.next_1d() as f64);
    trace_beam_with(
        scene, camera, sensor, index, pmf, max_depth, rr_depth, u, rng, stats, splat,
    );
}

/// [`trace_beam`] with the beam's eight uniforms `u` given (for callers with stratified
/// samples); the walk after the beam leaves its source draws from `rng`.
#[allow(clippy::too_many_arguments)]
pub fn trace_beam_with<S: UniformSource>(
    scene: &Scene,
    camera: &dyn Camera,
    sensor: &Sensor,
    index: usize,
    pmf: f32,
    max_depth: u32,
    rr_depth: u32,
    u: [f64; 8],
    rng: &mut S,
    stats: &mut PathStats,
    splat: &mut SplatFn<'_>,
) {
    let light = &scene.lights.lights()[index];
    let Some(beam) = light.next_beam(&spectrace_plugin_api::RandomSample { u }) else {
        return;
    };
    let dir = Vec3A::new(
        beam.direction.x as f32,
        beam.direction.y as f32,
        beam.direction.z as f32,
    );
    let origin = Vec3A::new(
        beam.origin.x as f32,
        beam.origin.y as f32,
        beam.origin.z as f32,
    );
    let power = beam.power_w / pmf as f64;
    if !(power.is_finite() && power > 0.0 && dir.length_squared() > 0.0 && origin.is_finite()) {
        return;
    }
    let nm = beam.wavelength_nm as f32;
    let lambda = SampledWavelengths {
        lambda: [nm; LANES],
        pdf: [1.0, 0.0, 0.0, 0.0],
        lanes: LaneMask::HERO,
    };
    let iy = sensor.observer().integral_y();
    let bar = sensor.observer().xyz_bar(beam.wavelength_nm);
    // An invisible beam may still become visible light at a fluorescent surface.
    if !(iy > 0.0) || (bar.iter().all(|&b| b == 0.0) && !scene.objects.fluorescence()) {
        return;
    }
    let beta = SampledSpectrum::splat(power as f32);
    let mut path = vec![Vertex::light(
        index as u32,
        origin,
        Vec3A::ZERO,
        Vec3A::ZERO,
        beta,
    )];
    random_walk(
        scene,
        Ray::new(origin, dir.normalize()),
        &lambda,
        rng,
        beta,
        1.0,
        max_depth as usize,
        TransportMode::Importance,
        rr_depth,
        &mut path,
        stats,
        WalkShift::LightLanes,
    );
    for s in 2..=path.len() {
        if let Some((c, raster, _)) =
            connect_to_camera(scene, camera, &path, s, &lambda, rng.next_2d(), stats)
        {
            let v = c.0[0] as f64 / iy;
            // After a fluorescent event the beam arrives at the wavelength it was shifted to.
            let (bar, nm) = match path[s - 1].shifted {
                Some(l) => (sensor.observer().xyz_bar(l[0] as f64), l[0]),
                None => (bar, nm),
            };
            splat(raster, bar.map(|b| b * v), &|| {
                LaneEnergies::single(nm, c.0[0] as f64)
            });
        }
    }
}
