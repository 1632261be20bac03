//! Integrators and what they share. Each integrator is one file implementing
//! [`driver::Integrator`] and one entry in [`select::registered`]: path tracing ([`path`]),
//! bidirectional path tracing ([`bdpt`]) and light tracing ([`light_tracer`]). The path-building
//! blocks they share live in files of their own ([`random_walk`], [`light_subpath`],
//! [`camera_connection`], [`beam`], [`flat_colour`], [`wavelength_mixture`], [`xyz_weights`], [`pixel_max`],
//! [`vertex`], [`wavelength_groups`], [`specular_chain`], [`specular_seeds`], [`manifold_connection`], [`camera_chain`]), as do the render settings ([`render`]) and the tiled,
//! parallel, deterministic pass loop ([`tiled`]). No integrator imports another.

pub mod bdpt;
pub mod connect;
pub mod driver;
pub mod fluorescence;
pub mod light_tracer;
pub mod mis;
pub mod path;
pub mod pixel_max;
pub mod render;
pub mod sampler;
pub mod select;
pub mod subpath;
#[cfg(test)]
mod test_support;
pub mod tiled;
pub mod wavelengths;

pub use driver::{Integrator, IntegratorInfo, IntegratorOptions, IntegratorOutput, Registration};
pub use path::render;
pub use render::{
    DroppedPass, PathStats, PathTracer, RenderError, RenderResult, RenderSettings, SampleBudget,
};
pub use sampler::{PixelSampler, SampleRng, SamplerKind};
pub use select::{registered, render_with, render_with_options, strategy_summary, IntegratorKind};
pub use wavelengths::sampling::WavelengthSampling;
