//! A spot light: a point light restricted to a cone, with a smooth (smoothstep) falloff between
//! the inner and outer cone angles.

use super::{
    incident_from_point, incident_from_point_into, Light, LightFlags, LightLeSample, LightLiSample,
    LightSampleContext,
};
use crate::geometry::Ray;
use crate::material::Frame;
use crate::spectrum::spd::spd_at;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spd};
use glam::{Vec2, Vec3A};
use std::f32::consts::PI;
use std::sync::Arc;

/// Solid angle (sr) of the falloff of a spot with half-angles `inner_deg` ≤ `outer_deg`:
/// ∫ falloff dω = 2π[(1 − cos inner) + (cos inner − cos outer)/2] (smoothstep averages ½ over
/// cos θ), so that power = peak intensity × this.
pub fn falloff_solid_angle_sr(inner_deg: f64, outer_deg: f64) -> f64 {
    let (ci, co) = (inner_deg.to_radians().cos(), outer_deg.to_radians().cos());
    2.0 * std::f64::consts::PI * ((1.0 - ci) + 0.5 * (ci - co))
}

/// Spot light of total power `P` W: intensity `I₀·falloff(cos θ)·S(λ)` with `I₀` chosen so the
/// emitted flux is exactly `P`.
#[derive(Debug, Clone)]
pub struct SpotLight {
    position: Vec3A,
    frame: Frame,
    spd: Arc<dyn Spd>,
    power: f32,
    cos_inner: f32,
    cos_outer: f32,
    /// Peak intensity `I₀` in W/sr.
    i0: f32,
}

impl SpotLight {
    /// A spot at `position` aimed at `target`; full intensity within `inner_deg` of the axis,
    /// fading smoothly to 0 at `outer_deg` (half-angles, degrees, 0 < inner ≤ outer < 180).
    pub fn new(
        position: Vec3A,
        target: Vec3A,
        inner_deg: f32,
        outer_deg: f32,
        spd: Arc<dyn Spd>,
        power_w: f32,
    ) -> Result<Self, String> {
        let axis = target - position;
        if !(axis.length() > 0.0) {
            return Err("spot light target must differ from its position".into());
        }
        if !(inner_deg >= 0.0 && inner_deg <= outer_deg && outer_deg > 0.0 && outer_deg < 180.0) {
            return Err(format!(
                "spot light cone angles must satisfy 0 ≤ inner ≤ outer < 180, got {inner_deg}, {outer_deg}"
            ));
        }
        let cos_inner = inner_deg.to_radians().cos();
        let cos_outer = outer_deg.to_radians().cos();
        let solid = 2.0 * PI * ((1.0 - cos_inner) + 0.5 * (cos_inner - cos_outer));
        Ok(Self {
            position,
            frame: Frame::from_normal(axis.normalize()),
            spd,
            power: power_w,
            cos_inner,
            cos_outer,
            i0: power_w / solid,
        })
    }

    /// Angular falloff for a direction with cosine `cos` to the axis, in [0, 1].
    fn falloff(&self, cos: f32) -> f32 {
        if cos >= self.cos_inner {
            return 1.0;
        }
        if cos <= self.cos_outer {
            return 0.0;
        }
        let t = (cos - self.cos_outer) / (self.cos_inner - self.cos_outer);
        t * t * (3.0 - 2.0 * t)
    }

    fn intensity(&self, w: Vec3A, lambda: &SampledWavelengths) -> SampledSpectrum {
        spd_at(self.spd.as_ref(), lambda) * (self.i0 * self.falloff(w.dot(self.frame.n)))
    }
}

impl Light for SpotLight {
    fn flags(&self) -> LightFlags {
        LightFlags::DELTA_POSITION
    }

    fn power(&self) -> f64 {
        self.power as f64
    }

    fn spd(&self) -> Arc<dyn Spd> {
        self.spd.clone()
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        _u: Vec2,
        lambda: &SampledWavelengths,
    ) -> Option<LightLiSample> {
        incident_from_point(self.position, ctx, |w| self.intensity(w, lambda))
    }

    fn sample_li_into(
        &self,
        ctx: &LightSampleContext,
        _u: Vec2,
        lambda: &SampledWavelengths,
        out: &mut LightLiSample,
    ) -> bool {
        incident_from_point_into(self.position, ctx, |w| self.intensity(w, lambda), out)
    }

    fn pdf_li(&self, _ctx: &LightSampleContext, _p: Vec3A, _n: Vec3A) -> f32 {
        0.0
    }

    fn radiance(
        &self,
        _p: Vec3A,
        _n: Vec3A,
        _uv: Vec2,
        _w: Vec3A,
        _l: &SampledWavelengths,
    ) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    fn sample_le(&self, _u1: Vec2, u2: Vec2, lambda: &SampledWavelengths) -> Option<LightLeSample> {
        // Uniform over the outer cone (simple, exact pdf; the falloff weights the result).
        let cos = 1.0 - u2.x * (1.0 - self.cos_outer);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * u2.y;
        let w = self
            .frame
            .to_world(Vec3A::new(sin * phi.cos(), sin * phi.sin(), cos));
        let pdf_dir = 1.0 / (2.0 * PI * (1.0 - self.cos_outer));
        Some(LightLeSample {
            ray: Ray::new(self.position, w),
            radiance: self.intensity(w, lambda),
            pdf_pos: 1.0,
            pdf_dir,
            normal: Vec3A::ZERO,
        })
    }

    fn pdf_le(&self, ray: &Ray, _n: Vec3A) -> (f32, f32) {
        let cos = ray.dir.normalize().dot(self.frame.n);
        if cos >= self.cos_outer {
            (0.0, 1.0 / (2.0 * PI * (1.0 - self.cos_outer)))
        } else {
            (0.0, 0.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::BuiltinSpd;

    /// `sample_li_into` of the point-like lights (which write in place instead of copying the
    /// default's `Option`) writes exactly what `sample_li` returns, and leaves the record as it
    /// was where there is no sample: receivers inside the cone, outside it (nothing emitted),
    /// behind the spot and on the emitter itself, for a spot and a point light.
    #[test]
    fn point_like_lights_write_in_place_what_they_return() {
        let spd: Arc<dyn Spd> = Arc::new(BuiltinSpd::blackbody(3000.0).unwrap());
        let spot = SpotLight::new(Vec3A::ZERO, Vec3A::Z, 20.0, 35.0, spd.clone(), 50.0).unwrap();
        let point = crate::light::PointLight::new(Vec3A::new(0.0, 1.0, 0.0), spd, 20.0);
        let lambda = SampledWavelengths::sample_visible(0.3);
        let stale = LightLiSample {
            radiance: SampledSpectrum::splat(7.0),
            wi: Vec3A::X,
            pdf: 3.0,
            p_light: Vec3A::ONE,
            p_light_error: Vec3A::ONE,
            n_light: Vec3A::Y,
        };
        let mut found = [0, 0];
        for p in [
            Vec3A::new(0.1, 0.0, 2.0),
            Vec3A::new(2.0, 0.0, 0.5),
            Vec3A::new(0.0, 0.0, -1.0),
            Vec3A::ZERO,
            Vec3A::new(0.0, 1.0, 0.0),
        ] {
            let ctx = LightSampleContext {
                p,
                p_error: Vec3A::ZERO,
                n: Vec3A::Z,
            };
            for light in [&spot as &dyn Light, &point] {
                let mut out = stale;
                let written = light.sample_li_into(&ctx, Vec2::new(0.3, 0.6), &lambda, &mut out);
                match light.sample_li(&ctx, Vec2::new(0.3, 0.6), &lambda) {
                    Some(s) => {
                        assert!(written, "{p}");
                        assert_eq!(out, s, "{p}");
                        found[0] += 1;
                    }
                    None => {
                        assert!(!written, "{p}");
                        assert_eq!(out, stale, "{p}");
                        found[1] += 1;
                    }
                }
            }
        }
        assert!(found[0] > 0 && found[1] > 0, "both cases seen: {found:?}");
    }

    /// The emitted flux equals the requested power: ∫ I₀·falloff dω integrated by a midpoint rule
    /// in cos θ (10⁵ cells; the smoothstep is C¹ so the error is ~1e-9) must be P within 1e-4.
    #[test]
    fn spot_emits_its_power() {
        let spd: Arc<dyn Spd> = Arc::new(BuiltinSpd::blackbody(3000.0).unwrap());
        let s = SpotLight::new(Vec3A::ZERO, Vec3A::Z, 20.0, 35.0, spd, 50.0).unwrap();
        let n = 100_000;
        let mut flux = 0.0f64;
        for i in 0..n {
            let c = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
            flux +=
                (s.i0 * s.falloff(c as f32)) as f64 * 2.0 * std::f64::consts::PI * 2.0 / n as f64;
        }
        assert!((flux / 50.0 - 1.0).abs() < 1e-4, "{flux}");
        assert!(SpotLight::new(Vec3A::ZERO, Vec3A::Z, 40.0, 30.0, s.spd.clone(), 1.0).is_err());
    }
}
