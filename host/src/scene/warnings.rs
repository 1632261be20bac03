//! Scene checks that run once the scene is built: a light whose total power is not a finite
//! number ≥ 0 is an error (also for lights from plugins, whose constructors the host cannot
//! see into); scenes that build but would probably not render what was meant get a warning
//! ([`super::Scene::warnings`]), printed in the render summary: lights that emit nothing, no
//! light at all, powers beyond what the renderer's 32-bit radiance arithmetic can carry, every
//! material black, a camera that sees nothing.

use super::SceneObject;
use crate::camera::manager::NamedCamera;
use crate::camera::CameraSample;
use crate::geometry::Geometry;
use crate::material::{ShadingContext, TransportMode};
use crate::spectrum::SampledWavelengths;
use glam::{Vec2, Vec3A};

/// Total power (W) above which a light gets a warning: radiance is carried in `f32`
/// (max ≈ 3.4e38), and geometry factors (1/distance², 1/pdf) need headroom of about 1e8 on
/// top of the power before a contribution overflows to infinity and is lost.
pub const POWER_WARN_W: f64 = 1e30;

/// Check light `item`'s total power `power_w` (W): an error if it is not finite or negative,
/// a warning if it is zero or above [`POWER_WARN_W`].
pub fn light_power(item: &str, power_w: f64, warnings: &mut Vec<String>) -> Result<(), String> {
    if !power_w.is_finite() || power_w < 0.0 {
        return Err(format!(
            "total power {power_w} W is not a finite number ≥ 0 (its parameters overflow the \
             renderer's 32-bit range); lower the power, radiance or scale"
        ));
    }
    if power_w == 0.0 {
        warnings.push(format!(
            "{item} emits nothing (total power 0 W): it contributes nothing to the image"
        ));
    } else if power_w > POWER_WARN_W {
        warnings.push(format!(
            "{item} has a total power of {power_w:.3e} W, above {POWER_WARN_W:e} W: its \
             contributions may overflow the renderer's 32-bit radiance (max {:e}) and be lost",
            f32::MAX
        ));
    }
    Ok(())
}

/// A warning when no light emits anything (`powers_w` of every light, W).
pub fn no_light(powers_w: &[f64]) -> Option<String> {
    if powers_w.is_empty() {
        Some(
            "the scene has no light (no emissive object, no `lights` entry): it renders black"
                .into(),
        )
    } else if powers_w.iter().all(|&p| p == 0.0) {
        Some("no light in the scene emits anything: it renders black".into())
    } else {
        None
    }
}

/// Whether `material` reflects or transmits anything: a few BSDF samples at normal and
/// oblique incidence over the visible range. Emitters (which do not scatter) count as not
/// black.
fn scatters(material: &dyn crate::material::Material) -> bool {
    if material.emission().is_some() {
        return true;
    }
    let ctx = ShadingContext::at(Vec3A::ZERO, Vec3A::Z, Vec3A::Z, Vec2::ZERO);
    let wos = [Vec3A::Z, Vec3A::new(0.6, 0.0, 0.8)];
    for wo in wos {
        for k in 0..4 {
            let lambda = SampledWavelengths::sample_uniform((k as f32 + 0.5) / 4.0, 360.0, 830.0);
            for i in 0..4 {
                for j in 0..4 {
                    let u = Vec2::new((i as f32 + 0.5) / 4.0, (j as f32 + 0.5) / 4.0);
                    for u_lobe in [0.1, 0.5, 0.9] {
                        if let Some(s) =
                            material.sample(wo, &ctx, &lambda, u_lobe, u, TransportMode::Radiance)
                        {
                            if s.pdf > 0.0 && s.f.max_value() > 0.0 {
                                return true;
                            }
                        }
                    }
                }
            }
        }
    }
    false
}

/// A warning when every object's material is black (reflects and transmits nothing).
pub fn all_black(objects: &[SceneObject]) -> Option<String> {
    let scattering = objects.iter().filter(|o| o.material.emission().is_none());
    let mut n = 0;
    for o in scattering {
        n += 1;
        if scatters(o.material.as_ref()) {
            return None;
        }
    }
    (n > 0).then(|| {
        "every material is black (reflects and transmits nothing): only lights seen \
         directly will show in the image"
            .into()
    })
}

/// A warning per object whose material declares `FLUORESCENT` but offers no re-radiation data
/// (a plugin material: the plugin interface cannot pass it yet). Such a surface renders its
/// reflectance only; the warning says so instead of dropping the flag silently.
pub fn fluorescence_without_data(objects: &[SceneObject]) -> Vec<String> {
    objects
        .iter()
        .filter(|o| {
            o.material
                .flags()
                .contains(crate::material::MaterialFlags::FLUORESCENT)
                && o.material.reradiation().is_none()
        })
        .map(|o| {
            format!(
                "object \"{}\": its material declares FLUORESCENT but gives the host no \
                 re-radiation data (the plugin interface cannot pass it yet): it renders its \
                 reflectance only, with no wavelength shift",
                o.name
            )
        })
        .collect()
}

/// Warnings for cameras none of whose rays on a 16 × 16 grid over the film hits an object,
/// in a scene without an environment light (their images are black).
pub fn blind_cameras(
    geometry: &Geometry,
    cameras: &[NamedCamera],
    has_environment: bool,
) -> Vec<String> {
    if has_environment {
        return Vec::new();
    }
    const GRID: u32 = 16;
    cameras
        .iter()
        .filter(|c| {
            let (w, h) = c.camera.resolution();
            !(0..GRID * GRID).any(|k| {
                let p_film = Vec2::new(
                    ((k % GRID) as f32 + 0.5) / GRID as f32 * w as f32,
                    ((k / GRID) as f32 + 0.5) / GRID as f32 * h as f32,
                );
                let sample = CameraSample {
                    p_film,
                    p_lens: Vec2::splat(0.5),
                };
                c.camera
                    .generate_ray(&sample)
                    .is_some_and(|r| geometry.intersect(&r.ray, f32::INFINITY).is_some())
            })
        })
        .map(|c| {
            format!(
                "camera {:?} sees no object ({} test rays across its view hit nothing) and \
                 there is no environment light: its image will be black",
                c.name,
                GRID * GRID
            )
        })
        .collect()
}
