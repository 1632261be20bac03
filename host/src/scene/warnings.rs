//! Scene checks that run once the scene is built: a light whose total power is not a finite
//! number ≥ 0 is an error (also for lights from plugins, whose constructors the host cannot
//! see into); scenes that build but would probably not render what was meant get a warning
//! ([`super::Scene::warnings`]), printed in the render summary: lights that emit nothing, no
//! light at all, powers beyond what the renderer's 32-bit radiance arithmetic can carry, every
//! material black, a camera that sees nothing, geometry beyond what 32-bit coordinates hold.

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
/// (a plugin material built before extension v3 of the plugin interface, or one that does not
/// override `Material::reradiation`). Such a surface renders its reflectance only; the warning
/// says so instead of dropping the flag silently.
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
                 re-radiation data (a plugin needs extension v3 of the plugin interface and \
                 `Material::reradiation` for that): it renders its reflectance only, with no \
                 wavelength shift",
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

/// Largest coordinate magnitude (scene units) the ray–triangle test handles: its edge
/// functions times the sheared z are cubic in the coordinates (relative to the ray origin) and
/// overflow f32 (3.4e38) near 7e12; 1e12 leaves a margin.
pub const MAX_COORDINATE: f32 = 1e12;

/// Smallest scene extent (scene units) the ray–triangle test handles: below ~1e-13 its cubic
/// products fall under f32's normal range (1.2e-38) and hits are lost; 1e-10 leaves a margin.
pub const MIN_SCENE_EXTENT: f32 = 1e-10;

/// An object is "quantised" when the spacing of f32 values at its coordinates exceeds this
/// fraction of its own size: features and gaps below that spacing (a lamp 0.1 mm under a
/// ceiling) merge or open, which no ray offset can repair.
pub const QUANTISATION_WARN: f32 = 1e-3;

/// Warnings for geometry the f32 numbers cannot represent faithfully: objects with
/// coordinates beyond [`MAX_COORDINATE`], a whole scene smaller than [`MIN_SCENE_EXTENT`], and
/// meshes and quads so far from the origin relative to their size that f32 spacing there is
/// more than [`QUANTISATION_WARN`] of the size (a 0.55 m box translated by 1e5 m: 1.2 cm).
/// `names[i]` names geometry object `i`.
pub fn coordinate_precision(geometry: &Geometry, names: &[&str]) -> Vec<String> {
    use crate::geometry::{Aabb, WorldShape};
    let mut too_far = Vec::new();
    let mut quantised = Vec::new();
    for (i, name) in names.iter().enumerate().take(geometry.object_count()) {
        let Some(shape) = geometry.shape(i as u32) else {
            continue;
        };
        // A sphere is solved in f64 about its centre: only its position is quantised.
        let vertices = !matches!(shape, WorldShape::Sphere(_));
        let b = match shape {
            WorldShape::Mesh(m) => m
                .positions
                .iter()
                .fold(Aabb::EMPTY, |b, &p| b.union(&Aabb::from_point(p))),
            WorldShape::Sphere(s) => Aabb {
                min: s.center - Vec3A::splat(s.radius),
                max: s.center + Vec3A::splat(s.radius),
            },
            WorldShape::Quad(q) => q
                .vertices
                .iter()
                .fold(Aabb::EMPTY, |b, &p| b.union(&Aabb::from_point(p))),
        };
        if !(b.min.x <= b.max.x) {
            continue;
        }
        let magnitude = b.min.abs().max(b.max.abs()).max_element();
        let extent = (b.max - b.min).max_element();
        if magnitude > MAX_COORDINATE {
            too_far.push((name, magnitude));
        } else if vertices && extent > 0.0 && magnitude * f32::EPSILON > QUANTISATION_WARN * extent
        {
            quantised.push((name, magnitude, magnitude * f32::EPSILON, extent));
        }
    }
    let list = |names: Vec<String>| {
        let n = names.len();
        let mut s = names.into_iter().take(3).collect::<Vec<_>>().join(", ");
        if n > 3 {
            s += &format!(" and {} more", n - 3);
        }
        s
    };
    let mut out = Vec::new();
    if !too_far.is_empty() {
        let worst = too_far.iter().map(|t| t.1).fold(0.0f32, f32::max);
        out.push(format!(
            "{} reach coordinates up to {worst:.3e} scene units, beyond {MAX_COORDINATE:e}: the \
             32-bit ray–triangle test overflows there and they may not be hit; use larger \
             units or a smaller scale",
            list(
                too_far
                    .iter()
                    .map(|t| format!("object {:?}", t.0))
                    .collect()
            )
        ));
    }
    if !quantised.is_empty() {
        out.push(format!(
            "{} lie far from the origin for their size, so 32-bit coordinates there are coarse \
             compared with it and details and gaps below that spacing merge or open (light \
             leaks, surfaces fighting); move the scene nearer the origin",
            list(
                quantised
                    .iter()
                    .map(|(n, m, s, e)| format!(
                        "object {n:?} (size {e:.3e} at {m:.3e}, spacing {s:.3e})"
                    ))
                    .collect()
            )
        ));
    }
    let all = geometry.bounds();
    if all.min.x <= all.max.x {
        let extent = (all.max - all.min).max_element();
        if extent > 0.0 && extent < MIN_SCENE_EXTENT {
            out.push(format!(
                "the scene's geometry is only {extent:.3e} m across, below \
                 {MIN_SCENE_EXTENT:e}: the 32-bit ray–triangle test underflows at that size and \
                 hits may be lost; use smaller units or a larger scale"
            ));
        }
    }
    out
}
