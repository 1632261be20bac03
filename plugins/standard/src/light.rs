//! The built-in lights (`host/src/builtin/light/`): `point`, `spot`, `directional` and
//! `environment`, same parameters, built by the host's own constructors and called through the
//! plugin interface as CONNECTABLE lights (no physics here, only conversions; f32 → f64 → f32
//! round trips are exact). Through extension v2 each hands the host its own emission SPD, and
//! learns the scene's extent (`scene_bounds`), which it passes to the host object's
//! `preprocess`/`preprocess_view`: a directional light's emitting disc and power, and an
//! environment's sphere and power, come from it exactly as for the built-ins.
//!
//! Through extension v6 the three calls the renderer makes per sample (`sample_toward`,
//! `sample_emission`, `emission_pdf`) cross in the host's own `f32` layout: the host's receiver
//! is read in place and the host light's sample is written straight into the host's record
//! (`spectrace::plugin::layout`), so nothing is converted.
//!
//! `environment` is an ENVIRONMENT light: the host places its own sky sphere around the same
//! bounds and asks this one for radiance, incident-direction sampling and power.

use crate::material::{host_lambdas, v3, va, values};
use crate::material::{host_v, v4f, wavelengths};
use crate::wrap::{context, params_doc, plugin_error, HostParams, HostSpd};
use glam::{Vec2, Vec3A};
use spectrace::builtin::light::{directional, environment, point, spot};
use spectrace::geometry::{Aabb, Ray};
use spectrace::light::{
    ConstantEnvironment, EnvironmentLight, EnvironmentRadiance, Light as HostLight, LightFlags,
    LightSampleContext,
};
use spectrace::plugin::layout::{as_light_context, as_light_sample_mut};
use spectrace_plugin_api::{
    light_flags, Beam, EmissionF32, EmissionPdf, EmissionSample, Flags, Host, IncidentF32,
    IncidentSample, LanesF32, LightSource, ParamDoc, PluginError, PluginResult, PluginType,
    RandomSample, ReceiverF32, SceneBounds, Spd, SpectralValues, Vec3, Vec4f, WavelengthSample,
    Wavelengths,
};
use std::sync::Arc;

/// The host's boxes for the interface's bounds.
fn boxes(b: &SceneBounds) -> (Aabb, Aabb) {
    (
        Aabb {
            min: va(b.min),
            max: va(b.max),
        },
        Aabb {
            min: va(b.view_min),
            max: va(b.view_max),
        },
    )
}

/// `sample_emission` through the host light `light`.
fn sample_emission(
    light: &dyn HostLight,
    sample: &RandomSample,
    lambda: &Wavelengths,
) -> EmissionSample {
    let u = sample.u.map(|x| x as f32);
    let s = light.sample_le(
        Vec2::new(u[0], u[1]),
        Vec2::new(u[2], u[3]),
        &host_lambdas(lambda),
    );
    match s {
        Some(s) => EmissionSample {
            origin: v3(s.ray.origin),
            direction: v3(s.ray.dir),
            normal: v3(s.normal),
            value: values(s.radiance),
            pdf_position: s.pdf_pos as f64,
            pdf_direction: s.pdf_dir as f64,
        },
        None => EmissionSample {
            direction: NO_DIRECTION,
            ..EmissionSample::default()
        },
    }
}

/// `emission_pdf` through the host light `light`.
fn emission_pdf(light: &dyn HostLight, origin: Vec3, direction: Vec3) -> EmissionPdf {
    let (position, direction) = light.pdf_le(&Ray::new(va(origin), va(direction)), Vec3A::ZERO);
    EmissionPdf {
        position: position as f64,
        direction: direction as f64,
    }
}

/// `sample_toward` in the host's layout (extension v6): the host's receiver read in place and
/// the host light's sample written in place (`spectrace::plugin::layout`), nothing converted.
#[inline]
fn sample_toward_v6<L: HostLight + ?Sized>(
    light: &L,
    receiver: &ReceiverF32,
    u: [f32; 2],
    lambda: &LanesF32,
    out: &mut IncidentF32,
) -> bool {
    let ctx = as_light_context(receiver);
    let mut slot = None;
    let lambda = wavelengths(lambda, &mut slot);
    // Written straight into the host's record (the same layout): point-like lights write it
    // in place, with no returned `Option<LightLiSample>` copied into it.
    light.sample_li_into(ctx, Vec2::new(u[0], u[1]), lambda, as_light_sample_mut(out))
}

/// `sample_emission` in the host's layout (extension v6).
#[inline]
fn sample_emission_v6<L: HostLight + ?Sized>(
    light: &L,
    u: [f32; 4],
    lambda: &LanesF32,
    out: &mut EmissionF32,
) -> bool {
    let u1 = Vec2::new(u[0], u[1]);
    let u2 = Vec2::new(u[2], u[3]);
    let mut slot = None;
    let lambda = wavelengths(lambda, &mut slot);
    match light.sample_le(u1, u2, lambda) {
        Some(s) => {
            *out = EmissionF32 {
                origin: v4f(s.ray.origin),
                direction: v4f(s.ray.dir),
                value: s.radiance.0,
                pdf_position: s.pdf_pos,
                pdf_direction: s.pdf_dir,
                normal: v4f(s.normal),
            };
            true
        }
        None => false,
    }
}

/// `emission_pdf` in the host's layout (extension v6).
#[inline]
fn emission_pdf_v6<L: HostLight + ?Sized>(
    light: &L,
    origin: &Vec4f,
    direction: &Vec4f,
) -> [f32; 2] {
    let ray = Ray::new(host_v(*origin), host_v(*direction));
    let (position, direction) = light.pdf_le(&ray, Vec3A::ZERO);
    [position, direction]
}

/// What a refused sample returns: valid fields, zero density (the host then skips it).
const NO_DIRECTION: Vec3 = Vec3 {
    x: 0.0,
    y: 0.0,
    z: 1.0,
};

macro_rules! light_type {
    ($ty:ident, $module:ident, $params:ty, $host:ty) => {
        /// The host's light of the same name, held as its concrete type (its calls reach the
        /// host's code directly, not through a second dynamic call).
        pub struct $ty {
            params: HostParams<$params>,
            light: $host,
        }

        impl PluginType for $ty {
            const TYPE_NAME: &'static str = $module::TYPE.name;
            const TYPE_VERSION: u32 = $module::TYPE.version;
            const DESCRIPTION: &'static str = $module::TYPE.description;
            type Params = HostParams<$params>;

            fn params_doc() -> Vec<ParamDoc> {
                params_doc(&$module::TYPE)
            }

            fn new(params: Self::Params, _host: &Host<'_, '_>) -> PluginResult<Self> {
                let light = $module::build_concrete(&params.0, &context(Self::TYPE_NAME))
                    .map_err(plugin_error)?;
                Ok(Self { params, light })
            }

            fn params(&self) -> &Self::Params {
                &self.params
            }
        }

        impl LightSource for $ty {
            fn next_beam(&self, sample: &RandomSample) -> PluginResult<Beam> {
                self.light
                    .next_beam(sample)
                    .ok_or_else(|| PluginError::unsupported("next_beam"))
            }
            fn total_power_w(&self) -> PluginResult<f64> {
                Ok(self.light.power())
            }
            fn capabilities(&self) -> Flags {
                let f = self.light.flags();
                let mut out = light_flags::CONNECTABLE;
                if f.contains(LightFlags::DELTA_POSITION) {
                    out = out | light_flags::DELTA_POSITION;
                }
                if f.contains(LightFlags::DELTA_DIRECTION) {
                    out = out | light_flags::DELTA_DIRECTION;
                }
                out
            }
            fn sample_wavelength(&self, u: f64) -> PluginResult<WavelengthSample> {
                let s = self.light.spd().sample(u);
                Ok(WavelengthSample {
                    nm: s.lambda,
                    pdf: s.pdf,
                })
            }
            fn wavelength_pdf(&self, nm: f64) -> PluginResult<f64> {
                Ok(self.light.spd().pdf(nm))
            }
            fn sample_emission(
                &self,
                sample: &RandomSample,
                lambda: &Wavelengths,
            ) -> PluginResult<EmissionSample> {
                Ok(sample_emission(&self.light, sample, lambda))
            }
            fn emission_pdf(&self, origin: Vec3, direction: Vec3) -> PluginResult<EmissionPdf> {
                Ok(emission_pdf(&self.light, origin, direction))
            }
            fn scene_bounds(&self, bounds: &SceneBounds) -> PluginResult<()> {
                let (scene, view) = boxes(bounds);
                self.light.preprocess(&scene);
                self.light.preprocess_view(&view);
                Ok(())
            }
            fn emission_spectrum(&self) -> PluginResult<Option<Box<dyn Spd>>> {
                Ok(Some(Box::new(HostSpd(self.light.spd()))))
            }
            // Extension v4: declared exactly where the built-in declares it.
            fn uniform_spectral_shape(&self) -> bool {
                self.light.uniform_spectral_shape()
            }
            #[inline]
            fn sample_toward_v6(
                &self,
                receiver: &ReceiverF32,
                u: [f32; 2],
                lambda: &LanesF32,
                out: &mut IncidentF32,
            ) -> PluginResult<bool> {
                Ok(sample_toward_v6(&self.light, receiver, u, lambda, out))
            }
            #[inline]
            fn sample_emission_v6(
                &self,
                u: [f32; 4],
                lambda: &LanesF32,
                out: &mut EmissionF32,
            ) -> PluginResult<bool> {
                Ok(sample_emission_v6(&self.light, u, lambda, out))
            }
            #[inline]
            fn emission_pdf_v6(&self, origin: &Vec4f, direction: &Vec4f) -> PluginResult<[f32; 2]> {
                Ok(emission_pdf_v6(&self.light, origin, direction))
            }
            fn sample_toward(
                &self,
                receiver: Vec3,
                sample: &RandomSample,
                lambda: &Wavelengths,
            ) -> PluginResult<IncidentSample> {
                let ctx = LightSampleContext {
                    p: va(receiver),
                    p_error: Vec3A::ZERO,
                    n: Vec3A::ZERO,
                };
                let u = Vec2::new(sample.u[0] as f32, sample.u[1] as f32);
                Ok(match self.light.sample_li(&ctx, u, &host_lambdas(lambda)) {
                    Some(s) => IncidentSample {
                        point: v3(s.p_light),
                        normal: v3(s.n_light),
                        direction: v3(s.wi),
                        distance: f64::from(s.p_light.distance(ctx.p)),
                        value: values(s.radiance),
                        pdf: s.pdf as f64,
                    },
                    None => IncidentSample {
                        direction: NO_DIRECTION,
                        distance: 1.0,
                        ..IncidentSample::default()
                    },
                })
            }
        }
    };
}

light_type!(
    Point,
    point,
    point::PointParams,
    spectrace::light::PointLight
);
light_type!(Spot, spot, spot::SpotParams, spectrace::light::SpotLight);
light_type!(
    Directional,
    directional,
    directional::DirectionalParams,
    spectrace::light::DirectionalLight
);

/// The host's `environment`: its radiance source and the light around it, which sizes itself
/// from the bounds the host hands over (`scene_bounds`).
pub struct Environment {
    params: HostParams<environment::EnvironmentParams>,
    source: Arc<ConstantEnvironment>,
    light: EnvironmentLight,
}

impl PluginType for Environment {
    const TYPE_NAME: &'static str = environment::TYPE.name;
    const TYPE_VERSION: u32 = environment::TYPE.version;
    const DESCRIPTION: &'static str = environment::TYPE.description;
    type Params = HostParams<environment::EnvironmentParams>;

    fn params_doc() -> Vec<ParamDoc> {
        params_doc(&environment::TYPE)
    }

    fn new(params: Self::Params, _host: &Host<'_, '_>) -> PluginResult<Self> {
        let source = Arc::new(
            environment::source(&params.0, &context(Self::TYPE_NAME)).map_err(plugin_error)?,
        );
        let light = EnvironmentLight::new(source.clone());
        Ok(Self {
            params,
            source,
            light,
        })
    }

    fn params(&self) -> &Self::Params {
        &self.params
    }
}

impl LightSource for Environment {
    fn next_beam(&self, _sample: &RandomSample) -> PluginResult<Beam> {
        // As for the built-in: the host starts an environment's light paths on its own sphere.
        Err(PluginError::unsupported("next_beam of an environment"))
    }
    fn total_power_w(&self) -> PluginResult<f64> {
        Ok(self.light.power())
    }
    fn capabilities(&self) -> Flags {
        light_flags::ENVIRONMENT | light_flags::CONNECTABLE
    }
    fn sample_wavelength(&self, u: f64) -> PluginResult<WavelengthSample> {
        let s = self.source.spd().sample(u);
        Ok(WavelengthSample {
            nm: s.lambda,
            pdf: s.pdf,
        })
    }
    fn wavelength_pdf(&self, nm: f64) -> PluginResult<f64> {
        Ok(self.source.spd().pdf(nm))
    }
    fn sample_emission(
        &self,
        sample: &RandomSample,
        lambda: &Wavelengths,
    ) -> PluginResult<EmissionSample> {
        Ok(sample_emission(&self.light, sample, lambda))
    }
    fn emission_pdf(&self, origin: Vec3, direction: Vec3) -> PluginResult<EmissionPdf> {
        Ok(emission_pdf(&self.light, origin, direction))
    }
    fn sample_toward(
        &self,
        receiver: Vec3,
        sample: &RandomSample,
        lambda: &Wavelengths,
    ) -> PluginResult<IncidentSample> {
        let p = va(receiver);
        let u = Vec2::new(sample.u[0] as f32, sample.u[1] as f32);
        let Some((wi, pdf)) = self.source.sample_direction(p, u) else {
            return Ok(IncidentSample {
                direction: NO_DIRECTION,
                distance: 1.0,
                ..IncidentSample::default()
            });
        };
        let (point, normal) = self
            .light
            .escape_point(&Ray::new(p, wi))
            .unwrap_or((p + wi, Vec3A::ZERO));
        Ok(IncidentSample {
            point: v3(point),
            normal: v3(normal),
            direction: v3(wi),
            distance: f64::from(point.distance(p)),
            value: values(self.source.radiance(wi, &host_lambdas(lambda))),
            pdf: pdf as f64,
        })
    }
    fn radiance(&self, direction: Vec3, lambda: &Wavelengths) -> PluginResult<SpectralValues> {
        Ok(values(
            self.source.radiance(va(direction), &host_lambdas(lambda)),
        ))
    }
    fn incident_pdf(&self, receiver: Vec3, direction: Vec3) -> PluginResult<f64> {
        Ok(self.source.direction_pdf(va(receiver), va(direction)) as f64)
    }
    fn scene_bounds(&self, bounds: &SceneBounds) -> PluginResult<()> {
        let (scene, view) = boxes(bounds);
        self.light.preprocess(&scene);
        self.light.preprocess_view(&view);
        Ok(())
    }
    fn emission_spectrum(&self) -> PluginResult<Option<Box<dyn Spd>>> {
        Ok(Some(Box::new(HostSpd(self.source.spd()))))
    }
    // Extension v4: declared exactly where the built-in declares it.
    fn uniform_spectral_shape(&self) -> bool {
        self.light.uniform_spectral_shape()
    }
}
