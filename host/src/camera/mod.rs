//! Cameras: turn film positions into rays, and (for light tracing) rays back into film positions
//! with their importance. Plus the pixel filter and the named camera collection.

pub mod filter;
pub mod interface;
pub mod manager;
pub mod perspective;

pub use filter::Filter;
pub use manager::CameraManager;
pub use perspective::{FovAxis, PerspectiveCamera};

pub use interface::{Camera, CameraRay, CameraSample, CameraWiSample};
