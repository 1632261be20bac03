//! Geometry: rays, shapes, the BVH and robust ray offsets.

pub mod ray;
pub use ray::Ray;
