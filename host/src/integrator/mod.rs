//! Integrators: the spectral path tracer ([`path`]) and the tiled, parallel, deterministic
//! render driver ([`render`]) that feeds the film.

pub mod bdpt;
pub mod light_tracer;
pub mod path;
pub mod render;
pub mod sampler;
pub mod select;
pub mod tiled;
pub mod vertex;
pub mod wavelength_groups;

pub use path::{PathStats, PathTracer, WavelengthSampling};
pub use render::{render, RenderError, RenderResult, RenderSettings, SampleBudget};
pub use sampler::{PixelSampler, SampleRng};
pub use select::{render_with, strategy_summary, IntegratorKind, IntegratorOutput};
