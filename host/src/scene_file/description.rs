//! The RON scene file format (serde). Every material, light, camera and object names its `type`
//! and carries a `params` block, read as a `ron::Value` and interpreted by an
//! [`super::ObjectFactory`] (built-in types or plugins). See `scenes/cornell_box.ron`.
//!
//! ```ron
//! (
//!     units: "m",
//!     observer: "cie1931-2",
//!     output: (spp: 64, max_depth: 64, rgb_space: "srgb"),
//!     materials: [ (name: "white", type: "lambertian", params: (reflectance: 0.8)) ],
//!     objects: [ (name: "ball", type: "sphere", material: "white",
//!                 params: (center: (0, 1, 0), radius: 1),
//!                 transform: [Scale((2, 2, 2)), Translate((0, 0, -5))]) ],
//!     lights: [ (name: "bulb", type: "point", params: (position: (0, 5, 0), power: 100, spd: "a")) ],
//!     cameras: [ (name: "main", type: "perspective",
//!                 params: (position: (0, 2, 10), look_at: (0, 1, 0), fov: 40, resolution: (320, 240))) ],
//! )
//! ```

use serde::{Deserialize, Serialize};

fn unit() -> ron::Value {
    ron::Value::Unit
}

/// A whole scene file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDescription {
    /// Length unit of every position, size and distance in the file: `m` (default), `cm`,
    /// `mm`, `in` or `ft`. Lengths are converted to metres when the scene is built; W, W/sr,
    /// W/m², W/(m²·sr·nm), lm, cd, lx and cd/m² are per metre whatever the unit.
    #[serde(default)]
    pub units: Option<String>,
    /// `absolute` (default): the lights' values are physical (W, lm, …); `relative`: they only
    /// have the right proportions (a measured spectrum of unknown scale, as in the Cornell box),
    /// so the render summary gives each light's share of the power instead of watts.
    #[serde(default)]
    pub emission_units: Option<String>,
    /// Colour-matching functions of the film: an observer type name — `cie1931-2` (default),
    /// `cie1964-10`, `cie2015-2`, `cie2015-10` or a plugin's — or `(type: .., params: ..)`
    /// (e.g. a blob).
    #[serde(default)]
    pub observer: Option<ObserverDescription>,
    /// Sampling and output defaults.
    #[serde(default)]
    pub output: OutputDescription,
    /// Named materials, referenced by objects.
    #[serde(default)]
    pub materials: Vec<ItemDescription>,
    /// Geometry with a material each.
    #[serde(default)]
    pub objects: Vec<ObjectDescription>,
    /// Non-area lights (area lights are objects with an emissive material).
    #[serde(default)]
    pub lights: Vec<ItemDescription>,
    /// Cameras; the first is the default.
    #[serde(default)]
    pub cameras: Vec<ItemDescription>,
    /// Illuminance sensors measured by the render (`illuminance_grid`, see
    /// [`crate::builtin::sensor::grid`]).
    #[serde(default)]
    pub sensors: Vec<ItemDescription>,
    /// Plugin libraries the scene needs, loaded before it is built: `"PATH"` or
    /// `(path: "PATH", sha256: "HEX")` (pinned; relative to the scene file; see
    /// [`super::pin`]).
    #[serde(default)]
    pub plugins: Vec<super::pin::ScenePlugin>,
}

/// The scene's observer: a type name with default parameters, or a type with parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum ObserverDescription {
    /// `observer: "cie1931-2"`.
    Name(String),
    /// `observer: (type: "blob", params: (file: "eye.blob"))`.
    Typed {
        /// Type name.
        #[serde(rename = "type")]
        type_name: String,
        /// Parameters (a RON struct).
        #[serde(default = "unit")]
        params: ron::Value,
    },
}

impl From<&str> for ObserverDescription {
    fn from(name: &str) -> Self {
        ObserverDescription::Name(name.to_string())
    }
}

impl ObserverDescription {
    /// Type name and parameters.
    pub fn type_and_params(&self) -> (&str, ron::Value) {
        match self {
            ObserverDescription::Name(n) => (n, ron::Value::Unit),
            ObserverDescription::Typed { type_name, params } => (type_name, params.clone()),
        }
    }
}

/// Output and sampling defaults of a scene.
#[derive(Clone, Debug, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputDescription {
    /// Samples per pixel (default 64).
    #[serde(default)]
    pub spp: Option<u32>,
    /// Maximum path length (default 64).
    #[serde(default)]
    pub max_depth: Option<u32>,
    /// RGB space of the EXR: `srgb` (default), `rec2020`, `display-p3`, `aces2065-1`.
    #[serde(default)]
    pub rgb_space: Option<String>,
    /// PNG preview exposure: a linear multiplier of the image before the sRGB encoding (default
    /// 1, i.e. 0 EV; `render --exposure EV` overrides it with 2^EV). Without either, `render`
    /// picks an exposure for the PNG when the image would be nearly black or mostly clipped.
    #[serde(default)]
    pub png_exposure: Option<f64>,
}

/// A material, light or camera: a name, a type and its parameters.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ItemDescription {
    /// Unique name.
    pub name: String,
    /// Type name, built in or from a plugin.
    #[serde(rename = "type")]
    pub type_name: String,
    /// Parameters (a RON struct).
    #[serde(default = "unit")]
    pub params: ron::Value,
}

/// One transform step; a list of steps is applied in order (the first step acts on the object
/// first).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum TransformStep {
    /// Move by (x, y, z).
    Translate([f64; 3]),
    /// Scale per axis (non-zero).
    Scale([f64; 3]),
    /// Rotate by `degrees` (right-handed) about `axis`.
    Rotate {
        /// Rotation axis.
        axis: [f64; 3],
        /// Angle in degrees.
        degrees: f64,
    },
    /// A row-major 4×4 matrix acting on column vectors (`p' = M·p`).
    Matrix([[f64; 4]; 4]),
}

/// A geometry object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectDescription {
    /// Unique name.
    pub name: String,
    /// Shape type: `mesh` (inline), `obj`, `ply`, `sphere`, `quad`.
    #[serde(rename = "type")]
    pub type_name: String,
    /// Name of a material in `materials`.
    pub material: String,
    /// Shape parameters.
    #[serde(default = "unit")]
    pub params: ron::Value,
    /// Object-to-world transform steps (identity when empty).
    #[serde(default)]
    pub transform: Vec<TransformStep>,
}
