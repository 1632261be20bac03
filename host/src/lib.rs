//! spectrace: a spectral bidirectional path tracer that is also a plugin host.
//!
//! Data flows one way: scene file → registry (built-ins and plugins) → scene → render plan →
//! integrator → film → output. Each module below is one concept and one floor; a floor imports
//! only from the floors below it, lowest first: `limits`, `spectrum`, `color`, `geometry`,
//! `sampler`, `film`, `texture`, `material`, `camera`, `photometry`, `light`, `scene_file`,
//! `builtin`, `scene`, `effects`, `integrator`, `plugin`, `analysis`, `sensor`, `cli`
//! (`docs/README.md` says what each holds; `host/tests/house_imports.rs` checks the order). The
//! integrator only sees the host traits in [`light`] and [`material`], never whether an object
//! came from a dynamic library, a blob or a built-in.

pub mod analysis;
pub mod builtin;
pub mod camera;
pub mod cli;
pub mod color;
pub mod effects;
pub mod film;
pub mod geometry;
pub mod integrator;
pub mod light;
pub mod limits;
pub mod material;
pub mod photometry;
pub mod plugin;
pub mod sampler;
pub mod scene;
pub mod scene_file;
pub mod sensor;
pub mod spectrum;
pub mod texture;
