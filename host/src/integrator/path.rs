//! A spectral unidirectional path tracer: next-event estimation with multiple importance
//! sampling (power heuristic, β = 2) between light and BSDF sampling, Russian roulette, and hero
//! wavelength sampling (all lanes share one path until a dispersive event keeps only the hero).

use super::PixelSampler;
use crate::geometry::{spawn_ray, spawn_ray_to, Ray};
use crate::light::LightSampleContext;
use crate::material::{Frame, MaterialFlags, ShadingContext, TransportMode};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Counters for the render summary (per thread, summed afterwards).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PathStats {
    /// Closest-hit rays traced.
    pub rays: u64,
    /// Shadow (any-hit) rays traced.
    pub shadow_rays: u64,
}

/// Path tracer settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathTracer {
    /// Maximum number of scattering events (bounces).
    pub max_depth: u32,
    /// Bounce from which Russian roulette may end paths.
    pub rr_depth: u32,
    /// Only direct lighting (emission seen directly plus one bounce of NEE/BSDF sampling):
    /// used for analytic tests.
    pub direct_only: bool,
    /// How camera paths draw their hero wavelength.
    pub wavelengths: WavelengthSampling,
}

impl Default for PathTracer {
    fn default() -> Self {
        Self {
            max_depth: 64,
            rr_depth: 3,
            direct_only: false,
            wavelengths: WavelengthSampling::Visible,
        }
    }
}

/// How camera paths draw their wavelengths (each lane's pdf is kept, so both are unbiased).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WavelengthSampling {
    /// Importance-sampled for the observer's luminance response (pbrt-v4's sech² fit):
    /// fewer wavelengths wasted where x̄ȳz̄ are near zero.
    #[default]
    Visible,
    /// Uniform over 360–830 nm: the plain baseline, more colour noise per sample.
    Uniform,
}

impl WavelengthSampling {
    /// Draw the path's wavelengths (hero plus rotations) from `u ∈ [0,1)`.
    #[inline]
    pub fn sample(self, u: f32) -> SampledWavelengths {
        match self {
            WavelengthSampling::Visible => SampledWavelengths::sample_visible(u),
            WavelengthSampling::Uniform => SampledWavelengths::sample_uniform(u, 360.0, 830.0),
        }
    }
}

/// Power heuristic with β = 2 for one sample from each of two strategies.
#[inline]
pub fn power_heuristic(pdf_a: f32, pdf_b: f32) -> f32 {
    let a = pdf_a * pdf_a;
    let b = pdf_b * pdf_b;
    if a.is_infinite() {
        return 1.0;
    }
    if a + b == 0.0 {
        return 0.0;
    }
    a / (a + b)
}

impl PathTracer {
    /// Radiance (W/(m²·sr·nm) per lane) arriving along `ray`. `lambda` may be modified (a
    /// dispersive event terminates the secondary lanes); the caller must use the returned
    /// wavelengths' pdfs for the film.
    pub fn li(
        &self,
        scene: &Scene,
        mut ray: Ray,
        lambda: &mut SampledWavelengths,
        rng: &mut PixelSampler,
        stats: &mut PathStats,
    ) -> SampledSpectrum {
        let mut l = SampledSpectrum::zero();
        let mut beta = SampledSpectrum::splat(1.0);
        let mut specular_bounce = true;
        let mut prev_bsdf_pdf = 0.0f32;
        let mut prev_ctx = LightSampleContext {
            p: ray.origin,
            p_error: glam::Vec3A::ZERO,
            n: glam::Vec3A::ZERO,
        };
        let max_depth = if self.direct_only { 1 } else { self.max_depth };
        let mut depth = 0u32;
        loop {
            stats.rays += 1;
            let Some(hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
                break;
            };
            let material = scene.objects.material(hit.object);
            let flags = material.flags();
            let frame = Frame::from_normal(hit.shading_normal);
            let wo = frame.to_local(-ray.dir.normalize());
            let sctx = ShadingContext { uv: hit.uv };

            // Emission found by the path itself.
            if flags.contains(MaterialFlags::EMISSIVE) {
                // Which side emits is a property of the surface (its geometric normal, as the
                // area light sees it), not of an interpolated shading normal.
                let wo_geo =
                    Frame::from_normal(hit.geometric_normal).to_local(-ray.dir.normalize());
                let le = material.emitted(wo_geo, &sctx, lambda);
                if !le.is_black() {
                    if depth == 0 || specular_bounce {
                        l += beta * le;
                    } else if let Some(li) = scene.lights.light_of_object(hit.object) {
                        let light = &scene.lights.lights()[li as usize];
                        let light_pdf = scene.lights.pmf(li as usize)
                            * light.pdf_li(&prev_ctx, hit.point, hit.geometric_normal);
                        l += beta * le * power_heuristic(prev_bsdf_pdf, light_pdf);
                    } else {
                        l += beta * le;
                    }
                }
            }
            if depth >= max_depth {
                break;
            }
            if !flags.intersects(
                MaterialFlags::DIFFUSE | MaterialFlags::GLOSSY | MaterialFlags::SPECULAR,
            ) {
                break;
            }
            let ctx = LightSampleContext {
                p: hit.point,
                p_error: hit.point_error,
                n: hit.geometric_normal,
            };

            // Next-event estimation.
            let u_light = rng.next_1d();
            let u_light2 = rng.next_2d();
            if flags.has_non_specular() {
                if let Some((li, pmf)) = scene.lights.sample(u_light) {
                    let light = &scene.lights.lights()[li];
                    if let Some(ls) = light.sample_li(&ctx, u_light2, lambda) {
                        if ls.pdf > 0.0 && !ls.radiance.is_black() {
                            let wi = frame.to_local(ls.wi);
                            let f = material.eval(wo, wi, &sctx, lambda, TransportMode::Radiance)
                                * wi.z.abs();
                            if !f.is_black() {
                                let (shadow, t_max) = spawn_ray_to(
                                    hit.point,
                                    hit.point_error,
                                    hit.geometric_normal,
                                    ls.p_light,
                                    ls.p_light_error,
                                    ls.n_light,
                                );
                                stats.shadow_rays += 1;
                                if !scene.geometry.occluded(&shadow, t_max) {
                                    let light_pdf = pmf * ls.pdf;
                                    let w = if light.flags().is_delta() {
                                        1.0
                                    } else {
                                        let bsdf_pdf = material.pdf(
                                            wo,
                                            wi,
                                            &sctx,
                                            lambda,
                                            TransportMode::Radiance,
                                        );
                                        power_heuristic(light_pdf, bsdf_pdf)
                                    };
                                    l += beta * f * ls.radiance * (w / light_pdf);
                                }
                            }
                        }
                    }
                }
            }

            // Continue the path by sampling the BSDF.
            let u_lobe = rng.next_1d();
            let u_dir = rng.next_2d();
            let Some(bs) =
                material.sample(wo, &sctx, lambda, u_lobe, u_dir, TransportMode::Radiance)
            else {
                break;
            };
            if !(bs.pdf > 0.0) || bs.f.is_black() {
                break;
            }
            if bs.flags.contains(MaterialFlags::DISPERSIVE) {
                lambda.terminate_secondary();
            }
            beta *= bs.f * (bs.wi.z.abs() / bs.pdf);
            if beta.has_non_finite() {
                break;
            }
            specular_bounce = bs.flags.is_specular();
            prev_bsdf_pdf = bs.pdf;
            prev_ctx = ctx;
            let wi_world = frame.to_world(bs.wi);
            ray = spawn_ray(hit.point, hit.point_error, hit.geometric_normal, wi_world);
            depth += 1;

            // Russian roulette on the throughput (the largest lane).
            if depth >= self.rr_depth {
                let m = beta.max_value();
                if m < 1.0 {
                    let q = (1.0 - m).max(0.05);
                    if rng.next_1d() < q {
                        break;
                    }
                    beta = beta / (1.0 - q);
                }
            }
        }
        l
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Power heuristic: symmetric weights sum to 1; a delta pdf (∞) takes all the weight.
    #[test]
    fn power_heuristic_properties() {
        let (a, b) = (0.3f32, 1.7f32);
        assert!((power_heuristic(a, b) + power_heuristic(b, a) - 1.0).abs() < 1e-6);
        assert_eq!(power_heuristic(f32::INFINITY, 1.0), 1.0);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
    }
}
