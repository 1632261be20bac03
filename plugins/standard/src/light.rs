//! The built-in lights (`host/src/builtin/light/`): `point`, `spot`, `directional` and
//! `environment`, same parameters, built by the host's own constructors and called through the
//! plugin interface as CONNECTABLE lights (no physics here). Each hands the host its own
//! emission SPD and learns the scene's extent (`scene_bounds`), which it passes to the host
//! object's `preprocess`/`preprocess_view`: a directional light's emitting disc and power, and an
//! environment's sphere and power, come from it exactly as for the built-ins.
//!
//! The calls the renderer makes per sample (`sample_toward`, `sample_emission`, `emission_pdf`)
//! cross in the host's own `f32` layout: the host's receiver is read in place and the host
//! light's sample is written straight into the host's record (`spectrace::plugin::layout`), so
//! nothing is converted.
//!
//! `environment` is an ENVIRONMENT light: the host places its own sky sphere around the same
//! bounds and asks this one for radiance, incident-direction sampling, power and (declared
//! SPHERE_EMISSION) its emitted rays, which start on that sphere.

use crate::material::{host_v, v4f, va, wavelengths};
use crate::wrap::{context, params_doc, plugin_error, HostParams, HostSpd};
use glam::{Vec2, Vec3A};
use spectrace::builtin::light::{directional, environment, point, spot};
use spectrace::geometry::{Aabb, Ray};
use spectrace::light::{
    ConstantEnvironment, EnvironmentLight, EnvironmentRadiance, Light as HostLight, LightFlags,
};
use spectrace::plugin::layout::{as_light_context, as_light_sample_mut, as_vec3a};
use spectrace_plugin_api::{
    light_flags, EmissionPdf, EmittedRay, Flags, Host, Incident, LightSource, ParamDoc,
    PluginError, PluginResult, PluginType, RandomSample, Receiver, RepresentedBeam, SceneBounds,
    Spd, Vec4f, Wavelengths, LANES,
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

/// `sample_toward` in the host's layout: the host's receiver read in place and the host light's
/// sample written in place (`spectrace::plugin::layout`), nothing converted.
#[inline]
fn sample_toward<L: HostLight + ?Sized>(
    light: &L,
    receiver: &Receiver,
    u: [f32; 2],
    lambda: &Wavelengths,
    out: &mut Incident,
) -> bool {
    let ctx = as_light_context(receiver);
    let mut slot = None;
    let lambda = wavelengths(lambda, &mut slot);
    // Written straight into the host's record (the same layout): point-like lights write it
    // in place, with no returned `Option<LightLiSample>` copied into it.
    light.sample_li_into(ctx, Vec2::new(u[0], u[1]), lambda, as_light_sample_mut(out))
}

/// `sample_emission` in the host's layout.
#[inline]
fn sample_emission<L: HostLight + ?Sized>(
    light: &L,
    u: [f32; 4],
    lambda: &Wavelengths,
    out: &mut EmittedRay,
) -> bool {
    let u1 = Vec2::new(u[0], u[1]);
    let u2 = Vec2::new(u[2], u[3]);
    let mut slot = None;
    let lambda = wavelengths(lambda, &mut slot);
    match light.sample_le(u1, u2, lambda) {
        Some(s) => {
            *out = EmittedRay {
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

/// `emission_pdf` in the host's layout. The host's lights answer 0 for the density of a delta
/// position or direction (no other strategy can produce it); the interface says 1 there, as
/// `sample_emission` writes it, so a delta part is reported as 1.
#[inline]
fn emission_pdf<L: HostLight + ?Sized>(
    light: &L,
    origin: &Vec4f,
    direction: &Vec4f,
) -> EmissionPdf {
    let ray = Ray::new(host_v(*origin), host_v(*direction));
    let (position, direction) = light.pdf_le(&ray, Vec3A::ZERO);
    let flags = light.flags();
    EmissionPdf {
        position: if flags.contains(LightFlags::DELTA_POSITION) {
            1.0
        } else {
            position
        },
        direction: if flags.contains(LightFlags::DELTA_DIRECTION) {
            1.0
        } else {
            direction
        },
    }
}

/// The seed's `next_beam` for a built-in, which samples its emission (`sample_le`) but keeps no
/// beams of its own: [`beam_from_emission`](spectrace::light::emission_beam::beam_from_emission).
fn beam_from_emission<L: HostLight + ?Sized>(
    light: &L,
    sample: &RandomSample,
) -> PluginResult<RepresentedBeam> {
    spectrace::light::emission_beam::beam_from_emission(light, sample)
        .map(Into::into)
        .map_err(|e| PluginError::unsupported(format!("next_beam: {e}")))
}

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
            fn flags(&self) -> Flags {
                let f = self.light.flags();
                let mut out = light_flags::CONNECTABLE;
                if f.contains(LightFlags::DELTA_POSITION) {
                    out = out | light_flags::DELTA_POSITION;
                }
                if f.contains(LightFlags::DELTA_DIRECTION) {
                    out = out | light_flags::DELTA_DIRECTION;
                }
                // Declared exactly where the built-in declares it.
                if self.light.uniform_spectral_shape() {
                    out = out | light_flags::UNIFORM_SPECTRAL_SHAPE;
                }
                out
            }
            fn emission_spectrum(&self) -> PluginResult<Option<Box<dyn Spd>>> {
                Ok(Some(Box::new(HostSpd(self.light.spd()))))
            }
            fn total_power_w(&self) -> PluginResult<f64> {
                Ok(self.light.power())
            }
            fn scene_bounds(&self, bounds: &SceneBounds) -> PluginResult<()> {
                let (scene, view) = boxes(bounds);
                self.light.preprocess(&scene);
                self.light.preprocess_view(&view);
                Ok(())
            }
            fn next_beam(&self, sample: &RandomSample) -> PluginResult<RepresentedBeam> {
                match self.light.next_beam(sample) {
                    Some(beam) => Ok(beam.into()),
                    None => beam_from_emission(&self.light, sample),
                }
            }
            #[inline]
            fn sample_toward(
                &self,
                receiver: &Receiver,
                u: [f32; 2],
                lambda: &Wavelengths,
                out: &mut Incident,
            ) -> PluginResult<bool> {
                Ok(sample_toward(&self.light, receiver, u, lambda, out))
            }
            #[inline]
            fn sample_emission(
                &self,
                u: [f32; 4],
                lambda: &Wavelengths,
                out: &mut EmittedRay,
            ) -> PluginResult<bool> {
                Ok(sample_emission(&self.light, u, lambda, out))
            }
            #[inline]
            fn emission_pdf(&self, origin: &Vec4f, direction: &Vec4f) -> PluginResult<EmissionPdf> {
                Ok(emission_pdf(&self.light, origin, direction))
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
    fn flags(&self) -> Flags {
        // SPHERE_EMISSION: `sample_emission` is the built-in's own, on the sphere the host
        // places around the same view bounds.
        let mut out =
            light_flags::ENVIRONMENT | light_flags::CONNECTABLE | light_flags::SPHERE_EMISSION;
        // Declared exactly where the built-in declares it.
        if self.light.uniform_spectral_shape() {
            out = out | light_flags::UNIFORM_SPECTRAL_SHAPE;
        }
        out
    }
    fn emission_spectrum(&self) -> PluginResult<Option<Box<dyn Spd>>> {
        Ok(Some(Box::new(HostSpd(self.source.spd()))))
    }
    fn total_power_w(&self) -> PluginResult<f64> {
        Ok(self.light.power())
    }
    fn scene_bounds(&self, bounds: &SceneBounds) -> PluginResult<()> {
        let (scene, view) = boxes(bounds);
        self.light.preprocess(&scene);
        self.light.preprocess_view(&view);
        Ok(())
    }
    fn next_beam(&self, sample: &RandomSample) -> PluginResult<RepresentedBeam> {
        // From the built-in's own emission, which starts on the disc of the scene's bounding
        // sphere across the sampled direction (sized in `scene_bounds`).
        beam_from_emission(&self.light, sample)
    }
    fn sample_emission(
        &self,
        u: [f32; 4],
        lambda: &Wavelengths,
        out: &mut EmittedRay,
    ) -> PluginResult<bool> {
        Ok(sample_emission(&self.light, u, lambda, out))
    }
    fn emission_pdf(&self, origin: &Vec4f, direction: &Vec4f) -> PluginResult<EmissionPdf> {
        Ok(emission_pdf(&self.light, origin, direction))
    }
    fn sample_toward(
        &self,
        receiver: &Receiver,
        u: [f32; 2],
        lambda: &Wavelengths,
        out: &mut Incident,
    ) -> PluginResult<bool> {
        let p = as_light_context(receiver).p;
        let Some((wi, pdf)) = self.source.sample_direction(p, Vec2::new(u[0], u[1])) else {
            return Ok(false);
        };
        let (point, normal) = self
            .light
            .escape_point(&Ray::new(p, wi))
            .unwrap_or((p + wi, Vec3A::ZERO));
        let mut slot = None;
        let lambda = wavelengths(lambda, &mut slot);
        *out = Incident {
            value: self.source.radiance(wi, lambda).0,
            direction: v4f(wi),
            pdf,
            point: v4f(point),
            point_error: Vec4f::default(),
            normal: v4f(normal),
        };
        Ok(true)
    }
    fn radiance(&self, direction: &Vec4f, lambda: &Wavelengths) -> PluginResult<[f32; LANES]> {
        let mut slot = None;
        let lambda = wavelengths(lambda, &mut slot);
        Ok(self.source.radiance(*as_vec3a(direction), lambda).0)
    }
    fn incident_pdf(&self, receiver: &Receiver, direction: &Vec4f) -> PluginResult<f32> {
        let p = as_light_context(receiver).p;
        Ok(self.source.direction_pdf(p, *as_vec3a(direction)))
    }
}
