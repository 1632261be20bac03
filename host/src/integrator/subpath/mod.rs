//! Building blocks of a path: the vertex, the random walk, the light subpath, the connection
//! to the camera and the light-tracing beam.

pub mod beam;
pub mod camera_connection;
pub mod light_subpath;
pub mod random_walk;
pub mod vertex;
