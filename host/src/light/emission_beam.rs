//! A beam from a light's emission sampling: how a light that can be evaluated
//! ([`Light::sample_le`]) answers the seed's `next_beam`, and how `rays export` draws its rays.

use super::interface::{Light, LightLeSample};
use crate::spectrum::{LaneMask, SampledWavelengths, LANES};
use glam::{Vec2, Vec3A};
use spectrace_plugin_api::{Beam, EmittedRay, RandomSample, Vec3, Vec4f};

/// One beam of `light` from `sample`: the wavelength drawn from the light's normalised SPD with
/// `u[4]`, the ray with `u[0..4]` (origin, direction), and the power the one-sample flux
/// estimate (`EmittedRay::to_beam`: `value · |cos θ| / (p_position · p_direction · p(λ))` W).
/// When the light emits nothing for these numbers, a beam that carries nothing (power 0, at the
/// origin, along +y, at the drawn wavelength). An error when the SPD gives no wavelength.
pub fn beam_from_emission<L: Light + ?Sized>(
    light: &L,
    sample: &RandomSample,
) -> Result<Beam, &'static str> {
    let drawn = light.spd().sample(sample.u[4]);
    if !(drawn.pdf > 0.0) {
        return Err("the light's spectrum gives no wavelength for these numbers");
    }
    let lambda = SampledWavelengths {
        lambda: [drawn.lambda as f32; LANES],
        pdf: [drawn.pdf as f32; LANES],
        lanes: LaneMask::ALL,
    };
    let u1 = Vec2::new(sample.u[0] as f32, sample.u[1] as f32);
    let u2 = Vec2::new(sample.u[2] as f32, sample.u[3] as f32);
    let beam = light
        .sample_le(u1, u2, &lambda)
        .and_then(|s| emitted_ray(&s).to_beam(drawn.lambda, drawn.pdf));
    Ok(beam.unwrap_or(Beam {
        origin: Vec3::new(0.0, 0.0, 0.0),
        direction: Vec3::new(0.0, 1.0, 0.0),
        wavelength_nm: drawn.lambda,
        power_w: 0.0,
        source_id: 0,
    }))
}

/// The host's emission sample in the plugin interface's record.
fn emitted_ray(s: &LightLeSample) -> EmittedRay {
    let v = |a: Vec3A| Vec4f::new(a.x, a.y, a.z);
    EmittedRay {
        origin: v(s.ray.origin),
        direction: v(s.ray.dir),
        value: s.radiance.0,
        pdf_position: s.pdf_pos,
        pdf_direction: s.pdf_dir,
        normal: v(s.normal),
    }
}
