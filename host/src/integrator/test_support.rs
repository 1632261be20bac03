//! Helpers shared by the integrators' unit tests (compiled for tests only).

use super::subpath::random_walk::generate_camera_subpath;
use super::subpath::vertex::Vertex;
use super::wavelengths::mixture::WavelengthMixture;
use super::{PathStats, SampleRng};
use crate::camera::CameraSample;
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;
use glam::Vec2;

/// Camera subpaths of `scene`'s default camera through a window of its film: for `k` in
/// `0..rays`, a [`SampleRng`] for `(seed, k)` draws the wavelengths from the scene's
/// [`WavelengthMixture`], then a film point uniform in `origin + size·u` (pixels) and a lens
/// point, and the subpath of at most `max_vertices` vertices (Russian roulette from vertex
/// `rr_depth`) is handed to `each` with its wavelengths.
pub fn for_each_camera_subpath(
    scene: &Scene,
    seed: u64,
    rays: u64,
    (origin, size): (Vec2, Vec2),
    (max_vertices, rr_depth): (usize, u32),
    mut each: impl FnMut(&[Vertex], &SampledWavelengths),
) {
    let cam = scene.cameras.get(None).unwrap();
    let camera = cam.camera.as_ref();
    let mixture = WavelengthMixture::new(scene);
    let mut path = Vec::new();
    let mut stats = PathStats::default();
    for k in 0..rays {
        let mut rng = SampleRng::for_sample(seed, k, 0);
        let lambda = mixture.sample(&mut rng);
        let u = rng.next_2d();
        let cs = CameraSample {
            p_film: origin + size * u,
            p_lens: rng.next_2d(),
        };
        let cray = camera.generate_ray(&cs).unwrap();
        generate_camera_subpath(
            scene,
            camera,
            cray.ray,
            cray.weight,
            &lambda,
            &mut rng,
            max_vertices,
            rr_depth,
            &mut path,
            &mut stats,
        );
        each(&path, &lambda);
    }
}
