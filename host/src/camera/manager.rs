//! The scene's cameras by name (the seed's CameraManager): render one by name, default the first.

use super::{Camera, Filter};
use std::sync::Arc;

/// One named camera with its pixel filter.
#[derive(Clone, Debug)]
pub struct NamedCamera {
    /// Name used by `--camera`.
    pub name: String,
    /// The camera.
    pub camera: Arc<dyn Camera>,
    /// Its reconstruction filter.
    pub filter: Filter,
}

/// All cameras of a scene, in file order.
#[derive(Clone, Debug, Default)]
pub struct CameraManager {
    cameras: Vec<NamedCamera>,
}

impl CameraManager {
    /// An empty manager.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a camera; names must be unique.
    pub fn add(&mut self, camera: NamedCamera) -> Result<(), String> {
        if self.cameras.iter().any(|c| c.name == camera.name) {
            return Err(format!("duplicate camera name {:?}", camera.name));
        }
        self.cameras.push(camera);
        Ok(())
    }

    /// The camera called `name`, or the first one for `None`. The error lists the names.
    pub fn get(&self, name: Option<&str>) -> Result<&NamedCamera, String> {
        match name {
            None => self
                .cameras
                .first()
                .ok_or_else(|| "the scene has no camera".to_string()),
            Some(n) => self.cameras.iter().find(|c| c.name == n).ok_or_else(|| {
                let names: Vec<&str> = self.cameras.iter().map(|c| c.name.as_str()).collect();
                format!("no camera named {n:?}; cameras: {}", names.join(", "))
            }),
        }
    }

    /// All cameras.
    pub fn cameras(&self) -> &[NamedCamera] {
        &self.cameras
    }
}
