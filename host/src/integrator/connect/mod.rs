//! Connections through specular surfaces: solving a specular chain, seeding it, manifold
//! connections to lights and camera chains.

pub mod camera_chain;
pub mod manifold_connection;
pub mod specular_chain;
pub mod specular_seeds;
