//! Where a scene comes from, so it can be rebuilt with other representation switches (the
//! accuracy benchmark builds one scene per distinct [`RepresentationOptions`]).

use super::{default_scene_with, load_scene_file_with, BuiltinFactory, Scene, SceneError};
use crate::scene_file::RepresentationOptions;
use std::path::PathBuf;

/// A scene that can be (re)built: the embedded Cornell box or a RON file (built-in types only).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneSource {
    /// The embedded measured Cornell box.
    Default,
    /// A scene file.
    File(PathBuf),
}

impl SceneSource {
    /// `File(path)` if given, else `Default`.
    pub fn from_path(path: Option<PathBuf>) -> Self {
        path.map_or(Self::Default, Self::File)
    }

    /// Build the scene with `representation`.
    pub fn build(&self, representation: &RepresentationOptions) -> Result<Scene, SceneError> {
        match self {
            Self::Default => default_scene_with(representation),
            Self::File(p) => load_scene_file_with(p, &[&BuiltinFactory], representation),
        }
    }

    /// A name for messages and plot titles.
    pub fn describe(&self) -> String {
        match self {
            Self::Default => "Cornell box".into(),
            Self::File(p) => p.display().to_string(),
        }
    }
}
