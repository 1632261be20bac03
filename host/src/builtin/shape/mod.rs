//! Built-in shapes (`objects: [(type: .., material: .., params: .., transform: ..)]`), one per
//! file. Shapes are in object space; the object's `transform` places them.

pub mod mesh;
pub mod mesh_file;
pub mod quad;
pub mod sphere;
