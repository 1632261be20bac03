//! From the expanded Mitsuba element tree ([`super::xml`]) to a spectrace [`SceneDescription`],
//! with a note for everything changed, approximated or dropped (one note per kind of element or
//! parameter, naming the elements it concerns). The table of what maps to what is in
//! `docs/mitsuba-import.md`.
//!
//! One file a part: [`tree`] walks the scene, [`converter`] holds the state every part shares,
//! [`shapes`], [`bsdfs`], [`colours`], [`emitters`] and [`sensors`] convert their elements,
//! [`props`] reads an element's properties and transforms, [`values`] and [`meshes`] build the
//! description's values.

mod bsdfs;
mod colours;
mod converter;
mod emitters;
mod meshes;
mod props;
mod sensors;
mod shapes;
mod tree;
mod values;

pub use bsdfs::IOR_TABLE;
pub use meshes::{cube_mesh, cylinder_mesh, disk_mesh, uv_sphere_mesh, ROUND_SEGMENTS};
pub use props::transform_of;
pub use tree::{convert_tree, Conversion};
#[cfg(test)]
pub(crate) use values::num;
pub use values::numbers;
