//! Integrators: the spectral path tracer ([`path`]) and the tiled, parallel, deterministic
//! render driver ([`render`]) that feeds the film.

pub mod path;
pub mod render;
pub mod sampler;

pub use path::{PathStats, PathTracer};
pub use render::{render, RenderError, RenderResult, RenderSettings, SampleBudget};
pub use sampler::SampleRng;
