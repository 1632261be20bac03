//! A built scene ([`Scene`]): geometry, materials, cameras, lights, observer, options and sensors, as the render plan takes it.

use super::objects::SceneObjectManager;
use crate::camera::CameraManager;
use crate::color::{Observer, RgbColorSpace};
use crate::geometry::Geometry;
use crate::light::LightSourceManager;
use crate::scene_file::units::LengthUnit;
use std::sync::Arc;

/// Render settings a scene file may carry (the command line overrides them).
#[derive(Clone, Debug, PartialEq)]
pub struct SceneOptions {
    /// Samples per pixel when the command line gives neither `--spp` nor `--time`.
    pub spp: u32,
    /// Longest path (number of scattering events); Russian roulette ends most paths earlier.
    pub max_depth: u32,
    /// RGB space of the EXR's R, G, B channels.
    pub rgb_space: RgbColorSpace,
    /// Name of that space (for messages).
    pub rgb_space_name: String,
    /// Exposure multiplier of the PNG preview.
    pub png_exposure: f64,
    /// True when the scene file set `png_exposure` (then `render` never picks an exposure).
    pub png_exposure_given: bool,
    /// The length unit the scene file was written in (lengths are metres once built).
    pub length_unit: LengthUnit,
    /// The scene declared `emission_units: "relative"`: its lights have the right proportions
    /// but no physical scale, so watts and lumens are not reported.
    pub relative_emission: bool,
    /// The scene item each light of [`Scene::lights`] came from (`object "lamp"`,
    /// `light "sun"`), in the same order, for messages.
    pub light_items: Vec<String>,
}

impl Default for SceneOptions {
    fn default() -> Self {
        Self {
            spp: 64,
            max_depth: 64,
            rgb_space: crate::color::SRGB,
            rgb_space_name: "srgb".into(),
            png_exposure: 1.0,
            png_exposure_given: false,
            length_unit: LengthUnit::Metre,
            relative_emission: false,
            light_items: Vec::new(),
        }
    }
}

/// Everything needed to render.
#[derive(Debug, Clone)]
pub struct Scene {
    /// All shapes and the BVH.
    pub geometry: Arc<Geometry>,
    /// Materials per object.
    pub objects: SceneObjectManager,
    /// Named cameras.
    pub cameras: CameraManager,
    /// Lights and the light chooser.
    pub lights: LightSourceManager,
    /// Colour-matching functions the film integrates with.
    pub observer: Arc<dyn Observer>,
    /// Output and sampling defaults.
    pub options: SceneOptions,
    /// What in the scene probably does not render as meant (lights that emit nothing, no
    /// light, powers near the renderer's limits, …); see [`warnings`]. Printed by `render`.
    pub warnings: Vec<String>,
    /// Illuminance sensors (the scene's `sensors`), measured after the image.
    pub sensors: Vec<crate::builtin::sensor::grid::IlluminanceGrid>,
    /// Glare observers (the scene's `glare_observer` sensors), measured after the image.
    pub glare: Vec<crate::builtin::sensor::glare_observer::GlareObserver>,
}

impl Scene {
    /// The scene's warnings (see [`Scene::warnings`](Scene#structfield.warnings)).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }
}
