//! Which pixels show a specular (delta-BSDF) surface: glass, mirrors. What the camera sees
//! through them is reached only by camera paths that continue specularly, so there the estimators
//! differ most and sub-pixel images of small lights (a lamp reflected in a glass ball) dominate
//! every whole-image error for a long time. Comparing the rest of the image measures how each
//! configuration renders the diffuse surfaces, where caustics land.

use crate::camera::CameraSample;
use crate::scene::Scene;
use glam::Vec2;

/// `true` for pixels of the scene's default camera whose footprint (a 3×3 grid of rays over the
/// pixel and half of each neighbour, as far as a one-pixel filter reaches) first hits a surface
/// with a specular lobe. Deterministic: rays through fixed positions, lens centre.
pub fn specular_view_mask(scene: &Scene) -> Vec<bool> {
    let Ok(cam) = scene.cameras.get(None) else {
        return Vec::new();
    };
    let (w, h) = cam.camera.resolution();
    let mut mask = vec![false; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            'footprint: for j in 0..3 {
                for i in 0..3 {
                    let sample = CameraSample {
                        p_film: Vec2::new(x as f32 - 0.5 + i as f32, y as f32 - 0.5 + j as f32),
                        p_lens: Vec2::splat(0.5),
                    };
                    let Some(r) = cam.camera.generate_ray(&sample) else {
                        continue;
                    };
                    if let Some(hit) = scene.geometry.intersect(&r.ray, f32::INFINITY) {
                        if scene.objects.material(hit.object).flags().is_specular() {
                            mask[(y * w + x) as usize] = true;
                            break 'footprint;
                        }
                    }
                }
            }
        }
    }
    mask
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{build_scene, parse_scene_str, BuiltinFactory};
    use std::path::Path;

    // The caustic scene as shipped: its glass ball (radius 0.5 at distance ≈ 4.7, fov 45° over
    // 160 px) covers a disc of ≈ 22 px radius, about 1 500 pixels; the mask must find that disc
    // (1 000–2 500 pixels with the one-pixel rim) and nothing in the image corners (floor, wall).
    #[test]
    fn caustic_mask_is_the_glass_ball() {
        let file = Path::new("caustic.ron");
        let desc = parse_scene_str(include_str!("../../../scenes/caustic.ron"), file).unwrap();
        let scene = build_scene(&desc, Path::new("."), file, &[&BuiltinFactory]).unwrap();
        let mask = specular_view_mask(&scene);
        assert_eq!(mask.len(), 160 * 120);
        let n = mask.iter().filter(|m| **m).count();
        assert!((1_000..2_500).contains(&n), "{n} pixels");
        for (x, y) in [(0, 0), (159, 0), (0, 119), (159, 119)] {
            assert!(!mask[y * 160 + x]);
        }
        // The default Cornell box has no specular surface.
        let cornell = crate::scene::default_scene().unwrap();
        assert!(specular_view_mask(&cornell).iter().all(|m| !m));
    }
}
