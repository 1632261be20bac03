//! Daylight factor: the illuminance at a point indoors as a percentage of the illuminance on
//! an unobstructed horizontal plane outdoors under the same sky (CIE 17.4 / ILV 845-09-97,
//! EN 17037), defined under the CIE standard overcast sky (`cie_sky` type 1) without sun.
//!
//! The outdoor reference is computed from the scene's environment light itself, by quadrature
//! over the upper hemisphere around +y (the scenes' vertical, and `cie_sky`'s default `up`) of
//! its luminance times cos Z, with no geometry in the way — so it is exact for any sky, not
//! only an analytic one: midpoint rule on 128 bands in cos Z × 512 azimuth sectors, each
//! direction's luminance from 32 stratified wavelength sets (for `cie_sky` types 1 and 12 this
//! agrees with the illuminance the sky was given to 3e-4, `tests/daylight_sky.rs`). A daylight factor is only computed when the
//! environment is the scene's only light with power (a sun or a lamp would add light the
//! definition excludes); otherwise [`reference`] says why not.

use super::estimate::{draw_wavelengths, Photometric};
use crate::geometry::Ray;
use crate::scene::Scene;
use glam::{Vec2, Vec3A};
use std::f64::consts::PI;

/// The outdoor reference: unobstructed horizontal illuminance of the environment, lx, or why
/// no daylight factor can be given for this scene.
pub fn reference(scene: &Scene) -> Result<f64, String> {
    let Some(ei) = scene.lights.environment() else {
        return Err("the scene has no sky (environment light)".into());
    };
    let lights = scene.lights.lights();
    let others: Vec<usize> = (0..lights.len())
        .filter(|&i| i != ei as usize && lights[i].power() > 0.0)
        .collect();
    if !others.is_empty() {
        return Err(format!(
            "the scene has {} light(s) besides the sky (a sun or lamps): the daylight factor \
             is defined for the sky alone",
            others.len()
        ));
    }
    let env = &lights[ei as usize];
    let photo = Photometric::new();
    let (nu, na, nl) = (128usize, 512usize, 32usize);
    let mut total = 0.0;
    for i in 0..nu {
        let mu = (i as f64 + 0.5) / nu as f64;
        let s = (1.0 - mu * mu).sqrt();
        let mut row = 0.0;
        for j in 0..na {
            let a = 2.0 * PI * (j as f64 + 0.5) / na as f64;
            let d = Vec3A::new((s * a.cos()) as f32, mu as f32, (s * a.sin()) as f32);
            let ray = Ray::new(Vec3A::ZERO, d);
            let Some((p, n)) = env.escape_point(&ray) else {
                continue;
            };
            let mut lv = 0.0;
            for k in 0..nl {
                let lambda = draw_wavelengths(((k as f64 + 0.5) / nl as f64) as f32);
                let l = env.radiance(p, n, Vec2::ZERO, -d, &lambda);
                lv += photo.of(&l, &lambda);
            }
            row += lv / nl as f64;
        }
        total += row * mu;
    }
    let e = total * (1.0 / nu as f64) * (2.0 * PI / na as f64);
    if !(e > 0.0) {
        return Err("the sky gives no light on the horizontal (0 lx)".into());
    }
    Ok(e)
}
