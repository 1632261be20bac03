//! The built-in point-like lights (`host/src/builtin/light/`): `point` and `spot`, same
//! parameters, built by the host's own constructors and called through the plugin interface as
//! CONNECTABLE lights (no physics here, only conversions; f32 → f64 → f32 round trips are
//! exact).
//!
//! Not exported: `directional` and `environment`. Both size themselves from the scene's bounds
//! (`Light::preprocess`), which the plugin interface does not hand to a light; the host places
//! a plugin environment itself, but from the plugin's radiance alone, so the built-in's own
//! importance sampling would be lost.

use crate::material::{host_lambdas, v3, va, values};
use crate::wrap::{context, params_doc, plugin_error, HostParams};
use glam::{Vec2, Vec3A};
use spectrace::builtin::light::{point, spot};
use spectrace::geometry::Ray;
use spectrace::light::{Light as HostLight, LightFlags, LightSampleContext};
use spectrace_plugin_api::{
    light_flags, Beam, EmissionPdf, EmissionSample, Flags, Host, IncidentSample, LightSource,
    ParamDoc, PluginError, PluginResult, PluginType, RandomSample, Vec3, WavelengthSample,
    Wavelengths,
};
use std::sync::Arc;

/// What a refused sample returns: valid fields, zero density (the host then skips it).
const NO_DIRECTION: Vec3 = Vec3 {
    x: 0.0,
    y: 0.0,
    z: 1.0,
};

macro_rules! light_type {
    ($ty:ident, $module:ident, $params:ty) => {
        /// The host's light of the same name.
        pub struct $ty {
            params: HostParams<$params>,
            light: Arc<dyn HostLight>,
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
                let light =
                    $module::build(&params.0, &context(Self::TYPE_NAME)).map_err(plugin_error)?;
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
                let u = sample.u.map(|x| x as f32);
                let s = self.light.sample_le(
                    Vec2::new(u[0], u[1]),
                    Vec2::new(u[2], u[3]),
                    &host_lambdas(lambda),
                );
                Ok(match s {
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
                })
            }
            fn emission_pdf(&self, origin: Vec3, direction: Vec3) -> PluginResult<EmissionPdf> {
                let (position, direction) = self
                    .light
                    .pdf_le(&Ray::new(va(origin), va(direction)), Vec3A::ZERO);
                Ok(EmissionPdf {
                    position: position as f64,
                    direction: direction as f64,
                })
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

light_type!(Point, point, point::PointParams);
light_type!(Spot, spot, spot::SpotParams);
