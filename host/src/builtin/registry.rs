//! The table of every built-in type, and lookups in it by kind and name.

use super::built_in_type::BuiltinType;
use super::{camera, light, material, observer, shape, spd};
use crate::scene_file::type_doc::Kind;

/// Every built-in type, in documentation order.
pub fn types() -> &'static [BuiltinType] {
    &ALL
}

static ALL: [BuiltinType; 32] = [
    material::lambertian::TYPE,
    material::mirror::TYPE,
    material::dielectric::TYPE,
    material::rough_dielectric::TYPE,
    material::conductor::TYPE,
    material::plastic::TYPE,
    material::rough_plastic::TYPE,
    material::thin_film::TYPE,
    material::emissive::TYPE,
    material::fluorescent::TYPE,
    light::point::TYPE,
    light::spot::TYPE,
    light::directional::TYPE,
    light::environment::TYPE,
    light::envmap::TYPE,
    light::luminaire::TYPE,
    light::cie_sky::TYPE,
    light::sun::TYPE,
    light::near_field::TYPE,
    light::ray_file::TYPE,
    light::gldf::TYPE,
    spd::spec::TYPE,
    spd::table::TYPE,
    observer::cie::CIE1931_2,
    observer::cie::CIE1964_10,
    observer::cie::CIE2015_2,
    observer::cie::CIE2015_10,
    shape::sphere::TYPE,
    shape::quad::TYPE,
    shape::mesh::TYPE,
    shape::mesh_file::OBJ,
    shape::mesh_file::PLY,
];

static CAMERAS: [BuiltinType; 2] = [camera::perspective::TYPE, camera::perspective::PINHOLE];

/// Every built-in type including cameras, in documentation order.
pub fn all() -> impl Iterator<Item = &'static BuiltinType> {
    ALL.iter().chain(CAMERAS.iter())
}

/// The built-in type `name` (or an alias) of `kind`.
pub fn find(kind: Kind, name: &str) -> Option<&'static BuiltinType> {
    all().find(|t| t.kind() == kind && (t.name == name || t.aliases.contains(&name)))
}

/// Names (and aliases) of the built-in types of `kind`.
pub fn names(kind: Kind) -> Vec<String> {
    all()
        .filter(|t| t.kind() == kind)
        .flat_map(|t| std::iter::once(t.name).chain(t.aliases.iter().copied()))
        .map(String::from)
        .collect()
}
