//! The seed's SceneObjectManager: what each geometry object is made of.

use crate::material::Material;
use std::sync::Arc;

/// One scene object: its name (from the scene file) and material. Its shape lives in
/// [`crate::geometry::Geometry`] under the same index.
#[derive(Clone, Debug)]
pub struct SceneObject {
    /// Name from the scene file.
    pub name: String,
    /// Surface material.
    pub material: Arc<dyn Material>,
}

/// All objects, indexed like the geometry's objects.
#[derive(Clone, Debug, Default)]
pub struct SceneObjectManager {
    objects: Vec<SceneObject>,
}

impl SceneObjectManager {
    /// From objects in geometry order.
    pub fn new(objects: Vec<SceneObject>) -> Self {
        Self { objects }
    }

    /// Object `index`.
    #[inline]
    pub fn get(&self, index: u32) -> Option<&SceneObject> {
        self.objects.get(index as usize)
    }

    /// Material of object `index`.
    #[inline]
    pub fn material(&self, index: u32) -> &dyn Material {
        self.objects[index as usize].material.as_ref()
    }

    /// All objects.
    pub fn objects(&self) -> &[SceneObject] {
        &self.objects
    }

    /// Number of objects.
    pub fn len(&self) -> usize {
        self.objects.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.objects.is_empty()
    }
}
