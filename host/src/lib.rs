//! spectrace: a spectral bidirectional path tracer that is also a plugin host.
//!
//! Data flows one way: scene file → plugin registry → scene (managers) → integrator → film → output.
//! Each module below is one concept; the integrator only sees the host traits in [`light`] and
//! [`material`], never whether an object came from a dynamic library, a blob or a built-in.

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
pub mod scene;
pub mod sensor;
pub mod spectrum;
pub mod texture;
