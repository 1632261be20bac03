//! `__TYPE__`: an ideal diffuse (Lambertian) reflector with a grey reflectance (a spectrace
//! plugin written by `spectrace plugins new`).
//!
//! | parameter     | unit | default | meaning                           |
//! |---------------|------|---------|-----------------------------------|
//! | `reflectance` |      | `0.5`   | fraction reflected, in [0, 1]     |
//!
//! f(wo, wi) = ρ/π for wo and wi on the same side, 0 otherwise; `sample` draws wi with the
//! cosine-weighted density |cos θi|/π on wo's side.

use serde::{Deserialize, Serialize};
use spectrace_plugin_api::{
    material_flags, Flags, Host, Material, ParamDoc, PluginError, PluginResult, PluginType,
    Scatter, Surface, TransportMode, Vec4f, Wavelengths, LANES,
};
use std::f32::consts::PI;

/// Parameters (and saved state).
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Params {
    /// Reflectance in [0, 1].
    pub reflectance: f32,
}

impl Default for Params {
    fn default() -> Self {
        Self { reflectance: 0.5 }
    }
}

/// The material.
pub struct Diffuse {
    params: Params,
}

impl PluginType for Diffuse {
    const TYPE_NAME: &'static str = "__TYPE__";
    const TYPE_VERSION: u32 = 1;
    const DESCRIPTION: &'static str = "ideal diffuse reflector with a grey reflectance";
    type Params = Params;

    fn params_doc() -> Vec<ParamDoc> {
        vec![ParamDoc::optional(
            "reflectance",
            "",
            "0.5",
            "fraction reflected, in [0, 1]",
        )]
    }

    fn new(params: Params, _host: &Host<'_, '_>) -> PluginResult<Self> {
        if !(0.0..=1.0).contains(&params.reflectance) {
            return Err(PluginError::invalid_parameter(format!(
                "`reflectance` must be in [0, 1], got {}",
                params.reflectance
            )));
        }
        Ok(Self { params })
    }

    fn params(&self) -> &Params {
        &self.params
    }
}

impl Material for Diffuse {
    fn flags(&self) -> Flags {
        material_flags::DIFFUSE | material_flags::RECIPROCAL
    }

    fn sample(
        &self,
        wo: &Vec4f,
        _surface: &Surface,
        _lambda: &Wavelengths,
        u: [f32; 3],
        _mode: TransportMode,
        out: &mut Scatter,
    ) -> PluginResult<bool> {
        if wo.z == 0.0 {
            return Ok(false);
        }
        // Malley's method: a uniform point on the disc, lifted to the hemisphere of wo.
        let r = u[1].sqrt();
        let phi = 2.0 * PI * u[2];
        let z = (1.0 - u[1]).max(0.0).sqrt().copysign(wo.z);
        if z == 0.0 {
            return Ok(false);
        }
        *out = Scatter {
            wi: Vec4f::new(r * phi.cos(), r * phi.sin(), z),
            value: [self.params.reflectance / PI; LANES],
            pdf: z.abs() / PI,
            flags: material_flags::DIFFUSE,
            eta: 1.0,
        };
        Ok(true)
    }

    fn eval(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        _surface: &Surface,
        _lambda: &Wavelengths,
        _mode: TransportMode,
    ) -> PluginResult<[f32; LANES]> {
        Ok(if wo.z * wi.z > 0.0 {
            [self.params.reflectance / PI; LANES]
        } else {
            [0.0; LANES]
        })
    }

    fn pdf(
        &self,
        wo: &Vec4f,
        wi: &Vec4f,
        _surface: &Surface,
        _lambda: &Wavelengths,
        _mode: TransportMode,
    ) -> PluginResult<f32> {
        Ok(if wo.z * wi.z > 0.0 { wi.z.abs() / PI } else { 0.0 })
    }
}

spectrace_plugin_api::export_plugin! {
    name: "__NAME__",
    version: env!("CARGO_PKG_VERSION"),
    lights: [],
    spds: [],
    observers: [],
    materials: [Diffuse],
}
