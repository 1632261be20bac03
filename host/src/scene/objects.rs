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
    /// Wavelength shifting is rendered: some material offers re-radiation and it was not
    /// switched off ([`set_fluorescence`](Self::set_fluorescence)).
    fluorescence: bool,
}

impl SceneObjectManager {
    /// From objects in geometry order. Fluorescence is on when some material offers
    /// re-radiation data.
    pub fn new(objects: Vec<SceneObject>) -> Self {
        let fluorescence = objects.iter().any(|o| o.material.reradiation().is_some());
        Self {
            objects,
            fluorescence,
        }
    }

    /// True when the integrators shift wavelengths at fluorescent surfaces (the scene has
    /// one and it was not switched off). When false, such surfaces show only their
    /// reflectance: no fluorescence bookkeeping runs.
    #[inline]
    pub fn fluorescence(&self) -> bool {
        self.fluorescence
    }

    /// Switch wavelength shifting off (`false`: reflectance only) or back on; on has an
    /// effect only when some material offers re-radiation. Returns the resulting state.
    pub fn set_fluorescence(&mut self, on: bool) -> bool {
        self.fluorescence = on
            && self
                .objects
                .iter()
                .any(|o| o.material.reradiation().is_some());
        self.fluorescence
    }

    /// The re-radiation data of object `index`'s material, when fluorescence is rendered.
    #[inline]
    pub fn reradiation(
        &self,
        index: u32,
    ) -> Option<&dyn crate::spectrum::reradiation::Reradiation> {
        if !self.fluorescence {
            return None;
        }
        self.objects[index as usize].material.reradiation()
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
