//! Integrators and what they share, as a small tree that reads like the algorithm:
//! - the three integrators, each implementing [`driver::Integrator`] and registered in
//!   [`select::registered`]: path tracing ([`path`]), bidirectional path tracing ([`bdpt`], with
//!   its MIS weights in [`bdpt::mis`] and [`bdpt::fluorescent_mis`]) and light tracing
//!   ([`light_tracer`]);
//! - the blocks they build paths from: [`subpath`] (vertex, random walk, light subpath, camera
//!   connection, beams), [`nee_guide`] (the path tracer's visibility-aware light-point
//!   sampling, learned by a pre-pass), [`connect`] (specular chains, manifold and camera-chain connections),
//!   [`fluorescence`] (wavelength-shifting events and joins) and [`wavelengths`] (which
//!   wavelengths a path carries and how they are weighed);
//! - the shared frame: the render plan they read ([`plan`]: what the render does about each
//!   effect), the trait ([`driver`]), the render settings and results ([`render`]), the tiled,
//!   parallel, deterministic pass loop ([`tiled`]), the power heuristic ([`mis`]) and the
//!   per-pixel maximum ([`pixel_max`]); the sample generator is a floor below
//!   ([`crate::sampler`]).
//!
//! Imports run one way: integrators use the blocks and the frame, never the reverse, and no
//! integrator imports another (`host/tests/house_imports.rs` checks that no circle appears).
//! This file only declares the modules and re-exports the public names.

pub mod bdpt;
pub mod connect;
pub mod driver;
pub mod fluorescence;
pub mod light_tracer;
pub mod mis;
pub mod nee_guide;
pub mod path;
pub mod pixel_max;
pub mod plan;
pub mod render;
pub mod select;
pub mod subpath;
#[cfg(test)]
mod test_support;
pub mod tiled;
pub mod wavelengths;

pub use crate::sampler::{PixelSampler, SampleRng, SamplerKind, UniformSource};
pub use driver::{Integrator, IntegratorInfo, IntegratorOptions, IntegratorOutput, Registration};
pub use path::render;
pub use plan::{EffectsMode, EffectsRequest, LightSubpathCount, LightSubpaths, RenderPlan, Switch};
pub use render::{
    DroppedPass, PathStats, PathTracer, RenderError, RenderResult, RenderSettings, SampleBudget,
};
pub use select::{registered, render_with, render_with_options, strategy_summary, IntegratorKind};
pub use wavelengths::sampling::WavelengthSampling;
